// OdeModel helpers and its flat-Modelica text form.
#include "mo/symbolic/ode.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>
#include <fmt/format.h>

#include "mo/frontend/ast.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic {

namespace {

template <class Vars>
std::optional<std::size_t> find_named(const Vars& vars, std::string_view name) {
  for (std::size_t i = 0; i < vars.size(); ++i)
    if (vars[i].info.name == name) return i;
  return std::nullopt;
}

/// " \"comment\"" with the comment as an escaped Modelica string, or "".
std::string comment(const VariableInfo& info) {
  if (info.description.empty()) return {};
  std::string out = " \"";
  for (char c : info.description) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "1e308" : "-1e308";
  return fmt::format("{}", v);
}

/// Subexpressions the printed equations share are written once each, as an
/// equation of a variable of their own, when writing them out at every use
/// would repeat at least this many nodes: the text of a lowered model that
/// shares values (a function's intermediates, a block's Jacobian) stays in
/// proportion to its graph instead of growing with the number of paths.
constexpr std::size_t kSharedTerms = 100;

/// Text of the model's expressions with its shared subexpressions' names.
struct Writer {
  const ExprArena& arena;
  ExprNames names;
  std::vector<Expr> shared;   ///< named nodes of the equations, operands before users
  std::vector<Expr> initial;  ///< named nodes only the initial system's steps use

  /// `e`'s text: its name if it has one.
  std::string text(Expr e) const {
    if (const auto it = names.find(e); it != names.end()) return it->second;
    return definition(e);
  }
  /// `e` written out, its shared subexpressions (not `e`) by their names.
  std::string definition(Expr e) const {
    std::string out;
    append_modelica(arena, e, out, names);
    return out;
  }
  /// Declared types of the variables that differ from Real (assignment targets).
  std::unordered_map<Expr, ValueType, ExprHash> types;
  /// `value` as the right-hand side of `target = value` in the target's type.
  std::string value_text(Expr target, Expr value) const {
    const auto it = types.find(target);
    return typed_text(value, it == types.end() ? ValueType::Real : it->second);
  }
  /// `e` as a value of `type`, through if-expressions: a Boolean's constants
  /// as false and true (the arena holds them as 0 and 1), an Integer's
  /// floor(x), which `integer(x)` lowers to, as integer(x) (floor is Real).
  std::string typed_text(Expr e, ValueType type) const {
    if (type == ValueType::Real || names.contains(e)) return text(e);
    if (type == ValueType::Boolean && arena.is_constant(e)) return arena.constant_value(e) != 0.0 ? "true" : "false";
    if (type == ValueType::Integer && arena.kind(e) == ExprKind::Floor)
      return "integer(" + text(arena.operand(e, 0)) + ")";
    if (arena.kind(e) == ExprKind::Select)
      return "if " + text(arena.operand(e, 0)) + " then " + typed_text(arena.operand(e, 1), type) + " else " +
             typed_text(arena.operand(e, 2), type);
    return text(e);
  }
};

/// True if a node of kind `k` is a Boolean (printed as a relation), given
/// which of its first three operands are.
bool boolean_kind(ExprKind k, const bool (&operand)[3]) {
  switch (k) {
  case ExprKind::Lt:
  case ExprKind::Le:
  case ExprKind::Gt:
  case ExprKind::Ge:
  case ExprKind::Eq:
  case ExprKind::Ne:
  case ExprKind::And:
  case ExprKind::Or:
  case ExprKind::Not: return true;
  case ExprKind::Select: return operand[1];
  case ExprKind::NoEvent: return operand[0];
  default: return false;
  }
}

/// Names `$cseK` for the Real subexpressions of `equations` and `initial`
/// used more than once whose text, with the names chosen below them, has
/// kSharedTerms nodes or more. Names already taken by `taken` are skipped.
Writer shared_terms(const ExprArena& a, std::vector<Expr> equations, std::span<const Expr> initial,
                    const std::unordered_set<std::string>& taken) {
  Writer w{a, {}, {}, {}};
  const std::vector<Expr> in_equations = topological_order(a, equations, LeafOperands::Visit);
  std::vector<Expr> roots = std::move(equations);
  roots.insert(roots.end(), initial.begin(), initial.end());
  const std::vector<Expr> order = topological_order(a, roots, LeafOperands::Visit);
  std::unordered_map<Expr, std::size_t, ExprHash> index;
  for (std::size_t i = 0; i < order.size(); ++i) index.emplace(order[i], i);
  std::vector<std::size_t> uses(order.size(), 0), size(order.size(), 1);
  std::vector<bool> boolean(order.size(), false);
  for (Expr r : roots) ++uses[index.at(r)];
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::size_t n = arity(a.kind(order[i]));
    for (std::size_t k = 0; k < n; ++k) ++uses[index.at(a.operand(order[i], k))];
  }
  std::size_t next = 1;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Expr e = order[i];
    const ExprKind k = a.kind(e);
    const std::size_t n = arity(k);
    bool operand_boolean[3] = {false, false, false};
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t o = index.at(a.operand(e, j));
      size[i] = std::min<std::size_t>(size[i] + (w.names.contains(order[o]) ? 1 : size[o]), 1u << 30);
      if (j < 3) operand_boolean[j] = boolean[o];
    }
    boolean[i] = boolean_kind(k, operand_boolean);
    if (uses[i] < 2 || size[i] < kSharedTerms || boolean[i] || a.is_leaf(e) ||
        k == ExprKind::External)
      continue;
    std::string name;
    do name = "$cse" + std::to_string(next++);
    while (taken.contains(name));
    w.names.emplace(e, modelica_name(name));
    // The initial system's own symbols ($init) are not variables of the model.
    const bool equation = std::binary_search(in_equations.begin(), in_equations.end(), e);
    (equation ? w.shared : w.initial).push_back(e);
  }
  return w;
}

void print_step(const Writer& w, const Step& step, std::string& out) {
  if (const auto* a = std::get_if<Assignment>(&step)) {
    out += "  " + w.text(a->target) + " = " + w.value_text(a->target, a->value) + ";\n";
    return;
  }
  const auto& b = std::get<EquationBlock>(step);
  out += fmt::format("  // {} block of {} equation{} for", b.linear ? "linear" : "nonlinear",
                     b.unknowns.size(), b.unknowns.size() == 1 ? "" : "s");
  for (Expr z : b.unknowns) out += " " + w.text(z);
  out += "\n";
  for (Expr r : b.residuals) out += "  0 = " + w.text(r) + ";\n";
}

/// True if output `y` is just the unknown of the same name (printed as an
/// `output` prefix on that unknown's declaration instead of twice).
bool is_self_output(const ExprArena& a, const OdeOutput& y) {
  return a.kind(y.value) == ExprKind::Symbol && a.symbol_info(y.value).name == y.info.name;
}

std::string prefix_of(const OdeModel& m, Expr symbol) {
  for (const auto& y : m.outputs)
    if (y.value == symbol && is_self_output(m.arena, y)) return "output ";
  return {};
}

/// The attribute list "(start = .., fixed = .., nominal = .., min = .., max = ..)",
/// `start` through the Writer, which names a large start value's shared parts
/// (a robot's start angles through its kinematic chain).
std::string attributes(const Writer& w, const VariableInfo& info, Expr start, std::optional<bool> fixed) {
  std::vector<std::string> parts;
  if (start.valid()) parts.push_back("start = " + w.text(start));
  if (fixed) parts.push_back(*fixed ? "fixed = true" : "fixed = false");
  if (info.nominal != 1.0) parts.push_back("nominal = " + number(info.nominal));
  if (std::isfinite(info.min)) parts.push_back("min = " + number(info.min));
  if (std::isfinite(info.max)) parts.push_back("max = " + number(info.max));
  if (parts.empty()) return {};
  return "(" + fmt::format("{}", fmt::join(parts, ", ")) + ")";
}

std::string_view type_name(const VariableInfo& info) {
  switch (info.type) {
  case ValueType::Integer: return "Integer";
  case ValueType::Boolean: return "Boolean";
  case ValueType::Real: break;
  }
  return "Real";
}

/// A start value in the variable's type: false and true for a Boolean.
std::string typed_number(const VariableInfo& info, double v) {
  if (info.type == ValueType::Boolean) return v != 0.0 ? "true" : "false";
  return number(v);
}

void print_declarations(const OdeModel& m, const Writer& w, std::string& out) {
  for (const auto& p : m.parameters)
    out += fmt::format("  parameter Real {}{} = {}{};\n", modelica_name(p.info.name),
                       attributes(w, p.info, Expr(), std::nullopt), number(p.value),
                       comment(p.info));
  for (const auto& u : m.inputs)
    out += fmt::format("  input {} {}{};\n", type_name(u.info), modelica_name(u.info.name), comment(u.info));
  for (const auto& x : m.states)
    out += fmt::format("  {}Real {}{}{};\n", prefix_of(m, x.symbol), modelica_name(x.info.name),
                       attributes(w, x.info, x.start, x.fixed), comment(x.info));
  for (const auto& z : m.algebraics)
    out += fmt::format("  {}{} {}{}{};\n", prefix_of(m, z.symbol), type_name(z.info), modelica_name(z.info.name),
                       attributes(w, z.info, Expr(), std::nullopt), comment(z.info));
  for (std::size_t i = 0; i < m.discrete.size(); ++i) {
    const OdeDiscrete& d = m.discrete[i];
    if (static_cast<std::int32_t>(i) == m.initial_flag) continue;  // printed as initial()
    if (d.info.name.starts_with("sample(")) continue;  // printed as the call
    out += fmt::format("  discrete {} {}(start = {}){};\n", type_name(d.info), modelica_name(d.info.name),
                       typed_number(d.info, d.start), comment(d.info));
  }
  for (const auto& y : m.outputs)
    if (!is_self_output(m.arena, y))
      out += fmt::format("  output {} {}{};\n", type_name(y.info), modelica_name(y.info.name), comment(y.info));
}

/// The clauses [first, last) of m.whens that print as one when-equation:
/// those after `first` of its group (elsewhen branches and the elements of a
/// vector condition, adjacent as the lowering keeps them).
std::size_t when_equation_end(const OdeModel& m, std::size_t first) {
  std::size_t last = first + 1;
  const WhenClause& w = m.whens[first];
  if (w.every_event || w.group < 0) return last;
  while (last < m.whens.size() && !m.whens[last].every_event && m.whens[last].group == w.group) ++last;
  return last;
}

void print_clause_body(const Writer& t, const OdeModel& m, const WhenClause& w, std::string& out) {
  for (const auto& s : w.assignments)
    out += "    " + t.text(s.target) + " = " + t.value_text(s.target, s.value) + ";\n";
  for (const auto& r : w.reinits)
    out += "    reinit(" + modelica_name(m.states[r.state].info.name) + ", " + t.text(r.value) +
           ");\n";
  if (w.terminates) out += "    terminate(\"" + frontend::ast::escape_string(w.terminate_message) + "\");\n";
}

/// m.whens[first, last) as `when c then ... elsewhen ... end when;`, a branch
/// of several clauses (a vector condition) as `{c1, c2}`.
void print_when(const Writer& t, const OdeModel& m, std::size_t first, std::size_t last, std::string& out) {
  const WhenClause& w0 = m.whens[first];
  if (w0.every_event) {  // printed back as the equation it came from
    for (const auto& s : w0.assignments)
      out += "  " + t.text(s.target) + " = " + t.value_text(s.target, s.value) + ";\n";
    return;
  }
  for (std::size_t i = first; i < last;) {
    std::size_t j = i + 1;
    while (j < last && m.whens[j].branch == m.whens[i].branch) ++j;
    std::string condition = t.text(m.whens[i].condition);
    if (j > i + 1) {
      condition = "{" + condition;
      for (std::size_t k = i + 1; k < j; ++k) condition += ", " + t.text(m.whens[k].condition);
      condition += "}";
    }
    out += (i == first ? "  when " : "  elsewhen ") + condition + " then\n";
    print_clause_body(t, m, m.whens[i], out);
    i = j;
  }
  out += "  end when;\n";
}

/// Appends what `steps` compute: assigned values, block residuals, offsets
/// and Jacobian entries.
void append_step_expressions(const std::vector<Step>& steps, std::vector<Expr>& out) {
  for (const Step& step : steps) {
    if (const auto* a = std::get_if<Assignment>(&step)) {
      out.push_back(a->value);
      continue;
    }
    const auto& b = std::get<EquationBlock>(step);
    out.insert(out.end(), b.residuals.begin(), b.residuals.end());
    out.insert(out.end(), b.offset.begin(), b.offset.end());
    for (const auto& entry : b.jacobian) out.push_back(entry.value);
  }
}

}  // namespace

std::vector<Expr> OdeModel::equation_expressions() const {
  std::vector<Expr> roots;
  append_step_expressions(steps, roots);
  for (const auto& y : outputs) roots.push_back(y.value);
  return roots;
}

std::vector<Expr> OdeModel::event_expressions() const {
  std::vector<Expr> roots(zero_crossings);
  for (const WhenClause& w : whens) {
    roots.push_back(w.condition);
    for (const Assignment& a : w.assignments) roots.push_back(a.value);
    for (const Reinit& r : w.reinits) roots.push_back(r.value);
  }
  return roots;
}

std::optional<std::size_t> OdeModel::parameter_index(std::string_view n) const {
  return find_named(parameters, n);
}

std::optional<std::size_t> OdeModel::state_index(std::string_view n) const {
  return find_named(states, n);
}

std::vector<bool> OdeModel::inputs_in_initial_system() const {
  std::vector<Expr> roots;
  for (const auto& s : states)
    if (s.start.valid()) roots.push_back(s.start);
  append_step_expressions(initial_steps, roots);
  std::vector<bool> out(inputs.size(), false);
  for (Expr leaf : leaves(arena, roots)) {
    if (arena.kind(leaf) != ExprKind::Symbol) continue;
    const SymbolInfo& info = arena.symbol_info(leaf);
    if (info.role == SymbolRole::Input && info.index >= 0 && std::size_t(info.index) < out.size())
      out[std::size_t(info.index)] = true;
  }
  return out;
}

std::size_t OdeModel::num_base_states() const {
  std::size_t n = 0;
  for (const auto& x : states) n += x.sensitivity ? 0 : 1;
  return n;
}

namespace {

/// The expressions `steps` print: targets, values, unknowns, residuals.
std::vector<Expr> printed_expressions(const std::vector<Step>& steps) {
  std::vector<Expr> roots;
  for (const Step& s : steps) {
    if (const auto* as = std::get_if<Assignment>(&s)) {
      roots.insert(roots.end(), {as->target, as->value});
      continue;
    }
    const auto& b = std::get<EquationBlock>(s);
    roots.insert(roots.end(), b.unknowns.begin(), b.unknowns.end());
    roots.insert(roots.end(), b.residuals.begin(), b.residuals.end());
  }
  return roots;
}

/// What print_ode() writes as expressions of the model, bar start values:
/// steps, outputs, when-clauses, eliminated variables.
std::vector<Expr> printed_expressions(const OdeModel& m) {
  std::vector<Expr> roots = printed_expressions(m.steps);
  for (const auto& y : m.outputs) roots.push_back(y.value);
  for (const WhenClause& w : m.whens) {
    roots.push_back(w.condition);
    for (const auto& s : w.assignments) roots.insert(roots.end(), {s.target, s.value});
    for (const auto& r : w.reinits) roots.push_back(r.value);
  }
  for (const auto& e : m.eliminated) roots.push_back(e.value);
  return roots;
}

/// Every name the printed model declares.
std::unordered_set<std::string> declared_names(const OdeModel& m) {
  std::unordered_set<std::string> out;
  for (const auto& p : m.parameters) out.insert(p.info.name);
  for (const auto& u : m.inputs) out.insert(u.info.name);
  for (const auto& x : m.states) out.insert(x.info.name);
  for (const auto& z : m.algebraics) out.insert(z.info.name);
  for (const auto& d : m.discrete) out.insert(d.info.name);
  for (const auto& y : m.outputs) out.insert(y.info.name);
  return out;
}

}  // namespace

std::string print_ode(const OdeModel& m) {
  const ExprArena& a = m.arena;
  std::vector<Expr> initial = printed_expressions(m.initial_steps);
  for (const auto& x : m.states)
    if (x.start.valid()) initial.push_back(x.start);
  Writer w = shared_terms(a, printed_expressions(m), initial, declared_names(m));
  for (const auto& z : m.algebraics)
    if (z.info.type != ValueType::Real) w.types.emplace(z.symbol, z.info.type);
  for (const auto& d : m.discrete)
    if (d.info.type != ValueType::Real) w.types.emplace(d.symbol, d.info.type);
  std::string out = "model " + modelica_name(m.name) + "\n";
  print_declarations(m, w, out);
  for (Expr e : w.shared)
    out += "  Real " + w.names.at(e) + " \"a subexpression the equations share\";\n";
  // Shared parts of start values over parameters alone are parameters;
  // those that read the initial system's unknowns ($init) go with its comment.
  std::vector<Expr> of_init;
  for (Expr e : w.initial) {
    const auto from = leaves(a, std::span(&e, 1));
    const bool parameters_only = std::all_of(from.begin(), from.end(), [&](Expr l) {
      return a.kind(l) == ExprKind::Symbol && a.symbol_info(l).role == SymbolRole::Parameter;
    });
    if (!parameters_only) {
      of_init.push_back(e);
      continue;
    }
    out += "  parameter Real " + w.names.at(e) + " = " + w.definition(e) +
           " \"a subexpression the start values share\";\n";
  }
  if (!m.initial_steps.empty() || !of_init.empty()) {
    // Comments: the $init symbols are not variables of the printed model.
    std::string init;
    for (Expr e : of_init) init += "  " + w.names.at(e) + " = " + w.definition(e) + ";\n";
    for (const Step& s : m.initial_steps) print_step(w, s, init);
    out += "  // initial system, solved at t0 before the start values that use its $init(...) unknowns:\n";
    for (std::size_t i = 0; i < init.size();) {
      const std::size_t end = init.find('\n', i);
      out += "  //" + init.substr(i, end - i) + "\n";
      i = end == std::string::npos ? init.size() : end + 1;
    }
  }
  out += "equation\n";
  for (Expr e : w.shared) out += "  " + w.names.at(e) + " = " + w.definition(e) + ";\n";
  for (const Step& s : m.steps) print_step(w, s, out);
  for (const auto& y : m.outputs)
    if (!is_self_output(a, y))
      out += "  " + modelica_name(y.info.name) + " = " +
             w.typed_text(y.value, y.info.type) + ";\n";
  for (std::size_t k = 0; k < m.whens.size();) {
    const std::size_t end = when_equation_end(m, k);
    print_when(w, m, k, end, out);
    k = end;
  }
  if (!m.eliminated.empty()) {
    out += "  // eliminated variables, recoverable for results:\n";
    for (const auto& e : m.eliminated)
      out += "  //   " + modelica_name(e.info.name) + " = " + w.text(e.value) + "\n";
  }
  out += "end " + modelica_name(m.name) + ";\n";
  return out;
}

std::string summary(const OdeModel& m) {
  std::size_t assignments = 0, linear = 0, nonlinear = 0, largest = 0;
  for (const Step& s : m.steps) {
    if (std::holds_alternative<Assignment>(s)) {
      ++assignments;
      continue;
    }
    const auto& b = std::get<EquationBlock>(s);
    (b.linear ? linear : nonlinear) += 1;
    largest = std::max(largest, b.unknowns.size());
  }
  return fmt::format(
      "{} states ({} sensitivity), {} algebraics, {} inputs, {} parameters, {} outputs, "
      "{} discrete; {} assignments, {} linear and {} nonlinear blocks (largest {}); "
      "{} zero crossings, {} when-clauses, {} eliminated",
      m.states.size(), m.states.size() - m.num_base_states(), m.algebraics.size(),
      m.inputs.size(), m.parameters.size(), m.outputs.size(), m.discrete.size(), assignments,
      linear, nonlinear, largest, m.zero_crossings.size(), m.whens.size(), m.eliminated.size());
}

}  // namespace mo::symbolic
