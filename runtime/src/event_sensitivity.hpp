// Forward sensitivities through one event instant (internal to simulate.cpp).
//
// With τ the event time, g the indicator that crossed and x⁺ = r(x⁻, p, t):
//   dτ/dp = −(g_x S⁻ + g_p) / (g_x f⁻ + g_t)
//   S⁺    = r_x S⁻ + r_p + (r_x f⁻ + r_t − f⁺) dτ/dp
// computed as the tangent of the event map along δ = (S⁻ + f⁻ dτ/dp, u̇ dτ/dp,
// e_p, dτ/dp), minus f⁺ dτ/dp (the model's event tangents, model.hpp), with
// ġ = g_x f⁻ + g_u u̇ + g_t in dτ/dp's denominator. A discrete
// variable d with discrete sensitivities (ModelInfo::discrete_sensitivities)
// moves along δd = S_d⁻, and S_d⁺ is its tangent after the handler.
#pragma once

#include <Eigen/Dense>

#include <span>
#include <string>
#include <vector>

#include "mo/runtime/model.hpp"

namespace mo::runtime::detail {

/// One event instant's sensitivity jump: construct before the first handler
/// call, call handle() instead of Model::handle_event, then finish().
class SensitivityJump {
public:
  /// `s`: S⁻, column j = ∂x/∂p_{params[j]} for the first s.rows() states.
  /// `crossings` empty (or all 0) for a time event: its time moves with p only
  /// at a sample() tick (Model::time_event_tangent).
  /// `udot`: the inputs' derivatives just before t (empty: all 0).
  /// Requires model.provides_event_tangents().
  SensitivityJump(Model& model, double t, std::span<const double> x, std::span<const double> u,
                  std::span<const double> udot, std::span<const double> p,
                  std::span<const int> crossings, const Eigen::MatrixXd& s,
                  std::span<const int> params);

  /// Model::handle_event_tangent with this instant's directions.
  EventResponse handle(const EventCause& cause, std::span<double> x, std::span<const double> u,
                       std::span<const double> p);

  /// S⁺ (same shape as S⁻) for the state x⁺ after the last handler call.
  Eigen::MatrixXd finish(double t, std::span<const double> x, std::span<const double> u,
                         std::span<const double> p);
  /// Writes S_d⁺ into the model's discrete sensitivities.
  void finish_discrete();
  /// A discrete variable whose S_d⁺ is not zero, or empty: CVODES'
  /// sensitivities (f_x s + f_p) cannot carry it.
  [[nodiscard]] std::string moved_discrete() const;

  /// dτ/dp_j per direction (0 for a tangential crossing or a time event that is
  /// no sample() tick moving with p).
  [[nodiscard]] const std::vector<double>& event_time_derivatives() const { return tau_; }
  /// A discrete variable whose value depends on x, p or t through a fired
  /// when-clause (its sensitivity is not carried); empty if none.
  [[nodiscard]] const std::string& unsupported() const { return unsupported_; }
  /// Why the jump cannot be taken (the time event's dτ/dp is not defined),
  /// or empty.
  [[nodiscard]] const std::string& failure() const { return failure_; }

private:
  Model& model_;
  std::vector<int> crossings_;
  Eigen::Index rows_;
  std::vector<int> params_;
  std::vector<std::vector<double>> dx_, dp_, dd_, du_;
  std::vector<double> tau_;
  std::string unsupported_, failure_;
};

/// S_d(t0): carries the directions (S(t0), e_p, 0) through the when-clauses
/// that fired at initialisation and writes the model's discrete
/// sensitivities. Returns what Model::initial_event_tangent names as
/// unsupported, or empty; `moved` is set to a discrete variable whose
/// sensitivity is not zero (empty if none).
std::string initial_discrete_sensitivities(Model& model, double t0, std::span<const double> x,
                                           std::span<const double> u, std::span<const double> p,
                                           const Eigen::MatrixXd& s, std::span<const int> params,
                                           std::string& moved);

}  // namespace mo::runtime::detail
