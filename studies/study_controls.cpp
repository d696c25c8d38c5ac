// Per-control options of a study and initial guesses from a result file:
// JModelica's blocking_factors as a dict, du_bounds, and init_traj given a
// result (study options input_blocking_factors via blocking_factors, du_bounds,
// init_result; docs/study-files.md).
#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <iostream>
#include <sstream>

#include "mo/runtime/simulate.hpp"

#include "study_internal.hpp"
#include "study_output.hpp"

namespace mo::tools::detail {
namespace {

/// The control of input `name`; UsageError naming `option` otherwise.
runtime::FreeControl& control_named(const runtime::ModelInfo& info, runtime::OptimalControlProblem& p,
                                    const std::string& name, const std::string& option) {
  for (runtime::FreeControl& c : p.controls)
    if (info.inputs[c.input].name == name) return c;
  std::string known;
  for (const runtime::FreeControl& c : p.controls)
    if (!c.per_point) known += (known.empty() ? "" : ", ") + info.inputs[c.input].name;
  throw UsageError(fmt::format("study option '{}': '{}' is not a control of the problem (controls: {})", option,
                               name, known.empty() ? "none" : known));
}

std::vector<int> factors(const std::string& list, const std::string& context) {
  std::vector<int> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    const double f = number(item, context);
    if (!(f >= 1) || f != static_cast<int>(f))
      throw UsageError(context + ": blocking factors are positive integers");
    out.push_back(static_cast<int>(f));
  }
  return out;
}

/// The column of `table` for state or variable `name`, or null.
std::shared_ptr<const runtime::InputSignal> column(const std::shared_ptr<const runtime::InputTable>& table,
                                                   const std::string& name) {
  for (const auto& n : table->names)
    if (n == name) return runtime::table_input(table, name);
  return nullptr;
}

/// With a free final time the problem runs on τ ∈ [0, 1]: the result's own
/// span [first, last time] is mapped onto it (as JModelica does).
void normalise_time(runtime::InputTable& t) {
  if (t.times.empty() || !(t.times.back() > t.times.front())) return;
  const double first = t.times.front(), span = t.times.back() - first;
  for (double& time : t.times) time = (time - first) / span;
}

}  // namespace

void apply_control_options(const Study& s, runtime::OptimalControlProblem& p) {
  const runtime::ModelInfo& info = s.info();
  if (!s.opt.piecewise_constant_controls) {
    if (s.opt.task != "optimal_control")
      throw UsageError("study option piecewise_constant_controls = false is supported by task optimal_control only");
    for (runtime::FreeControl& c : p.controls)
      if (c.blocking_factors.empty()) c.per_point = true;
  }
  for (const auto& text : s.opt.input_blocking_factors) {
    auto [name, list] = split_assignment(text, "study option blocking_factors:");
    runtime::FreeControl& c = control_named(info, p, name, "blocking_factors");
    c.blocking_factors = factors(list, "study option blocking_factors: " + name);
    c.per_point = false;
  }
  for (const auto& text : s.opt.du_bounds) {
    auto [name, value] = split_assignment(text, "study option du_bounds:");
    const double d = number(value, "study option du_bounds: " + name);
    if (!(d >= 0)) throw UsageError("study option du_bounds: " + name + ": the bound must be ≥ 0");
    control_named(info, p, name, "du_bounds").max_change = d;
  }
}

void guess_iteration_variables(const Study& s, runtime::OptimalControlProblem& p) {
  if (!s.newton || s.loops.inputs.empty() || !p.collocation.init_traj) return;
  runtime::Model& model = *s.newton->model;
  const runtime::ModelInfo& info = model.info();
  std::vector<std::unique_ptr<runtime::InputSignal>> signals(info.inputs.size());
  for (const auto& [input, signal] : p.fixed_inputs)
    if (input < signals.size()) signals[input] = runtime::shared_input(signal);
  for (const runtime::FreeControl& c : p.controls)
    if (c.input < signals.size())  // the loop inputs come after the model's own
      signals[c.input] = c.initial_guess ? runtime::shared_input(c.initial_guess)
                                         : runtime::constant_input(std::clamp(0.0, c.bounds.lo, c.bounds.hi));
  const int rows = std::max(2, p.collocation.n_e * (p.collocation.n_cp + 1));
  runtime::SimulationOptions so;
  so.relative_tolerance = 1e-8;
  const runtime::SimulationResult sim =
      runtime::simulate(model, runtime::Inputs(std::move(signals)),
                        p.parameters.empty() ? info.default_parameters() : p.parameters,
                        runtime::OutputGrid::uniform(p.t0, p.tf, rows), so);
  if (!sim.ok()) {  // the NLP's own simulation would take the start values as given signals: no better
    std::cerr << "morun: note: the states and the iteration variables of nonlinear blocks start at their "
                 "start values (init_traj = false): simulating the model with Newton for their initial guess "
                 "failed: " << sim.message << "\n";
    p.collocation.init_traj = false;
    p.collocation.nominal_traj = false;
    return;
  }
  auto table = std::make_shared<runtime::InputTable>();
  table->times = sim.trajectory.times();
  const std::size_t nx = info.states.size();
  for (const symbolic::LoopInput& li : s.loops.inputs) {
    const auto y = info.output_index(li.variable);
    if (!y) continue;
    table->names.push_back(li.variable);
    table->columns.emplace_back();
    for (std::size_t k = 0; k < sim.trajectory.rows(); ++k) table->columns.back().push_back(sim.trajectory.at(k, nx + *y));
  }
  std::shared_ptr<const runtime::InputTable> shared = table;
  for (const symbolic::LoopInput& li : s.loops.inputs)
    for (runtime::FreeControl& c : p.controls)
      if (c.per_point && c.input == li.input)
        if (auto signal = column(shared, li.variable)) c.initial_guess = std::move(signal);
}

std::size_t apply_init_result(const Study& s, runtime::OptimalControlProblem& p) {
  if (s.opt.init_result.empty()) return 0;
  const std::string path = resolve_path(s.cli.study_file, s.opt.init_result);
  std::shared_ptr<const runtime::InputTable> table;
  try {
    runtime::InputTable read = runtime::read_result_table(path);
    if (s.problem.free_final_time) normalise_time(read);
    table = std::make_shared<const runtime::InputTable>(std::move(read));
  } catch (const runtime::InputFileError& e) {
    throw UsageError(std::string("study option init_result: ") + e.what());
  }
  const runtime::ModelInfo& info = s.info();
  std::size_t used = 0;
  auto& guesses = p.collocation.state_guesses;
  guesses.assign(info.states.size(), nullptr);
  for (std::size_t k = 0; k < info.states.size(); ++k)
    if ((guesses[k] = column(table, info.states[k].name))) ++used;
  std::vector<std::string> loop_variable(info.inputs.size());
  for (const symbolic::LoopInput& li : s.loops.inputs) loop_variable[li.input] = li.variable;
  for (runtime::FreeControl& c : p.controls) {
    const std::string& name = c.per_point ? loop_variable[c.input] : info.inputs[c.input].name;
    if (auto signal = column(table, name)) c.initial_guess = std::move(signal), ++used;
  }
  if (used == 0)
    throw UsageError("study option init_result: " + path + " has no column named like a state or control");
  return used;
}

}  // namespace mo::tools::detail
