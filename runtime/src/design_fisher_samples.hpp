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
///
/// Every sensitivity s_r is handled on its own columns: in a multi-phase
/// design one point carries the samples of all phases as outputs r, each
/// depending on its own phase's states, so nothing here is dense over the
/// union of the columns (the cost is linear in the outputs r).
class FisherSamples {
public:
  /// Throws ProblemError for no outputs or parameters, σ ≤ 0 or a time outside [t0, tf].
  FisherSamples(const CollocationNlp& nlp, const MeasurementDesign& m,
                std::vector<std::vector<std::size_t>> sensitivity_outputs);
  /// Number of parameters n.
  [[nodiscard]] int size() const { return n_; }
  /// Σ_k Σ_r w_r s_r s_rᵀ at v.
  [[nodiscard]] Eigen::MatrixXd fisher(CollocationNlp& nlp, std::span<const double> v) const;
  /// The columns (z-indices, ascending) that s_ra or s_rb depend on for some r (a ≥ b).
  [[nodiscard]] const std::vector<int>& columns(int a, int b) const { return columns_[packed(a, b)]; }
  /// ∂s_r/∂z per output r at one sample: n × (r's own columns, see local_).
  using LocalJacobians = std::vector<Eigen::MatrixXd>;
  /// Per sample k, calls f(k's point, s (r × a), the LocalJacobians of k).
  template <class F>
  void each_sample(CollocationNlp& nlp, std::span<const double> v, F&& f) const {
    for (const PointRef& pt : points_) f(pt, sensitivities(nlp, v, pt), local_jacobians(nlp, v, pt));
  }
  /// ∂/∂z (Σ_r w_r s_ra s_rb) at one sample, over columns(a, b) (a ≥ b).
  [[nodiscard]] Eigen::VectorXd product_gradient(const Eigen::MatrixXd& s, const LocalJacobians& j, int a,
                                                 int b) const;
  /// The Gauss–Newton positions (c, d) in deps (c ≥ d) that Q_G can couple
  /// when G's pattern is `coupled` (pairs (a, b), a ≥ b, of parameters).
  void set_pattern(const std::vector<std::pair<int, int>>& coupled);
  /// Adds scale·∇²_v Q_G (lower triangle) on the pattern of set_pattern().
  void add_hessian(CollocationNlp& nlp, std::span<const double> v, const Eigen::MatrixXd& g,
                   double scale, SparseAssembler& hess) const;

private:
  /// One Gauss–Newton entry of output r: its index in gn_pairs_ and the
  /// positions of its two columns in local_[r].
  struct LocalPair {
    std::size_t pair;
    int c, d;
  };
  [[nodiscard]] static std::size_t packed(int a, int b) { return std::size_t(a * (a + 1) / 2 + b); }
  Eigen::MatrixXd sensitivities(CollocationNlp& nlp, std::span<const double> v,
                                const PointRef& pt) const;
  LocalJacobians local_jacobians(CollocationNlp& nlp, std::span<const double> v, const PointRef& pt) const;
  /// Fills columns_ and in_columns_ from local_ and of_.
  void index_columns();

  std::vector<PointRef> points_;
  std::vector<double> weight_;                   // 1/σ_r²
  std::vector<std::vector<std::size_t>> sens_;   // [r][a] → output index
  std::vector<int> deps_;                        // z-indices the s outputs depend on
  std::vector<std::vector<int>> local_;          // [r]: z-indices s_r depends on (ascending)
  std::vector<std::vector<std::vector<int>>> of_;  // [r][a]: positions in local_[r] of s_ra's dependencies
  std::vector<std::vector<int>> columns_;        // [packed (a, b)]: columns(a, b)
  std::vector<std::vector<std::vector<int>>> in_columns_;  // [packed][r]: local_[r]'s positions in columns_
  std::vector<std::pair<int, int>> gn_pairs_;    // positions (c ≥ d) in deps_ of the Gauss–Newton term
  std::vector<std::vector<LocalPair>> gn_local_;  // [r]: r's entries of gn_pairs_
  std::size_t num_outputs_ = 0;
  int n_ = 0;
};

}  // namespace mo::runtime::detail
