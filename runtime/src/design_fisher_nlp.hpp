// Input design with the Fisher matrix lifted into the NLP (exact sparse Hessians).
//
// The p(p+1)/2 entries F_ab (a ≥ b) of the Fisher matrix become NLP variables,
// tied to the trajectory by one equality row each:
//   F_ab − Σ_k Σ_r w_r s_ra(z_k) s_rb(z_k) = 0,   w_r = 1/σ_r²,
// where s_ra = ∂y_r/∂p_a is the model output `d(y_r)/d(p_a)` that the compiler
// appends with the sensitivity states, evaluated at the point z_k = (x, u, p)
// of measurement time t_k. The criterion is then a function of the F variables
// alone (dense among those few), and the rows' second derivatives are
// block-diagonal per sample:
//   ∇²(Σ_ab λ_ab g_ab) = −Σ_k Σ_r w_r [2 J_rᵀ Λ J_r + ∇²_z(μ_rᵀ h)],
//   Λ_aa = λ_aa, Λ_ab = Λ_ba = λ_ab/2, J_r = ∂s_r/∂z, μ_r,a = 2(Λ s_r)_a on the
//   outputs d(y_r)/d(p_a),
// with the model's generated Hessian of μᵀh. Criteria on F (docs/study-files.md):
//   A: min tr F⁻¹   T: max tr F   D: max log det F (Cholesky factor of F)
//   E: max t subject to F − tI = LLᵀ (L lower triangular, extra variables).
#pragma once

#include "collocation_nlp.hpp"
#include "design_fisher_samples.hpp"
#include "mo/runtime/design.hpp"

namespace mo::runtime::detail {

/// The F variables and their defining rows F_ab − Σ w s_a s_b = 0 (experiment 0).
class LiftedFisher final : public ConstraintBlock {
public:
  /// Adds the F variables, started from F at the NLP's initial guess (shifted to be
  /// positive definite when `positive_start`). Throws ProblemError on a bad design.
  LiftedFisher(CollocationNlp& nlp, const MeasurementDesign& m,
               std::vector<std::vector<std::size_t>> sensitivity_outputs, bool positive_start);
  [[nodiscard]] int rows() const override { return n_ * (n_ + 1) / 2; }
  void bounds(std::span<double> lo, std::span<double> hi) const override;
  void values(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  void jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                SparseAssembler& jac) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp& nlp) const override;
  void hessian(CollocationNlp& nlp, std::span<const double> v, std::span<const double> lambda,
               SparseAssembler& hess) override;
  void scaling(std::span<double> s) const override;

  /// Σ_k Σ_r w_r s_r s_rᵀ at v (the trajectory's F, not the F variables).
  [[nodiscard]] Eigen::MatrixXd trajectory_fisher(CollocationNlp& nlp, std::span<const double> v) const {
    return samples_.fisher(nlp, v);
  }
  /// The F variables of v as a symmetric matrix.
  [[nodiscard]] Eigen::MatrixXd fisher_variables(std::span<const double> v) const;
  /// Variable of F_ab (either order).
  [[nodiscard]] int f_var(int a, int b) const;
  [[nodiscard]] int size() const { return n_; }
  /// The largest |F_ab| at the start (at least 1).
  [[nodiscard]] double magnitude() const { return magnitude_; }
  /// The scaling magnitude of F_ab: sqrt(|F_aa F_bb|) at the start, floored.
  [[nodiscard]] double nominal(int a, int b) const;

private:
  FisherSamples samples_;
  std::vector<double> nominal_;                  // per F variable (packed)
  int n_ = 0, f_ = 0;
  double magnitude_ = 1.0;
};

/// A, T or D as an objective on the F variables, with its exact dense Hessian.
class FisherVariableCriterion final : public ObjectiveTerm {
public:
  FisherVariableCriterion(const LiftedFisher& fisher, DesignCriterion criterion)
      : fisher_(fisher), criterion_(criterion) {}
  double value(CollocationNlp& nlp, std::span<const double> v) override;
  void gradient(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp&) const override { return true; }
  void hessian(CollocationNlp& nlp, std::span<const double> v, double factor,
               SparseAssembler& hess) override;

private:
  const LiftedFisher& fisher_;
  DesignCriterion criterion_;
};

/// E criterion: rows F_ab − t·δ_ab − (L Lᵀ)_ab = 0 over the F variables; the
/// objective is MaximiseVariable(t).
class FisherVariableEpigraph final : public ConstraintBlock {
public:
  /// Adds t and L, started from the F variables' start (t below λ_min).
  FisherVariableEpigraph(CollocationNlp& nlp, const LiftedFisher& fisher);
  [[nodiscard]] int rows() const override { return n_ * (n_ + 1) / 2; }
  void bounds(std::span<double> lo, std::span<double> hi) const override;
  void values(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  void jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                SparseAssembler& jac) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp&) const override { return true; }
  void hessian(CollocationNlp& nlp, std::span<const double> v, std::span<const double> lambda,
               SparseAssembler& hess) override;
  void scaling(std::span<double> s) const override;
  [[nodiscard]] int epigraph_variable() const { return t_; }

private:
  [[nodiscard]] int l_var(int a, int c) const { return l_ + a * (a + 1) / 2 + c; }
  const LiftedFisher& fisher_;
  int n_ = 0, t_ = 0, l_ = 0;
};

}  // namespace mo::runtime::detail
