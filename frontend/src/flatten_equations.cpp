// Phase 2 of flattening: bindings, equations, Optimica problem, balance.
#include "flattener.hpp"
#include "mo/frontend/printer.hpp"

#include <fmt/format.h>
#include <set>

namespace mo::frontend::detail {

using ast::EquationKind;
using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;

namespace {

enum class ValueKind { Number, Boolean, String };

/// The kind of value a flat expression has (coarse, for binding checks).
ValueKind value_kind(const Expr &e, const flat::Model &m) {
  switch (e.kind) {
  case ExprKind::String: return ValueKind::String;
  case ExprKind::Boolean: return ValueKind::Boolean;
  case ExprKind::Binary:
    if (e.op >= ast::Op::Lt && e.op <= ast::Op::Or) return ValueKind::Boolean;
    return ValueKind::Number;
  case ExprKind::Unary: return e.op == ast::Op::Not ? ValueKind::Boolean : ValueKind::Number;
  case ExprKind::Ref:
    if (e.var >= 0) {
      auto t = m.variables[e.var].type;
      return t == flat::BaseType::Boolean ? ValueKind::Boolean
             : t == flat::BaseType::String ? ValueKind::String : ValueKind::Number;
    }
    return ValueKind::Number;
  case ExprKind::If: return value_kind(*e.args[1], m);
  case ExprKind::Call: {
    // Built-ins whose value is that of their argument, or a Boolean/String.
    const std::string n = e.var < 0 && e.ref.parts.size() == 1 ? e.ref.parts[0].name : "";
    if ((n == "pre" || n == "noEvent" || n == "smooth") && !e.args.empty() && e.args.back())
      return value_kind(*e.args.back(), m);
    if (n == "edge" || n == "change" || n == "initial" || n == "terminal" || n == "sample")
      return ValueKind::Boolean;
    return n == "String" ? ValueKind::String : ValueKind::Number;
  }
  default: return ValueKind::Number;
  }
}

/// "a scalar" or "[2, 3]".
std::string sizes_text(const std::vector<int> &dims) {
  if (dims.empty())
    return "a scalar";
  std::string s = "[";
  for (std::size_t i = 0; i < dims.size(); ++i)
    s += (i ? ", " : "") + std::to_string(dims[i]);
  return s + "]";
}

const char *value_kind_text(ValueKind k) {
  return k == ValueKind::String ? "a String" : k == ValueKind::Boolean ? "a Boolean" : "a number";
}

} // namespace

bool Flattener::is_constant(const Expr &e) const {
  std::vector<const Expr *> work{&e};
  while (!work.empty()) {
    const Expr *x = work.back();
    work.pop_back();
    if (x->kind == ExprKind::Ref) {
      if (x->var < 0) return false; // time
      auto v = model_->variables[x->var].variability;
      if (v != ast::Variability::Parameter && v != ast::Variability::Constant) return false;
    }
    if (x->kind == ExprKind::Call) {
      const std::string &n = x->ref.parts.empty() ? "" : x->ref.parts[0].name;
      if (x->var >= 0 || n == "der" || n == "pre" || n == "initial" || n == "terminal" ||
          n == "sample" || n == "edge" || n == "change" || n == "delay")
        return false;
    }
    for (const auto &a : x->args)
      if (a) work.push_back(a.get());
  }
  return true;
}

bool Flattener::already_evaluated(const Expr &e) const {
  std::vector<const Expr *> work{&e};
  while (!work.empty()) {
    const Expr *x = work.back();
    work.pop_back();
    if (x->kind == ExprKind::Ref) {
      if (x->var < 0 || static_cast<std::size_t>(x->var) >= param_state_.size() || param_state_[x->var] != 2 ||
          !model_->variables[x->var].value)
        return false;
    }
    // Pure numeric built-ins of such values are known too (`mod(m, 2) == 0`
    // on the phase count that sized MultiPhase's symmetricOrientation).
    static const std::set<std::string> kPure{"mod", "rem", "div", "integer", "floor", "ceil",
                                             "abs", "sign", "min", "max", "sqrt"};
    if (x->kind == ExprKind::Call && (x->args.empty() || !kPure.count(x->ref.str()) || !x->named.empty()))
      return false;
    for (const auto &a : x->args)
      if (a) work.push_back(a.get());
  }
  return true;
}

bool Flattener::structural(const Expr &e) const {
  if (!is_constant(e))
    return false;
  std::vector<const Expr *> work{&e};
  while (!work.empty()) {
    const Expr *x = work.back();
    work.pop_back();
    if (x->kind == ExprKind::Ref) {
      const flat::Variable &v = model_->variables[static_cast<std::size_t>(x->var)];
      const bool fixed = static_cast<std::size_t>(x->var) < param_state_.size() && param_state_[x->var] == 2 && v.value;
      if (v.variability != ast::Variability::Constant && !v.evaluate && !fixed)
        return false;
    }
    for (const auto &a : x->args)
      if (a) work.push_back(a.get());
  }
  return true;
}

void Flattener::flatten_bindings() {
  for (auto &p : pending_) {
    if (!p.mod.binding)
      continue; // already flattened on demand (a parameter used as a size)
    if (!graph_closed_ && reads_connection_graph(*p.mod.binding))
      continue; // once the connection graph is known (flatten_equations)
    try {
      flat::Variable &v = model_->variables[p.var];
      const std::string &a = p.attribute;
      if (a == "unit" || a == "displayUnit" || a == "quantity") {
        ExprPtr e = binding_expr(p.mod);
        if (e->kind != ExprKind::String)
          fail(DiagId::TypeMismatch, p.mod.binding->range, "attribute '" + a + "' must be a string");
        (a == "unit" ? v.attr.unit : a == "displayUnit" ? v.attr.display_unit : v.attr.quantity) = e->text;
        continue;
      }
      if (a == "stateSelect") {
        ExprPtr e = binding_expr(p.mod);
        static const char *const kLevels[] = {"never", "avoid", "default", "prefer", "always"};
        // A literal, or a parameter of type StateSelect (MSL's `stateSelect = stateSelect`).
        const double level = is_constant(*e) ? eval(*e, p.mod.binding->range) : 0;
        if (level < 1 || level > 5 || level != static_cast<int>(level))
          fail(DiagId::TypeMismatch, p.mod.binding->range, "stateSelect must be a StateSelect value");
        model_->variables[p.var].attr.state_select = kLevels[static_cast<int>(level) - 1];
        continue;
      }
      const flat::Variable &declared = model_->variables[p.var];
      const Flag on(intermediates_on_, a.empty() && declared.type == flat::BaseType::Real &&
                                           declared.variability == ast::Variability::Continuous);
      ExprPtr e = binding_expr(p.mod);
      flat::Variable &var = model_->variables[p.var];
      ValueKind got = value_kind(*e, *model_);
      ValueKind want = a == "fixed" || a == "free" ? ValueKind::Boolean
                       : var.type == flat::BaseType::Boolean && (a.empty() || a == "start") ? ValueKind::Boolean
                       : var.type == flat::BaseType::String ? ValueKind::String : ValueKind::Number;
      if (got != want)
        fail(DiagId::TypeMismatch, p.mod.binding->range,
             fmt::format("{} of {} '{}' must be {}, not {}", a.empty() ? "the value" : "attribute '" + a + "'",
                         flat::base_type_text(var.type), var.name, value_kind_text(want), value_kind_text(got)));
      if (a.empty()) {
        if (var.variability == ast::Variability::Parameter || var.variability == ast::Variability::Constant) {
          var.binding = std::move(e);
        } else {
          ast::Equation eq;
          eq.kind = EquationKind::Simple;
          eq.range = p.mod.binding->range;
          eq.lhs = ast::make_ref(var.name, var.range);
          eq.lhs->var = p.var;
          eq.rhs = std::move(e);
          model_->equations.push_back(std::move(eq));
        }
      } else {
        ExprPtr *slot = a == "start" ? &var.attr.start : a == "fixed" ? &var.attr.fixed
                      : a == "min" ? &var.attr.min : a == "max" ? &var.attr.max
                      : a == "nominal" ? &var.attr.nominal : a == "free" ? &var.attr.free
                      : &var.attr.initial_guess;
        *slot = std::move(e);
      }
      p.mod.binding = nullptr;
    } catch (Reported &) {
      if (p.attribute.empty()) { // do not also warn that it has no value
        param_state_.resize(model_->variables.size(), 0);
        param_state_[p.var] = 3;
      }
    }
  }
}

void Flattener::flatten_equations(Instance &top) {
  flatten_bindings();
  // The connections first, so that cardinality() counts them all (those
  // inside if-equations excepted). Instances were recorded in creation
  // order: parents before children. By index: a reference to an element of
  // an expandable connector may instantiate it now
  // (Flattener::present_member), appending instances.
  for (std::size_t k = 0; k < all_instances_.size(); ++k) {
    Instance *inst = all_instances_[k];
    for (auto &[eq, cls] : inst->equations) {
      try {
        if (only_connections(*eq))
          equation(*eq, Scope{inst, cls, nullptr}, model_->equations);
        else
          collect_graph_statements(*eq, Scope{inst, cls, nullptr});
      } catch (Reported &) {
      }
    }
  }
  connections_counted_ = true;
  try {
    close_connection_graph();
  } catch (Reported &) {
  }
  flatten_bindings(); // those that read the graph
  for (std::size_t k = 0; k < all_instances_.size(); ++k) {
    Instance *inst = all_instances_[k];
    for (auto &[eq, cls] : inst->equations) {
      if (only_connections(*eq))
        continue;
      try {
        const Flag continuous(continuous_section_, true);
        equation(*eq, Scope{inst, cls, nullptr}, model_->equations);
      } catch (Reported &) {
      }
    }
    std::vector<std::pair<const ast::AlgorithmSection *, ClassNode *>> initial_algorithms;
    for (auto &[alg, cls] : inst->algorithms) {
      if (alg->initial) {
        initial_algorithms.emplace_back(alg, cls);
        continue;
      }
      try {
        algorithm_section(*alg, Scope{inst, cls, nullptr}, model_->equations);
      } catch (Reported &) {
      }
    }
    for (auto &[eq, cls] : inst->initial_equations) {
      std::vector<ast::Equation> produced;
      try {
        equation(*eq, Scope{inst, cls, nullptr}, produced);
      } catch (Reported &) {
      }
      // Now, so that the next initial equations can evaluate these parameters.
      bind_computed_parameters(produced);
      for (auto &e : produced)
        model_->initial_equations.push_back(std::move(e));
    }
    for (auto &[alg, cls] : initial_algorithms) {
      std::vector<ast::Equation> produced;
      try {
        algorithm_section(*alg, Scope{inst, cls, nullptr}, produced);
      } catch (Reported &) {
      }
      bind_computed_parameters(produced);
      for (auto &e : produced)
        model_->initial_equations.push_back(std::move(e));
    }
  }
  flush_intermediates();
  if (top.cls->def->restriction == ast::Restriction::Optimization)
    flatten_optimization();
  else if (!top.constraints.empty())
    diags_.report(DiagId::BadOptimization, top.constraints.front().first->range,
                  "constraint sections are only allowed in optimization classes");
  for (std::int32_t i = 0; i < static_cast<std::int32_t>(model_->variables.size()); ++i) {
    const flat::Variable &v = model_->variables[i];
    if (v.variability != ast::Variability::Parameter || v.type == flat::BaseType::String)
      continue; // a String has no number to evaluate to (eval_string compares them)
    if (i < static_cast<std::int32_t>(param_state_.size()) && param_state_[i] == 3)
      continue; // its binding already has an error
    if (!v.binding && !v.attr.start) {
      if (!v.free_parameter()) // else the initial equations compute it
        diags_.report(DiagId::ParameterWithoutValue, v.range, "parameter '" + v.name + "' has no value");
      continue;
    }
    try {
      if (is_constant(v.binding ? *v.binding : *v.attr.start))
        eval_param(i, v.range);
    } catch (Reported &) {
    }
  }
}

void Flattener::flatten_optimization() {
  const ast::ClassDef &def = *top_->cls->def;
  flat::Optimization opt;
  opt.range = def.range;
  Scope s{top_.get(), top_->cls, nullptr, true};
  const std::vector<const ast::ElementMod *> attributes = optimization_attributes();
  declare_free_final_time(attributes);
  opt.free_final_time = free_final_time_;
  for (const ast::ElementMod *attribute : attributes) {
    const ast::ElementMod &em = *attribute;
    std::string n = em.path.empty() ? "" : em.path[0];
    ExprPtr *slot = n == "objective" ? &opt.objective : n == "objectiveIntegrand" ? &opt.objective_integrand
                  : n == "startTime" ? &opt.start_time : n == "finalTime" ? &opt.final_time : nullptr;
    const bool time_attributes = (n == "startTime" || n == "finalTime") && !em.mod.args.empty();
    if (time_attributes && !em.mod.binding && em.path.size() == 1)
      continue; // `finalTime(free = true, ...)`: declare_free_final_time handled it
    if (!slot || em.path.size() != 1 || !em.mod.binding) {
      diags_.report(DiagId::BadOptimization, em.range,
                    "'" + n + "' is not an attribute of an optimization class (expected objective, "
                              "objectiveIntegrand, startTime or finalTime with a value or attributes)");
      continue;
    }
    try {
      *slot = scalar_expr(*em.mod.binding, s);
    } catch (Reported &) {
    }
  }
  // Constraints may be written in any class of the problem (usually the top).
  for (Instance *inst : all_instances_)
    for (auto &[eq, cls] : inst->constraints) {
      try {
        Scope cs{inst, cls, nullptr, true};
        equation(*eq, cs, opt.constraints);
      } catch (Reported &) {
      }
    }
  for (const ast::ElementMod &em : def.vendor_annotation.args) {
    std::string name;
    for (const auto &part : em.path) name += (name.empty() ? "" : ".") + part;
    opt.options.push_back({name, em.mod.binding ? em.mod.binding->clone() : nullptr, em.range});
  }
  model_->optimization = std::move(opt);
}

/// `(a, , b) = f(x)`: one equation per named output of the user function f.
void Flattener::tuple_equation(const ast::Equation &eq, const Scope &s, std::vector<ast::Equation> &out) {
  ClassNode *fn = eq.rhs->kind == ast::ExprKind::Call ? lookup_function(*eq.rhs, s) : nullptr;
  if (!fn)
    fail(DiagId::Unsupported, eq.rhs->range, "the right side of a tuple equation must call a user function");
  const auto &targets = eq.lhs->args;
  std::vector<Tensor> values = call_function(fn, *eq.rhs, s, targets.size());
  if (values.size() < targets.size())
    fail(DiagId::WrongArgumentCount, eq.lhs->range,
         fmt::format("{} outputs are assigned but the function has {}", targets.size(), values.size()));
  for (std::size_t k = 0; k < targets.size(); ++k) {
    if (!targets[k])
      continue; // an omitted output
    Tensor l = expr(*targets[k], s);
    equal_elements(eq, l, values[k], out);
  }
}

/// The scalar equations l[i] = r[i] (or l[i] rel r for a scalar constraint side).
void Flattener::equal_elements(const ast::Equation &eq, Tensor &l, Tensor &r, std::vector<ast::Equation> &out) {
  if (!same_record_type(l.record, r.record))
    fail(DiagId::TypeMismatch, eq.range,
         l.record && r.record ? "the two sides of this equation are records with different fields"
                              : "one side of this equation is a record and the other is not");
  if (l.dims != r.dims && !(eq.kind == EquationKind::Constraint && r.is_scalar()))
    fail(DiagId::TypeMismatch, eq.range,
         fmt::format("the two sides of this equation have different sizes ({} and {})",
                     sizes_text(l.dims), sizes_text(r.dims)));
  for (std::size_t i = 0; i < l.elems.size(); ++i) {
    // The right side's element i (a scalar right side is reused): element
    // 0 of an array has already been moved out when i > 0.
    const Expr &r_i = *r.elems[r.is_scalar() ? 0 : i];
    ValueKind lk = value_kind(*l.elems[i], *model_), rk = value_kind(r_i, *model_);
    if (lk == ValueKind::String || rk == ValueKind::String)
      fail(DiagId::TypeMismatch, eq.range, "strings cannot appear in equations");
    if (eq.kind == EquationKind::Simple && lk != rk)
      fail(DiagId::TypeMismatch, eq.range,
           fmt::format("this equation sets {} equal to {}", value_kind_text(lk), value_kind_text(rk)));
    ast::Equation f;
    f.kind = eq.kind;
    f.rel = eq.rel;
    f.range = eq.range;
    f.lhs = std::move(l.elems[i]);
    f.rhs = r.is_scalar() ? r_i.clone() : std::move(r.elems[i]);
    out.push_back(std::move(f));
  }
}

void Flattener::for_each_iteration(const ast::Equation &eq, const Scope &s,
                                   const std::function<void(const Scope &)> &body) {
  // Nested loops over every index, innermost last.
  LoopEnv env = s.env ? *s.env : LoopEnv{};
  std::function<void(std::size_t)> loop = [&](std::size_t k) {
    Scope inner = s;
    inner.env = &env;
    if (k == eq.indices.size()) {
      if (++loop_iterations_ > opts_.max_elements)
        fail(DiagId::Unsupported, eq.range,
             fmt::format("the model's for-equations run more than {} times, mocompile's limit", opts_.max_elements));
      body(inner);
      return;
    }
    if (!eq.indices[k].range)
      fail(DiagId::Unsupported, eq.indices[k].loc, "for-loops without 'in range' are not supported");
    for (double v : eval_range(*eq.indices[k].range, inner)) {
      env.values.emplace_back(eq.indices[k].name, v);
      loop(k + 1);
      env.values.pop_back();
    }
  };
  loop(0);
}

void Flattener::equation(const ast::Equation &eq, const Scope &s, std::vector<ast::Equation> &out) {
  switch (eq.kind) {
  case EquationKind::Simple:
  case EquationKind::Constraint: {
    const Flag on(intermediates_on_, eq.kind == EquationKind::Simple && continuous_section_ && !s.in_when &&
                                         !s.in_optimization);
    if (eq.kind == EquationKind::Simple && eq.lhs->kind == ast::ExprKind::Tuple) {
      tuple_equation(eq, s, out);
      return;
    }
    Tensor l = expr(*eq.lhs, s);
    Tensor r = expr(*eq.rhs, s);
    equal_elements(eq, l, r, out);
    return;
  }
  case EquationKind::Connect:
    if (s.in_when)
      fail(DiagId::Unsupported, eq.range, "connect() inside a when-clause is not allowed");
    connect(eq, s);
    return;
  case EquationKind::For:
    for_each_iteration(eq, s, [&](const Scope &inner) {
      for (const auto &b : eq.body)
        equation(b, inner, out);
    });
    return;
  case EquationKind::If: {
    // Branches under parameter conditions are chosen now; otherwise the
    // if-equation stays, each branch flattened.
    ast::Equation f;
    f.kind = EquationKind::If;
    f.range = eq.range;
    for (const auto &b : eq.branches) {
      ExprPtr c;
      if (b.condition) {
        c = scalar_expr(*b.condition, s);
        if (is_constant(*c) && f.branches.empty()) {
          if (eval(*c, b.condition->range) == 0)
            continue;
          for (const auto &x : b.body)
            equation(x, s, out);
          return;
        }
      } else if (f.branches.empty()) {
        for (const auto &x : b.body)
          equation(x, s, out);
        return;
      }
      ast::EquationBranch fb{std::move(c), {}, b.range};
      const Flag varying(continuous_section_, false); // would be computed outside the branch
      for (const auto &x : b.body)
        equation(x, s, fb.body);
      f.branches.push_back(std::move(fb));
    }
    if (!f.branches.empty()) {
      std::size_t n = 0;
      for (const auto &x : f.branches[0].body) n += flat::equation_count(x);
      for (const auto &b : f.branches) {
        std::size_t m = 0;
        for (const auto &x : b.body) m += flat::equation_count(x);
        if (m != n)
          fail(DiagId::UnbalancedModel, b.range,
               fmt::format("the branches of this if-equation have different numbers of equations ({} and {})", n, m));
      }
      if (f.branches.back().condition == nullptr || n == 0)
        out.push_back(std::move(f));
      else
        fail(DiagId::UnbalancedModel, eq.range, "an if-equation with time-varying conditions needs an else branch");
    }
    return;
  }
  case EquationKind::When: {
    if (s.in_when)
      fail(DiagId::Unsupported, eq.range, "when-clauses cannot be nested");
    ast::Equation f;
    f.kind = EquationKind::When;
    f.range = eq.range;
    Scope inner = s;
    inner.in_when = true;
    for (const auto &b : eq.branches) {
      Tensor c = expr(*b.condition, s);
      ExprPtr cond;
      if (c.is_scalar()) {
        cond = std::move(c.elems[0]);
      } else {
        cond = std::make_unique<Expr>(ExprKind::Array, b.condition->range);
        for (auto &x : c.elems) cond->args.push_back(std::move(x));
      }
      ast::EquationBranch fb{std::move(cond), {}, b.range};
      ++when_branch_serial_;
      for (const auto &x : b.body)
        equation(x, inner, fb.body);
      impure_draws_of_branch(fb.body);
      f.branches.push_back(std::move(fb));
    }
    out.push_back(std::move(f));
    return;
  }
  case EquationKind::Call: {
    const Expr &call = *eq.lhs;
    const std::string n = call.ref.str();
    if (is_connections_statement(eq))
      return; // collected before (collect_graph_statements)
    if (n == "reinit") {
      if (!s.in_when)
        fail(DiagId::Unsupported, eq.range, "reinit() is only allowed inside a when-clause");
      if (call.args.size() != 2)
        fail(DiagId::WrongArgumentCount, call.range, fmt::format("reinit() takes 2 arguments, {} given", call.args.size()));
    } else if (n == "assert") {
      if (call.args.size() < 2 || call.args.size() > 3)
        fail(DiagId::WrongArgumentCount, call.range, "assert() takes 2 or 3 arguments");
    } else if (n != "terminate") {
      // A function called as an equation, for its checks (no equation).
      if (ClassNode *callee = call.resolved ? nullptr : lookup_function(call, s); callee && call_statement(callee, call, s))
        return;
      fail(DiagId::Unsupported, call.range, "'" + n + "(...)' cannot be used as an equation");
    }
    Tensor first = call.args.empty() ? Tensor{} : expr(*call.args[0], s);
    std::size_t count = call.args.empty() ? 1 : first.elems.size();
    std::vector<Tensor> rest;
    for (std::size_t i = 1; i < call.args.size(); ++i)
      rest.push_back(expr(*call.args[i], s));
    for (std::size_t k = 0; k < count; ++k) {
      auto c = std::make_unique<Expr>(ExprKind::Call, call.range);
      c->resolved = true;
      c->ref = ast::ComponentRef{};
      c->ref.parts.push_back(ast::RefPart{n, {}});
      if (!call.args.empty())
        c->args.push_back(first.elems[k]->clone());
      for (auto &t : rest)
        c->args.push_back((t.is_scalar() ? t.elems[0] : t.elems.at(k))->clone());
      if (n == "reinit" && (c->args[0]->kind != ExprKind::Ref || c->args[0]->var < 0))
        fail(DiagId::TypeMismatch, call.args[0]->range, "the first argument of reinit() must be a variable");
      ast::Equation f;
      f.kind = EquationKind::Call;
      f.range = eq.range;
      f.lhs = std::move(c);
      out.push_back(std::move(f));
    }
    return;
  }
  }
}

} // namespace mo::frontend::detail
