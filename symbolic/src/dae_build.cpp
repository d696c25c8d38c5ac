// flat::Model → Dae; see dae_build.hpp.
#include "dae_build.hpp"

#include <cmath>
#include <map>
#include <unordered_set>

#include "dae_expr.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/traversal.hpp"
#include "mo/symbolic/substitute.hpp"

namespace mo::symbolic::detail {

namespace ast = frontend::ast;
namespace flat = frontend::flat;
using frontend::DiagId;

int Dae::add_var(DaeVar v) {
  const int index = static_cast<int>(vars.size());
  // Internal names start with a control character no Modelica name has, so
  // the final symbols (with their proper roles) can take the plain names.
  v.symbol = arena.symbol(symbol_prefix + v.info.name, SymbolRole::Algebraic, index);
  if (var_of_symbol.size() <= v.symbol.id()) var_of_symbol.resize(v.symbol.id() + 1, none);
  var_of_symbol[v.symbol.id()] = index;
  vars.push_back(std::move(v));
  return index;
}

int Dae::derivative_of(int v) {
  if (vars[static_cast<std::size_t>(v)].derivative != none)
    return vars[static_cast<std::size_t>(v)].derivative;
  DaeVar d;
  const DaeVar& base = vars[static_cast<std::size_t>(v)];
  d.info.name = "der(" + base.info.name + ")";
  d.info.nominal = base.info.nominal;
  d.integral = v;
  d.range = base.range;
  const int di = add_var(std::move(d));
  vars[static_cast<std::size_t>(v)].derivative = di;
  return di;
}

namespace {

/// True for a parameter declared `fixed = false` without a binding: its
/// value is computed by the initial equations (the MSL's
/// SaturatingInductor.Ipar). With a binding it stays a parameter of that
/// value: Scilab's flat files mark every block parameter fixed = false.
bool computed_parameter(const flat::Variable& v) { return v.free_parameter() && !v.binding; }

/// The first Integer or Boolean parameter computed by the initial equations
/// that `e` references, or -1 (a Real one is an unknown of the initial system).
std::int32_t free_start_parameter(const ast::Expr& e, const flat::Model& f) {
  std::vector<const ast::Expr*> todo{&e};
  while (!todo.empty()) {
    const ast::Expr* x = todo.back();
    todo.pop_back();
    if (x->var >= 0) {
      const flat::Variable& v = f.variables[static_cast<std::size_t>(x->var)];
      if (computed_parameter(v) && v.type != flat::BaseType::Real) return x->var;
    }
    for (const auto& a : x->args) if (a) todo.push_back(a.get());
    for (const auto& n : x->named) if (n.value) todo.push_back(n.value.get());
    for (const auto& row : x->rows) for (const auto& a : row) if (a) todo.push_back(a.get());
  }
  return -1;
}

/// The targets of `w`'s assignments that `e` reads outside pre() (indices
/// into w.assignments), and the pre() nodes of `e`.
void clause_reads(const ExprArena& a, const DaeWhen& w, Expr e, std::vector<std::size_t>& reads,
                  std::vector<Expr>& pres) {
  std::vector<Expr> stack{e};
  std::unordered_set<std::uint32_t> seen;
  while (!stack.empty()) {
    const Expr x = stack.back();
    stack.pop_back();
    if (!seen.insert(x.id()).second) continue;
    const ExprKind k = a.kind(x);
    if (k == ExprKind::Pre) {
      pres.push_back(x);
      continue;
    }
    if (k == ExprKind::Symbol) {
      for (std::size_t i = 0; i < w.assignments.size(); ++i)
        if (w.assignments[i].target == x) reads.push_back(i);
      continue;
    }
    for (std::size_t j = 0; j < arity(k); ++j) stack.push_back(a.operand(x, j));
  }
}

/// The equations of a when-clause hold together (Modelica 3 §8.3.5): one
/// that reads another's target reads its new value (the MSL's IntegerTable:
/// `index = pre(index) + 1; nextTime = table[index, 1]`). Substitutes each
/// assigned value into the values and reinit values that read it, in
/// dependency order; a cycle among them is left as written.
void resolve_within_clause(ExprArena& a, DaeWhen& w) {
  const std::size_t n = w.assignments.size();
  if (n == 0) return;
  std::vector<std::vector<std::size_t>> reads(n);
  std::vector<std::vector<Expr>> pres(n);
  for (std::size_t i = 0; i < n; ++i) clause_reads(a, w, w.assignments[i].value, reads[i], pres[i]);
  std::vector<int> state(n, 0);  // 0 new, 1 in progress, 2 resolved
  std::vector<std::size_t> order;
  bool cycle = false;
  std::vector<std::pair<std::size_t, std::size_t>> stack;  // (assignment, next read)
  for (std::size_t root = 0; root < n && !cycle; ++root) {
    if (state[root]) continue;
    stack.push_back({root, 0});
    state[root] = 1;
    while (!stack.empty() && !cycle) {
      auto& [i, next] = stack.back();
      if (next == reads[i].size()) {
        state[i] = 2;
        order.push_back(i);
        stack.pop_back();
        continue;
      }
      const std::size_t j = reads[i][next++];
      if (state[j] == 1) cycle = true;
      else if (state[j] == 0) {
        state[j] = 1;
        stack.push_back({j, 0});
      }
    }
  }
  if (cycle) return;
  ExprMap resolved;
  auto resolve = [&](Expr e, const std::vector<Expr>& own_pres) {
    ExprMap map = resolved;
    for (Expr p : own_pres) map[p] = p;  // pre(v) stays the value before
    return substitute(a, e, map);
  };
  for (std::size_t i : order) {
    Assignment& as = w.assignments[i];
    if (!reads[i].empty()) as.value = resolve(as.value, pres[i]);
    resolved[as.target] = as.value;
  }
  for (auto& [v, value] : w.reinits) {
    std::vector<std::size_t> r;
    std::vector<Expr> p;
    clause_reads(a, w, value, r, p);
    if (!r.empty()) value = resolve(value, p);
  }
}

/// What a flat variable became.
struct Slot {
  enum Kind { Unset, Var, Value } kind = Unset;
  int var = none;  ///< DaeVar index (Var)
  Expr value;      ///< symbol or inlined expression (Value)
};

class Builder {
public:
  Builder(const flat::Model& f, frontend::DiagnosticEngine& d)
      : f_(f), diags_(d), slots_(f.variables.size()) {
    dae_.name = f.name;
    dae_.time = dae_.arena.symbol("time", SymbolRole::Time, 0);
    conv_.emplace(dae_.arena, dae_.time, diags_,
                  [this](const ast::Expr& r) { return ref(r); },
                  [this](const ast::Expr& x) { return der(x); });
    conv_->on_initial([this] { return initial_flag(); });
    conv_->on_sample([this](const ast::Expr& c) {
      std::unordered_set<Expr, ExprHash> computed;  // computed_parameters(): constant after the start
      for (int i : computed_) {
        const int var = slots_[static_cast<std::size_t>(i)].var;
        computed.insert(dae_.vars[static_cast<std::size_t>(var)].symbol);
      }
      return sample_flag(dae_, *conv_, c, param_values_, computed);
    });
  }

  std::optional<Dae> run() {
    mark_discrete();
    for (std::size_t i = 0; i < f_.variables.size(); ++i) declare(static_cast<int>(i));
    for (std::size_t k = 0; k < dae_.parameters.size(); ++k) {
      param_values_[dae_.parameters[k].symbol] = dae_.parameters[k].value;
      info_of_[dae_.parameters[k].symbol] = &dae_.parameters[k].info;
    }
    for (auto& d : dae_.discrete) info_of_[d.symbol] = &d.info;
    for (auto& u : dae_.inputs) info_of_[u.symbol] = &u.info;
    for (std::size_t i = 0; i < f_.variables.size(); ++i) attributes(static_cast<int>(i));
    for (const ast::Equation& eq : f_.equations) equation(eq);
    computed_parameters();
    initial_equations();
    in_initial_ = false;
    outputs();
    if (!conv_->ok() || !ok_) return std::nullopt;
    return std::move(dae_);
  }

private:
  const flat::Variable& fv(int i) const { return f_.variables[static_cast<std::size_t>(i)]; }

  void error(DiagId id, frontend::SourceRange r, const std::string& msg) {
    diags_.report(id, r, msg);
    ok_ = false;
  }

  void mark_discrete() {
    // What a when-clause assigns, through if-equations inside it too.
    std::vector<const ast::Equation*> work;
    for (const ast::Equation& eq : f_.equations)
      if (eq.kind == ast::EquationKind::When) work.push_back(&eq);
    while (!work.empty()) {
      const ast::Equation& eq = *work.back();
      work.pop_back();
      for (const auto& br : eq.branches)
        for (const ast::Equation& s : br.body) {
          if (s.kind == ast::EquationKind::If) work.push_back(&s);
          if (s.kind == ast::EquationKind::Simple && s.lhs->kind == ast::ExprKind::Ref && s.lhs->var >= 0)
            discrete_.insert(s.lhs->var);
        }
    }
    for (const ast::Equation& eq : f_.initial_equations)
      if (const int p = computes_discrete_parameter(eq); p >= 0) discrete_.insert(p);
    mark_event_equations();
  }

  /// The Boolean or Integer parameter computed by the initial equation `eq`
  /// when it is `p = expr` or `expr = p` (p fixed = false, unbound), or -1.
  int computes_discrete_parameter(const ast::Equation& eq) const {
    if (eq.kind != ast::EquationKind::Simple) return -1;
    for (const ast::Expr* side : {eq.lhs.get(), eq.rhs.get()})
      if (side->kind == ast::ExprKind::Ref && side->var >= 0 && computed_parameter(fv(side->var)) &&
          fv(side->var).type != flat::BaseType::Real)
        return side->var;
    return -1;
  }

  /// Modelica 3 §8.6: a Boolean, Integer or `discrete` variable changes only
  /// at events, where the event iteration solves its equation together with
  /// the continuous ones (pre() being the value of the previous iteration).
  /// For an equation `d = expr` outside when-clauses whose d is such a
  /// variable and that reads pre() (or whose d some pre() reads), solving it
  /// as a continuous unknown would put pre(d) = d into a Newton block (the
  /// MSL's friction: `startForward = pre(mode) == Stuck and (sa > tau0_max or
  /// pre(startForward) and sa > tau0) ...`); one with a relation would switch
  /// inside the Newton iterations (has_event_relation). It becomes an
  /// every-event assignment (WhenClause::every_event) and d a discrete variable.
  void mark_event_equations() {
    std::unordered_set<int> pre_read;
    std::vector<const ast::Expr*> roots;
    for (const ast::Equation& eq : f_.equations) {
      if (eq.lhs) roots.push_back(eq.lhs.get());
      if (eq.rhs) roots.push_back(eq.rhs.get());
      for (const auto& br : eq.branches) {
        if (br.condition) roots.push_back(br.condition.get());
        for (const ast::Equation& s : br.body) {
          if (s.lhs) roots.push_back(s.lhs.get());
          if (s.rhs) roots.push_back(s.rhs.get());
        }
      }
    }
    for (const ast::Expr* r : roots) pre_reads(*r, pre_read);
    std::unordered_set<int> on_left;  // variables alone on the left of some equation
    for (const ast::Equation& eq : f_.equations)
      if (eq.kind == ast::EquationKind::Simple && eq.lhs->kind == ast::ExprKind::Ref && eq.lhs->var >= 0)
        on_left.insert(eq.lhs->var);
    for (const ast::Equation& eq : f_.equations) {
      if (eq.kind != ast::EquationKind::Simple) continue;
      const ast::Expr* lhs = eq.lhs.get();
      const ast::Expr* rhs = eq.rhs.get();
      // `a = v` (a connection) with v read by pre(), a not, and v on the
      // left of no equation: the equation is v's
      if (rhs->kind == ast::ExprKind::Ref && rhs->var >= 0 && pre_read.contains(rhs->var) &&
          !on_left.contains(rhs->var) && !(lhs->kind == ast::ExprKind::Ref && lhs->var >= 0 && pre_read.contains(lhs->var)))
        std::swap(lhs, rhs);
      if (lhs->kind != ast::ExprKind::Ref || lhs->var < 0) continue;
      const int v = lhs->var;
      const flat::Variable& var = fv(v);
      const bool discrete_type = var.type == flat::BaseType::Boolean || var.type == flat::BaseType::Integer ||
                                 var.variability == ast::Variability::Discrete;
      if (!discrete_type || var.top_level_input || discrete_.contains(v) ||
          (var.variability != ast::Variability::Continuous && var.variability != ast::Variability::Discrete))
        continue;
      std::unordered_set<int> own;
      if (!pre_read.contains(v) && !pre_reads(*rhs, own) && !has_event_relation(*rhs)) continue;
      discrete_.insert(v);
      event_equations_.emplace(&eq, lhs == eq.lhs.get());
    }
  }

  /// True if `e` holds a relation outside noEvent(): a Boolean equation
  /// `off = s < 0` (the MSL's ideal diode) is discrete too, held between
  /// events, its relation an event indicator. Evaluated where it is used, it
  /// switched during the Newton iterations of the algebraic loop around it.
  static bool has_event_relation(const ast::Expr& e) {
    std::vector<const ast::Expr*> stack{&e};
    while (!stack.empty()) {
      const ast::Expr* x = stack.back();
      stack.pop_back();
      if (x->kind == ast::ExprKind::Call && x->ref.str() == "noEvent") continue;
      if (x->kind == ast::ExprKind::Binary && x->op >= ast::Op::Lt && x->op <= ast::Op::Ne) return true;
      for (const auto& a : x->args)
        if (a) stack.push_back(a.get());
    }
    return false;
  }

  /// Adds the flat variables that pre() calls in `e` read to `out`; true if
  /// `e` calls pre() at all (edge(v) and change(v) read pre(v) too).
  /// Iterative (expressions may be deep).
  static bool pre_reads(const ast::Expr& e, std::unordered_set<int>& out) {
    bool any = false;
    std::vector<const ast::Expr*> stack{&e};
    while (!stack.empty()) {
      const ast::Expr* x = stack.back();
      stack.pop_back();
      if (x->kind == ast::ExprKind::Call &&
          (x->ref.str() == "pre" || x->ref.str() == "edge" || x->ref.str() == "change")) {
        any = true;
        if (!x->args.empty() && x->args[0] && x->args[0]->kind == ast::ExprKind::Ref && x->args[0]->var >= 0)
          out.insert(x->args[0]->var);
      }
      for (const auto& a : x->args)
        if (a) stack.push_back(a.get());
      for (const auto& row : x->rows)
        for (const auto& a : row)
          if (a) stack.push_back(a.get());
    }
    return any;
  }

  void declare(int i) {
    const flat::Variable& v = fv(i);
    Slot& s = slots_[static_cast<std::size_t>(i)];
    VariableInfo info{v.name, v.description, v.attr.unit};
    info.type = v.type == flat::BaseType::Boolean   ? ValueType::Boolean
                : v.type == flat::BaseType::Integer ? ValueType::Integer
                                                    : ValueType::Real;
    if (v.type == flat::BaseType::String) {
      // A String parameter (a table's file name, a machine's terminal
      // connection) served the flattening; only a use in an equation is an error (ref()).
      if (v.variability != ast::Variability::Parameter && v.variability != ast::Variability::Constant) {
        error(DiagId::UnsupportedInLowering, v.range, "String variables cannot be lowered");
        s = {Slot::Value, none, dae_.arena.constant(0.0)};
      }
    } else if (v.variability == ast::Variability::Parameter && discrete_.contains(i)) {
      // A Boolean or Integer parameter that an initial equation `p = expr`
      // computes (fixed = false): a discrete variable that `when initial()`
      // sets (discrete_initial_assignment) and nothing changes after. The
      // MSL's RevoluteWithLengthConstraint picks its branch of the loop's
      // solution so from the positions at t0.
      declare_discrete(i, info);
    } else if (v.variability == ast::Variability::Constant ||
               (v.variability == ast::Variability::Parameter &&
                (v.type != flat::BaseType::Real || (v.evaluate && v.value && !reads_computed_parameter(i))))) {
      // Evaluate = true: a structural value, used as a constant (the MSL's
      // HeatingNPN_OrGate sets every capacitance to CapVal = 0 so). Not one
      // the initial equations compute, or whose binding reads one: its value
      // is unknown until then (the MSL's JointRRR declares its axis n_b
      // `fixed = false` and Evaluate = true, and an initial equation gives it).
      s = {Slot::Value, none, dae_.arena.constant(v.value.value_or(0.0))};
    } else if (computed_parameter(v)) {
      // Real, fixed = false, no binding: an unknown of the initial system that keeps
      // its value, i.e. a state with der(p) = 0 (see computed_parameters()).
      DaeVar d;
      d.info = info;
      d.range = v.range;
      s = {Slot::Var, dae_.add_var(std::move(d)), Expr()};
      computed_.push_back(i);
    } else if (v.variability == ast::Variability::Parameter) {
      declare_parameter(i, info);
    } else if (v.top_level_input) {
      const auto k = static_cast<std::int32_t>(dae_.inputs.size());
      s = {Slot::Value, none, dae_.arena.symbol(v.name, SymbolRole::Input, k)};
      dae_.inputs.push_back({info, s.value});
    } else if (discrete_.contains(i)) {
      declare_discrete(i, info);
    } else {
      DaeVar d;
      d.info = info;
      d.state_select = v.attr.state_select;
      d.range = v.range;
      s = {Slot::Var, dae_.add_var(std::move(d)), Expr()};
    }
  }

  /// Variable i as a discrete variable (its start value is set with the
  /// other attributes).
  void declare_discrete(int i, const VariableInfo& info) {
    const auto k = static_cast<std::int32_t>(dae_.discrete.size());
    Slot& s = slots_[static_cast<std::size_t>(i)];
    s = {Slot::Value, none, dae_.arena.symbol(fv(i).name, SymbolRole::Discrete, k)};
    dae_.discrete.push_back({info, s.value, 0.0});
  }

  /// Whether parameter i is computed by the initial equations or its binding
  /// reads, at any depth, one that is.
  bool reads_computed_parameter(int i) {
    auto& known = reads_computed_[i];  // inserted as false: a cycle reads nothing more
    if (computed_parameter(fv(i))) return known = true;
    if (!fv(i).binding) return false;
    std::vector<const ast::Expr*> todo{fv(i).binding.get()};
    while (!todo.empty()) {
      const ast::Expr* x = todo.back();
      todo.pop_back();
      if (x->var >= 0 && fv(x->var).variability == ast::Variability::Parameter) {
        const auto it = reads_computed_.find(x->var);
        if (it != reads_computed_.end() ? it->second : reads_computed_parameter(x->var)) return known = true;
      }
      for (const auto& a : x->args) if (a) todo.push_back(a.get());
      for (const auto& n : x->named) if (n.value) todo.push_back(n.value.get());
      for (const auto& row : x->rows) for (const auto& a : row) if (a) todo.push_back(a.get());
    }
    return false;
  }

  /// A Real parameter with a literal value becomes a parameter symbol; one
  /// bound to an expression of other parameters is inlined when referenced.
  void declare_parameter(int i, const VariableInfo& info) {
    const flat::Variable& v = fv(i);
    const bool literal = !v.binding || v.binding->kind == ast::ExprKind::Real ||
                         v.binding->kind == ast::ExprKind::Integer;
    if (!literal) return;  // Slot stays Unset: converted on first reference
    if (!v.value)
      diags_.report(DiagId::ParameterWithoutValue, v.range,
                    "parameter '" + v.name + "' has no value; using 0");
    const auto k = static_cast<std::int32_t>(dae_.parameters.size());
    const Expr sym = dae_.arena.symbol(v.name, SymbolRole::Parameter, k);
    slots_[static_cast<std::size_t>(i)] = {Slot::Value, none, sym};
    dae_.parameters.push_back({info, sym, v.value.value_or(0.0)});
  }

  Expr ref(const ast::Expr& r) {
    Slot& s = slots_[static_cast<std::size_t>(r.var)];
    if (s.kind == Slot::Var) return dae_.vars[static_cast<std::size_t>(s.var)].symbol;
    if (s.kind == Slot::Value) return s.value;
    if (in_progress_.contains(r.var))
      return conv_->fail(r, "parameter '" + fv(r.var).name + "' depends on itself");
    if (fv(r.var).type == flat::BaseType::String)
      return conv_->fail(r, "String parameter '" + fv(r.var).name + "' cannot be used in an equation");
    in_progress_.insert(r.var);
    const Expr value = conv_->convert(*fv(r.var).binding);
    in_progress_.erase(r.var);
    s = {Slot::Value, none, value};
    return value;
  }

  Expr der(const ast::Expr& x) {
    const Expr e = conv_->convert(x);
    bool input_hit = false;
    const Expr d = time_derivative(dae_, e, input_hit, in_initial_);
    if (input_hit)
      error(DiagId::DifferentiatedInput, x.range,
            "der() of an expression with an input: inputs cannot be differentiated");
    return d;
  }

  /// Evaluates an attribute expression at the default parameter values.
  std::optional<double> value_of(Expr e) {
    if (dae_.arena.is_constant(e)) return dae_.arena.constant_value(e);
    try {
      return evaluate(dae_.arena, std::span(&e, 1), param_values_)[0];
    } catch (const std::invalid_argument&) {
      return std::nullopt;
    }
  }

  void attributes(int i) {
    const flat::Variable& v = fv(i);
    const Slot& s = slots_[static_cast<std::size_t>(i)];
    const flat::Attributes& at = v.attr;
    auto number = [&](const ast::ExprPtr& p, double fallback) {
      if (!p) return fallback;
      return value_of(conv_->convert(*p)).value_or(fallback);
    };
    VariableInfo* info = nullptr;
    if (s.kind == Slot::Var) info = &dae_.vars[static_cast<std::size_t>(s.var)].info;
    if (s.kind == Slot::Value && info_of_.contains(s.value)) info = info_of_.at(s.value);
    if (!info) return;
    if (s.kind == Slot::Value && dae_.arena.kind(s.value) == ExprKind::Symbol &&
        dae_.arena.symbol_info(s.value).role == SymbolRole::Discrete)
      dae_.discrete[static_cast<std::size_t>(dae_.arena.symbol_info(s.value).index)].start =
          number(at.start, 0.0);
    info->nominal = std::abs(number(at.nominal, 1.0));
    if (info->nominal == 0.0) info->nominal = 1.0;
    info->min = number(at.min, info->min);
    info->max = number(at.max, info->max);
    if (s.kind != Slot::Var) return;
    DaeVar& d = dae_.vars[static_cast<std::size_t>(s.var)];
    d.start_given = at.start != nullptr;
    d.start_guess = at.start != nullptr && v.start_by_user;
    d.start = at.start ? conv_->convert(*at.start) : dae_.arena.constant(0.0);
    // fixed = true of an Integer or Boolean variable (the MSL's friction
    // `mode`, `startForward`) fixes pre(v) = start, which the discrete reset
    // gives: it is not an equation of the continuous initial system.
    d.fixed = v.type == flat::BaseType::Real && number(at.fixed, 0.0) != 0.0;
  }

  /// The discrete flag `initial()` reads (made on first use, start 0).
  Expr initial_flag() {
    if (dae_.initial_flag < 0) {
      dae_.initial_flag = static_cast<std::int32_t>(dae_.discrete.size());
      const Expr s = dae_.arena.symbol("initial()", SymbolRole::Discrete, dae_.initial_flag);
      dae_.discrete.push_back({{"initial()", "true during initialisation", ""}, s, 0.0});
    }
    return dae_.discrete[static_cast<std::size_t>(dae_.initial_flag)].symbol;
  }

  /// The discrete variable `e` refers to, or a null Expr.
  Expr discrete_ref(const ast::Expr& e) const {
    if (e.kind != ast::ExprKind::Ref || e.var < 0) return {};
    const Slot& s = slots_[static_cast<std::size_t>(e.var)];
    if (s.kind != Slot::Value || dae_.arena.kind(s.value) != ExprKind::Symbol ||
        dae_.arena.symbol_info(s.value).role != SymbolRole::Discrete)
      return {};
    return s.value;
  }

  void equation(const ast::Equation& eq);
  void computed_parameters();
  void initial_equations();
  bool discrete_initial_assignment(const ast::Equation& eq);
  bool initial_pre(const ast::Equation& eq);
  bool initial_through_pre(const ast::Equation& eq);
  const ast::Expr* pre_definition(int v);
  void solve_pre_values();
  void if_equation(const ast::Equation& eq);
  std::optional<std::vector<Expr>> if_residuals(const ast::Equation& eq);
  void when_equation(const ast::Equation& eq);
  void when_clause(const ast::Expr& condition, const ast::EquationBranch& branch, std::int32_t group,
                   std::int32_t index);
  bool branches_assign_alike(std::size_t first) const;
  /// The assignments of an if-equation inside a when-clause, as `v =
  /// if c1 then e1 elseif ... else en` per variable; false (reported) unless
  /// every branch, an else included, assigns the same variables.
  bool when_if(const ast::Equation& eq, std::map<std::int32_t, std::pair<Expr, Expr>>& out);
  /// The text of a String literal or of a String parameter bound to one; empty otherwise.
  std::string string_value(const ast::Expr* e) const;
  void outputs();

  const flat::Model& f_;
  frontend::DiagnosticEngine& diags_;
  Dae dae_;
  std::vector<Slot> slots_;
  std::unordered_set<int> discrete_;
  /// see mark_event_equations(); true if the variable is on the left
  std::unordered_map<const ast::Equation*, bool> event_equations_;
  std::unordered_set<int> in_progress_;
  std::vector<int> computed_;  ///< Real parameters declared fixed = false
  std::vector<PreEquation> pre_eqs_;  ///< initial equations on pre() values
  struct PreLinks {
    std::unordered_map<int, std::vector<int>> equal;        ///< a = b between variables
    std::unordered_map<int, const ast::Expr*> defines;      ///< every-event right sides
  };
  std::optional<PreLinks> pre_links_;  ///< pre_definition()'s, built on first use
  std::optional<ExprConverter> conv_;
  LeafValues param_values_;  ///< default value of every parameter symbol
  std::unordered_map<Expr, VariableInfo*, ExprHash> info_of_;  ///< parameter/input/discrete info
  std::int32_t when_groups_ = 0;  ///< when-equations seen (WhenClause::group)
  std::unordered_map<int, bool> reads_computed_;  ///< reads_computed_parameter(), memoised
  bool ok_ = true;
  bool in_initial_ = false;  ///< converting the initial equations (der() placeholders)
};

void Builder::equation(const ast::Equation& eq) {
  switch (eq.kind) {
  case ast::EquationKind::Simple: {
    if (const auto it = event_equations_.find(&eq); it != event_equations_.end()) {
      DaeWhen w;
      w.condition = dae_.arena.constant(1.0);
      w.every_event = true;
      w.range = eq.range;
      const ast::Expr& target = it->second ? *eq.lhs : *eq.rhs;
      w.assignments.push_back({ref(target), conv_->convert(it->second ? *eq.rhs : *eq.lhs)});
      dae_.whens.push_back(std::move(w));
      return;
    }
    DaeEq e;
    e.residual = dae_.arena.sub(conv_->convert(*eq.lhs), conv_->convert(*eq.rhs));
    e.range = eq.range;
    if (eq.lhs->kind == ast::ExprKind::Ref && eq.lhs->var >= 0 &&
        slots_[static_cast<std::size_t>(eq.lhs->var)].kind == Slot::Var)
      e.lhs_var = slots_[static_cast<std::size_t>(eq.lhs->var)].var;
    dae_.eqs.push_back(e);
    return;
  }
  case ast::EquationKind::If: if_equation(eq); return;
  case ast::EquationKind::When: when_equation(eq); return;
  case ast::EquationKind::Call: {
    const std::string n = eq.lhs->ref.str();
    if (n == "assert") return;  // checked by the front end's balance only; see README
    error(DiagId::UnsupportedInLowering, eq.range, "'" + n + "' equations cannot be lowered");
    return;
  }
  case ast::EquationKind::Connect:
  case ast::EquationKind::For:
  case ast::EquationKind::Constraint: break;
  }
  error(DiagId::UnsupportedInLowering, eq.range,
        "this equation should have been expanded by flattening");
}

/// A Real parameter computed by the initial equations (computed_parameter())
/// keeps the value the initial system gives it: der(p) = 0 in the model,
/// its start value Newton's guess.
void Builder::computed_parameters() {
  for (int i : computed_) {
    const int v = slots_[static_cast<std::size_t>(i)].var;
    DaeEq e;
    e.residual = dae_.vars[static_cast<std::size_t>(dae_.derivative_of(v))].symbol;
    e.range = fv(i).range;
    dae_.eqs.push_back(e);
  }
}

/// if c1 then A elseif c2 then B else C end if, every branch with the same
/// number of simple equations: residual_i = if c1 then a_i else if c2 ...
/// The initial equations as residuals. der(v) of a variable the model's
/// equations do not differentiate becomes a placeholder that the initial
/// system defines (Dae::initial_derivatives): the model gains no unknown.
void Builder::initial_equations() {
  in_initial_ = true;
  for (const ast::Equation& eq : f_.initial_equations) {
    switch (eq.kind) {
    case ast::EquationKind::Simple: {
      if (computes_discrete_parameter(eq) >= 0 && discrete_initial_assignment(eq)) continue;
      std::int32_t p = free_start_parameter(*eq.lhs, f_);
      if (p < 0) p = free_start_parameter(*eq.rhs, f_);
      if (p >= 0) {  // a parameter computed at initialisation: not supported
        diags_.report(DiagId::ParameterWithoutValue, eq.range,
                      "parameter '" + fv(p).name + "' is declared fixed = false: parameters "
                      "computed by initial equations are not supported, so this initial "
                      "equation is ignored and the parameter keeps its value");
        continue;
      }
      if (initial_pre(eq) || initial_through_pre(eq) || discrete_initial_assignment(eq)) continue;
      DaeEq e;
      e.residual = dae_.arena.sub(conv_->convert(*eq.lhs), conv_->convert(*eq.rhs));
      e.range = eq.range;
      dae_.initial_eqs.push_back(e);
      continue;
    }
    case ast::EquationKind::Call:
      if (eq.lhs->ref.str() == "assert") continue;
      break;
    case ast::EquationKind::If:
    case ast::EquationKind::When:
    case ast::EquationKind::Connect:
    case ast::EquationKind::For:
    case ast::EquationKind::Constraint: break;
    }
    error(DiagId::UnsupportedInLowering, eq.range,
          "only simple equations (lhs = rhs) are supported in an initial equation section");
  }
  solve_pre_values();
}

/// `d = expr` (or `expr = d`) of a discrete variable d in an initial section
/// (an `initial algorithm` assignment): discrete variables are not unknowns
/// of the continuous initial system, so it becomes `when initial() then d =
/// expr; end when`, fired by the event at initialisation in source order (a
/// later assignment sees the value an earlier one gave).
bool Builder::discrete_initial_assignment(const ast::Equation& eq) {
  Expr target = discrete_ref(*eq.lhs);
  const ast::Expr* value = eq.rhs.get();
  if (!target.valid()) {
    target = discrete_ref(*eq.rhs);
    value = eq.lhs.get();
  }
  if (!target.valid()) return false;
  DaeWhen w;
  w.condition = initial_flag();
  w.range = eq.range;
  w.assignments.push_back({target, conv_->convert(*value)});
  dae_.whens.push_back(std::move(w));
  return true;
}

/// `pre(v) = expr` (or `expr = pre(v)`) in an initial section, v Boolean,
/// Integer or discrete. Modelica 3 §8.6: pre(v) at initialisation is the value
/// before the event at initialisation, an unknown of the initial system that
/// this equation fixes, as `fixed = true` fixes it to v.start. For a discrete
/// v it sets the value pre(v) (and v until the event at initialisation)
/// starts from, like a start value, solved with the other equations on
/// pre() values after the section (solve_pre_values; MathBoolean.OnDelay's
/// `pre(t_next) = time - 1`, StateGraph's `pre(newActive) =
/// pre(localActive)`). A v that stays continuous has no
/// pre() read anywhere (mark_event_equations), so there is nothing to fix and
/// the equation is dropped. Returns false for other equations.
bool Builder::initial_pre(const ast::Equation& eq) {
  auto is_pre = [](const ast::Expr& e) {
    return e.kind == ast::ExprKind::Call && e.ref.str() == "pre" && e.args.size() == 1 &&
           e.args[0]->kind == ast::ExprKind::Ref && e.args[0]->var >= 0;
  };
  const ast::Expr* call = eq.lhs.get();
  const ast::Expr* value = eq.rhs.get();
  if (!is_pre(*call)) std::swap(call, value);
  if (!is_pre(*call)) return false;
  const flat::Variable& v = fv(call->args[0]->var);
  const Expr d = discrete_ref(*call->args[0]);
  if (!d.valid())
    return v.type == flat::BaseType::Boolean || v.type == flat::BaseType::Integer ||
           v.variability == ast::Variability::Discrete;
  pre_eqs_.push_back({conv_->convert(*call), conv_->convert(*value), eq.range});
  return true;
}

/// `v = expr` (or `expr = v`) in an initial section, v Boolean, Integer or
/// discrete, not assigned by a when-clause, and equal (through equations
/// `a = b` between variables) to a variable whose every-event equation reads
/// only pre() values, parameters and time: the equation fixes those pre()
/// values (InitialStep of the MSL's StateGraph: `active = true` with `active =
/// localActive` and `localActive = pre(newActive)`). Returns false for other
/// equations.
bool Builder::initial_through_pre(const ast::Equation& eq) {
  for (const bool left : {true, false}) {
    const ast::Expr& side = left ? *eq.lhs : *eq.rhs;
    if (side.kind != ast::ExprKind::Ref || side.var < 0) continue;
    const ast::Expr* def = pre_definition(side.var);
    if (!def) continue;
    const Expr defined = conv_->convert(*def);
    bool pre_only = true;
    for (const Expr leaf : leaves(dae_.arena, std::span(&defined, 1))) {
      const ExprKind k = dae_.arena.kind(leaf);
      if (k == ExprKind::Constant || k == ExprKind::Pre || leaf == dae_.time) continue;
      if (k != ExprKind::Symbol || !param_values_.contains(leaf)) pre_only = false;
    }
    if (!pre_only) continue;
    pre_eqs_.push_back({defined, conv_->convert(left ? *eq.rhs : *eq.lhs), eq.range});
    return true;
  }
  return false;
}

/// The right side of the every-event equation of `v` or of a variable equal
/// to it through equations `a = b` between variables, if exactly one of them
/// has one; null otherwise (or if a when-clause assigns one of them).
const ast::Expr* Builder::pre_definition(int v) {
  const flat::Variable& var = fv(v);
  if (var.type != flat::BaseType::Boolean && var.type != flat::BaseType::Integer &&
      var.variability != ast::Variability::Discrete)
    return nullptr;
  if (!pre_links_) {  // once: equations `a = b` between variables, every-event right sides
    pre_links_.emplace();
    for (const ast::Equation& eq : f_.equations)
      if (eq.kind == ast::EquationKind::Simple && eq.lhs->kind == ast::ExprKind::Ref && eq.lhs->var >= 0 &&
          eq.rhs->kind == ast::ExprKind::Ref && eq.rhs->var >= 0) {
        pre_links_->equal[eq.lhs->var].push_back(eq.rhs->var);
        pre_links_->equal[eq.rhs->var].push_back(eq.lhs->var);
      }
    for (const auto& [eq, target_left] : event_equations_)
      pre_links_->defines[(target_left ? eq->lhs : eq->rhs)->var] = (target_left ? eq->rhs : eq->lhs).get();
  }
  auto& equal = pre_links_->equal;
  const auto& defines = pre_links_->defines;
  std::unordered_set<int> seen{v};
  std::vector<int> work{v};
  const ast::Expr* found = nullptr;
  while (!work.empty()) {
    const int u = work.back();
    work.pop_back();
    if (discrete_.contains(u) && !defines.contains(u)) return nullptr;  // a when-clause's
    if (const auto it = defines.find(u); it != defines.end()) {
      if (found) return nullptr;
      found = it->second;
    }
    for (const int w : equal[u])
      if (seen.insert(w).second) work.push_back(w);
  }
  return found;
}

/// The pre() values that the initial equations fix (solve_initial_pre).
void Builder::solve_pre_values() {
  if (pre_eqs_.empty()) return;
  LeafValues at_t0 = param_values_;  // the event at initialisation runs at t = 0
  at_t0[dae_.time] = 0.0;
  std::vector<bool> boolean(dae_.discrete.size(), false);
  for (std::size_t i = 0; i < f_.variables.size(); ++i) {
    const Slot& s = slots_[i];
    if (s.kind == Slot::Value && dae_.arena.kind(s.value) == ExprKind::Symbol &&
        dae_.arena.symbol_info(s.value).role == SymbolRole::Discrete &&
        f_.variables[i].type == flat::BaseType::Boolean)
      boolean[static_cast<std::size_t>(dae_.arena.symbol_info(s.value).index)] = true;
  }
  if (!solve_initial_pre(dae_, pre_eqs_, at_t0, boolean, diags_)) ok_ = false;
}

void Builder::if_equation(const ast::Equation& eq) {
  const std::optional<std::vector<Expr>> rs = if_residuals(eq);
  if (!rs) return;
  for (const Expr r : *rs) {
    DaeEq e;
    e.residual = r;
    e.range = eq.range;
    dae_.eqs.push_back(e);
  }
}

/// The residuals of an if-equation with a time-varying condition (Modelica 3
/// §8.3.4): equation i of every branch, as `lhs - rhs`, becomes
/// `select(c1, r1_i, select(c2, r2_i, ... r_else_i))`. A nested if-equation
/// contributes its own residuals in place (IdealSwitchWithArc's `if off then
/// if quenched then ... else ... end if; else ... end if`); asserts are
/// skipped as elsewhere. Every branch must have as many equations and there
/// must be an else branch. Returns nullopt after a diagnostic.
std::optional<std::vector<Expr>> Builder::if_residuals(const ast::Equation& eq) {
  std::vector<std::vector<Expr>> branch_residuals;
  for (const auto& br : eq.branches) {
    std::vector<Expr> rs;
    for (const ast::Equation& s : br.body) {
      if (s.kind == ast::EquationKind::Simple) {
        rs.push_back(dae_.arena.sub(conv_->convert(*s.lhs), conv_->convert(*s.rhs)));
      } else if (s.kind == ast::EquationKind::If) {
        const std::optional<std::vector<Expr>> inner = if_residuals(s);
        if (!inner) return std::nullopt;
        rs.insert(rs.end(), inner->begin(), inner->end());
      } else if (s.kind == ast::EquationKind::Call && s.lhs->ref.str() == "assert") {
        continue;
      } else {
        error(DiagId::UnsupportedInLowering, s.range,
              "only equations `lhs = rhs` and if-equations are supported inside an "
              "if-equation with a time-varying condition");
        return std::nullopt;
      }
    }
    branch_residuals.push_back(std::move(rs));
  }
  const bool has_else = !eq.branches.empty() && !eq.branches.back().condition;
  for (const auto& rs : branch_residuals)
    if (rs.size() != branch_residuals.front().size() || !has_else) {
      error(DiagId::UnsupportedInLowering, eq.range,
            "an if-equation with a time-varying condition needs an else branch and the "
            "same number of equations in every branch");
      return std::nullopt;
    }
  std::vector<Expr> out;
  for (std::size_t i = 0; i < branch_residuals.front().size(); ++i) {
    Expr r = branch_residuals.back()[i];
    for (std::size_t b = eq.branches.size() - 1; b-- > 0;)
      r = dae_.arena.select(conv_->convert(*eq.branches[b].condition), branch_residuals[b][i], r);
    out.push_back(r);
  }
  return out;
}

/// `when {c1, c2, ...}` fires when any element becomes true (Modelica 3
/// §8.3.5): one clause per element with the same body. Elements that become
/// true at one call run the body once each, over the same pre() values, so
/// their assignments agree.
void Builder::when_equation(const ast::Equation& eq) {
  const auto group = when_groups_++;
  const std::size_t first = dae_.whens.size();
  for (std::size_t b = 0; b < eq.branches.size(); ++b) {
    const auto& br = eq.branches[b];
    const auto index = static_cast<std::int32_t>(b);
    if (br.condition->kind == ast::ExprKind::Array) {
      for (const auto& c : br.condition->args) when_clause(*c, br, group, index);
    } else {
      when_clause(*br.condition, br, group, index);
    }
  }
  if (!branches_assign_alike(first)) {
    diags_.report(DiagId::ElsewhenBranchesDiffer, eq.range,
                  "the branches of this when-equation assign different variables, which Modelica forbids "
                  "(§8.3.5.2); as in Scilab's modelicac, every branch whose condition becomes true fires");
    for (std::size_t k = first; k < dae_.whens.size(); ++k) dae_.whens[k].prioritised = false;
  }
}

/// Whether the branches of the when-equation whose clauses are
/// dae_.whens[first, end) assign the same set of variables (reinit() and
/// terminate() are not assignments).
bool Builder::branches_assign_alike(std::size_t first) const {
  std::optional<std::unordered_set<Expr, ExprHash>> assigned_by_first;
  for (std::size_t k = first; k < dae_.whens.size(); ++k) {
    std::unordered_set<Expr, ExprHash> targets;
    for (const Assignment& a : dae_.whens[k].assignments) targets.insert(a.target);
    if (!assigned_by_first) assigned_by_first = std::move(targets);
    else if (targets != *assigned_by_first) return false;
  }
  return true;
}

void Builder::when_clause(const ast::Expr& condition, const ast::EquationBranch& br, std::int32_t group,
                          std::int32_t index) {
  {
    DaeWhen w;
    w.condition = conv_->convert(condition);
    w.range = br.range;
    w.group = group;
    w.branch = index;
    for (const ast::Equation& s : br.body) {
      if (s.kind == ast::EquationKind::Simple && s.lhs->kind == ast::ExprKind::Ref &&
          s.lhs->var >= 0) {
        w.assignments.push_back({ref(*s.lhs), conv_->convert(*s.rhs)});
      } else if (s.kind == ast::EquationKind::Call && s.lhs->ref.str() == "reinit") {
        const ast::Expr& target = *s.lhs->args[0];
        const Slot& slot = slots_[static_cast<std::size_t>(target.var)];
        if (slot.kind != Slot::Var) {
          error(DiagId::UnsupportedInLowering, s.range, "reinit() of a non-continuous variable");
          continue;
        }
        w.reinits.emplace_back(slot.var, conv_->convert(*s.lhs->args[1]));
      } else if (s.kind == ast::EquationKind::Call && s.lhs->ref.str() == "assert") {
        continue;
      } else if (s.kind == ast::EquationKind::Call && s.lhs->ref.str() == "terminate") {
        w.terminates = true;
        w.terminate_message = string_value(s.lhs->args.empty() ? nullptr : s.lhs->args[0].get());
      } else if (std::map<std::int32_t, std::pair<Expr, Expr>> chosen;
                 s.kind == ast::EquationKind::If && when_if(s, chosen)) {
        for (auto& [var, assignment] : chosen) w.assignments.push_back(Assignment{assignment.first, assignment.second});
      } else if (s.kind != ast::EquationKind::If) {
        error(DiagId::UnsupportedInLowering, s.range,
              "only `v = expr`, reinit(x, expr) and if-equations of them are supported inside when-clauses");
      }
    }
    resolve_within_clause(dae_.arena, w);
    dae_.whens.push_back(std::move(w));
  }
}

std::string Builder::string_value(const ast::Expr* e) const {
  if (e && e->kind == ast::ExprKind::String) return e->text;
  if (e && e->kind == ast::ExprKind::Ref && e->var >= 0) {  // a String parameter
    const flat::Variable& v = f_.variables[static_cast<std::size_t>(e->var)];
    if (v.binding && v.binding->kind == ast::ExprKind::String) return v.binding->text;
  }
  return {};
}

bool Builder::when_if(const ast::Equation& eq, std::map<std::int32_t, std::pair<Expr, Expr>>& out) {
  std::vector<std::map<std::int32_t, std::pair<Expr, Expr>>> per_branch;
  for (const auto& br : eq.branches) {
    auto& assigned = per_branch.emplace_back();
    for (const ast::Equation& s : br.body) {
      if (s.kind == ast::EquationKind::Simple && s.lhs->kind == ast::ExprKind::Ref && s.lhs->var >= 0) {
        assigned[s.lhs->var] = {ref(*s.lhs), conv_->convert(*s.rhs)};
      } else if (s.kind == ast::EquationKind::If) {
        std::map<std::int32_t, std::pair<Expr, Expr>> inner;
        if (!when_if(s, inner)) return false;
        for (auto& [var, a] : inner) assigned[var] = a;
      } else if (!(s.kind == ast::EquationKind::Call && s.lhs->ref.str() == "assert")) {
        error(DiagId::UnsupportedInLowering, s.range,
              "only `v = expr` and if-equations of them are supported in an if-equation inside a when-clause");
        return false;
      }
    }
  }
  const bool has_else = !eq.branches.empty() && !eq.branches.back().condition;
  for (const auto& assigned : per_branch) {
    bool same = has_else && assigned.size() == per_branch.front().size();
    for (const auto& [var, a] : assigned) same = same && per_branch.front().count(var);
    if (!same) {
      error(DiagId::UnsupportedInLowering, eq.range,
            "an if-equation inside a when-clause needs an else branch, and every branch must assign "
            "the same variables");
      return false;
    }
  }
  for (const auto& [var, last] : per_branch.back()) {
    Expr value = last.second;
    for (std::size_t b = eq.branches.size() - 1; b-- > 0;)
      value = dae_.arena.select(conv_->convert(*eq.branches[b].condition), per_branch[b].at(var).second, value);
    out[var] = {last.first, value};
  }
  return true;
}

void Builder::outputs() {
  for (std::size_t i = 0; i < f_.variables.size(); ++i) {
    const flat::Variable& v = f_.variables[i];
    if (v.causality != ast::Causality::Output || v.name.find('.') != std::string::npos) continue;
    ast::Expr r(ast::ExprKind::Ref, v.range);
    r.var = static_cast<std::int32_t>(i);
    dae_.outputs.push_back({{v.name, v.description, v.attr.unit}, ref(r)});
  }
}

}  // namespace

std::optional<Dae> build_dae(const flat::Model& flat, frontend::DiagnosticEngine& diags) {
  return Builder(flat, diags).run();
}

}  // namespace mo::symbolic::detail
