// Time scaling for a free final time; see study_time_scaling.hpp.
#include "study_time_scaling.hpp"

#include <algorithm>
#include <vector>

namespace mo::tools {

namespace ast = frontend::ast;
namespace flat = frontend::flat;

namespace {

/// (tf − t0) as a flat expression.
ast::ExprPtr horizon_length(const FreeFinalTime& f, frontend::SourceRange r) {
  auto tf = ast::make_ref(f.parameter, r);
  tf->var = f.var;
  return ast::make_binary(ast::Op::Sub, std::move(tf), ast::make_real(f.start, r), r);
}

bool is_time(const ast::Expr& e) {
  return e.kind == ast::ExprKind::Ref && e.var < 0 && e.ref.is_simple() && e.ref.parts[0].name == "time";
}

bool is_der(const ast::Expr& e) {
  return e.kind == ast::ExprKind::Call && e.ref.is_simple() && e.ref.parts[0].name == "der";
}

/// Rewrites one expression tree (iteratively: trees may be deep).
void scale_expr(ast::ExprPtr& root, const FreeFinalTime& f) {
  std::vector<ast::ExprPtr*> stack{&root};
  while (!stack.empty()) {
    ast::ExprPtr& slot = *stack.back();
    stack.pop_back();
    if (!slot) continue;
    const frontend::SourceRange r = slot->range;
    if (is_der(*slot)) {  // dx/dt = (dx/dτ)/(tf − t0)
      slot = ast::make_binary(ast::Op::Div, std::move(slot), horizon_length(f, r), r);
      continue;
    }
    if (is_time(*slot)) {  // t = t0 + (tf − t0)·τ
      auto scaled = ast::make_binary(ast::Op::Mul, horizon_length(f, r), std::move(slot), r);
      slot = ast::make_binary(ast::Op::Add, ast::make_real(f.start, r), std::move(scaled), r);
      continue;
    }
    for (auto& a : slot->args) stack.push_back(&a);
    for (auto& n : slot->named) stack.push_back(&n.value);
  }
}

/// Rewrites every expression of the equations (branches and bodies included).
void scale_equations(std::vector<ast::Equation>& equations, const FreeFinalTime& f) {
  std::vector<ast::Equation*> stack;
  for (auto& eq : equations) stack.push_back(&eq);
  while (!stack.empty()) {
    ast::Equation& eq = *stack.back();
    stack.pop_back();
    scale_expr(eq.lhs, f);
    scale_expr(eq.rhs, f);
    for (auto& b : eq.body) stack.push_back(&b);
    for (auto& br : eq.branches) {
      scale_expr(br.condition, f);
      for (auto& b : br.body) stack.push_back(&b);
    }
  }
}

ast::ExprPtr* integrand_equation(flat::Model& m, const std::string& output) {
  const std::int32_t var = m.find(output);
  for (auto& eq : m.equations)
    if (eq.kind == ast::EquationKind::Simple && eq.lhs && eq.lhs->kind == ast::ExprKind::Ref &&
        eq.lhs->var == var)
      return &eq.rhs;
  return nullptr;
}

}  // namespace

void scale_time(flat::Model& m, const ProblemOutputs& problem) {
  const FreeFinalTime& f = *problem.free_final_time;
  scale_equations(m.equations, f);
  scale_equations(m.initial_equations, f);
  if (problem.lagrange)
    if (ast::ExprPtr* rhs = integrand_equation(m, *problem.lagrange)) {
      const frontend::SourceRange r = (*rhs)->range;
      *rhs = ast::make_binary(ast::Op::Mul, horizon_length(f, r), std::move(*rhs), r);
    }
}

void bound_final_time(runtime::OptimalControlProblem& p, std::size_t tf_index, double t0) {
  for (auto& fp : p.free_parameters)
    if (fp.parameter == tf_index) fp.bounds.lo = std::max(fp.bounds.lo, t0);
}

namespace {

runtime::ResultTable rescaled(const runtime::ResultTable& t, double t0, double length) {
  runtime::ResultTable out(t.names());
  for (std::size_t k = 0; k < t.rows(); ++k) out.add_row(t0 + length * t.times()[k], t.row(k));
  return out;
}

}  // namespace

void rescale_result(runtime::OptimizationResult& r, double t0, double tf) {
  const double length = tf - t0;
  r.trajectories = rescaled(r.trajectories, t0, length);
  r.check.resimulated = rescaled(r.check.resimulated, t0, length);
  for (double& t : r.element_times) t = t0 + length * t;
  r.check.worst_state_time = t0 + length * r.check.worst_state_time;
  r.check.worst_bound_time = t0 + length * r.check.worst_bound_time;
}

}  // namespace mo::tools
