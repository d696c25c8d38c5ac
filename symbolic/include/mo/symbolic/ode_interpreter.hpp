// A reference interpreter of an OdeModel: evaluates the steps in order with
// the expression evaluator, solving linear blocks by Gaussian elimination with
// partial pivoting and nonlinear blocks by Newton's method. Slow compared to
// generated code, but independent of it: tests check generated code and the
// lowering against it, and it needs no compiler.
#pragma once

#include <span>
#include <stdexcept>
#include <vector>

#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/ode.hpp"

namespace mo::symbolic {

/// Raised when a block cannot be solved (singular matrix, Newton failure).
class BlockFailure : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Evaluates a model's right-hand side, outputs and start values.
class OdeInterpreter {
public:
  /// Prepares evaluators for every step; `model` must outlive the interpreter.
  explicit OdeInterpreter(const OdeModel& model);

  /// x0(p), one value per state: the initial steps (at t = 0, inputs 0),
  /// then the start expressions. Throws BlockFailure if a block fails.
  std::vector<double> initial_state(std::span<const double> p) const;
  /// der(x) at (t, x, u, p) with discrete variables d (empty: their starts).
  std::vector<double> rhs(double t, std::span<const double> x, std::span<const double> u,
                          std::span<const double> p, std::span<const double> d = {});
  /// Outputs at (t, x, u, p) with discrete variables d.
  std::vector<double> outputs(double t, std::span<const double> x, std::span<const double> u,
                              std::span<const double> p, std::span<const double> d = {});
  /// The value every leaf had in the last rhs()/outputs() call (symbol → value).
  [[nodiscard]] double value(Expr leaf) const;

private:
  void load(double t, std::span<const double> x, std::span<const double> u,
            std::span<const double> p, std::span<const double> d);
  void run_steps() const { run(m_.steps, step_evals_); }
  void run(const std::vector<Step>& steps, const std::vector<std::vector<Evaluator>>& evals) const;
  double eval(const Evaluator& e) const;
  void solve_linear(const EquationBlock& b, const std::vector<Evaluator>& evals, std::size_t index) const;
  void solve_nonlinear(const EquationBlock& b, const std::vector<Evaluator>& evals, std::size_t index) const;

  const OdeModel& m_;
  std::vector<std::vector<Evaluator>> step_evals_;  ///< per step: its expressions
  std::vector<std::vector<Evaluator>> initial_evals_;  ///< per initial step
  // Scratch state of one evaluation (initial_state() is const but solves blocks).
  mutable LeafValues values_;
  mutable std::vector<double> args_, work_;
};

}  // namespace mo::symbolic
