// Layout, points and derivative mapping of the collocation NLP.
#include "collocation_nlp.hpp"

#include "collocation_equations.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace mo::runtime::detail {
namespace {

std::vector<double> normalised_lengths(const CollocationOptions& c) {
  if (c.element_lengths.empty()) return std::vector<double>(std::size_t(c.n_e), 1.0 / c.n_e);
  if (static_cast<int>(c.element_lengths.size()) != c.n_e)
    throw ProblemError("element_lengths has " + std::to_string(c.element_lengths.size()) +
                       " entries, n_e is " + std::to_string(c.n_e));
  double total = std::accumulate(c.element_lengths.begin(), c.element_lengths.end(), 0.0);
  std::vector<double> out;
  for (double h : c.element_lengths) {
    if (!(h > 0.0)) throw ProblemError("element_lengths must be positive");
    out.push_back(h / total);
  }
  return out;
}

std::vector<int> element_blocks(const FreeControl& c, int n_e, int n_cp) {
  std::vector<int> block;
  if (c.per_point) {
    if (!c.blocking_factors.empty()) throw ProblemError("a per-point control takes no blocking factors");
    for (int i = 0; i < n_e; ++i) block.push_back(i * n_cp);
    return block;
  }
  if (c.blocking_factors.empty()) {
    for (int i = 0; i < n_e; ++i) block.push_back(i);
    return block;
  }
  for (std::size_t b = 0; b < c.blocking_factors.size(); ++b) {
    if (c.blocking_factors[b] <= 0) throw ProblemError("blocking factors must be positive");
    block.insert(block.end(), std::size_t(c.blocking_factors[b]), static_cast<int>(b));
  }
  if (static_cast<int>(block.size()) != n_e)
    throw ProblemError("blocking factors sum to " + std::to_string(block.size()) +
                       ", n_e is " + std::to_string(n_e));
  return block;
}

Bounds intersect(Bounds a, Bounds b) { return {std::max(a.lo, b.lo), std::min(a.hi, b.hi)}; }

}  // namespace

CollocationNlp::CollocationNlp(const Model& model, NlpSetup setup,
                               std::vector<ExperimentSetup> experiments)
    : setup_(std::move(setup)) {
  const ModelInfo& info = model.info();
  if (setup_.parameters.empty()) setup_.parameters = info.default_parameters();
  if (setup_.collocation.n_e < 1) throw ProblemError("n_e must be at least 1");
  if (experiments.empty()) throw ProblemError("no experiment to transcribe");
  // The collocation equations relate each element's own points; a value at
  // t − T from another element would be a new kind of constraint.
  if (info.num_delays > 0)
    throw ProblemError("model '" + info.name + "' calls delay(): collocation (optimal control, "
                       "estimation, design) does not support delays; simulate it instead");
  poly_ = make_collocation_polynomials(setup_.collocation.scheme == CollocationScheme::radau
                                           ? NodeFamily::radau
                                           : NodeFamily::gauss,
                                       setup_.collocation.n_cp);
  for (auto& ex : experiments) {
    experiments_.push_back(Experiment{std::move(ex), {}, {}, {}, {}, {}, 0});
    models_.push_back(model.clone());
  }
  check_setup();
  parameter_var_.assign(info.parameters.size(), -1);
  for (const FreeParameter& fp : setup_.free_parameters) {
    double guess = fp.initial_guess.value_or(setup_.parameters[fp.parameter]);
    parameter_var_[fp.parameter] = add_variables(1, fp.bounds, guess);
  }
  for (auto& ex : experiments_) layout_experiment(ex);
  for (int e = 0; e < num_experiments(); ++e) {
    initial_guess_from_simulation(e);  // before the rows: it may set their scaling
    add_constraints(std::make_unique<CollocationEquations>(*this, e));
  }
}

void CollocationNlp::check_setup() {
  const ModelInfo& info = this->info();
  if (setup_.parameters.size() != info.parameters.size())
    throw ProblemError("expected " + std::to_string(info.parameters.size()) +
                       " parameter values, got " + std::to_string(setup_.parameters.size()));
  for (const FreeParameter& fp : setup_.free_parameters)
    if (fp.parameter >= info.parameters.size())
      throw ProblemError("free parameter index " + std::to_string(fp.parameter) + " out of range");
  for (const Experiment& ex : experiments_) {
    const ExperimentSetup& s = ex.setup;
    if (!(s.tf > s.t0)) throw ProblemError("the horizon needs tf > t0");
    std::vector<int> claimed(info.inputs.size(), 0);
    for (const FreeControl& c : s.controls)
      if (c.input >= claimed.size() || claimed[c.input]++)
        throw ProblemError("control input index " + std::to_string(c.input) +
                           " out of range or given twice");
    for (const auto& [input, signal] : s.fixed_inputs)
      if (input >= claimed.size() || claimed[input]++ || !signal)
        throw ProblemError("fixed input index " + std::to_string(input) +
                           " out of range, null, or also a control");
    for (std::size_t i = 0; i < claimed.size(); ++i)
      if (!claimed[i])
        throw ProblemError("input '" + info.inputs[i].name + "' is neither a control nor fixed");
    // x0 = x0(p, u(t0)) has no derivative with respect to u: an input that the
    // initial system reads must be a given signal here.
    for (const FreeControl& c : s.controls)
      if (c.input < info.input_in_initial.size() && info.input_in_initial[c.input])
        throw ProblemError("the initial system reads input '" + info.inputs[c.input].name +
                           "' (the start values depend on its value at the start time), so it cannot be "
                           "a free control of a collocation problem; give it as a fixed signal, or "
                           "initialise without it");
    for (const auto& [state, b] : s.state_bounds)
      if (state >= info.states.size()) throw ProblemError("state bound index out of range");
    for (const FinalStateConstraint& f : s.final_state)
      if (f.state >= info.states.size()) throw ProblemError("final-state index out of range");
  }
}

int CollocationNlp::add_variables(int count, Bounds bounds, double initial, double scale) {
  int first = num_variables();
  for (int k = 0; k < count; ++k) {
    lower_.push_back(bounds.lo);
    upper_.push_back(bounds.hi);
    initial_.push_back(initial);
    scale_.push_back(scale);
  }
  return first;
}

void CollocationNlp::layout_experiment(Experiment& ex) {
  const ModelInfo& info = this->info();
  const int n_e = num_elements(), nodes = num_points() + 1;
  std::vector<double> rel = normalised_lengths(setup_.collocation);
  const double t0 = ex.setup.t0, span = ex.setup.tf - ex.setup.t0;
  const bool uniform = setup_.collocation.element_lengths.empty();
  double fraction = 0.0;  // uniform grids use t0 + i·span/n_e exactly, like uniform sample times
  for (int i = 0; i < n_e; ++i) {
    ex.element_start.push_back(uniform ? t0 + double(i) * span / double(n_e) : t0 + fraction * span);
    fraction += rel[std::size_t(i)];
  }
  for (int i = 0; i < n_e; ++i)
    ex.element_length.push_back((i + 1 < n_e ? ex.element_start[std::size_t(i) + 1] : ex.setup.tf) -
                                ex.element_start[std::size_t(i)]);
  ex.state_offset = num_variables();
  for (const StateVariable& sv : info.states) ex.nominal.push_back(sv.nominal);
  auto add_node = [&](bool final_node) {
    for (std::size_t s = 0; s < info.states.size(); ++s) {
      const StateVariable& sv = info.states[s];
      Bounds b{sv.min, sv.max};
      if (auto it = ex.setup.state_bounds.find(s); it != ex.setup.state_bounds.end()) b = it->second;
      if (final_node)
        for (const FinalStateConstraint& f : ex.setup.final_state)
          if (f.state == s) b = intersect(b, f.bounds);
      add_variables(1, b, sv.start, 1.0 / sv.nominal);
    }
  };
  for (int i = 0; i < n_e; ++i)
    for (int k = 0; k < nodes; ++k) add_node(false);
  add_node(true);
  for (const FreeControl& c : ex.setup.controls) {
    ex.control_block.push_back(element_blocks(c, n_e, num_points()));
    const int blocks = c.per_point ? n_e * num_points() : ex.control_block.back().back() + 1;
    ex.control_offset.push_back(add_variables(blocks, c.bounds, std::clamp(0.0, c.bounds.lo, c.bounds.hi)));
  }
}

int CollocationNlp::state_var(int e, int i, int k, int s) const {
  const int nx = static_cast<int>(info().states.size());
  return experiments_[e].state_offset + (i * (num_points() + 1) + k) * nx + s;
}

int CollocationNlp::control_var(int e, int c, int i) const {
  const Experiment& ex = experiments_[e];
  return ex.control_offset[c] + ex.control_block[c][i];
}

int CollocationNlp::control_point_var(int e, int c, int i, int j) const {
  return control_var(e, c, i) + j;
}

double CollocationNlp::element_start(int e, int i) const {
  return experiments_[e].element_start[i];
}
double CollocationNlp::element_length(int e, int i) const {
  return experiments_[e].element_length[i];
}

PointRef CollocationNlp::point(int e, int i, double tau) const {
  return PointRef{e, i, tau, element_start(e, i) + tau * element_length(e, i), poly_.basis(tau),
                  lagrange_weights(collocation_points(), tau)};
}

PointRef CollocationNlp::point_at(int e, double t) const {
  const Experiment& ex = experiments_[e];
  auto it = std::lower_bound(ex.element_start.begin(), ex.element_start.end(), t);
  int i = std::max(0, static_cast<int>(it - ex.element_start.begin()) - 1);
  double tau = std::clamp((t - ex.element_start[i]) / ex.element_length[i], 0.0, 1.0);
  return point(e, i, tau);
}

void CollocationNlp::point_state(std::span<const double> v, const PointRef& pt,
                                 std::span<double> x) const {
  for (std::size_t s = 0; s < x.size(); ++s) {
    double sum = 0.0;
    for (std::size_t k = 0; k < pt.basis.size(); ++k)
      if (pt.basis[k] != 0.0)
        sum += pt.basis[k] * v[state_var(pt.experiment, pt.element, int(k), int(s))];
    x[s] = sum;
  }
}

void CollocationNlp::point_inputs(std::span<const double> v, const PointRef& pt,
                                  std::span<double> u) const {
  const ExperimentSetup& s = experiments_[pt.experiment].setup;
  for (std::size_t c = 0; c < s.controls.size(); ++c) {
    if (!s.controls[c].per_point) {
      u[s.controls[c].input] = v[control_var(pt.experiment, int(c), pt.element)];
      continue;
    }
    double sum = 0.0;
    for (std::size_t j = 0; j < pt.point_basis.size(); ++j)
      sum += pt.point_basis[j] * v[control_point_var(pt.experiment, int(c), pt.element, int(j))];
    u[s.controls[c].input] = sum;
  }
  for (const auto& [input, signal] : s.fixed_inputs)  // left limit at the element's end
    u[input] = pt.tau == 1.0 ? signal->value_before(pt.time) : signal->value(pt.time);
}

void CollocationNlp::parameters(std::span<const double> v, std::span<double> p) const {
  for (std::size_t j = 0; j < p.size(); ++j)
    p[j] = parameter_var_[j] >= 0 ? v[parameter_var_[j]] : setup_.parameters[j];
}

VariableMap CollocationNlp::variable_map(const PointRef& pt) const {
  const ModelInfo& info = this->info();
  const std::size_t nx = info.states.size(), nu = info.inputs.size();
  VariableMap map(nx + nu + info.parameters.size());
  for (std::size_t s = 0; s < nx; ++s)
    for (std::size_t k = 0; k < pt.basis.size(); ++k)
      if (pt.basis[k] != 0.0)
        map[s].emplace_back(state_var(pt.experiment, pt.element, int(k), int(s)), pt.basis[k]);
  const ExperimentSetup& s = experiments_[pt.experiment].setup;
  for (std::size_t c = 0; c < s.controls.size(); ++c) {
    auto& entry = map[nx + s.controls[c].input];
    if (!s.controls[c].per_point) {
      entry.emplace_back(control_var(pt.experiment, int(c), pt.element), 1.0);
      continue;
    }
    for (std::size_t j = 0; j < pt.point_basis.size(); ++j)
      if (pt.point_basis[j] != 0.0)
        entry.emplace_back(control_point_var(pt.experiment, int(c), pt.element, int(j)), pt.point_basis[j]);
  }
  for (std::size_t j = 0; j < parameter_var_.size(); ++j)
    if (parameter_var_[j] >= 0) map[nx + nu + j].emplace_back(parameter_var_[j], 1.0);
  return map;
}

}  // namespace mo::runtime::detail
