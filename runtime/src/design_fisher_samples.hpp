// The measurement samples of an input design and the quadratic forms of their
// sensitivities (used by the lifted Fisher rows and by the T criterion on the
// trajectory):
//   Q_G(v) = Σ_k Σ_r w_r s_r(z_k)ᵀ G s_r(z_k),   G symmetric (n × n),
// s_r = ∂y_r/∂p (the model outputs d(y_r)/d(p_a)) at the collocation point z_k
// of measurement time t_k, w_r = 1/σ_r². With J_r = ∂s_r/∂z,
//   ∇_z Q_G  = Σ_r w_r 2 J_rᵀ G s_r,
//   ∇²_z Q_G = Σ_r w_r [2 J_rᵀ G J_r + ∇²_z(μ_rᵀ h)],  μ_r,a = 2 (G s_r)_a on
// the outputs d(y_r)/d(p_a): block-diagonal per sample, with the model's
// generated Hessian of μᵀh.
#pragma once

#include "collocation_nlp.hpp"
#include "mo/runtime/design.hpp"

namespace mo::runtime::detail {

/// The model outputs d(y_r)/d(p_a) for every measured output r and parameter a,
/// indexed [r][a]; nullopt if the model lacks one of them.
std::optional<std::vector<std::vector<std::size_t>>> sensitivity_outputs(
    const ModelInfo& info, const MeasurementDesign& m, const std::vector<std::size_t>& parameters);

/// s_r(z_k) at the measurement times of experiment 0, and Q_G's derivatives.
class FisherSamples {
public:
  /// Throws ProblemError for no outputs or parameters, σ ≤ 0 or a time outside [t0, tf].
  FisherSamples(const CollocationNlp& nlp, const MeasurementDesign& m,
                std::vector<std::vector<std::size_t>> sensitivity_outputs);
  /// Number of parameters n.
  [[nodiscard]] int size() const { return n_; }
  /// Σ_k Σ_r w_r s_r s_rᵀ at v.
  [[nodiscard]] Eigen::MatrixXd fisher(CollocationNlp& nlp, std::span<const double> v) const;
  /// The columns (z-indices, ascending) that s_ra or s_rb depend on for some r.
  [[nodiscard]] std::vector<int> columns(int a, int b) const;
  /// Per sample k, calls f(k's point, s (r × a), J = ∂y/∂z (all outputs × z)).
  template <class F>
  void each_sample(CollocationNlp& nlp, std::span<const double> v, F&& f) const {
    for (const PointRef& pt : points_) f(pt, sensitivities(nlp, v, pt), nlp.output_jacobian(v, pt));
  }
  /// ∂/∂z (Σ_r w_r s_ra s_rb) at one sample, over `cols` = columns(a, b).
  [[nodiscard]] Eigen::VectorXd product_gradient(const Eigen::MatrixXd& s, const Eigen::MatrixXd& j,
                                                 int a, int b, const std::vector<int>& cols) const;
  /// The Gauss–Newton positions (c, d) in deps (c ≥ d) that Q_G can couple
  /// when G's pattern is `coupled` (pairs (a, b), a ≥ b, of parameters).
  void set_pattern(const std::vector<std::pair<int, int>>& coupled);
  /// Adds scale·∇²_v Q_G (lower triangle) on the pattern of set_pattern().
  void add_hessian(CollocationNlp& nlp, std::span<const double> v, const Eigen::MatrixXd& g,
                   double scale, SparseAssembler& hess) const;

private:
  Eigen::MatrixXd sensitivities(CollocationNlp& nlp, std::span<const double> v,
                                const PointRef& pt) const;
  /// ∂s_r/∂z over deps_ (n × |deps|).
  Eigen::MatrixXd sensitivity_jacobian(const Eigen::MatrixXd& j, std::size_t r) const;

  std::vector<PointRef> points_;
  std::vector<double> weight_;                   // 1/σ_r²
  std::vector<std::vector<std::size_t>> sens_;   // [r][a] → output index
  std::vector<int> deps_;                        // z-indices the s outputs depend on
  std::vector<std::vector<std::vector<int>>> of_;  // [r][a]: positions in deps_ of s_ra's dependencies
  std::vector<std::pair<int, int>> gn_pairs_;    // positions (c ≥ d) in deps_ of the Gauss–Newton term
  std::size_t num_outputs_ = 0;
  int n_ = 0;
};

}  // namespace mo::runtime::detail
