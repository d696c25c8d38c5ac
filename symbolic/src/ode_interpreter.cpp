// Reference interpreter of lowered models; see ode_interpreter.hpp.
#include "mo/symbolic/ode_interpreter.hpp"

#include <cmath>
#include <fmt/format.h>

namespace mo::symbolic {

namespace {

/// Solves A z = b in place (A row-major n×n); false if A is singular.
bool gauss_solve(std::vector<double>& A, std::vector<double>& b) {
  const std::size_t n = b.size();
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t piv = k;
    for (std::size_t i = k + 1; i < n; ++i)
      if (std::abs(A[i * n + k]) > std::abs(A[piv * n + k])) piv = i;
    if (A[piv * n + k] == 0.0 || !std::isfinite(A[piv * n + k])) return false;
    if (piv != k) {
      for (std::size_t j = 0; j < n; ++j) std::swap(A[k * n + j], A[piv * n + j]);
      std::swap(b[k], b[piv]);
    }
    for (std::size_t i = k + 1; i < n; ++i) {
      const double f = A[i * n + k] / A[k * n + k];
      if (f == 0.0) continue;
      for (std::size_t j = k; j < n; ++j) A[i * n + j] -= f * A[k * n + j];
      b[i] -= f * b[k];
    }
  }
  for (std::size_t k = n; k-- > 0;) {
    double s = b[k];
    for (std::size_t j = k + 1; j < n; ++j) s -= A[k * n + j] * b[j];
    b[k] = s / A[k * n + k];
  }
  return true;
}

}  // namespace

namespace {

std::vector<std::vector<Evaluator>> step_evaluators(const ExprArena& arena, const std::vector<Step>& steps) {
  std::vector<std::vector<Evaluator>> out;
  for (const Step& s : steps) {
    std::vector<Evaluator> evals;
    if (const auto* a = std::get_if<Assignment>(&s)) {
      evals.emplace_back(arena, std::span(&a->value, 1));
    } else {
      const auto& b = std::get<EquationBlock>(s);
      for (const BlockEntry& e : b.jacobian) evals.emplace_back(arena, std::span(&e.value, 1));
      const auto& rest = b.linear ? b.offset : b.residuals;
      for (const Expr& r : rest) evals.emplace_back(arena, std::span(&r, 1));
    }
    out.push_back(std::move(evals));
  }
  return out;
}

}  // namespace

OdeInterpreter::OdeInterpreter(const OdeModel& model)
    : m_(model), step_evals_(step_evaluators(model.arena, model.steps)),
      initial_evals_(step_evaluators(model.arena, model.initial_steps)) {}

std::vector<double> OdeInterpreter::initial_state(std::span<const double> p) const {
  values_.clear();
  values_[m_.time] = 0.0;
  for (const auto& u : m_.inputs) values_[u.symbol] = 0.0;
  for (std::size_t k = 0; k < m_.parameters.size(); ++k) values_[m_.parameters[k].symbol] = p[k];
  for (const auto& d : m_.discrete) values_[d.symbol] = d.start;
  run(m_.initial_steps, initial_evals_);
  std::vector<double> out;
  for (const auto& s : m_.states) out.push_back(eval(Evaluator(m_.arena, std::span(&s.start, 1))));
  return out;
}

void OdeInterpreter::load(double t, std::span<const double> x, std::span<const double> u,
                          std::span<const double> p, std::span<const double> d) {
  values_[m_.time] = t;
  for (std::size_t i = 0; i < m_.states.size(); ++i) values_[m_.states[i].symbol] = x[i];
  for (std::size_t i = 0; i < m_.inputs.size(); ++i) values_[m_.inputs[i].symbol] = u[i];
  for (std::size_t i = 0; i < m_.parameters.size(); ++i) values_[m_.parameters[i].symbol] = p[i];
  for (std::size_t i = 0; i < m_.discrete.size(); ++i) {
    values_[m_.discrete[i].symbol] = d.empty() ? m_.discrete[i].start : d[i];
  }
}

double OdeInterpreter::eval(const Evaluator& e) const {
  args_.clear();
  for (Expr l : e.leaves()) {
    // pre(d) between events equals d.
    const Expr key = m_.arena.kind(l) == ExprKind::Pre ? m_.arena.operand(l, 0) : l;
    const auto it = values_.find(key);
    args_.push_back(it == values_.end() ? 0.0 : it->second);
  }
  double out = 0;
  e.evaluate(args_, std::span(&out, 1), work_);
  return out;
}

void OdeInterpreter::solve_linear(const EquationBlock& b, const std::vector<Evaluator>& evals,
                                  std::size_t index) const {
  const std::size_t n = b.unknowns.size();
  std::vector<double> A(n * n, 0.0), rhs(n);
  for (std::size_t k = 0; k < b.jacobian.size(); ++k)
    A[b.jacobian[k].row * n + b.jacobian[k].col] = eval(evals[k]);
  for (std::size_t i = 0; i < n; ++i) rhs[i] = -eval(evals[b.jacobian.size() + i]);
  if (!gauss_solve(A, rhs))
    throw BlockFailure(fmt::format("singular linear block of {} equations (step {})", n, index));
  for (std::size_t i = 0; i < n; ++i) values_[b.unknowns[i]] = rhs[i];
}

void OdeInterpreter::solve_nonlinear(const EquationBlock& b, const std::vector<Evaluator>& evals,
                                     std::size_t index) const {
  const std::size_t n = b.unknowns.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!values_.contains(b.unknowns[i])) values_[b.unknowns[i]] = b.start[i];
  for (int iter = 0; iter < 50; ++iter) {
    std::vector<double> A(n * n, 0.0), r(n);
    double norm = 0;
    for (std::size_t i = 0; i < n; ++i) {
      r[i] = -eval(evals[b.jacobian.size() + i]);
      norm = std::max(norm, std::abs(r[i]));
    }
    if (norm < 1e-12) return;
    for (std::size_t k = 0; k < b.jacobian.size(); ++k)
      A[b.jacobian[k].row * n + b.jacobian[k].col] = eval(evals[k]);
    if (!gauss_solve(A, r)) break;
    for (std::size_t i = 0; i < n; ++i) values_[b.unknowns[i]] += r[i];
  }
  throw BlockFailure(fmt::format("Newton failed on a nonlinear block of {} equations (step {})",
                                 n, index));
}

void OdeInterpreter::run(const std::vector<Step>& steps,
                         const std::vector<std::vector<Evaluator>>& evals) const {
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (const auto* a = std::get_if<Assignment>(&steps[i])) {
      values_[a->target] = eval(evals[i][0]);
      continue;
    }
    const auto& b = std::get<EquationBlock>(steps[i]);
    if (b.linear)
      solve_linear(b, evals[i], i);
    else
      solve_nonlinear(b, evals[i], i);
  }
}

std::vector<double> OdeInterpreter::rhs(double t, std::span<const double> x,
                                        std::span<const double> u, std::span<const double> p,
                                        std::span<const double> d) {
  load(t, x, u, p, d);
  run_steps();
  std::vector<double> out;
  for (const auto& s : m_.states) out.push_back(values_.at(s.derivative));
  return out;
}

std::vector<double> OdeInterpreter::outputs(double t, std::span<const double> x,
                                            std::span<const double> u,
                                            std::span<const double> p,
                                            std::span<const double> d) {
  load(t, x, u, p, d);
  run_steps();
  std::vector<double> out;
  for (const auto& y : m_.outputs) {
    Evaluator e(m_.arena, std::span(&y.value, 1));
    out.push_back(eval(e));
  }
  return out;
}

double OdeInterpreter::value(Expr leaf) const { return values_.at(leaf); }

}  // namespace mo::symbolic
