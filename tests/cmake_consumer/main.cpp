// Simulates the generated cart pendulum through its typed header and checks
// what a user would rely on: named indices, sizes, a successful simulation.
#include <cmath>
#include <cstdio>

#include "cart.hpp"
#include "mo/runtime/simulate.hpp"

int main() {
  auto model = cart::create();
  const auto& info = model->info();
  if (info.states.at(cart::state::phi).name != "phi" || cart::num_inputs != 1) return 1;
  mo::runtime::Inputs inputs;
  inputs.add(mo::runtime::sine_input(3.0, 1.0));
  mo::runtime::SimulationOptions options;
  options.sensitivities.method = mo::runtime::SensitivityMethod::model_states;
  const auto result = mo::runtime::simulate(*model, inputs, info.default_parameters(),
                                            mo::runtime::OutputGrid::uniform(0, 2, 20), options);
  if (!result.ok()) return 2;
  const double phi = result.trajectory.column("phi").back();
  std::printf("phi(2) = %.6f, d(phi)/d(m2)(2) = %.6f\n", phi,
              result.state_sensitivities.back()(static_cast<Eigen::Index>(cart::state::phi), 0));
  return std::isfinite(phi) ? 0 : 3;
}
