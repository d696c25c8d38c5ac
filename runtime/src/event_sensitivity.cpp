// Sensitivity jumps at events; see event_sensitivity.hpp.
#include "event_sensitivity.hpp"

#include <algorithm>
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

/// The directions (S⁻_j, e_{params[j]}) for the columns of `s` (the first
/// s.rows() of nx states).
void unit_directions(const Eigen::MatrixXd& s, std::span<const int> params, std::size_t nx,
                     std::size_t np, std::vector<std::vector<double>>& dx,
                     std::vector<std::vector<double>>& dp) {
  dx.assign(params.size(), std::vector<double>(nx, 0.0));
  dp.assign(params.size(), std::vector<double>(np, 0.0));
  for (std::size_t j = 0; j < params.size(); ++j) {
    for (Eigen::Index i = 0; i < s.rows(); ++i)
      dx[j][static_cast<std::size_t>(i)] = s(i, static_cast<Eigen::Index>(j));
    dp[j][static_cast<std::size_t>(params[j])] = 1.0;
  }
}

/// δd per direction: the model's discrete sensitivities of params[j]; empty
/// rows when the model has none.
std::vector<std::vector<double>> discrete_seeds(Model& model, std::span<const int> params) {
  const auto& sens = model.info().discrete_sensitivities;
  std::vector<std::vector<double>> dd(params.size());
  if (sens.empty()) return dd;
  const std::span<double> d = model.discrete();
  for (std::size_t j = 0; j < params.size(); ++j) {
    dd[j].assign(d.size(), 0.0);
    for (const DiscreteSensitivity& c : sens)
      if (c.parameter == static_cast<std::size_t>(params[j])) dd[j][c.discrete] = d[c.index];
  }
  return dd;
}

/// Writes dd back into the model's discrete sensitivities.
void write_discrete(Model& model, std::span<const int> params,
                    const std::vector<std::vector<double>>& dd) {
  const auto& sens = model.info().discrete_sensitivities;
  const std::span<double> d = model.discrete();
  for (std::size_t j = 0; j < params.size() && !dd[j].empty(); ++j)
    for (const DiscreteSensitivity& c : sens)
      if (c.parameter == static_cast<std::size_t>(params[j])) d[c.index] = dd[j][c.discrete];
}

/// A discrete variable with a nonzero δd in some direction, or empty.
std::string first_moved(const Model& model, const std::vector<std::vector<double>>& dd) {
  for (const auto& row : dd)
    for (std::size_t i = 0; i < row.size(); ++i)
      if (row[i] != 0.0) return model.info().discrete[i].name;
  return {};
}

}  // namespace

SensitivityJump::SensitivityJump(Model& model, double t, std::span<const double> x,
                                 std::span<const double> u, std::span<const double> udot,
                                 std::span<const double> p, std::span<const int> crossings,
                                 const Eigen::MatrixXd& s, std::span<const int> params)
    : model_(model), crossings_(crossings.begin(), crossings.end()), rows_(s.rows()),
      params_(params.begin(), params.end()), dd_(discrete_seeds(model, params)) {
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
    const EventTangent along_time{f_before, zero_p, 1.0, {}, udot};
    model.event_indicator_tangent(t, x, u, p, before, along_time, slope);
    g = steepest(crossings, slope);
  }
  unit_directions(s, params, nx, np, dx_, dp_);
  tau_.assign(ns, 0.0);
  du_.assign(ns, {});
  for (std::size_t j = 0; j < ns; ++j) {
    if (g >= 0) {
      model.event_indicator_tangent(t, x, u, p, before, {dx_[j], dp_[j], 0.0, dd_[j]}, dg);
      tau_[j] = -dg[static_cast<std::size_t>(g)] / slope[static_cast<std::size_t>(g)];
    } else if (std::all_of(crossings.begin(), crossings.end(), [](int c) { return c == 0; })) {
      // A time event: a sample() tick whose start or interval moves with p.
      tau_[j] = model.time_event_tangent(t, x, u, p, {dx_[j], dp_[j], 0.0, dd_[j]});
      if (!std::isfinite(tau_[j])) {
        failure_ = "sample() ticks at this time move apart with the parameters";
        tau_[j] = 0.0;
      }
    }
    for (std::size_t i = 0; i < static_cast<std::size_t>(rows_); ++i)
      dx_[j][i] += f_before[i] * tau_[j];
    for (double v : udot) du_[j].push_back(v * tau_[j]);
  }
}

EventResponse SensitivityJump::handle(const EventCause& cause, std::span<double> x,
                                      std::span<const double> u, std::span<const double> p) {
  std::vector<EventTangent> directions;
  directions.reserve(dx_.size());
  for (std::size_t j = 0; j < dx_.size(); ++j)
    directions.push_back({dx_[j], dp_[j], tau_[j], dd_[j], du_[j]});
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

void SensitivityJump::finish_discrete() { write_discrete(model_, params_, dd_); }

std::string SensitivityJump::moved_discrete() const { return first_moved(model_, dd_); }

std::string initial_discrete_sensitivities(Model& model, double t0, std::span<const double> x,
                                           std::span<const double> u, std::span<const double> p,
                                           const Eigen::MatrixXd& s, std::span<const int> params,
                                           std::string& moved) {
  std::vector<std::vector<double>> dx, dp, dd = discrete_seeds(model, params);
  unit_directions(s, params, x.size(), p.size(), dx, dp);
  std::vector<EventTangent> directions;
  for (std::size_t j = 0; j < params.size(); ++j) directions.push_back({dx[j], dp[j], 0.0, dd[j]});
  std::string unsupported;
  model.initial_event_tangent(t0, x, u, p, directions, unsupported);
  write_discrete(model, params, dd);
  moved = first_moved(model, dd);
  return unsupported;
}

}  // namespace mo::runtime::detail
