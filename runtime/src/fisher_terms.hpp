// The Fisher information of a collocation solution and the design criteria
// built on it (see mo/runtime/design.hpp). For a symmetric weight G,
//   d tr(G F) = Σ_k 2 tr(G S_kᵀ W dS_k),  S_k = H_x S_x + H_p  (measured rows),
// so with Λ_k = 2 W S_k G: ∂/∂S_x = H_xᵀ Λ_k, and the dependence of H_x, H_p on
// z = (x, u, p) contributes Σ_j ∇²_z(Λ_k(:,j)ᵀ h)·(S_x(:,j); 0; e_{p_j}), by a
// central difference of the output Jacobians along that direction (exactly
// zero when h is affine in x and p, the usual case of measured states).
#pragma once

#include "collocation_nlp.hpp"
#include "mo/runtime/design.hpp"

namespace mo::runtime::detail {

/// [base state i][j] → the state ∂x_i/∂p_j of `parameters[j]`, −1 where the
/// model has none (structurally zero).
std::vector<std::vector<int>> sensitivity_state_map(const ModelInfo& info, const std::vector<std::size_t>& parameters);
/// Whether every parameter has a sensitivity state (FisherEvaluator's need):
/// a multi-phase model has its phases' sensitivities as outputs only.
bool has_sensitivity_states(const ModelInfo& info, const std::vector<std::size_t>& parameters);

/// F(v) and ∇_v tr(G F(v)) at the measurement points of experiment 0.
class FisherEvaluator {
public:
  /// Throws ProblemError if a sensitivity state, output or time is missing/out of range.
  FisherEvaluator(const CollocationNlp& nlp, MeasurementDesign measurements,
                  std::vector<std::size_t> parameters);
  [[nodiscard]] Eigen::MatrixXd fisher(CollocationNlp& nlp, std::span<const double> v) const;
  /// Adds ∇_v tr(G F) to `grad`, G symmetric |J| × |J|.
  void add_gradient(CollocationNlp& nlp, std::span<const double> v, const Eigen::MatrixXd& g,
                    std::span<double> grad) const;
  /// Every variable that F can depend on, ascending.
  [[nodiscard]] const std::vector<int>& variables() const { return variables_; }
  [[nodiscard]] int size() const { return int(parameters_.size()); }

private:
  struct Sample {
    PointRef point;
    Eigen::MatrixXd s_x;  // base states × J
    Eigen::MatrixXd h_x, h_p, s_y;  // measured rows
    std::vector<double> x, u, p;
  };
  Sample evaluate(CollocationNlp& nlp, std::span<const double> v, const PointRef& pt) const;
  Eigen::VectorXd curvature(CollocationNlp& nlp, const Sample& s, const Eigen::VectorXd& mu,
                            std::size_t j) const;

  MeasurementDesign m_;
  std::vector<std::size_t> parameters_;
  std::vector<PointRef> points_;
  std::vector<std::vector<int>> sensitivity_state_;  // [base state][j] → state index
  std::vector<int> variables_;
  std::size_t base_states_ = 0;
};

/// A, T or D criterion as an objective to minimise.
class FisherCriterion final : public ObjectiveTerm {
public:
  FisherCriterion(std::shared_ptr<const FisherEvaluator> fisher, DesignCriterion criterion)
      : fisher_(std::move(fisher)), criterion_(criterion) {}
  double value(CollocationNlp& nlp, std::span<const double> v) override;
  void gradient(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp&) const override { return false; }
  void hessian(CollocationNlp&, std::span<const double>, double, SparseAssembler&) override {}

private:
  std::shared_ptr<const FisherEvaluator> fisher_;
  DesignCriterion criterion_;
};

/// E criterion's rows F_ab − s·δ_ab − (L Lᵀ)_ab = 0, a ≥ b (objective: MaximiseVariable(s)).
class FisherEpigraph final : public ConstraintBlock {
public:
  /// Adds s and L to the NLP, started from F at the NLP's initial guess.
  FisherEpigraph(CollocationNlp& nlp, std::shared_ptr<const FisherEvaluator> fisher);
  [[nodiscard]] int rows() const override;
  void bounds(std::span<double> lo, std::span<double> hi) const override;
  void values(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  void jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                SparseAssembler& jac) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp&) const override { return false; }
  void hessian(CollocationNlp&, std::span<const double>, std::span<const double>,
               SparseAssembler&) override {}
  void scaling(std::span<double> s) const override;
  [[nodiscard]] int epigraph_variable() const { return s_; }

private:
  [[nodiscard]] int l_var(int a, int c) const { return l_ + a * (a + 1) / 2 + c; }
  std::shared_ptr<const FisherEvaluator> fisher_;
  int s_ = 0, l_ = 0;
  double row_scale_ = 1.0;
};

/// The objective −v[var] (maximise one variable).
class MaximiseVariable final : public ObjectiveTerm {
public:
  explicit MaximiseVariable(int var) : var_(std::size_t(var)) {}
  double value(CollocationNlp&, std::span<const double> v) override { return -v[var_]; }
  void gradient(CollocationNlp&, std::span<const double>, std::span<double> g) override {
    g[var_] -= 1.0;
  }
  [[nodiscard]] bool has_hessian(const CollocationNlp&) const override { return true; }
  void hessian(CollocationNlp&, std::span<const double>, double, SparseAssembler&) override {}

private:
  std::size_t var_;
};

}  // namespace mo::runtime::detail
