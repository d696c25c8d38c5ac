// Bounds on algebraic variables and outputs as path constraints; see
// study_problem.hpp (add_bound_constraints).
#include <algorithm>
#include <cmath>
#include <string>

#include "study_problem.hpp"

namespace mo::tools {

namespace ast = frontend::ast;
namespace flat = frontend::flat;

namespace {

/// The constant value of an attribute, or `fallback` when it is unset or not constant.
double attribute_or(const flat::Model& m, const ast::ExprPtr& attr, double fallback) {
  if (!attr) return fallback;
  return constant_value(m, *attr).value_or(fallback);
}

}  // namespace

void add_bound_constraints(flat::Model& m, ProblemOutputs& out) {
  const std::size_t n = m.variables.size();  // the outputs added below are not visited
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const flat::Variable& v = m.variables[i];
    if (v.type != flat::BaseType::Real || v.variability != ast::Variability::Continuous ||
        !v.is_unknown())
      continue;
    ProblemConstraint c;
    c.lo = attribute_or(m, v.attr.min, c.lo);
    c.hi = attribute_or(m, v.attr.max, c.hi);
    if (std::isinf(c.lo) && std::isinf(c.hi)) continue;
    c.range = v.range;
    c.bounded_variable = v.name;
    c.output = "$bounds[" + std::to_string(++count) + "]";  // outputs are undotted names
    auto ref = ast::make_ref(v.name, v.range);
    ref->var = static_cast<std::int32_t>(i);
    flat::Variable y;
    y.name = c.output;
    y.causality = ast::Causality::Output;
    y.range = v.range;
    y.description = "min/max of " + v.name + ", added by mocompile for the optimization problem";
    const auto range = v.range;  // m.add may move the variables: `v` dangles after it
    const std::int32_t index = m.add(std::move(y));
    ast::Equation eq;
    eq.kind = ast::EquationKind::Simple;
    eq.range = range;
    eq.lhs = ast::make_ref(c.output, range);
    eq.lhs->var = index;
    eq.rhs = std::move(ref);
    m.equations.push_back(std::move(eq));
    out.constraints.push_back(std::move(c));
  }
}

void drop_state_bounds(ProblemOutputs& out, const std::vector<std::string>& states) {
  std::erase_if(out.constraints, [&](const ProblemConstraint& c) {
    return !c.bounded_variable.empty() &&
           std::find(states.begin(), states.end(), c.bounded_variable) != states.end();
  });
}

}  // namespace mo::tools
