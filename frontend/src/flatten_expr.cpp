// Flattening expressions: names resolved to flat variables, arrays
// scalarised into tensors of scalar expressions, constants substituted.
#include "flattener.hpp"
#include "mo/frontend/printer.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;
using ast::Op;

namespace {

std::string dims_text(const std::vector<int> &dims) {
  std::string s = "[";
  for (std::size_t i = 0; i < dims.size(); ++i)
    s += (i ? ", " : "") + std::to_string(dims[i]);
  return s + "]";
}

ExprPtr literal(double v, SourceRange r, bool integer = false) {
  return integer ? ast::make_integer(v, r) : ast::make_real(v, r);
}

bool is_literal(const Expr &e) {
  return e.kind == ExprKind::Real || e.kind == ExprKind::Integer || e.kind == ExprKind::Boolean;
}

/// True if `e` is literals joined by operators (`1 == 1` once a loop index
/// is substituted): no variable, parameter or call, so its value is fixed.
bool of_literals(const Expr &e) {
  if (is_literal(e))
    return true;
  if (e.kind != ExprKind::Unary && e.kind != ExprKind::Binary)
    return false;
  for (const auto &a : e.args)
    if (!a || !of_literals(*a))
      return false;
  return true;
}

struct BuiltinInfo {
  const char *name;
  int min_args, max_args;
  bool elementwise; ///< applies to each element of array arguments
};

// Built-in functions kept as calls in the flat model.
constexpr BuiltinInfo kBuiltins[] = {
    {"sin", 1, 1, true},   {"cos", 1, 1, true},     {"tan", 1, 1, true},    {"asin", 1, 1, true},
    {"acos", 1, 1, true},  {"atan", 1, 1, true},    {"sinh", 1, 1, true},   {"cosh", 1, 1, true},
    {"tanh", 1, 1, true},  {"exp", 1, 1, true},     {"log", 1, 1, true},    {"log10", 1, 1, true},
    {"sqrt", 1, 1, true},  {"abs", 1, 1, true},     {"sign", 1, 1, true},   {"floor", 1, 1, true},
    {"ceil", 1, 1, true},  {"integer", 1, 1, true}, {"noEvent", 1, 1, true}, {"pre", 1, 1, true},
    {"edge", 1, 1, true},  {"change", 1, 1, true},  {"der", 1, 1, true},    {"atan2", 2, 2, true},
    {"div", 2, 2, true},   {"mod", 2, 2, true},     {"rem", 2, 2, true},    {"smooth", 2, 2, false},
    {"initial", 0, 0, false}, {"terminal", 0, 0, false}, {"sample", 2, 2, false},
    {"delay", 2, 3, false},
    // Integer(e): an enumeration literal's ordinal; enumerations are flattened
    // to their ordinals already, so the value itself.
    {"Integer", 1, 1, true},
    // Flat models' calls of ModelicaExternalC's random generators: output k,
    // then the state (flatten_random.cpp); what --emit flat prints parses again.
    {"ModelicaRandom_xorshift64star", 3, 3, false}, {"ModelicaRandom_xorshift128plus", 5, 5, false},
    {"ModelicaRandom_xorshift1024star", 34, 34, false},
};

const BuiltinInfo *find_builtin(const std::string &n) {
  for (const auto &b : kBuiltins)
    if (n == b.name)
      return &b;
  return nullptr;
}

} // namespace

// ------------------------------------------------------------------ lookup

/// Instances selected by `subs` from `a`: all elements for no subscripts on
/// an array, the instance itself for a scalar.
static void select(Flattener &f, Instance *a, const std::vector<ExprPtr> &subs, const Scope &s,
                   SourceRange where, std::vector<int> &dims, std::vector<Instance *> &out) {
  if (subs.empty()) {
    if (a->dims.empty()) {
      out.push_back(a);
    } else {
      dims.insert(dims.end(), a->dims.begin(), a->dims.end());
      for (auto &el : a->elements)
        out.push_back(el.get());
    }
    return;
  }
  if (subs.size() != a->dims.size())
    f.fail(DiagId::BadSubscript, where,
           fmt::format("'{}' has {} dimension(s) but {} subscript(s) are given", a->flat,
                       a->dims.size(), subs.size()));
  std::vector<std::vector<int>> picks(subs.size());
  for (std::size_t i = 0; i < subs.size(); ++i) {
    const Expr &sub = *subs[i];
    if (sub.kind == ExprKind::Colon) {
      for (int k = 1; k <= a->dims[i]; ++k)
        picks[i].push_back(k);
      dims.push_back(a->dims[i]);
      continue;
    }
    LoopEnv env = s.env ? *s.env : LoopEnv{};
    env.values.emplace_back("end", a->dims[i]);
    Scope sub_scope = s;
    sub_scope.env = &env;
    Tensor t = f.expr(sub, sub_scope);
    for (auto &e : t.elems) {
      double v = f.eval(*e, sub.range);
      if (v != std::floor(v) || v < 1 || v > a->dims[i])
        f.fail(DiagId::BadSubscript, sub.range,
               fmt::format("subscript {} is out of bounds 1..{} of '{}'", v, a->dims[i], a->flat));
      picks[i].push_back(static_cast<int>(v));
    }
    if (!t.is_scalar())
      dims.push_back(static_cast<int>(t.elems.size()));
  }
  // An empty range (`x[1:0]`, `x[2:n]` with n = 1) selects nothing.
  for (const auto &p : picks)
    if (p.empty())
      return;
  // Row-major combinations of the picked indices.
  std::vector<std::size_t> pos(picks.size(), 0);
  while (true) {
    std::size_t flat_index = 0;
    for (std::size_t i = 0; i < picks.size(); ++i)
      flat_index = flat_index * a->dims[i] + (picks[i][pos[i]] - 1);
    out.push_back(a->elements[flat_index].get());
    std::size_t i = picks.size();
    while (i-- > 0) {
      if (++pos[i] < picks[i].size()) break;
      pos[i] = 0;
    }
    if (i == static_cast<std::size_t>(-1)) break;
  }
}

Tensor Flattener::cardinality(const ast::Expr &call, const Scope &s) {
  if (call.args.size() != 1 || !call.named.empty() || call.args[0]->kind != ast::ExprKind::Ref)
    fail(DiagId::WrongArgumentCount, call.range, "cardinality() takes one connector, cardinality(c)");
  if (!connections_counted_)
    fail(DiagId::Unsupported, call.range,
         "cardinality() is supported in equations, not in bindings or declarations");
  std::vector<int> dims;
  std::vector<Instance *> found;
  const ast::Expr &c = *call.args[0];
  if (!resolve_instances(c.ref, s, c.range, dims, found))
    fail(DiagId::UnknownComponent, c.range, "unknown connector '" + c.ref.str() + "' in cardinality()");
  if (found.size() != 1 || !found[0]->is_connector)
    fail(DiagId::BadSubscript, c.range, "cardinality() needs one scalar connector, '" + c.ref.str() + "' is not");
  const auto it = connect_count_.find(found[0]);
  return Tensor::scalar(literal(it == connect_count_.end() ? 0 : it->second, call.range, true));
}

bool Flattener::resolve_instances(const ast::ComponentRef &ref, const Scope &s, SourceRange where,
                                  std::vector<int> &dims, std::vector<Instance *> &out) {
  if (ref.global || !s.inst)
    return false;
  Instance *first = member(*s.inst, ref.parts[0].name);
  if (!first)
    return false;
  select(*this, first, ref.parts[0].subscripts, s, where, dims, out);
  for (std::size_t p = 1; p < ref.parts.size(); ++p) {
    std::vector<Instance *> next;
    std::vector<int> sub_dims;
    for (Instance *inst : out) {
      Instance *m = member(*inst, ref.parts[p].name);
      if (!m) {
        std::string what = inst->var >= 0 ? "a scalar" : "of type '" + (inst->decl ? inst->decl->type.str() : "?") + "'";
        fail(DiagId::UnknownComponent, where,
             "'" + inst->flat + "' (" + what + ") has no component '" + ref.parts[p].name + "'");
      }
      std::vector<int> d;
      select(*this, m, ref.parts[p].subscripts, s, where, d, next);
      sub_dims = d;
    }
    dims.insert(dims.end(), sub_dims.begin(), sub_dims.end());
    out.swap(next);
  }
  return true;
}

/// The constant `name` of `cls`, declared there or inherited (FoundConstant);
/// a base scope's are those of its derived class.
static FoundConstant find_constant(Flattener &f, ClassNode *cls, const std::string &name, unsigned depth = 0) {
  if (!cls || depth > 32)
    return {};
  if (cls->context) // a base scope: the constants of the class derived from it
    return find_constant(f, cls->context, name, depth + 1);
  if (!cls->def)
    return {};
  for (const auto &c : cls->def->components)
    if (c.name == name)
      return {&c, c.mod.binding.get(), cls};
  if (const auto &sb = cls->def->short_base) { // `package P = Q(k = 2)`: Q's, as modified here
    ClassNode *base = f.lookup_class(cls->parent, sb->parts, sb->global, sb->range, false);
    FoundConstant found = base && base != cls ? find_constant(f, base, name, depth + 1) : FoundConstant{};
    if (const ast::Expr *b = found.decl ? element_binding(cls->def->class_mod, name) : nullptr)
      return {found.decl, b, cls->parent};
    return found;
  }
  // Silent: this probes enclosing classes for a constant; a broken extends
  // there is reported where that class is used, not at every name searched.
  for (auto &[ext, base] : f.bases(cls, false)) {
    FoundConstant found = find_constant(f, base, name, depth + 1);
    if (!found.decl)
      continue;
    if (const ast::Expr *b = element_binding(ext->mod, name))
      return {found.decl, b, cls};
    if (found.scope) {
      ClassNode *declaring = found.scope->context ? found.scope->origin : found.scope;
      found.scope = f.base_scope(declaring, cls);
    }
    return found;
  }
  return {};
}

FoundConstant Flattener::imported_constant(ClassNode *cls, const std::string &name) {
  if (!cls->def)
    return {};
  for (const auto &imp : cls->def->imports) {
    std::vector<std::string> pkg_path = imp.path;
    if (imp.wildcard || (!imp.names.empty() && std::count(imp.names.begin(), imp.names.end(), name))) {
      // `import P.*;`, `import P.{name, ...};`: a constant of P
    } else if (!imp.path.empty() && (imp.alias.empty() ? imp.path.back() == name : imp.alias == name)) {
      pkg_path.pop_back(); // `import P.name;`, `import name = P.c;`
    } else {
      continue;
    }
    const std::string member = imp.alias.empty() || imp.wildcard ? name : imp.path.back();
    ClassNode *pkg = pkg_path.empty() ? &lib_.root : lookup_class(&lib_.root, pkg_path, true, imp.range, false);
    if (FoundConstant c = pkg ? find_constant(*this, pkg, member) : FoundConstant{}; c.decl)
      return c;
  }
  return {};
}

bool Flattener::lookup_constant(const ast::ComponentRef &ref, const Scope &s, SourceRange where, Tensor &out) {
  return named_constant(ref, s, where, out) || (ref.parts.size() > 1 && record_constant_field(ref, s, where, out));
}

bool Flattener::record_constant_field(const ast::ComponentRef &ref, const Scope &s, SourceRange where, Tensor &out) {
  // The longest prefix that names a record constant; the rest designates
  // into its value, as into a function's local record.
  for (std::size_t k = ref.parts.size() - 1; k >= 1; --k) {
    ast::ComponentRef bare;
    bare.global = ref.global;
    for (std::size_t i = 0; i < k; ++i)
      bare.parts.push_back(ast::RefPart{ref.parts[i].name, {}});
    bool subscripted = false;
    for (std::size_t i = 0; i + 1 < k; ++i)
      subscripted = subscripted || !ref.parts[i].subscripts.empty();
    Tensor whole;
    if (!subscripted && named_constant(bare, s, where, whole) && whole.record) {
      ast::ComponentRef rest;
      for (std::size_t i = k - 1; i < ref.parts.size(); ++i) {
        rest.parts.push_back(ast::RefPart{ref.parts[i].name, {}});
        for (const auto &sub : ref.parts[i].subscripts)
          rest.parts.back().subscripts.push_back(sub->clone());
      }
      for (const std::size_t i : designate(whole, rest, s, where, out))
        out.elems.push_back(whole.elems[i]->clone());
      return true;
    }
  }
  return false;
}

bool Flattener::named_constant(const ast::ComponentRef &ref, const Scope &s, SourceRange where, Tensor &out) {
  for (std::size_t i = 0; i + 1 < ref.parts.size(); ++i)
    if (!ref.parts[i].subscripts.empty())
      return false;
  if (!ref.parts.back().subscripts.empty()) {
    // `Tables.AndTable[1, :]`: the constant's value, subscripted. A subscript
    // that varies is varying_subscript()'s, on this with a colon there.
    for (const auto &sub : ref.parts.back().subscripts)
      if (sub->kind != ExprKind::Colon) {
        const Tensor index = expr(*sub, s);
        if (!std::all_of(index.elems.begin(), index.elems.end(), [&](const ExprPtr &x) { return is_constant(*x); }))
          return false;
      }
    ast::ComponentRef bare;
    bare.global = ref.global;
    for (const auto &part : ref.parts)
      bare.parts.push_back(ast::RefPart{part.name, {}});
    Tensor whole;
    if (!named_constant(bare, s, where, whole))
      return false;
    ast::ComponentRef own;
    own.parts.push_back(ast::RefPart{ref.parts.back().name, {}});
    for (const auto &sub : ref.parts.back().subscripts)
      own.parts.back().subscripts.push_back(sub->clone());
    const std::vector<std::size_t> picked = designate(whole, own, s, where, out);
    for (const std::size_t k : picked)
      out.elems.push_back(whole.elems[k]->clone());
    return true;
  }
  const std::size_t n = ref.parts.size();
  auto value_of = [&](const FoundConstant &c) {
    if (c.decl->variability != ast::Variability::Constant && c.decl->variability != ast::Variability::Parameter)
      fail(DiagId::NotConstant, where, "'" + ref.str() + "' is not a constant");
    std::optional<Tensor> record;
    if (!c.binding && !(record = record_from_modifiers(c.scope, *c.decl, where)))
      fail(DiagId::NotConstant, where, "constant '" + ref.str() + "' has no value");
    Tensor t = record ? std::move(*record) : expr(*c.binding, Scope{nullptr, c.scope, nullptr});
    for (auto &e : t.elems)
      if (e->kind != ExprKind::String) // a String constant's value is its text
        e = literal(eval(*e, where), where);
    out = std::move(t);
  };
  if (n == 1) {
    for (ClassNode *c = s.cls; c; c = c->parent) {
      FoundConstant found = find_constant(*this, c, ref.parts[0].name);
      if (!found.decl)
        found = imported_constant(c, ref.parts[0].name);
      if (found.decl) {
        value_of(found);
        return true;
      }
    }
    return false;
  }
  std::vector<std::string> path;
  for (std::size_t i = 0; i + 1 < n; ++i)
    path.push_back(ref.parts[i].name);
  const std::string &last = ref.parts[n - 1].name;
  if (path.size() == 1 && path[0] == "StateSelect") {
    static const char *const kLevels[] = {"never", "avoid", "default", "prefer", "always"};
    for (int i = 0; i < 5; ++i)
      if (last == kLevels[i]) {
        out = Tensor::scalar(literal(i + 1, where, true));
        return true;
      }
  }
  if (path.size() == 1 && path[0] == "AssertionLevel" && (last == "error" || last == "warning")) {
    out = Tensor::scalar(literal(last == "error" ? 1 : 2, where, true));
    return true;
  }
  ClassNode *cls = ref.global ? nullptr : replaced_class(s.inst, path);
  if (!cls)
    cls = lookup_class(s.cls ? s.cls : &lib_.root, path, ref.global, where, false);
  if (!cls || !cls->def)
    return false;
  const auto &lits = cls->def->enumeration;
  for (std::size_t i = 0; i < lits.size(); ++i)
    if (lits[i] == last) {
      out = Tensor::scalar(literal(static_cast<double>(i + 1), where, true));
      return true;
    }
  if (FoundConstant found = find_constant(*this, cls, last); found.decl) {
    value_of(found);
    return true;
  }
  return false;
}

// ------------------------------------------------------------- expressions

void Flattener::no_record(const Tensor &t, SourceRange where, const std::string &operation) {
  if (t.record)
    fail(DiagId::TypeMismatch, where,
         "a record of type '" + t.record->cls->path() + "' cannot be an operand of " + operation);
}

void Flattener::no_record(const Tensor &t, SourceRange where, Op op) {
  if (t.record)
    no_record(t, where, std::string("'") + ast::op_text(op) + "'");
}

/// `{a, b, c}`, `{f(i) for i in r}` and the same written `array(...)`.
Tensor Flattener::array_constructor(const Expr &e, const Scope &s) {
  std::vector<Tensor> parts;
  if (!e.iterators.empty()) {
    if (e.args.size() != 1)
      fail(DiagId::Unsupported, e.range, "an array constructor with iterators has one expression");
    return comprehension(*e.args[0], e.iterators, s, e.range);
  }
  for (const auto &a : e.args)
    parts.push_back(expr(*a, s));
  Tensor t;
  t.dims.push_back(static_cast<int>(parts.size()));
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (i == 0)
      t.dims.insert(t.dims.end(), parts[0].dims.begin(), parts[0].dims.end());
    else if (parts[i].dims != parts[0].dims)
      fail(DiagId::TypeMismatch, e.range, "the elements of this array have different sizes");
    if (!same_record_type(parts[i].record, parts[0].record))
      fail(DiagId::TypeMismatch, e.range, "the elements of this array are records of different types");
    t.record = parts[0].record;
    for (auto &x : parts[i].elems)
      t.elems.push_back(std::move(x));
  }
  return t;
}

ExprPtr Flattener::scalar_expr(const Expr &e, const Scope &s) {
  Tensor t = expr(e, s);
  if (t.record)
    fail(DiagId::TypeMismatch, e.range, "expected a number, got a record of type '" + t.record->cls->path() + "'");
  if (!t.is_scalar())
    fail(DiagId::TypeMismatch, e.range, "expected a scalar, got an array of size " + dims_text(t.dims));
  return std::move(t.elems[0]);
}

static Tensor elementwise(Tensor a, const std::function<ExprPtr(ExprPtr)> &fn) {
  for (auto &e : a.elems)
    e = fn(std::move(e));
  return a;
}

static Tensor binary(Flattener &f, Op op, Tensor a, Tensor b, SourceRange r) {
  f.no_record(a, r, op);
  f.no_record(b, r, op);
  Op scalar_op = op == Op::ElemAdd ? Op::Add : op == Op::ElemSub ? Op::Sub : op == Op::ElemMul ? Op::Mul
               : op == Op::ElemDiv ? Op::Div : op == Op::ElemPow ? Op::Pow : op;
  auto spair = [&](ExprPtr x, ExprPtr y) { return ast::make_binary(scalar_op, std::move(x), std::move(y), r); };
  if (a.is_scalar() && b.is_scalar()) {
    const Expr &x = *a.elems[0], &y = *b.elems[0];
    if (x.kind == ExprKind::String && y.kind == ExprKind::String) {
      // Literal strings (String constants included) compare and join here:
      // lowering has no strings (the MSL's transformers test `C1 == "D"`).
      if (scalar_op == Op::Eq || scalar_op == Op::Ne)
        return Tensor::scalar(ast::make_bool((x.text == y.text) == (scalar_op == Op::Eq), r));
      if (scalar_op == Op::Add) {
        // A loop that doubles a string (`s := s + s`) would take all memory.
        constexpr std::size_t kMaxString = 1'000'000;
        if (x.text.size() + y.text.size() > kMaxString)
          f.fail(DiagId::Unsupported, r,
                 fmt::format("the joined string is longer than {} characters, mocompile's limit", kMaxString));
        auto joined = std::make_unique<Expr>(ExprKind::String, r);
        joined->text = x.text + y.text;
        return Tensor::scalar(std::move(joined));
      }
    }
    return Tensor::scalar(spair(std::move(a.elems[0]), std::move(b.elems[0])));
  }
  bool elementwise_op = op == Op::Add || op == Op::Sub || op == Op::ElemAdd || op == Op::ElemSub ||
                        op == Op::ElemMul || op == Op::ElemDiv || op == Op::ElemPow ||
                        op == Op::And || op == Op::Or;
  if (a.dims == b.dims && elementwise_op) {
    for (std::size_t i = 0; i < a.elems.size(); ++i)
      a.elems[i] = spair(std::move(a.elems[i]), std::move(b.elems[i]));
    return a;
  }
  bool broadcast = op == Op::Mul || op == Op::ElemMul || op == Op::ElemAdd || op == Op::ElemSub ||
                   op == Op::ElemDiv || op == Op::ElemPow || op == Op::Div;
  if (broadcast && b.is_scalar()) {
    for (auto &e : a.elems)
      e = spair(std::move(e), b.elems[0]->clone());
    return a;
  }
  if (broadcast && a.is_scalar() && op != Op::Div) {
    for (auto &e : b.elems)
      e = spair(a.elems[0]->clone(), std::move(e));
    return b;
  }
  if (op == Op::Mul) {
    // Terms of the product, counted before any is made: A * A of 300 x 300
    // matrices is 2.7e7 products, which took 21 GB.
    f.element_count({static_cast<long long>(a.elems.size()), b.dims.size() == 2 ? b.dims[1] : 1}, r,
                    "the product", "multiplications");
    auto dot = [&](auto get_a, auto get_b, int n) {
      if (n == 0)
        return ast::make_real(0, r);
      std::vector<ExprPtr> terms;
      for (int k = 0; k < n; ++k)
        terms.push_back(ast::make_binary(Op::Mul, get_a(k), get_b(k), r));
      return join_terms(std::move(terms),
                        [&](ExprPtr x, ExprPtr y) { return ast::make_binary(Op::Add, std::move(x), std::move(y), r); });
    };
    if (a.dims.size() == 1 && b.dims.size() == 1 && a.dims == b.dims)
      return Tensor::scalar(dot([&](int k) { return a.elems[k]->clone(); },
                                [&](int k) { return b.elems[k]->clone(); }, a.dims[0]));
    if (a.dims.size() == 2 && b.dims.size() == 1 && a.dims[1] == b.dims[0]) {
      Tensor t;
      t.dims = {a.dims[0]};
      for (int i = 0; i < a.dims[0]; ++i)
        t.elems.push_back(dot([&](int k) { return a.elems[i * a.dims[1] + k]->clone(); },
                              [&](int k) { return b.elems[k]->clone(); }, a.dims[1]));
      return t;
    }
    if (a.dims.size() == 1 && b.dims.size() == 2 && a.dims[0] == b.dims[0]) {
      Tensor t;
      t.dims = {b.dims[1]};
      for (int j = 0; j < b.dims[1]; ++j)
        t.elems.push_back(dot([&](int k) { return a.elems[k]->clone(); },
                              [&](int k) { return b.elems[k * b.dims[1] + j]->clone(); }, a.dims[0]));
      return t;
    }
    if (a.dims.size() == 2 && b.dims.size() == 2 && a.dims[1] == b.dims[0]) {
      Tensor t;
      t.dims = {a.dims[0], b.dims[1]};
      for (int i = 0; i < a.dims[0]; ++i)
        for (int j = 0; j < b.dims[1]; ++j)
          t.elems.push_back(dot([&](int k) { return a.elems[i * a.dims[1] + k]->clone(); },
                                [&](int k) { return b.elems[k * b.dims[1] + j]->clone(); }, a.dims[1]));
      return t;
    }
  }
  f.fail(DiagId::TypeMismatch, r,
         fmt::format("operator '{}' cannot combine sizes {} and {}", ast::op_text(op), dims_text(a.dims),
                     dims_text(b.dims)));
}

// Out of expr()'s frame, which recursion through operators repeats.
Tensor Flattener::unary_on_record(const Expr &e, Tensor a) {
  std::vector<Tensor> operands;
  operands.push_back(std::move(a));
  return overloaded_operator(e.op, std::move(operands), e);
}

Tensor Flattener::binary_on_records(const Expr &e, Tensor a, Tensor b) {
  std::vector<Tensor> operands;
  operands.push_back(std::move(a));
  operands.push_back(std::move(b));
  return overloaded_operator(e.op, std::move(operands), e);
}

Tensor Flattener::expr(const Expr &e, const Scope &s) {
  // Only the operators recurse in this frame: `a + b + ... ` nests as deep as
  // it has terms, and expr_node's frame (every other kind, with its
  // temporaries) is several kilobytes in an unoptimised build.
  switch (e.kind) {
  case ExprKind::Unary: {
    Tensor a = expr(*e.args[0], s);
    if (a.record && e.op != Op::Plus)
      return unary_on_record(e, std::move(a));
    if (e.op == Op::Plus)
      return a;
    return elementwise(std::move(a), [&](ExprPtr x) { return ast::make_unary(e.op, std::move(x), e.range); });
  }
  case ExprKind::Binary: {
    Tensor a = expr(*e.args[0], s), b = expr(*e.args[1], s);
    if (a.record || b.record)
      return binary_on_records(e, std::move(a), std::move(b));
    Tensor t = binary(*this, e.op, std::move(a), std::move(b), e.range);
    const bool relation = e.op == Op::Lt || e.op == Op::Le || e.op == Op::Gt || e.op == Op::Ge;
    if (relation && no_event_depth_ > 0) // a function's own relation (see no_event_depth_)
      for (ExprPtr &x : t.elems)
        if (!of_literals(*x))
          x = ast::make_call1("noEvent", std::move(x), e.range);
    return t;
  }
  default:
    return expr_node(e, s);
  }
}

Tensor Flattener::expr_node(const Expr &e, const Scope &s) {
  switch (e.kind) {
  case ExprKind::Real:
  case ExprKind::Integer:
  case ExprKind::Boolean:
  case ExprKind::String:
    return Tensor::scalar(e.clone());
  case ExprKind::End:
    if (s.env)
      if (const double *v = s.env->find("end"))
        return Tensor::scalar(literal(*v, e.range, true));
    fail(DiagId::BadSubscript, e.range, "'end' is only allowed inside a subscript");
  case ExprKind::Ref: {
    if (s.locals && !(s.env && e.ref.is_simple() && s.env->find(e.ref.parts[0].name))) {
      Tensor t; // an input, output or local of a function being inlined
      if (s.locals->count(e.ref.parts[0].name) && varying_subscript(e, s, t))
        return t;
      if (local_value(e.ref, s, e.range, t))
        return t;
    }
    if (e.ref.is_simple()) {
      const std::string &n = e.ref.parts[0].name;
      if (s.env)
        if (const double *v = s.env->find(n))
          return Tensor::scalar(literal(*v, e.range, true));
      if (n == "time" && !(s.inst && s.inst->member_index.count(n)))
        return Tensor::scalar(ast::make_ref("time", e.range));
      if (s.in_optimization && (n == "startTime" || n == "finalTime")) {
        if (n == "finalTime" && free_final_time_ >= 0) { // the free parameter
          auto ref = ast::make_ref(n, e.range);
          ref->var = free_final_time_;
          return Tensor::scalar(std::move(ref));
        }
        for (const ast::ElementMod *attribute : optimization_attributes())
          if (const ast::ElementMod &em = *attribute; em.path.size() == 1 && em.path[0] == n && em.mod.binding) {
            Scope top_scope{top_.get(), top_->cls, nullptr};
            ExprPtr v = scalar_expr(*em.mod.binding, top_scope);
            return Tensor::scalar(literal(eval(*v, e.range), e.range, v->kind == ExprKind::Integer));
          }
        if (!(s.inst && s.inst->member_index.count(n))) // Optimica's defaults
          return Tensor::scalar(literal(n == "startTime" ? 0.0 : 1.0, e.range));
      }
    }
    std::vector<int> dims;
    std::vector<Instance *> insts;
    if (Tensor chosen; s.inst && s.inst->member_index.count(e.ref.parts[0].name) && varying_subscript(e, s, chosen))
      return chosen;
    if (resolve_instances(e.ref, s, e.range, dims, insts)) {
      if (!insts.empty() && insts[0]->var < 0 && is_record_instance(*insts[0]))
        return record_value(insts, dims, e.range);
      Tensor t;
      t.dims = dims;
      for (Instance *inst : insts) {
        if (inst->var < 0)
          fail(DiagId::TypeMismatch, e.range,
               "'" + inst->flat + "' is a component of type '" + (inst->decl ? inst->decl->type.str() : "?") +
                   "', not a number; only scalar variables and records can be used in expressions");
        t.elems.push_back(variable_expr(inst->var, e.range));
      }
      return t;
    }
    Tensor t;
    if (lookup_constant(e.ref, s, e.range, t))
      return t;
    // A constant of a package, subscripted by signals (the MSL's Digital:
    // `Tables.AndTable[a, b]` with a, b of the Logic enumeration).
    if (varying_subscript(e, s, t))
      return t;
    std::string where = s.inst && s.inst->decl ? " (in component '" + s.inst->flat + "')"
                        : s.cls ? " (in class '" + s.cls->path() + "')" : "";
    fail(DiagId::UnknownComponent, e.range, "unknown component '" + e.ref.str() + "'" + where);
  }
  case ExprKind::Call:
    break; // below
  case ExprKind::Unary:
  case ExprKind::Binary:
    return expr(e, s); // the operators' own frame
  case ExprKind::If: {
    // Conditions that are literal after flattening (loop indices) select a
    // branch, and the others are not flattened: the MSL's StateGraph writes
    // `if i == 1 then localActive else inPort[i-1].occupied` for i = 1. So do
    // conditions on parameters marked Evaluate = true: Fluid's
    // `T_start = if use_T_start then system.T_start else
    // temperature_phX(p_start, h_start, X_start)` and h_start's binding, the
    // other way round, only read each other in the branches not taken.
    std::vector<ExprPtr> conds;
    std::vector<Tensor> branches;
    for (std::size_t i = 0; i + 1 < e.args.size(); i += 2) {
      ExprPtr c = scalar_expr(*e.args[i], s);
      if (!is_literal(*c) && (of_literals(*c) || structural(*c)))
        c = literal(eval(*c, e.args[i]->range), e.args[i]->range);
      if (is_literal(*c)) {
        if (c->number != 0 && conds.empty())
          return expr(*e.args[i + 1], s);
        if (c->number == 0)
          continue;
      }
      conds.push_back(std::move(c));
      branches.push_back(expr(*e.args[i + 1], s));
    }
    Tensor result = expr(*e.args.back(), s);
    // Branches of different sizes need conditions known now (MLS 10.6.13:
    // `if size(offset, 1) == 1 then ones(n) * offset[1] else offset`).
    const bool sizes_differ = std::any_of(branches.begin(), branches.end(),
                                          [&](const Tensor &b) { return b.dims != result.dims; });
    if (sizes_differ && std::all_of(conds.begin(), conds.end(), [&](const ExprPtr &c) { return is_constant(*c); })) {
      for (std::size_t i = 0; i < conds.size(); ++i)
        if (eval(*conds[i], e.range) != 0)
          return std::move(branches[i]);
      return result;
    }
    for (std::size_t i = conds.size(); i-- > 0;) {
      if (branches[i].dims != result.dims)
        fail(DiagId::TypeMismatch, e.range, "the branches of this if-expression have different sizes");
      for (std::size_t k = 0; k < result.elems.size(); ++k) {
        auto n = std::make_unique<Expr>(ExprKind::If, e.range);
        n->args.push_back(conds[i]->clone());
        n->args.push_back(std::move(branches[i].elems[k]));
        n->args.push_back(std::move(result.elems[k]));
        result.elems[k] = std::move(n);
      }
    }
    return result;
  }
  case ExprKind::Array:
    return array_constructor(e, s);
  case ExprKind::Matrix:
    return matrix_constructor(e, s);
  case ExprKind::Range: {
    std::vector<double> values = eval_range(e, s);
    Tensor t;
    t.dims = {static_cast<int>(values.size())};
    for (double v : values)
      t.elems.push_back(literal(v, e.range, v == std::floor(v)));
    return t;
  }
  case ExprKind::Tuple:
  case ExprKind::Colon:
    fail(DiagId::Unsupported, e.range, "this kind of expression is not supported here");
  }

  // ---- calls
  const std::string name = e.ref.str();
  auto arg = [&](std::size_t i) {
    Tensor t = expr(*e.args[i], s);
    if (t.record)
      no_record(t, e.args[i]->range, name + "()");
    return t;
  };
  auto want_args = [&](std::size_t lo, std::size_t hi) {
    if (e.args.size() < lo || e.args.size() > hi)
      fail(DiagId::WrongArgumentCount, e.range,
           fmt::format("{}() takes {} argument{}, {} given", name,
                       lo == hi ? std::to_string(lo) : fmt::format("{} to {}", lo, hi), hi == 1 ? "" : "s",
                       e.args.size()));
  };
  if (ClassNode *fn = enclosing_function(e, s))
    return std::move(call_function(fn, e, s)[0]);
  if (Tensor t; array_function(e, s, t))
    return t;
  if (name == "Connections.isRoot" || name == "Connections.rooted" || name == "rooted")
    return Tensor::scalar(ast::make_bool(connections_query(e, s), e.range));
  if (e.ref.is_simple()) {
    if (name == "homotopy") {
      for (const auto &na : e.named)
        if (na.name == "actual")
          return expr(*na.value, s);
      want_args(2, 2);
      return arg(0);
    }
    if (name == "String")
      return string_call(e, s);
    if (!e.named.empty() && !lookup_called_class(e, s))
      fail(DiagId::Unsupported, e.range, "named arguments are only supported for homotopy()");
    if (name == "smooth" && e.args.size() == 2) { // of an array: of each element (Math.Vectors.normalize)
      ExprPtr order = scalar_expr(*e.args[0], s);
      return elementwise(arg(1), [&](ExprPtr x) {
        std::vector<ExprPtr> v;
        v.push_back(order->clone());
        v.push_back(std::move(x));
        return ast::make_call(name, std::move(v), e.range);
      });
    }
    if (const BuiltinInfo *b = find_builtin(name)) {
      want_args(b->min_args, b->max_args);
      if (b->elementwise && e.args.size() == 1) {
        Tensor a = arg(0);
        if (name == "der")
          for (auto &x : a.elems)
            if (x->kind == ExprKind::Ref && x->var >= 0 &&
                model_->variables[x->var].variability == ast::Variability::Parameter)
              fail(DiagId::DerOfNonReal, e.range,
                   "der() of parameter '" + model_->variables[x->var].name + "': a parameter is constant in time");
        return elementwise(std::move(a), [&](ExprPtr x) {
          std::vector<ExprPtr> v;
          v.push_back(std::move(x));
          return ast::make_call(name, std::move(v), e.range);
        });
      }
      std::vector<ExprPtr> args;
      for (std::size_t i = 0; i < e.args.size(); ++i)
        args.push_back(scalar_expr(*e.args[i], s));
      return Tensor::scalar(ast::make_call(name, std::move(args), e.range));
    }
    if (name == "min" || name == "max") {
      want_args(1, 2);
      if (e.args.size() == 2) {
        std::vector<ExprPtr> v;
        v.push_back(scalar_expr(*e.args[0], s));
        v.push_back(scalar_expr(*e.args[1], s));
        return Tensor::scalar(ast::make_call(name, std::move(v), e.range));
      }
      return reduce_elements(*this, name, arg(0), e.range);
    }
    if (name == "sum" || name == "product") {
      want_args(1, 1);
      return reduce_elements(*this, name, arg(0), e.range);
    }
    if (name == "cardinality")
      return cardinality(e, s);
    if (name == "inStream" || name == "actualStream")
      return stream_operator(e, s);
    if (name == "size") {
      want_args(1, 2);
      // A function's local array has its size before it is assigned.
      const Expr &x = *e.args[0];
      const bool local = s.locals && x.kind == ExprKind::Ref && !x.ref.global && x.ref.parts.size() == 1 &&
                         x.ref.parts[0].subscripts.empty() && s.locals->count(x.ref.parts[0].name);
      Tensor a;
      if (local)
        a.dims = s.locals->at(x.ref.parts[0].name).dims;
      else
        a = arg(0);
      if (e.args.size() == 2) {
        long long k = eval_int(*e.args[1], s);
        if (k < 1 || k > static_cast<long long>(a.dims.size()))
          fail(DiagId::BadSubscript, e.range, fmt::format("size(..., {}) of an array with {} dimension(s)", k, a.dims.size()));
        return Tensor::scalar(literal(a.dims[k - 1], e.range, true));
      }
      Tensor t;
      t.dims = {static_cast<int>(a.dims.size())};
      for (int d : a.dims)
        t.elems.push_back(literal(d, e.range, true));
      return t;
    }
    if (name == "array") // array(a, b) is {a, b} (MLS 10.4)
      return array_constructor(e, s);
    if (name == "zeros" || name == "ones" || name == "fill") {
      std::size_t first = name == "fill" ? 1 : 0;
      if (e.args.size() <= first)
        fail(DiagId::WrongArgumentCount, e.range, name + "() needs at least one size");
      Tensor t;
      std::vector<long long> sizes;
      for (std::size_t i = first; i < e.args.size(); ++i) {
        long long n = eval_int(*e.args[i], s);
        if (n < 0 || n > 1'000'000)
          fail(DiagId::BadSubscript, e.args[i]->range, "array size out of range");
        t.dims.push_back(static_cast<int>(n));
        sizes.push_back(n);
      }
      const std::size_t total = element_count(sizes, e.range, name + "()");
      if (name == "fill") { // fill(A, n1, ...): dims n1, ..., then A's own
        Tensor a = expr(*e.args[0], s);
        sizes.push_back(static_cast<long long>(a.elems.size()));
        element_count(sizes, e.range, "fill()");
        t.record = a.record; // fill(Complex(0), m): an array of records
        t.dims.insert(t.dims.end(), a.dims.begin(), a.dims.end());
        for (std::size_t i = 0; i < total; ++i)
          for (const ExprPtr &x : a.elems)
            t.elems.push_back(x->clone());
        return t;
      }
      ExprPtr v = literal(name == "ones" ? 1 : 0, e.range, true);
      for (std::size_t i = 0; i < total; ++i)
        t.elems.push_back(v->clone());
      return t;
    }
    if (name == "identity") {
      want_args(1, 1);
      long long n = eval_int(*e.args[0], s);
      if (n < 0 || n > 10'000)
        fail(DiagId::BadSubscript, e.range, "identity() size out of range");
      Tensor t;
      t.dims = {static_cast<int>(n), static_cast<int>(n)};
      for (long long i = 0; i < n; ++i)
        for (long long j = 0; j < n; ++j)
          t.elems.push_back(literal(i == j ? 1 : 0, e.range, true));
      return t;
    }
    if (name == "transpose") {
      want_args(1, 1);
      Tensor a = arg(0);
      if (a.dims.size() != 2)
        fail(DiagId::TypeMismatch, e.range, "transpose() needs a matrix");
      Tensor t;
      t.dims = {a.dims[1], a.dims[0]};
      for (int j = 0; j < a.dims[1]; ++j)
        for (int i = 0; i < a.dims[0]; ++i)
          t.elems.push_back(std::move(a.elems[i * a.dims[1] + j]));
      return t;
    }
    if (name == "cross") {
      want_args(2, 2);
      Tensor a = arg(0), b = arg(1);
      if (a.dims != std::vector<int>{3} || b.dims != std::vector<int>{3})
        fail(DiagId::TypeMismatch, e.range, "cross() needs two vectors of size 3");
      Tensor t;
      t.dims = {3};
      for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        t.elems.push_back(ast::make_binary(
            Op::Sub, ast::make_binary(Op::Mul, a.elems[j]->clone(), b.elems[k]->clone(), e.range),
            ast::make_binary(Op::Mul, a.elems[k]->clone(), b.elems[j]->clone(), e.range), e.range));
      }
      return t;
    }
    if (name == "scalar") {
      want_args(1, 1);
      Tensor a = arg(0);
      if (a.elems.size() != 1)
        fail(DiagId::TypeMismatch, e.range, "scalar() of an array with more than one element");
      return Tensor::scalar(std::move(a.elems[0]));
    }
    if (name == "vector") {
      want_args(1, 1);
      Tensor a = arg(0);
      a.dims = {static_cast<int>(a.elems.size())};
      return a;
    }
    if (name == "semiLinear") { // element by element over arrays (`port.Xi` of a medium: MLS 12.4.6)
      want_args(3, 3);
      Tensor x = arg(0), k1 = arg(1), k2 = arg(2);
      if (k1.dims != k2.dims || (!x.is_scalar() && x.dims != k1.dims))
        fail(DiagId::TypeMismatch, e.range, "semiLinear(): the arguments have different sizes");
      Tensor t;
      t.dims = k1.dims;
      for (std::size_t i = 0; i < k1.elems.size(); ++i) {
        const Expr &xi = *x.elems[x.is_scalar() ? 0 : i];
        auto n = std::make_unique<Expr>(ExprKind::If, e.range);
        n->args.push_back(ast::make_binary(Op::Ge, xi.clone(), literal(0, e.range), e.range));
        n->args.push_back(ast::make_binary(Op::Mul, std::move(k1.elems[i]), xi.clone(), e.range));
        n->args.push_back(ast::make_binary(Op::Mul, std::move(k2.elems[i]), xi.clone(), e.range));
        t.elems.push_back(std::move(n));
      }
      return t;
    }
  }
  // Optimica: `x(finalTime)` is the variable x at a time point.
  if (s.in_optimization && e.args.size() == 1 && e.named.empty()) {
    std::vector<int> dims;
    std::vector<Instance *> insts;
    if (resolve_instances(e.ref, s, e.range, dims, insts)) {
      ExprPtr at = scalar_expr(*e.args[0], s);
      Tensor t;
      t.dims = dims;
      for (Instance *inst : insts) {
        if (inst->var < 0)
          fail(DiagId::TypeMismatch, e.range, "'" + inst->flat + "' is not a scalar variable");
        std::vector<ExprPtr> v;
        v.push_back(at->clone());
        auto c = ast::make_call(model_->variables[inst->var].name, std::move(v), e.range);
        c->var = inst->var;
        t.elems.push_back(std::move(c));
      }
      return t;
    }
  }
  if (ClassNode *fn = lookup_function(e, s))
    return std::move(call_function(fn, e, s)[0]);
  if (ClassNode *rec = lookup_called_class(e, s); rec && is_record_class(rec)) {
    if (std::optional<Tensor> t = overloaded_constructor(rec, e, s))
      return std::move(*t);
    return record_constructor(rec, e, s);
  }
  fail(DiagId::UnknownFunction, e.range, "unknown function '" + name + "'");
}

// -------------------------------------------------------------- evaluation

double Flattener::eval_param(std::int32_t var, SourceRange where) {
  if (param_state_.size() < model_->variables.size())
    param_state_.resize(model_->variables.size(), 0);
  // Indexed anew after every call that flattens an expression: that can
  // instantiate a later element (member()) and so grow model_->variables.
  const flat::Variable &v = model_->variables[var];
  if (v.variability != ast::Variability::Parameter && v.variability != ast::Variability::Constant)
    fail(DiagId::NotConstant, where,
         "'" + v.name + "' is a time-varying variable; a parameter or constant is needed here");
  if (param_state_[var] == 2 && v.value)
    return *v.value;
  if (param_state_[var] == 1)
    fail(DiagId::EvaluationError, where, "parameter '" + v.name + "' depends on itself");
  if (param_state_[var] == 3)
    throw Reported{};
  param_state_[var] = 1;
  try {
    if (!model_->variables[var].binding) {
      ExprPtr b = take_pending(var, "");
      model_->variables[var].binding = std::move(b);
    }
    const Expr *src = model_->variables[var].binding.get();
    if (!src) {
      if (!model_->variables[var].attr.start) {
        ExprPtr b = take_pending(var, "start");
        model_->variables[var].attr.start = std::move(b);
      }
      src = model_->variables[var].attr.start.get();
    }
    if (!src)
      fail(DiagId::NotConstant, where, "parameter '" + model_->variables[var].name + "' has no value");
    double value = eval(*src, where);
    model_->variables[var].value = value;
    param_state_[var] = 2;
    return value;
  } catch (Reported &) {
    param_state_[var] = 3;
    throw;
  }
}

double Flattener::eval(const Expr &e, SourceRange where) {
  switch (e.kind) {
  case ExprKind::Real:
  case ExprKind::Integer:
  case ExprKind::Boolean:
    return e.number;
  case ExprKind::Ref:
    if (e.var >= 0)
      return eval_param(e.var, where);
    fail(DiagId::NotConstant, where, "'" + e.ref.str() + "' varies in time; a constant is needed here");
  case ExprKind::Unary: {
    double a = eval(*e.args[0], where);
    return e.op == Op::Neg ? -a : e.op == Op::Not ? (a == 0) : a;
  }
  case ExprKind::Binary: {
    if (e.op == Op::Eq || e.op == Op::Ne)
      if (const auto sa = eval_string(*e.args[0], where))
        if (const auto sb = eval_string(*e.args[1], where))
          return (*sa == *sb) == (e.op == Op::Eq);
    double a = eval(*e.args[0], where), b = eval(*e.args[1], where);
    switch (e.op) {
    case Op::Add: case Op::ElemAdd: return a + b;
    case Op::Sub: case Op::ElemSub: return a - b;
    case Op::Mul: case Op::ElemMul: return a * b;
    case Op::Div: case Op::ElemDiv:
      if (b == 0 && e.args[0]->kind == ExprKind::Integer && e.args[1]->kind == ExprKind::Integer)
        fail(DiagId::EvaluationError, e.range, "integer division by zero");
      return a / b;
    case Op::Pow: case Op::ElemPow: return std::pow(a, b);
    case Op::Lt: return a < b;
    case Op::Le: return a <= b;
    case Op::Gt: return a > b;
    case Op::Ge: return a >= b;
    case Op::Eq: return a == b;
    case Op::Ne: return a != b;
    case Op::And: return a != 0 && b != 0;
    case Op::Or: return a != 0 || b != 0;
    case Op::Neg: case Op::Plus: case Op::Not: break;
    }
    break;
  }
  case ExprKind::If:
    for (std::size_t i = 0; i + 1 < e.args.size(); i += 2)
      if (eval(*e.args[i], where) != 0)
        return eval(*e.args[i + 1], where);
    return eval(*e.args.back(), where);
  case ExprKind::Call: {
    const std::string n = e.ref.parts.empty() ? "" : e.ref.parts[0].name;
    std::vector<double> a;
    for (const auto &x : e.args)
      a.push_back(eval(*x, where));
    auto one = [&](double (*fn)(double)) { return a.size() == 1 ? fn(a[0]) : NAN; };
    if (e.var < 0) {
      if (n == "sin") return one(std::sin);
      if (n == "cos") return one(std::cos);
      if (n == "tan") return one(std::tan);
      if (n == "asin") return one(std::asin);
      if (n == "acos") return one(std::acos);
      if (n == "atan") return one(std::atan);
      if (n == "sinh") return one(std::sinh);
      if (n == "cosh") return one(std::cosh);
      if (n == "tanh") return one(std::tanh);
      if (n == "exp") return one(std::exp);
      if (n == "log") return one(std::log);
      if (n == "log10") return one(std::log10);
      if (n == "sqrt") return one(std::sqrt);
      if (n == "abs") return one(std::fabs);
      if (n == "floor" || n == "integer") return one(std::floor);
      if (n == "ceil") return one(std::ceil);
      if (n == "sign") return a.size() == 1 ? (a[0] > 0) - (a[0] < 0) : NAN;
      if (n == "noEvent" || n == "Integer") return a.size() == 1 ? a[0] : NAN;
      if (n == "atan2" && a.size() == 2) return std::atan2(a[0], a[1]);
      if (n == "min" && a.size() == 2) return std::min(a[0], a[1]);
      if (n == "max" && a.size() == 2) return std::max(a[0], a[1]);
      if (n == "div" && a.size() == 2) return std::trunc(a[0] / a[1]);
      if (n == "mod" && a.size() == 2) return a[0] - std::floor(a[0] / a[1]) * a[1];
      if (n == "rem" && a.size() == 2) return a[0] - std::trunc(a[0] / a[1]) * a[1];
      if (n == "smooth" && a.size() == 2) return a[1];
    }
    fail(DiagId::NotConstant, where, "'" + print_expr(e) + "' cannot be evaluated before simulation");
  }
  case ExprKind::String:
  case ExprKind::Array:
  case ExprKind::Matrix:
  case ExprKind::Range:
  case ExprKind::Tuple:
  case ExprKind::Colon:
  case ExprKind::End:
    break;
  }
  fail(DiagId::NotConstant, where, "expression cannot be evaluated to a number");
}

std::optional<std::string> Flattener::eval_string(const Expr &e, SourceRange where, unsigned depth) {
  if (depth > 64)
    return std::nullopt;
  switch (e.kind) {
  case ExprKind::String:
    return e.text;
  case ExprKind::Ref: {
    if (e.var < 0 || model_->variables[e.var].type != flat::BaseType::String ||
        model_->variables[e.var].variability == ast::Variability::Continuous)
      return std::nullopt;
    if (!model_->variables[e.var].binding) {
      ExprPtr b = take_pending(e.var, "");
      model_->variables[e.var].binding = std::move(b);
    }
    const Expr *b = model_->variables[e.var].binding.get();
    return b ? eval_string(*b, where, depth + 1) : std::nullopt;
  }
  case ExprKind::If:
    for (std::size_t i = 0; i + 1 < e.args.size(); i += 2)
      if (eval(*e.args[i], where) != 0)
        return eval_string(*e.args[i + 1], where, depth + 1);
    return eval_string(*e.args.back(), where, depth + 1);
  default:
    return std::nullopt;
  }
}

long long Flattener::eval_int(const Expr &e, const Scope &s) {
  ExprPtr f = scalar_expr(e, s);
  double v = eval(*f, e.range);
  if (v != std::floor(v) || std::fabs(v) > 1e15)
    fail(DiagId::TypeMismatch, e.range, fmt::format("expected an integer, got {}", v));
  return static_cast<long long>(v);
}

std::vector<double> Flattener::eval_range(const Expr &e, const Scope &s) {
  if (e.kind == ExprKind::Ref) // `for p in Phase`: an enumeration type's literals
    if (int n = enumeration_size(e.ref, s, e.range); n >= 0) {
      std::vector<double> out;
      for (int i = 1; i <= n; ++i)
        out.push_back(i);
      return out;
    }
  if (e.kind != ExprKind::Range) {
    Tensor t = expr(e, s);
    if (t.dims.size() > 1)
      fail(DiagId::TypeMismatch, e.range, "a for-range must be a vector");
    std::vector<double> out;
    for (auto &x : t.elems)
      out.push_back(eval(*x, e.range));
    return out;
  }
  double a = eval(*scalar_expr(*e.args[0], s), e.range);
  double step = e.args.size() == 3 ? eval(*scalar_expr(*e.args[1], s), e.range) : 1.0;
  double b = eval(*scalar_expr(*e.args.back(), s), e.range);
  if (step == 0 || !std::isfinite(a) || !std::isfinite(b) || !std::isfinite(step))
    fail(DiagId::EvaluationError, e.range, "invalid range");
  double n = std::floor((b - a) / step + 1e-10) + 1;
  if (n > 10'000'000)
    fail(DiagId::EvaluationError, e.range, "range has more than 10^7 elements");
  std::vector<double> out;
  for (long long i = 0; i < static_cast<long long>(n); ++i)
    out.push_back(a + static_cast<double>(i) * step);
  return out;
}

ExprPtr Flattener::take_pending(std::int32_t var, const std::string &attribute) {
  auto it = pending_by_var_.find(var);
  if (it == pending_by_var_.end())
    return nullptr;
  for (std::size_t i : it->second) {
    if (pending_[i].attribute == attribute && pending_[i].mod.binding) {
      const Modifier mod = pending_[i].mod; // binding_expr may grow pending_ (member())
      pending_[i].mod.binding = nullptr;    // consumed: phase 2 skips it
      return binding_expr(mod);
    }
  }
  return nullptr;
}

ExprPtr Flattener::binding_expr(const Modifier &m) {
  Tensor t = binding_tensor(m);
  if (t.record)
    fail(DiagId::TypeMismatch, m.binding->range, "a record is bound to a number");
  if (!t.is_scalar())
    fail(DiagId::TypeMismatch, m.binding->range,
         "an array of size " + dims_text(t.dims) + " is bound to a scalar");
  return std::move(t.elems[0]);
}

namespace {
ast::ExprPtr join_range(std::vector<ast::ExprPtr> &terms, std::size_t begin, std::size_t end,
                        const std::function<ast::ExprPtr(ast::ExprPtr, ast::ExprPtr)> &join) {
  constexpr std::size_t kRun = 256;
  if (end - begin > kRun) {
    const std::size_t mid = begin + (end - begin) / 2;
    ast::ExprPtr left = join_range(terms, begin, mid, join);
    return join(std::move(left), join_range(terms, mid, end, join));
  }
  ast::ExprPtr acc = std::move(terms[begin]);
  for (std::size_t i = begin + 1; i < end; ++i)
    acc = join(std::move(acc), std::move(terms[i]));
  return acc;
}
} // namespace

ast::ExprPtr join_terms(std::vector<ast::ExprPtr> terms,
                        const std::function<ast::ExprPtr(ast::ExprPtr, ast::ExprPtr)> &join) {
  return join_range(terms, 0, terms.size(), join);
}

namespace {
/// A copy of the element `index` selects of array `whole` (the whole array's
/// value of a binding); an index longer than its dimensions stops at them.
Tensor element_copy(Flattener &f, const Tensor &whole, const std::vector<int> &index, SourceRange where) {
  std::size_t offset = 0, count = whole.elems.size(), used = 0;
  for (int i : index) {
    if (used == whole.dims.size())
      break;
    const int n = whole.dims[used++];
    if (i < 1 || i > n)
      f.fail(DiagId::BadSubscript, where, fmt::format("the binding has {} elements; element {} is needed", n, i));
    count /= static_cast<std::size_t>(n);
    offset += static_cast<std::size_t>(i - 1) * count;
  }
  Tensor t;
  t.dims.assign(whole.dims.begin() + static_cast<std::ptrdiff_t>(used), whole.dims.end());
  t.record = whole.record;
  for (std::size_t k = 0; k < count; ++k)
    t.elems.push_back(whole.elems[offset + k] ? whole.elems[offset + k]->clone() : nullptr);
  return t;
}
} // namespace

Tensor Flattener::binding_tensor(const Modifier &m) {
  Scope s{m.scope, m.lexical, nullptr};
  Tensor t;
  const auto key = std::make_tuple(m.binding, m.scope, m.lexical);
  auto cached = array_bindings_.find(key);
  if (cached == array_bindings_.end() && !m.index.empty() && failed_bindings_.count(key))
    throw Reported{}; // reported for an earlier element
  if (cached == array_bindings_.end()) {
    try {
      t = expr(*m.binding, s);
    } catch (const Reported &) {
      if (!m.index.empty())
        failed_bindings_.insert(key);
      throw;
    }
    if (!m.index.empty() && !t.dims.empty()) // taken element by element: keep it for the others
      cached = array_bindings_.emplace(key, std::move(t)).first;
  }
  if (cached != array_bindings_.end())
    t = element_copy(*this, cached->second, m.index, m.binding->range);
  const auto take = [&](const std::vector<int> &index) {
    for (int i : index) {
      if (t.dims.empty())
        break; // a scalar binding applies to every element
      int n = t.dims[0];
      if (i < 1 || i > n)
        fail(DiagId::BadSubscript, m.binding->range,
             fmt::format("the binding has {} elements; element {} is needed", n, i));
      std::size_t stride = t.elems.size() / static_cast<std::size_t>(n);
      Tensor sub;
      sub.dims.assign(t.dims.begin() + 1, t.dims.end());
      sub.record = t.record;
      for (std::size_t k = 0; k < stride; ++k)
        sub.elems.push_back(std::move(t.elems[(i - 1) * stride + k]));
      t = std::move(sub);
    }
  };
  if (cached == array_bindings_.end())
    take(m.index);
  for (const auto &[field, index] : m.fields) {
    t = record_field(t, field, m.binding->range);
    take(index);
  }
  return t;
}

} // namespace mo::frontend::detail
