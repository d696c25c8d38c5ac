// Objective terms and constraints built from model outputs at points:
//   weighted outputs      Σ_q w_q·y_{k_q}(point_q)          (Mayer, Lagrange quadrature)
//   weighted least squares Σ_q Σ_k ((y_k(point_q) − m_qk)/σ_k)²  (NaN m_qk are skipped)
//   output constraints    lo_q ≤ y_{k_q}(point_q) ≤ hi_q      (path and point constraints)
// Derivatives come from h's Jacobians; exact Hessians from ∇²(μᵀh) when the model
// provides it (the least-squares term adds its Gauss–Newton part 2 Jᵀ Σ⁻¹ J).
#pragma once

#include <map>
#include <tuple>

#include "collocation_nlp.hpp"

namespace mo::runtime::detail {

/// One output at one point with a weight or bounds.
struct OutputAtPoint {
  PointRef point;
  std::size_t output = 0;
  double weight = 1.0;
  Bounds bounds;
};

/// Σ_q w_q·y_{k_q}(point_q).
class WeightedOutputs final : public ObjectiveTerm {
public:
  explicit WeightedOutputs(std::vector<OutputAtPoint> terms) : terms_(std::move(terms)) {}
  double value(CollocationNlp& nlp, std::span<const double> v) override;
  void gradient(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp& nlp) const override;
  void hessian(CollocationNlp& nlp, std::span<const double> v, double factor,
               SparseAssembler& hess) override;

private:
  std::vector<OutputAtPoint> terms_;
};

/// One sample of measured outputs: m_k (NaN = missing) with σ_k, at a point.
struct MeasuredSample {
  PointRef point;
  std::vector<double> measured;  ///< per model output; NaN if not measured
  std::vector<double> sigma;     ///< per model output
};

/// Σ over samples and measured outputs of ((y − m)/σ)².
class LeastSquares final : public ObjectiveTerm {
public:
  explicit LeastSquares(std::vector<MeasuredSample> samples) : samples_(std::move(samples)) {}
  double value(CollocationNlp& nlp, std::span<const double> v) override;
  void gradient(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp& nlp) const override;
  void hessian(CollocationNlp& nlp, std::span<const double> v, double factor,
               SparseAssembler& hess) override;

private:
  std::vector<MeasuredSample> samples_;
};

/// lo ≤ y_k(point) ≤ hi, one row per entry.
///
/// Rows at one point share one evaluation of the outputs, of their (sparse)
/// Jacobian and of the model's output Hessian (weighted by all their
/// multipliers): a multi-phase model has many outputs, and each evaluation
/// costs as much as all of them.
class OutputConstraints final : public ConstraintBlock {
public:
  explicit OutputConstraints(std::vector<OutputAtPoint> rows);
  [[nodiscard]] int rows() const override { return static_cast<int>(rows_.size()); }
  void bounds(std::span<double> lo, std::span<double> hi) const override;
  void values(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  void jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                SparseAssembler& jac) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp& nlp) const override;
  void hessian(CollocationNlp& nlp, std::span<const double> v, std::span<const double> lambda,
               SparseAssembler& hess) override;

private:
  std::vector<OutputAtPoint> rows_;
  std::vector<std::vector<std::size_t>> at_point_;  ///< rows_ indices per distinct point
  std::vector<std::vector<int>> dependencies_;  ///< all_output_dependencies(), once needed
};

/// Per output k, the z-indices (x, u, p) on which it depends structurally,
/// ascending (one scan of the output Jacobians' patterns).
std::vector<std::vector<int>> all_output_dependencies(const Model& model);
/// Adds Σ_z grad_z·∂z/∂v to the NLP gradient through the point's variable map.
void add_mapped_gradient(const CollocationNlp& nlp, const PointRef& pt,
                         const Eigen::VectorXd& grad_z, std::span<double> g);

}  // namespace mo::runtime::detail
