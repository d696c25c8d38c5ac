#include "ast_builder.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace mo::frontend::detail {

using namespace mo::frontend::ast;

SourceRange AstBuilder::range(antlr4::Token *t) const {
  if (!t)
    return {file_, 0, 0};
  auto b = static_cast<std::uint32_t>(t->getStartIndex());
  auto e = static_cast<std::uint32_t>(t->getStopIndex() + 1);
  if (t->getType() == antlr4::Token::EOF)
    b = e = static_cast<std::uint32_t>(text_.size());
  return {file_, b, e < b ? b : e};
}

SourceRange AstBuilder::range(antlr4::ParserRuleContext *ctx) const {
  SourceRange r = range(ctx->getStart());
  if (ctx->getStop() && ctx->getStop()->getStopIndex() + 1 >= r.begin)
    r.end = static_cast<std::uint32_t>(ctx->getStop()->getStopIndex() + 1);
  return r;
}

std::string AstBuilder::text(antlr4::Token *t) const {
  SourceRange r = range(t);
  return std::string(text_.substr(r.begin, r.end - r.begin));
}

/// Identifier text: backquotes of the Xcos dialect are dropped (the name is
/// what is inside); Modelica 'quoted' identifiers keep their quotes, which
/// are part of the name.
std::string AstBuilder::ident(antlr4::tree::TerminalNode *n) const {
  std::string s = text(n->getSymbol());
  if (s.size() >= 2 && s.front() == '`')
    return s.substr(1, s.size() - 2);
  return s;
}

std::unique_ptr<StoredDefinition> AstBuilder::build(P::Stored_definitionContext *ctx) {
  auto sd = std::make_unique<StoredDefinition>();
  sd->file = file_;
  if (ctx->WITHIN() && ctx->name())
    sd->within = name(ctx->name());
  for (auto *c : ctx->class_definition())
    sd->classes.push_back(class_definition(c));
  return sd;
}

static Restriction restriction_of(g::ModelicaParser::Class_prefixesContext *p) {
  if (p->CLASS()) return Restriction::Class;
  if (p->MODEL()) return Restriction::Model;
  if (p->RECORD()) return p->OPERATOR() ? Restriction::OperatorRecord : Restriction::Record;
  if (p->BLOCK()) return Restriction::Block;
  if (p->CONNECTOR()) return p->EXPANDABLE() ? Restriction::ExpandableConnector : Restriction::Connector;
  if (p->TYPE()) return Restriction::Type;
  if (p->PACKAGE()) return Restriction::Package;
  if (p->FUNCTION()) return Restriction::Function;
  if (p->OPTIMIZATION()) return Restriction::Optimization;
  return Restriction::Operator;
}

ClassPtr AstBuilder::class_definition(P::Class_definitionContext *ctx) {
  auto cls = std::make_unique<ClassDef>();
  cls->encapsulated = ctx->ENCAPSULATED() != nullptr;
  cls->partial = ctx->class_prefixes()->PARTIAL() != nullptr;
  cls->restriction = restriction_of(ctx->class_prefixes());
  cls->full_range = range(ctx);
  auto *spec = ctx->class_specifier();
  if (++class_depth_ > kMaxClassDepth) {
    if (class_depth_ == kMaxClassDepth + 1)
      diags_.report(DiagId::NestingTooDeep, range(spec),
                    "classes nested more than " + std::to_string(kMaxClassDepth) + " levels deep");
    --class_depth_;
    return cls;
  }
  struct Leave {
    unsigned &d;
    ~Leave() { --d; }
  } leave{class_depth_};
  if (auto *lc = spec->long_class_specifier()) {
    auto ids = lc->IDENT();
    cls->name = ident(ids.front());
    cls->range = range(ids.front());
    if (lc->EXTENDS()) { // `redeclare model extends M(mods)`: M extends the inherited M
      Extends base;
      base.base.parts.push_back(cls->name);
      base.base.range = cls->range;
      base.range = range(lc->EXTENDS());
      base.inherited_class = true;
      if (lc->class_modification())
        base.mod = class_modification(lc->class_modification());
      cls->extends.push_back(std::move(base));
    } else if (lc->class_modification()) {
      cls->class_mod = class_modification(lc->class_modification());
    }
    cls->description = string_comment(lc->string_comment());
    composition(lc->composition(), *cls);
    std::string end_name = ident(ids.back());
    if (end_name != cls->name) {
      diags_.report(DiagId::MismatchedEndName, range(ids.back()),
                    "'end " + end_name + "' does not match the class name '" + cls->name + "'");
      diags_.note(cls->range, "class '" + cls->name + "' starts here");
    }
  } else if (auto *sc = spec->short_class_specifier()) {
    short_class(sc, *cls);
  } else {
    auto *dc = spec->der_class_specifier();
    cls->name = ident(dc->IDENT().front());
    cls->range = range(dc->IDENT().front());
    diags_.report(DiagId::Unsupported, range(dc), "derivative function declarations are not supported");
  }
  return cls;
}

void AstBuilder::short_class(P::Short_class_specifierContext *sc, ClassDef &cls) {
  cls.name = ident(sc->IDENT());
  cls.range = range(sc->IDENT());
  if (sc->ENUMERATION()) {
    if (sc->enum_list())
      for (auto *lit : sc->enum_list()->enumeration_literal())
        cls.enumeration.push_back(ident(lit->IDENT()));
  } else {
    cls.short_base = type_specifier(sc->type_specifier());
    if (sc->array_subscripts())
      cls.short_dims = array_subscripts(sc->array_subscripts());
    if (sc->class_modification())
      cls.class_mod = class_modification(sc->class_modification());
    if (sc->base_prefix()->INPUT()) cls.short_causality = Causality::Input;
    if (sc->base_prefix()->OUTPUT()) cls.short_causality = Causality::Output;
  }
  cls.description = comment(sc->comment());
}

ClassPtr AstBuilder::short_class_definition(P::Short_class_definitionContext *ctx) {
  auto cls = std::make_unique<ClassDef>();
  cls->partial = ctx->class_prefixes()->PARTIAL() != nullptr;
  cls->restriction = restriction_of(ctx->class_prefixes());
  cls->full_range = range(ctx);
  short_class(ctx->short_class_specifier(), *cls);
  return cls;
}

void AstBuilder::composition(P::CompositionContext *ctx, ClassDef &cls) {
  // Sections come in source order; element lists after `protected` are protected.
  bool is_protected = false;
  for (auto *child : ctx->children) {
    if (auto *t = dynamic_cast<antlr4::tree::TerminalNode *>(child)) {
      auto type = t->getSymbol()->getType();
      if (type == P::PUBLIC) is_protected = false;
      if (type == P::PROTECTED) is_protected = true;
      if (type == P::EXTERNAL) {
        cls.is_external = true;
        external_clause(ctx, cls);
      }
    } else if (auto *el = dynamic_cast<P::Element_listContext *>(child)) {
      element_list(el, cls, is_protected);
      for (auto *an : el->annotation())
        vendor_annotation(an, cls);
    } else if (auto *an = dynamic_cast<P::AnnotationContext *>(child)) {
      vendor_annotation(an, cls);
    } else if (auto *eq = dynamic_cast<P::Equation_sectionContext *>(child)) {
      auto &target = eq->INITIAL() ? cls.initial_equations : cls.equations;
      for (auto *e : eq->equation())
        target.push_back(equation(e));
      for (auto *note : eq->annotation()) // a class annotation written last lands here
        vendor_annotation(note, cls);
    } else if (auto *alg = dynamic_cast<P::Algorithm_sectionContext *>(child)) {
      for (auto *note : alg->annotation()) // a class annotation written last lands here
        vendor_annotation(note, cls);
      auto section = statements(alg->statement());
      auto &target = alg->INITIAL() ? cls.initial_equations : cls.equations;
      if (cls.restriction != Restriction::Function) {
        if (algorithm_as_equations(section, target))
          continue;
        cls.model_algorithms.push_back(AlgorithmSection{alg->INITIAL() != nullptr, range(alg->ALGORITHM()),
                                                        std::move(section)});
        continue;
      }
      if (!cls.has_algorithm)
        cls.algorithm_range = range(alg->ALGORITHM());
      cls.has_algorithm = true;
      for (auto &st : section)
        cls.algorithm.push_back(std::move(st));
    } else if (auto *con = dynamic_cast<P::Constraint_sectionContext *>(child)) {
      for (auto *c : con->constraint())
        cls.constraints.push_back(constraint(c));
      for (auto *note : con->annotation())
        vendor_annotation(note, cls);
    }
  }
}

/// Keeps the arguments of `__mocompile(...)` and `GenerateEvents` from a
/// class annotation; the rest of the annotation is not read.
void AstBuilder::vendor_annotation(P::AnnotationContext *ctx, ClassDef &cls) {
  Modification m = class_modification(ctx->class_modification());
  for (auto &arg : m.args) {
    if (arg.path.size() == 1 && arg.path[0] == "GenerateEvents" && arg.mod.binding &&
        arg.mod.binding->kind == ExprKind::Boolean)
      cls.generate_events = arg.mod.binding->number != 0.0;
    if (arg.path.size() != 1 || arg.path[0] != "__mocompile")
      continue;
    for (auto &inner : arg.mod.args)
      cls.vendor_annotation.args.push_back(std::move(inner));
    cls.vendor_annotation.range = arg.range;
  }
}

void AstBuilder::element_list(P::Element_listContext *ctx, ClassDef &cls, bool is_protected) {
  for (auto *e : ctx->element())
    element(e, cls, is_protected);
}

void AstBuilder::element(P::ElementContext *ctx, ClassDef &cls, bool is_protected) {
  if (auto *imp = ctx->import_clause()) {
    cls.imports.push_back(import_clause(imp));
    return;
  }
  if (auto *ext = ctx->extends_clause()) {
    Extends e;
    e.base = type_specifier(ext->type_specifier());
    if (ext->class_modification())
      e.mod = class_modification(ext->class_modification());
    e.range = range(ext);
    e.is_protected = is_protected;
    cls.extends.push_back(std::move(e));
    return;
  }
  if (auto *cd = ctx->class_definition()) {
    auto nested = class_definition(cd);
    nested->final_ = ctx->FINAL() != nullptr;
    nested->is_protected = is_protected;
    nested->replaceable = ctx->REPLACEABLE() != nullptr;
    nested->redeclare = ctx->REDECLARE() != nullptr;
    // A class extension replaces the inherited class (MLS 7.3.1), with or
    // without the `redeclare` written.
    for (const auto &e : nested->extends)
      nested->redeclare = nested->redeclare || e.inherited_class;
    cls.classes.push_back(std::move(nested));
    return;
  }
  if (auto *cc = ctx->component_clause()) {
    component_clause(cc, cls, is_protected, ctx);
    return;
  }
}

void AstBuilder::component_clause(P::Component_clauseContext *ctx, ClassDef &cls, bool is_protected,
                                  P::ElementContext *prefixes) {
  auto *tp = ctx->type_prefix();
  TypeName type = type_specifier(ctx->type_specifier());
  for (auto *decl : ctx->component_list()->component_declaration()) {
    Component c = declaration(tp, type, decl->declaration(), ctx->array_subscripts());
    c.final_ = prefixes->FINAL() != nullptr;
    c.inner = prefixes->INNER() != nullptr;
    c.outer = prefixes->OUTER() != nullptr;
    c.replaceable = prefixes->REPLACEABLE() != nullptr;
    c.redeclare = prefixes->REDECLARE() != nullptr;
    c.is_protected = is_protected;
    if (auto *cc = prefixes->constraining_clause()) {
      c.has_constraint = true;
      if (cc->class_modification())
        c.constraint_mod = class_modification(cc->class_modification());
    }
    if (decl->condition_attribute())
      c.condition = expression(decl->condition_attribute()->expression());
    c.description = comment(decl->comment());
    c.evaluate = evaluate_annotation(decl->comment());
    cls.components.push_back(std::move(c));
  }
}

Component AstBuilder::declaration(P::Type_prefixContext *tp, const TypeName &type, P::DeclarationContext *d,
                                  P::Array_subscriptsContext *type_dims) {
  Component c;
  auto *name_token = d->IDENT() ? d->IDENT() : d->CONSTRAINT(); // `constraint` outside optimization
  c.name = ident(name_token);
  c.range = range(name_token);
  c.type = type;
  if (tp->PARAMETER()) c.variability = Variability::Parameter;
  if (tp->CONSTANT()) c.variability = Variability::Constant;
  if (tp->DISCRETE()) c.variability = Variability::Discrete;
  if (tp->INPUT()) c.causality = Causality::Input;
  if (tp->OUTPUT()) c.causality = Causality::Output;
  if (tp->FLOW()) c.connection = Connection::Flow;
  if (tp->STREAM()) c.connection = Connection::Stream;
  if (type_dims)
    c.dims = array_subscripts(type_dims);
  if (d->array_subscripts())
    for (auto &s : array_subscripts(d->array_subscripts()))
      c.dims.push_back(std::move(s));
  if (d->modification())
    c.mod = modification(d->modification());
  return c;
}

Import AstBuilder::import_clause(P::Import_clauseContext *ctx) {
  Import imp;
  imp.range = range(ctx);
  imp.path = name(ctx->name());
  if (ctx->IDENT())
    imp.alias = ident(ctx->IDENT());
  if (ctx->import_list())
    for (auto *id : ctx->import_list()->IDENT())
      imp.names.push_back(ident(id));
  for (auto *child : ctx->children)
    if (auto *t = dynamic_cast<antlr4::tree::TerminalNode *>(child))
      if (text(t->getSymbol()) == ".*" || text(t->getSymbol()) == "*")
        imp.wildcard = true;
  return imp;
}

TypeName AstBuilder::type_specifier(P::Type_specifierContext *ctx) {
  TypeName t;
  t.global = ctx->getStart()->getType() != P::IDENT;
  t.parts = name(ctx->name());
  t.range = range(ctx);
  return t;
}

std::vector<std::string> AstBuilder::name(P::NameContext *ctx) {
  std::vector<std::string> parts;
  for (auto *id : ctx->IDENT())
    parts.push_back(ident(id));
  return parts;
}

Modification AstBuilder::modification(P::ModificationContext *ctx) {
  Modification m;
  if (ctx->class_modification())
    m = class_modification(ctx->class_modification());
  if (ctx->expression())
    m.binding = expression(ctx->expression());
  m.range = range(ctx);
  return m;
}

Modification AstBuilder::class_modification(P::Class_modificationContext *ctx) {
  Modification m;
  m.range = range(ctx);
  if (ctx->argument_list())
    for (auto *a : ctx->argument_list()->argument())
      m.args.push_back(argument(a));
  return m;
}

ElementMod AstBuilder::argument(P::ArgumentContext *ctx) {
  ElementMod em;
  em.range = range(ctx);
  if (auto *mr = ctx->element_modification_or_replaceable()) {
    em.each = mr->EACH() != nullptr;
    em.final_ = mr->FINAL() != nullptr;
    if (auto *m = mr->element_modification()) {
      em.path = name(m->name());
      em.range = range(m->name());
      if (m->modification())
        em.mod = modification(m->modification());
    } else {
      redeclaration(mr->element_replaceable(), em); // `replaceable` in a modifier redeclares
    }
    return em;
  }
  auto *rd = ctx->element_redeclaration();
  em.each = rd->EACH() != nullptr;
  em.final_ = rd->FINAL() != nullptr;
  if (auto *sc = rd->short_class_definition())
    em.class_def = short_class_definition(sc);
  else if (auto *c1 = rd->component_clause1())
    em.component = component_clause1(c1);
  else
    redeclaration(rd->element_replaceable(), em);
  em.redeclare = true;
  em.path = {em.component ? em.component->name : em.class_def->name};
  return em;
}

void AstBuilder::redeclaration(P::Element_replaceableContext *ctx, ElementMod &em) {
  em.redeclare = true;
  if (auto *sc = ctx->short_class_definition()) {
    em.class_def = short_class_definition(sc);
    em.class_def->replaceable = true;
  } else {
    em.component = component_clause1(ctx->component_clause1());
    em.component->replaceable = true;
    if (auto *cc = ctx->constraining_clause()) {
      em.component->has_constraint = true;
      if (cc->class_modification())
        em.component->constraint_mod = class_modification(cc->class_modification());
    }
  }
  em.path = {em.component ? em.component->name : em.class_def->name};
}

std::unique_ptr<Component> AstBuilder::component_clause1(P::Component_clause1Context *ctx) {
  auto *d1 = ctx->component_declaration1();
  auto c = std::make_unique<Component>(
      declaration(ctx->type_prefix(), type_specifier(ctx->type_specifier()), d1->declaration(), nullptr));
  c->redeclare = true;
  c->description = comment(d1->comment());
  c->evaluate = evaluate_annotation(d1->comment());
  return c;
}

std::string AstBuilder::string_comment(P::String_commentContext *ctx) {
  std::string out;
  if (!ctx)
    return out;
  for (auto *s : ctx->STRING()) {
    std::string raw = text(s->getSymbol());
    out += unescape_string(raw.substr(1, raw.size() - 2));
  }
  return out;
}

std::string AstBuilder::comment(P::CommentContext *ctx) {
  return ctx ? string_comment(ctx->string_comment()) : std::string();
}

bool AstBuilder::evaluate_annotation(P::CommentContext *ctx) {
  if (!ctx || !ctx->annotation())
    return false;
  const Modification m = class_modification(ctx->annotation()->class_modification());
  for (const auto &arg : m.args)
    if (arg.path.size() == 1 && arg.path[0] == "Evaluate" && arg.mod.binding &&
        arg.mod.binding->kind == ExprKind::Boolean)
      return arg.mod.binding->number != 0.0;
  return false;
}

std::vector<ForIndex> AstBuilder::for_indices(P::For_indicesContext *ctx) {
  std::vector<ForIndex> out;
  for (auto *fi : ctx->for_index()) {
    ForIndex idx;
    auto *name_token = fi->IDENT() ? fi->IDENT() : fi->CONSTRAINT(); // `constraint` outside optimization
    idx.name = ident(name_token);
    idx.loc = range(name_token);
    if (fi->expression())
      idx.range = expression(fi->expression());
    out.push_back(std::move(idx));
  }
  return out;
}

Equation AstBuilder::equation(P::EquationContext *ctx) {
  Equation eq;
  eq.range = range(ctx);
  eq.description = comment(ctx->comment());
  if (ctx->simple_expression()) {
    eq.kind = EquationKind::Simple;
    eq.lhs = simple_expression(ctx->simple_expression());
    eq.rhs = expression(ctx->expression());
  } else if (auto *c = ctx->connect_clause()) {
    eq.kind = EquationKind::Connect;
    eq.lhs = ref_expr(c->component_reference(0));
    eq.rhs = ref_expr(c->component_reference(1));
  } else if (auto *f = ctx->for_equation()) {
    eq.kind = EquationKind::For;
    eq.indices = for_indices(f->for_indices());
    for (auto *e : f->equation())
      eq.body.push_back(equation(e));
  } else if (auto *i = ctx->if_equation()) {
    eq.kind = EquationKind::If;
    // Children in order: if cond then eqs (elseif cond then eqs)* (else eqs)? end if
    EquationBranch *cur = nullptr;
    std::size_t cond_index = 0;
    auto conds = i->expression();
    for (auto *child : i->children) {
      if (auto *t = dynamic_cast<antlr4::tree::TerminalNode *>(child)) {
        auto type = t->getSymbol()->getType();
        if ((type == P::IF && cur == nullptr) || type == P::ELSEIF) {
          eq.branches.push_back(EquationBranch{expression(conds[cond_index++]), {}, range(t)});
          cur = &eq.branches.back();
        } else if (type == P::ELSE) {
          eq.branches.push_back(EquationBranch{nullptr, {}, range(t)});
          cur = &eq.branches.back();
        }
      } else if (auto *e = dynamic_cast<P::EquationContext *>(child)) {
        cur->body.push_back(equation(e));
      }
    }
  } else if (auto *w = ctx->when_equation()) {
    eq.kind = EquationKind::When;
    EquationBranch *cur = nullptr;
    std::size_t cond_index = 0;
    auto conds = w->expression();
    for (auto *child : w->children) {
      if (auto *t = dynamic_cast<antlr4::tree::TerminalNode *>(child)) {
        auto type = t->getSymbol()->getType();
        if ((type == P::WHEN && cur == nullptr) || type == P::ELSEWHEN) {
          eq.branches.push_back(EquationBranch{expression(conds[cond_index++]), {}, range(t)});
          cur = &eq.branches.back();
        }
      } else if (auto *e = dynamic_cast<P::EquationContext *>(child)) {
        cur->body.push_back(equation(e));
      }
    }
  } else {
    eq.kind = EquationKind::Call;
    auto callee = std::make_unique<Expr>(ExprKind::Call, range(ctx->component_reference()));
    callee->ref = component_reference(ctx->component_reference());
    if (ctx->function_call_args()->function_arguments())
      function_arguments(ctx->function_call_args()->function_arguments(), *callee);
    callee->range.end = range(ctx->function_call_args()).end;
    eq.lhs = std::move(callee);
  }
  return eq;
}

Equation AstBuilder::constraint(P::ConstraintContext *ctx) {
  Equation eq;
  eq.kind = EquationKind::Constraint;
  eq.range = range(ctx);
  eq.description = comment(ctx->comment());
  auto exprs = ctx->expression();
  if (exprs.size() == 2) {
    eq.lhs = expression(exprs[0]);
    eq.rhs = expression(exprs[1]);
    eq.rel = Op::Eq;
    return eq;
  }
  ExprPtr e = expression(exprs[0]);
  if (e->kind == ExprKind::Binary && (e->op == Op::Le || e->op == Op::Ge)) {
    eq.rel = e->op;
    eq.lhs = std::move(e->args[0]);
    eq.rhs = std::move(e->args[1]);
  } else {
    diags_.report(DiagId::BadOptimization, eq.range,
                  "a constraint must have the form 'a = b', 'a <= b' or 'a >= b'");
    eq.lhs = std::move(e);
    eq.rhs = make_real(0);
  }
  return eq;
}

// ------------------------------------------------------------- expressions

ExprPtr AstBuilder::expression(P::ExpressionContext *ctx) {
  if (auto *s = dynamic_cast<P::SimpleExprContext *>(ctx))
    return simple_expression(s->simple_expression());
  auto *ie = static_cast<P::IfExprContext *>(ctx);
  auto e = std::make_unique<Expr>(ExprKind::If, range(ctx));
  for (auto *sub : ie->expression())
    e->args.push_back(expression(sub));
  return e;
}

ExprPtr AstBuilder::simple_expression(P::Simple_expressionContext *ctx) {
  auto parts = ctx->logical_expression();
  if (parts.size() == 1)
    return logical_expression(parts[0]);
  auto e = std::make_unique<Expr>(ExprKind::Range, range(ctx));
  for (auto *p : parts)
    e->args.push_back(logical_expression(p));
  return e;
}

ExprPtr AstBuilder::logical_expression(P::Logical_expressionContext *ctx) {
  auto terms = ctx->logical_term();
  ExprPtr e = logical_term(terms[0]);
  for (std::size_t i = 1; i < terms.size(); ++i) {
    SourceRange r{file_, e->range.begin, range(terms[i]).end};
    e = make_binary(Op::Or, std::move(e), logical_term(terms[i]), r);
  }
  return e;
}

ExprPtr AstBuilder::logical_term(P::Logical_termContext *ctx) {
  auto factors = ctx->logical_factor();
  ExprPtr e = logical_factor(factors[0]);
  for (std::size_t i = 1; i < factors.size(); ++i) {
    SourceRange r{file_, e->range.begin, range(factors[i]).end};
    e = make_binary(Op::And, std::move(e), logical_factor(factors[i]), r);
  }
  return e;
}

ExprPtr AstBuilder::logical_factor(P::Logical_factorContext *ctx) {
  ExprPtr e = relation(ctx->relation());
  if (ctx->NOT())
    return make_unary(Op::Not, std::move(e), range(ctx));
  return e;
}

ExprPtr AstBuilder::relation(P::RelationContext *ctx) {
  auto parts = ctx->arithmetic_expression();
  ExprPtr a = arithmetic_expression(parts[0]);
  if (parts.size() == 1)
    return a;
  std::string op = text(ctx->relational_operator()->getStart());
  Op o = op == "<" ? Op::Lt : op == "<=" ? Op::Le : op == ">" ? Op::Gt
       : op == ">=" ? Op::Ge : op == "==" ? Op::Eq : Op::Ne;
  return make_binary(o, std::move(a), arithmetic_expression(parts[1]), range(ctx));
}

static Op add_op(const std::string &s) {
  return s == "+" ? Op::Add : s == "-" ? Op::Sub : s == ".+" ? Op::ElemAdd : Op::ElemSub;
}

ExprPtr AstBuilder::arithmetic_expression(P::Arithmetic_expressionContext *ctx) {
  auto terms = ctx->term();
  auto ops = ctx->add_operator();
  std::size_t op_index = 0;
  ExprPtr e = term(terms[0]);
  if (ops.size() == terms.size()) { // leading unary + or -
    std::string s = text(ops[0]->getStart());
    SourceRange r{file_, range(ops[0]).begin, e->range.end};
    e = make_unary(s == "-" || s == ".-" ? Op::Neg : Op::Plus, std::move(e), r);
    op_index = 1;
  }
  for (std::size_t i = 1; i < terms.size(); ++i, ++op_index) {
    Op o = add_op(text(ops[op_index]->getStart()));
    SourceRange r{file_, e->range.begin, range(terms[i]).end};
    e = make_binary(o, std::move(e), term(terms[i]), r);
  }
  return e;
}

ExprPtr AstBuilder::term(P::TermContext *ctx) {
  auto factors = ctx->factor();
  auto ops = ctx->mul_operator();
  ExprPtr e = factor(factors[0]);
  for (std::size_t i = 1; i < factors.size(); ++i) {
    std::string s = text(ops[i - 1]->getStart());
    Op o = s == "*" ? Op::Mul : s == "/" ? Op::Div : s == ".*" ? Op::ElemMul : Op::ElemDiv;
    SourceRange r{file_, e->range.begin, range(factors[i]).end};
    e = make_binary(o, std::move(e), factor(factors[i]), r);
  }
  return e;
}

ExprPtr AstBuilder::factor(P::FactorContext *ctx) {
  auto prims = ctx->primary();
  ExprPtr e = primary(prims[0]);
  if (prims.size() == 2) {
    auto *t = dynamic_cast<antlr4::tree::TerminalNode *>(ctx->children[1]);
    bool elem = t && text(t->getSymbol()) == ".^";
    e = make_binary(elem ? Op::ElemPow : Op::Pow, std::move(e), primary(prims[1]), range(ctx));
  }
  return e;
}

ExprPtr AstBuilder::number(antlr4::tree::TerminalNode *n) {
  std::string s = text(n->getSymbol());
  bool is_real = s.find_first_of(".eE") != std::string::npos;
  errno = 0;
  double v = std::strtod(s.c_str(), nullptr);
  if (errno == ERANGE && std::isinf(v))
    diags_.report(DiagId::BadNumber, range(n), "number '" + s + "' is too large for a Real");
  return is_real ? make_real(v, range(n)) : make_integer(v, range(n));
}

ExprPtr AstBuilder::primary(P::PrimaryContext *ctx) {
  if (auto *p = dynamic_cast<P::NumberPrimaryContext *>(ctx))
    return number(p->UNSIGNED_NUMBER());
  if (auto *p = dynamic_cast<P::StringPrimaryContext *>(ctx)) {
    auto e = std::make_unique<Expr>(ExprKind::String, range(ctx));
    std::string raw = text(p->STRING()->getSymbol());
    e->text = unescape_string(raw.substr(1, raw.size() - 2));
    return e;
  }
  if (dynamic_cast<P::FalsePrimaryContext *>(ctx))
    return make_bool(false, range(ctx));
  if (dynamic_cast<P::TruePrimaryContext *>(ctx))
    return make_bool(true, range(ctx));
  if (auto *p = dynamic_cast<P::CallPrimaryContext *>(ctx))
    return call(p);
  if (auto *p = dynamic_cast<P::RefPrimaryContext *>(ctx))
    return ref_expr(p->component_reference());
  if (auto *p = dynamic_cast<P::ParenPrimaryContext *>(ctx)) {
    // `(e)` is e; `(a, b)` or `(a, )` is an output tuple.
    auto *list = p->output_expression_list();
    bool has_comma = false;
    for (auto *child : list->children)
      if (dynamic_cast<antlr4::tree::TerminalNode *>(child))
        has_comma = true;
    if (!has_comma && list->expression().size() == 1) {
      ExprPtr inner = expression(list->expression(0));
      inner->range = range(ctx);
      return inner;
    }
    auto e = std::make_unique<Expr>(ExprKind::Tuple, range(ctx));
    bool pending = true;
    for (auto *child : list->children) {
      if (auto *ex = dynamic_cast<P::ExpressionContext *>(child)) {
        e->args.push_back(expression(ex));
        pending = false;
      } else {
        if (pending)
          e->args.push_back(nullptr);
        pending = true;
      }
    }
    if (pending)
      e->args.push_back(nullptr);
    return e;
  }
  if (auto *p = dynamic_cast<P::MatrixPrimaryContext *>(ctx)) {
    auto e = std::make_unique<Expr>(ExprKind::Matrix, range(ctx));
    for (auto *row : p->expression_list()) {
      std::vector<ExprPtr> r;
      for (auto *x : row->expression())
        r.push_back(expression(x));
      e->rows.push_back(std::move(r));
    }
    return e;
  }
  if (auto *p = dynamic_cast<P::ArrayPrimaryContext *>(ctx)) {
    auto e = std::make_unique<Expr>(ExprKind::Array, range(ctx));
    auto *aa = p->array_arguments();
    for (auto *x : aa->expression())
      e->args.push_back(expression(x));
    if (aa->for_indices())
      e->iterators = for_indices(aa->for_indices());
    return e;
  }
  return std::make_unique<Expr>(ExprKind::End, range(ctx));
}

ExprPtr AstBuilder::call(P::CallPrimaryContext *ctx) {
  auto e = std::make_unique<Expr>(ExprKind::Call, range(ctx));
  if (ctx->component_reference()) {
    e->ref = component_reference(ctx->component_reference());
  } else {
    RefPart part;
    part.name = text(ctx->getStart()); // der, initial, pure
    e->ref.parts.push_back(std::move(part));
  }
  if (auto *fa = ctx->function_call_args()->function_arguments())
    function_arguments(fa, *e);
  return e;
}

void AstBuilder::function_arguments(P::Function_argumentsContext *ctx, Expr &call) {
  if (ctx->FUNCTION()) {
    diags_.report(DiagId::Unsupported, range(ctx), "function partial application is not supported");
    return;
  }
  if (ctx->named_arguments()) {
    named_arguments(ctx->named_arguments(), call);
    return;
  }
  call.args.push_back(expression(ctx->expression()));
  if (ctx->for_indices())
    call.iterators = for_indices(ctx->for_indices());
  if (ctx->function_arguments_non_first())
    function_arguments_non_first(ctx->function_arguments_non_first(), call);
}

void AstBuilder::function_arguments_non_first(P::Function_arguments_non_firstContext *ctx, Expr &call) {
  // Iterative: long argument lists must not deepen the C++ stack.
  while (ctx) {
    if (ctx->named_arguments()) {
      named_arguments(ctx->named_arguments(), call);
      return;
    }
    call.args.push_back(function_argument(ctx->function_argument()));
    ctx = ctx->function_arguments_non_first();
  }
}

void AstBuilder::named_arguments(P::Named_argumentsContext *ctx, Expr &call) {
  for (auto *na : ctx->named_argument())
    call.named.push_back(NamedArg{ident(na->IDENT()), function_argument(na->function_argument())});
}

ExprPtr AstBuilder::function_argument(P::Function_argumentContext *ctx) {
  if (ctx->FUNCTION()) {
    diags_.report(DiagId::Unsupported, range(ctx), "function partial application is not supported");
    return make_real(0, range(ctx));
  }
  return expression(ctx->expression());
}

ComponentRef AstBuilder::component_reference(P::Component_referenceContext *ctx) {
  ComponentRef ref;
  ref.global = ctx->getStart()->getType() != P::IDENT && ctx->getStart()->getType() != P::CONSTRAINT;
  // Children: '.'? IDENT subscripts? ('.' IDENT subscripts?)*, where
  // CONSTRAINT stands for an IDENT outside optimization classes.
  for (auto *child : ctx->children) {
    if (auto *t = dynamic_cast<antlr4::tree::TerminalNode *>(child)) {
      if (t->getSymbol()->getType() == P::IDENT || t->getSymbol()->getType() == P::CONSTRAINT)
        ref.parts.push_back(RefPart{ident(t), {}});
    } else if (auto *s = dynamic_cast<P::Array_subscriptsContext *>(child)) {
      ref.parts.back().subscripts = array_subscripts(s);
    }
  }
  return ref;
}

ExprPtr AstBuilder::ref_expr(P::Component_referenceContext *ctx) {
  auto e = std::make_unique<Expr>(ExprKind::Ref, range(ctx));
  e->ref = component_reference(ctx);
  return e;
}

std::vector<ExprPtr> AstBuilder::array_subscripts(P::Array_subscriptsContext *ctx) {
  std::vector<ExprPtr> out;
  for (auto *s : ctx->subscript()) {
    if (s->expression())
      out.push_back(expression(s->expression()));
    else
      out.push_back(std::make_unique<Expr>(ExprKind::Colon, range(s)));
  }
  return out;
}

} // namespace mo::frontend::detail
