// The figures of a study (the paper's Figs 6-9), PNG and SVG, with the data
// files they need beyond the study's results:
//
//   optimisation  states (one panel per state: collocation, re-simulation
//                 dotted, bounds dashed, end-point targets marked), inputs
//   design        + sensitivities.csv / sensitivities: ∂y/∂p of the measured
//                 outputs under the designed input (CVODES)
//   estimation    prediction[_k].csv / fit[_k], per experiment: measurements as points, the model at
//                 the estimate as a line, its confidence band (t · sqrt(s Cov sᵀ))
#pragma once

#include <string>

#include "mo/runtime/design.hpp"
#include "mo/runtime/estimate.hpp"
#include "study_problem.hpp"

namespace mo::tools {

/// DIR/states.{png,svg} and DIR/inputs.{png,svg} of an optimisation, from
/// trajectories.csv and resimulated.csv; targets from the problem's point
/// constraints on plain variables. Throws std::runtime_error if gnuplot fails.
void plot_optimization(const std::string& dir, const runtime::ModelInfo& info,
                       const runtime::OptimalControlProblem& problem,
                       const ProblemOutputs& outputs, const std::string& title);

/// DIR/sensitivities.csv: ∂y/∂p of each measured output to each parameter of
/// interest under the designed input (CVODES, 500 intervals); false (and no
/// file) if the simulation fails.
bool write_design_sensitivities(const std::string& dir, runtime::Model& model,
                                const runtime::InputDesignProblem& d,
                                const runtime::OptimizationResult& r);

/// DIR/sensitivities.{png,svg} from sensitivities.csv, panels by unit.
void plot_design_sensitivities(const std::string& dir, const runtime::ModelInfo& info,
                               const runtime::InputDesignProblem& d);

/// DIR/prediction.csv (experiment 1) and DIR/prediction_<k>.csv (experiment
/// k ≥ 2): on 500 intervals, each measured output at the estimate with the
/// lower and upper edge of its confidence band (no band if the covariance is
/// missing). False if a simulation fails (the others are still written).
bool write_prediction(const std::string& dir, runtime::Model& model, const runtime::EstimationProblem& e,
                      const runtime::EstimationResult& r);

/// DIR/fit.{png,svg} (experiment 1) and DIR/fit_<k>.{png,svg} (experiment
/// k ≥ 2): per measured output, the experiment's measurements (points, from
/// fit.csv), the prediction and its band.
void plot_fit(const std::string& dir, const runtime::ModelInfo& info, const runtime::EstimationProblem& e,
              const runtime::EstimationResult& r);

}  // namespace mo::tools
