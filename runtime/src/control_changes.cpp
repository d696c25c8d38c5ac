// Bounds on the change of a control between consecutive values; see control_changes.hpp.
#include "control_changes.hpp"

#include <cmath>

namespace mo::runtime::detail {

bool ControlChanges::needed(const CollocationNlp& nlp, int e) {
  for (const FreeControl& c : nlp.experiment(e).controls)
    if (std::isfinite(c.max_change)) return true;
  return false;
}

ControlChanges::ControlChanges(const CollocationNlp& nlp, int e) {
  const auto& controls = nlp.experiment(e).controls;
  for (std::size_t c = 0; c < controls.size(); ++c) {
    if (!std::isfinite(controls[c].max_change)) continue;
    if (!(controls[c].max_change >= 0.0)) throw ProblemError("a control's max_change must be ≥ 0");
    std::vector<int> vars;  // the control's distinct variables in time order
    for (int i = 0; i < nlp.num_elements(); ++i)
      for (int j = 0; j < (controls[c].per_point ? nlp.num_points() : 1); ++j) {
        const int var = controls[c].per_point ? nlp.control_point_var(e, int(c), i, j)
                                              : nlp.control_var(e, int(c), i);
        if (vars.empty() || vars.back() != var) vars.push_back(var);
      }
    for (std::size_t k = 1; k < vars.size(); ++k) pairs_.push_back({vars[k - 1], vars[k], controls[c].max_change});
  }
}

void ControlChanges::bounds(std::span<double> lo, std::span<double> hi) const {
  for (std::size_t r = 0; r < pairs_.size(); ++r) lo[r] = -pairs_[r].limit, hi[r] = pairs_[r].limit;
}

void ControlChanges::values(CollocationNlp&, std::span<const double> v, std::span<double> g) {
  for (std::size_t r = 0; r < pairs_.size(); ++r)
    g[r] = v[std::size_t(pairs_[r].after)] - v[std::size_t(pairs_[r].before)];
}

void ControlChanges::jacobian(CollocationNlp&, std::span<const double>, int row0, SparseAssembler& jac) {
  for (std::size_t r = 0; r < pairs_.size(); ++r) {
    jac.add(row0 + int(r), pairs_[r].before, -1.0);
    jac.add(row0 + int(r), pairs_[r].after, 1.0);
  }
}

}  // namespace mo::runtime::detail
