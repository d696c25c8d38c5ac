// mocompile --emit ast: the AST as an indented tree, one node per line.
#include "mo/frontend/ast.hpp"
#include "mo/frontend/printer.hpp"

namespace mo::frontend::ast {

namespace {

class Dumper {
public:
  std::string out;

  void cls(const ClassDef &c, int depth) {
    line(depth, std::string(c.partial ? "partial " : "") + restriction_text(c.restriction) + " " +
                    quote_name(c.name) + desc(c.description));
    if (c.short_base) {
      std::string s = "= " + c.short_base->str();
      for (auto &d : c.short_dims) s += "[" + print_expr(*d) + "]";
      line(depth + 1, s);
    }
    if (!c.enumeration.empty()) {
      std::string s = "enumeration(";
      for (std::size_t i = 0; i < c.enumeration.size(); ++i) s += (i ? ", " : "") + c.enumeration[i];
      line(depth + 1, s + ")");
    }
    if (!c.class_mod.empty()) line(depth + 1, "modification " + mod(c.class_mod));
    for (auto &i : c.imports) {
      std::string s = "import ";
      if (!i.alias.empty()) s += i.alias + " = ";
      for (std::size_t k = 0; k < i.path.size(); ++k) s += (k ? "." : "") + i.path[k];
      if (i.wildcard) s += ".*";
      line(depth + 1, s);
    }
    for (auto &e : c.extends)
      line(depth + 1, std::string(e.inherited_class ? "extends inherited " : "extends ") + e.base.str() +
                          (e.mod.empty() ? "" : mod(e.mod)));
    for (auto &n : c.classes) cls(*n, depth + 1);
    for (auto &comp : c.components) component(comp, depth + 1);
    section("equation", c.equations, depth + 1);
    section("initial equation", c.initial_equations, depth + 1);
    section("constraint", c.constraints, depth + 1);
    if (c.has_algorithm) line(depth + 1, "algorithm (not flattened)");
    for (auto &a : c.model_algorithms)
      line(depth + 1, std::string(a.initial ? "initial " : "") + "algorithm (" + std::to_string(a.body.size()) +
                          " statements, flattened by execution)");
  }

private:
  static std::string desc(const std::string &d) {
    return d.empty() ? "" : " \"" + escape_string(d) + "\"";
  }
  void line(int depth, const std::string &s) { out += std::string(2 * depth, ' ') + s + "\n"; }

  std::string mod(const Modification &m) {
    std::string s;
    if (!m.args.empty()) {
      s += "(";
      for (std::size_t i = 0; i < m.args.size(); ++i) {
        const ElementMod &a = m.args[i];
        if (i) s += ", ";
        if (a.redeclare) { s += "redeclare ..."; continue; }
        if (a.each) s += "each ";
        if (a.final_) s += "final ";
        for (std::size_t k = 0; k < a.path.size(); ++k) s += (k ? "." : "") + quote_name(a.path[k]);
        s += mod(a.mod);
      }
      s += ")";
    }
    if (m.binding) s += " = " + print_expr(*m.binding);
    return s;
  }

  void component(const Component &c, int depth) {
    std::string s = "component ";
    if (c.is_protected) s += "protected ";
    if (c.final_) s += "final ";
    if (c.inner) s += "inner ";
    if (c.outer) s += "outer ";
    if (c.connection == Connection::Flow) s += "flow ";
    if (c.connection == Connection::Stream) s += "stream ";
    if (c.variability != Variability::Continuous) s += std::string(variability_text(c.variability)) + " ";
    if (c.causality == Causality::Input) s += "input ";
    if (c.causality == Causality::Output) s += "output ";
    s += c.type.str() + " " + quote_name(c.name);
    if (!c.dims.empty()) {
      s += "[";
      for (std::size_t i = 0; i < c.dims.size(); ++i) s += (i ? ", " : "") + print_expr(*c.dims[i]);
      s += "]";
    }
    s += mod(c.mod);
    if (c.condition) s += " if " + print_expr(*c.condition);
    line(depth, s + desc(c.description));
  }

  void section(const char *name, const std::vector<Equation> &eqs, int depth) {
    if (eqs.empty()) return;
    line(depth, name);
    for (auto &e : eqs) equation(e, depth + 1);
  }

  void equation(const Equation &e, int depth) {
    switch (e.kind) {
    case EquationKind::Simple:
      line(depth, print_expr(*e.lhs) + " = " + print_expr(*e.rhs));
      return;
    case EquationKind::Constraint:
      line(depth, print_expr(*e.lhs) + (e.rel == Op::Eq ? " = " : std::string(" ") + op_text(e.rel) + " ") +
                      print_expr(*e.rhs));
      return;
    case EquationKind::Connect:
      line(depth, "connect(" + print_expr(*e.lhs) + ", " + print_expr(*e.rhs) + ")");
      return;
    case EquationKind::Call:
      line(depth, print_expr(*e.lhs));
      return;
    case EquationKind::For: {
      std::string s = "for";
      for (auto &i : e.indices) s += " " + i.name + (i.range ? " in " + print_expr(*i.range) : "");
      line(depth, s);
      for (auto &b : e.body) equation(b, depth + 1);
      return;
    }
    case EquationKind::If:
    case EquationKind::When:
      for (std::size_t i = 0; i < e.branches.size(); ++i) {
        const auto &b = e.branches[i];
        const char *kw = e.kind == EquationKind::If ? (i == 0 ? "if" : b.condition ? "elseif" : "else")
                                                    : (i == 0 ? "when" : "elsewhen");
        line(depth, std::string(kw) + (b.condition ? " " + print_expr(*b.condition) : ""));
        for (auto &x : b.body) equation(x, depth + 1);
      }
      return;
    }
  }
};

} // namespace

std::string dump(const StoredDefinition &sd) {
  Dumper d;
  if (!sd.within.empty()) {
    std::string w = "within ";
    for (std::size_t i = 0; i < sd.within.size(); ++i) w += (i ? "." : "") + sd.within[i];
    d.out += w + "\n";
  }
  for (auto &c : sd.classes) d.cls(*c, 0);
  return d.out;
}

} // namespace mo::frontend::ast
