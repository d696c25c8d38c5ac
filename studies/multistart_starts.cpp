// The starts of a multistart design; see multistart_starts.hpp.
#include "multistart_starts.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numeric>
#include <random>

#include "common.hpp"

namespace mo::tools {

namespace {

/// Element boundaries τ_0 = t0 < ... < τ_ne = tf.
std::vector<double> element_times(const runtime::OptimalControlProblem& ocp) {
  const auto& c = ocp.collocation;
  std::vector<double> lengths = c.element_lengths;
  if (static_cast<int>(lengths.size()) != c.n_e) lengths.assign(static_cast<std::size_t>(c.n_e), 1.0);
  const double total = std::accumulate(lengths.begin(), lengths.end(), 0.0);
  std::vector<double> t{ocp.t0};
  double sum = 0.0;
  for (double h : lengths) sum += h, t.push_back(ocp.t0 + (ocp.tf - ocp.t0) * sum / total);
  return t;
}

/// A draw in [0, 1) from the top 53 bits (exact and platform independent).
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace

std::vector<double> control_interval_times(const runtime::OptimalControlProblem& ocp,
                                           const runtime::FreeControl& c) {
  const std::vector<double> tau = element_times(ocp);
  std::vector<double> starts;
  if (c.blocking_factors.empty()) return {tau.begin(), tau.end() - 1};
  std::size_t e = 0;
  for (int b : c.blocking_factors) {
    if (e + 1 >= tau.size()) break;
    starts.push_back(tau[e]);
    e += static_cast<std::size_t>(std::max(b, 1));
  }
  return starts;
}

DesignStart random_start(const runtime::OptimalControlProblem& ocp, const runtime::ModelInfo& info,
                         int seed, std::size_t r) {
  std::seed_seq seq{static_cast<std::uint64_t>(seed), static_cast<std::uint64_t>(r)};
  std::mt19937_64 rng(seq);
  DesignStart s{"random", fmt::format("random {} (seed {})", r + 1, seed), {}};
  for (const runtime::FreeControl& c : ocp.controls) {
    if (!std::isfinite(c.bounds.lo) || !std::isfinite(c.bounds.hi))
      throw UsageError(fmt::format("random starts draw each free input uniformly within its bounds: input "
                                   "'{}' needs a finite min and max",
                                   info.inputs[c.input].name));
    std::vector<double> times = control_interval_times(ocp, c), values;
    for (std::size_t k = 0; k < times.size(); ++k)
      values.push_back(c.bounds.lo + (c.bounds.hi - c.bounds.lo) * unit(rng));
    s.guesses.push_back(runtime::piecewise_constant_input(std::move(times), std::move(values)));
  }
  return s;
}

std::vector<DesignStart> design_starts(const StudyOptions& o, const runtime::OptimalControlProblem& ocp,
                                       const runtime::ModelInfo& info) {
  std::vector<DesignStart> out;
  const std::size_t n = ocp.controls.size();
  if (o.starts.empty()) out.push_back({"initial_guess", "initialGuess", std::vector<std::shared_ptr<const runtime::InputSignal>>(n)});
  for (const std::string& spec : o.starts) {
    if (n == 0) throw UsageError("study option 'starts' needs a free input");
    DesignStart s{"listed", spec, std::vector<std::shared_ptr<const runtime::InputSignal>>(n)};
    s.guesses[0] = parse_signal(info.inputs[ocp.controls[0].input].name, spec);
    out.push_back(std::move(s));
  }
  if (o.random_starts > 0 && n == 0) throw UsageError("random starts need a free input");
  for (int r = 0; r < o.random_starts; ++r) out.push_back(random_start(ocp, info, o.seed, static_cast<std::size_t>(r)));
  return out;
}

}  // namespace mo::tools
