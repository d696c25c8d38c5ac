// The flat model: variables, equations, and its text form.
#include "mo/frontend/flat.hpp"
#include "mo/frontend/printer.hpp"

#include <stdexcept>

namespace mo::frontend::flat {

const char *base_type_text(BaseType t) {
  switch (t) {
  case BaseType::Real: return "Real";
  case BaseType::Integer: return "Integer";
  case BaseType::Boolean: return "Boolean";
  case BaseType::String: return "String";
  }
  return "Real";
}

std::int32_t Model::add(Variable v) {
  auto id = static_cast<std::int32_t>(variables.size());
  if (!index.emplace(v.name, id).second)
    throw std::logic_error("internal error: flat variable '" + v.name + "' added twice");
  variables.push_back(std::move(v));
  return id;
}

std::int32_t Model::find(const std::string &name) const {
  auto it = index.find(name);
  return it == index.end() ? -1 : it->second;
}

std::size_t equation_count(const ast::Equation &eq) {
  switch (eq.kind) {
  case ast::EquationKind::Simple:
    return 1;
  case ast::EquationKind::If: {
    std::size_t n = 0;
    if (!eq.branches.empty())
      for (const auto &x : eq.branches[0].body) n += equation_count(x);
    return n;
  }
  case ast::EquationKind::When: {
    // A when-clause defines the variables it assigns (reinit defines none).
    std::size_t n = 0;
    if (!eq.branches.empty())
      for (const auto &x : eq.branches[0].body)
        if (x.kind != ast::EquationKind::Call) n += equation_count(x);
    return n;
  }
  case ast::EquationKind::Connect:
  case ast::EquationKind::For:
  case ast::EquationKind::Call:
  case ast::EquationKind::Constraint:
    return 0;
  }
  return 0;
}

namespace {

class FlatPrinter {
public:
  explicit FlatPrinter(const Model &m) : m_(m) {
    namer_ = [this](std::int32_t v) { return m_.variables[v].name; };
  }

  std::string run() {
    bool opt = m_.optimization.has_value();
    out_ += (opt ? "optimization " : "class ") + quote_name(m_.name);
    if (opt) optimization_header();
    out_ += "\n";
    for (std::int32_t v : declaration_order())
      if (!opt || v != m_.optimization->free_final_time) // declared by the header
        declaration(m_.variables[v]);
    section("equation", m_.equations);
    section("initial equation", m_.initial_equations);
    if (opt) section("constraint", m_.optimization->constraints);
    out_ += "end " + quote_name(m_.name) + ";\n";
    return out_;
  }

private:
  const Model &m_;
  VarNamer namer_;
  std::string out_;

  std::string ex(const ast::Expr &e) { return print_expr(e, namer_); }

  void optimization_header() {
    const Optimization &o = *m_.optimization;
    std::vector<std::string> parts;
    if (o.objective) parts.push_back("objective = " + ex(*o.objective));
    if (o.objective_integrand) parts.push_back("objectiveIntegrand = " + ex(*o.objective_integrand));
    if (o.start_time) parts.push_back("startTime = " + ex(*o.start_time));
    if (o.free_final_time >= 0) { // finalTime(free = true, min, max, initialGuess)
      const Variable &tf = m_.variables[o.free_final_time];
      std::string text = "finalTime(free = true";
      if (tf.attr.min) text += ", min = " + ex(*tf.attr.min);
      if (tf.attr.max) text += ", max = " + ex(*tf.attr.max);
      if (tf.attr.initial_guess) text += ", initialGuess = " + ex(*tf.attr.initial_guess);
      parts.push_back(text + ")" + (o.final_time ? " = " + ex(*o.final_time) : ""));
    } else if (o.final_time) {
      parts.push_back("finalTime = " + ex(*o.final_time));
    }
    if (parts.empty()) return;
    out_ += "(";
    for (std::size_t i = 0; i < parts.size(); ++i) out_ += (i ? ", " : "") + parts[i];
    out_ += ")";
  }

  /// Parameters first, each after the parameters its binding uses; then the
  /// other variables in declaration order.
  std::vector<std::int32_t> declaration_order() {
    const auto n = static_cast<std::int32_t>(m_.variables.size());
    std::vector<std::int32_t> order;
    std::vector<char> state(n, 0);
    for (std::int32_t root = 0; root < n; ++root) {
      if (m_.variables[root].variability != ast::Variability::Parameter || state[root]) continue;
      // Iterative depth-first post-order over binding dependencies.
      std::vector<std::pair<std::int32_t, bool>> stack{{root, false}};
      while (!stack.empty()) {
        auto [v, expanded] = stack.back();
        stack.pop_back();
        if (expanded) {
          if (state[v] != 2) { state[v] = 2; order.push_back(v); }
          continue;
        }
        if (state[v]) continue;
        state[v] = 1;
        stack.emplace_back(v, true);
        const Variable &var = m_.variables[v];
        std::vector<const ast::Expr *> work;
        if (var.binding) work.push_back(var.binding.get());
        while (!work.empty()) {
          const ast::Expr *x = work.back();
          work.pop_back();
          if (x->kind == ast::ExprKind::Ref && x->var >= 0 && !state[x->var] &&
              m_.variables[x->var].variability == ast::Variability::Parameter)
            stack.emplace_back(x->var, false);
          for (const auto &a : x->args) if (a) work.push_back(a.get());
        }
      }
    }
    for (std::int32_t v = 0; v < n; ++v)
      if (!state[v]) order.push_back(v);
    return order;
  }

  void declaration(const Variable &v) {
    std::string s = "  ";
    if (v.variability == ast::Variability::Parameter) s += "parameter ";
    else if (v.variability == ast::Variability::Constant) s += "constant ";
    else if (v.variability == ast::Variability::Discrete && v.type == BaseType::Real) s += "discrete ";
    if (v.causality == ast::Causality::Input) s += "input ";
    if (v.causality == ast::Causality::Output) s += "output ";
    s += std::string(base_type_text(v.type)) + " " + quote_name(v.name);
    std::vector<std::string> attrs;
    const Attributes &a = v.attr;
    auto add = [&](const char *name, const ast::ExprPtr &e) {
      if (e) attrs.push_back(std::string(name) + " = " + ex(*e));
    };
    add("start", a.start);
    add("fixed", a.fixed);
    add("min", a.min);
    add("max", a.max);
    add("nominal", a.nominal);
    add("free", a.free);
    add("initialGuess", a.initial_guess);
    if (!a.unit.empty()) attrs.push_back("unit = \"" + ast::escape_string(a.unit) + "\"");
    if (!a.display_unit.empty()) attrs.push_back("displayUnit = \"" + ast::escape_string(a.display_unit) + "\"");
    if (!a.quantity.empty()) attrs.push_back("quantity = \"" + ast::escape_string(a.quantity) + "\"");
    if (!a.state_select.empty()) attrs.push_back("stateSelect = StateSelect." + a.state_select);
    if (!attrs.empty()) {
      s += "(";
      for (std::size_t i = 0; i < attrs.size(); ++i) s += (i ? ", " : "") + attrs[i];
      s += ")";
    }
    if (v.binding) s += " = " + ex(*v.binding);
    if (!v.description.empty()) s += " \"" + ast::escape_string(v.description) + "\"";
    if (v.evaluate) s += " annotation(Evaluate = true)";
    out_ += s + ";\n";
  }

  void section(const char *name, const std::vector<ast::Equation> &eqs) {
    if (eqs.empty()) return;
    out_ += std::string(name) + "\n";
    for (const auto &e : eqs) equation(e, 1);
  }

  void equation(const ast::Equation &e, int depth) {
    std::string ind(2 * depth, ' ');
    switch (e.kind) {
    case ast::EquationKind::Simple:
      out_ += ind + ex(*e.lhs) + " = " + ex(*e.rhs) + ";\n";
      return;
    case ast::EquationKind::Constraint:
      out_ += ind + ex(*e.lhs) + (e.rel == ast::Op::Eq ? " = " : std::string(" ") + ast::op_text(e.rel) + " ") +
              ex(*e.rhs) + ";\n";
      return;
    case ast::EquationKind::Call:
      out_ += ind + ex(*e.lhs) + ";\n";
      return;
    case ast::EquationKind::If:
    case ast::EquationKind::When: {
      bool when = e.kind == ast::EquationKind::When;
      for (std::size_t i = 0; i < e.branches.size(); ++i) {
        const auto &b = e.branches[i];
        if (!b.condition) out_ += ind + "else\n";
        else out_ += ind + (i == 0 ? (when ? "when " : "if ") : (when ? "elsewhen " : "elseif ")) +
                     ex(*b.condition) + " then\n";
        for (const auto &x : b.body) equation(x, depth + 1);
      }
      out_ += ind + (when ? "end when;\n" : "end if;\n");
      return;
    }
    case ast::EquationKind::Connect:
    case ast::EquationKind::For:
      throw std::logic_error("internal error: connect/for left in a flat model");
    }
  }
};

} // namespace

std::string Model::print() const { return FlatPrinter(*this).run(); }

} // namespace mo::frontend::flat
