// Bounds on the change of a control between consecutive values (JModelica's
// du_bounds): −d ≤ u_{β+1} − u_β ≤ d for each FreeControl with a finite
// max_change, over its blocks (or, for a per-point control, its points in time
// order). Linear rows: constant Jacobian entries ±1, zero Hessian.
#pragma once

#include "collocation_nlp.hpp"

#include <utility>
#include <vector>

namespace mo::runtime::detail {

/// The rows of experiment e's control-change bounds.
class ControlChanges final : public ConstraintBlock {
public:
  /// One row per pair of consecutive values of every control with a finite max_change.
  ControlChanges(const CollocationNlp& nlp, int e);
  /// True if experiment e has a control with a finite max_change.
  static bool needed(const CollocationNlp& nlp, int e);
  [[nodiscard]] int rows() const override { return static_cast<int>(pairs_.size()); }
  void bounds(std::span<double> lo, std::span<double> hi) const override;
  void values(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  void jacobian(CollocationNlp& nlp, std::span<const double> v, int row0, SparseAssembler& jac) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp&) const override { return true; }
  void hessian(CollocationNlp&, std::span<const double>, std::span<const double>, SparseAssembler&) override {}

private:
  struct Pair {
    int before, after;  // NLP variables u_β, u_{β+1}
    double limit;       // d
  };
  std::vector<Pair> pairs_;
};

}  // namespace mo::runtime::detail
