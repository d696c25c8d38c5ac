// Sensitivity jumps at events; see event_sensitivity.hpp.
#include "event_sensitivity.hpp"

#include <cmath>

namespace mo::runtime::detail {

namespace {

/// The crossed indicator with the steepest slope ġ = g_x f⁻ + g_t (the best
/// conditioned event time), or -1 if none crossed or all are tangential.
int steepest(std::span<const int> crossings, const std::vector<double>& slope) {
  int best = -1;
  for (std::size_t i = 0; i < crossings.size() && i < slope.size(); ++i) {
    if (crossings[i] == 0 || !(std::abs(slope[i]) > 0.0)) continue;
    if (best < 0 || std::abs(slope[i]) > std::abs(slope[static_cast<std::size_t>(best)]))
      best = static_cast<int>(i);
  }
  return best;
}

}  // namespace

SensitivityJump::SensitivityJump(Model& model, double t, std::span<const double> x,
                                 std::span<const double> u, std::span<const double> p,
                                 std::span<const int> crossings, const Eigen::MatrixXd& s,
                                 std::span<const int> params)
    : model_(model), crossings_(crossings.begin(), crossings.end()), rows_(s.rows()) {
  const std::size_t nx = x.size(), np = p.size();
  const std::size_t ng = model.info().num_event_indicators;
  const auto ns = static_cast<std::size_t>(s.cols());
  // Relations valued as just before the event: the opposite of the crossing.
  std::vector<int> before(crossings.size());
  for (std::size_t i = 0; i < crossings.size(); ++i) before[i] = -crossings[i];
  std::vector<double> f_before(nx), zero_p(np, 0.0), dg(ng), slope(ng);
  model.rhs_at_event(t, x, u, p, before, f_before);
  int g = -1;
  if (!crossings.empty() && ng > 0) {
    model.event_indicator_tangent(t, x, u, p, before, f_before, zero_p, 1.0, slope);
    g = steepest(crossings, slope);
  }
  dx_.assign(ns, std::vector<double>(nx, 0.0));
  dp_.assign(ns, std::vector<double>(np, 0.0));
  tau_.assign(ns, 0.0);
  for (std::size_t j = 0; j < ns; ++j) {
    for (Eigen::Index i = 0; i < rows_; ++i)
      dx_[j][static_cast<std::size_t>(i)] = s(i, static_cast<Eigen::Index>(j));
    dp_[j][static_cast<std::size_t>(params[j])] = 1.0;
    if (g < 0) continue;
    model.event_indicator_tangent(t, x, u, p, before, dx_[j], dp_[j], 0.0, dg);
    tau_[j] = -dg[static_cast<std::size_t>(g)] / slope[static_cast<std::size_t>(g)];
    for (std::size_t i = 0; i < static_cast<std::size_t>(rows_); ++i)
      dx_[j][i] += f_before[i] * tau_[j];
  }
}

EventResponse SensitivityJump::handle(const EventCause& cause, std::span<double> x,
                                      std::span<const double> u, std::span<const double> p) {
  std::vector<EventTangent> directions;
  directions.reserve(dx_.size());
  for (std::size_t j = 0; j < dx_.size(); ++j) directions.push_back({dx_[j], dp_[j], tau_[j]});
  return model_.handle_event_tangent(cause, x, u, p, directions, unsupported_);
}

Eigen::MatrixXd SensitivityJump::finish(double t, std::span<const double> x,
                                        std::span<const double> u, std::span<const double> p) {
  std::vector<double> f_after(x.size());
  model_.rhs_at_event(t, x, u, p, crossings_, f_after);
  Eigen::MatrixXd s(rows_, static_cast<Eigen::Index>(dx_.size()));
  for (std::size_t j = 0; j < dx_.size(); ++j)
    for (Eigen::Index i = 0; i < rows_; ++i)
      s(i, static_cast<Eigen::Index>(j)) =
          dx_[j][static_cast<std::size_t>(i)] - f_after[static_cast<std::size_t>(i)] * tau_[j];
  return s;
}

}  // namespace mo::runtime::detail
