// Model evaluation at points and assembly of the NLP functions.
#include "collocation_nlp.hpp"

#include "mo/runtime/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace mo::runtime::detail {
namespace {

struct PointValues {
  std::vector<double> x, u, p;
};

PointValues values_at(const CollocationNlp& nlp, std::span<const double> v, const PointRef& pt) {
  const ModelInfo& info = nlp.info();
  PointValues pv{std::vector<double>(info.states.size()), std::vector<double>(info.inputs.size()),
                 std::vector<double>(info.parameters.size())};
  nlp.point_state(v, pt, pv.x);
  nlp.point_inputs(v, pt, pv.u);
  nlp.parameters(v, pv.p);
  return pv;
}

}  // namespace

std::vector<double> CollocationNlp::outputs(std::span<const double> v, const PointRef& pt) {
  PointValues pv = values_at(*this, v, pt);
  std::vector<double> y(info().outputs.size());
  model(pt.experiment).outputs(pt.time, pv.x, pv.u, pv.p, y);
  return y;
}

Eigen::SparseMatrix<double, Eigen::RowMajor> CollocationNlp::output_jacobian(std::span<const double> v,
                                                                              const PointRef& pt) {
  const ModelInfo& i = info();
  const int nx = int(i.states.size()), nu = int(i.inputs.size()), np = int(i.parameters.size());
  PointValues pv = values_at(*this, v, pt);
  Model& m = model(pt.experiment);
  std::vector<Eigen::Triplet<double>> entries;
  auto add = [&](Jacobian block, int offset) {
    const Sparsity& sp = m.jacobian_sparsity(block);
    std::vector<double> values(std::size_t(sp.nnz()));
    m.jacobian_values(block, pt.time, pv.x, pv.u, pv.p, values);
    for (int c = 0; c < sp.cols; ++c)
      for (int e = sp.col_start[c]; e < sp.col_start[c + 1]; ++e)
        entries.emplace_back(sp.row_index[e], offset + c, values[std::size_t(e)]);
  };
  add(Jacobian::h_x, 0);
  add(Jacobian::h_u, nx);
  add(Jacobian::h_p, nx + nu);
  Eigen::SparseMatrix<double, Eigen::RowMajor> j(Eigen::Index(i.outputs.size()), nx + nu + np);
  j.setFromTriplets(entries.begin(), entries.end());
  return j;
}

void CollocationNlp::add_model_hessian(Hessian which, std::span<const double> v,
                                       const PointRef& pt, std::span<const double> weights,
                                       double scale, SparseAssembler& hess) {
  Model& m = model(pt.experiment);
  const Sparsity& sp = m.hessian_sparsity(which);
  std::vector<double> values(std::size_t(sp.nnz()));
  PointValues pv = values_at(*this, v, pt);
  VariableMap map = variable_map(pt);
  std::vector<std::uint8_t> wanted(map.size());  // columns that are NLP variables here
  for (std::size_t c = 0; c < map.size(); ++c) wanted[c] = !map[c].empty();
  m.hessian_values_for(wanted, which, pt.time, pv.x, pv.u, pv.p, weights, values);
  auto visit = [&](int a, int b, double h) {
    for (auto [va, ca] : map[std::size_t(a)])
      for (auto [vb, cb] : map[std::size_t(b)])
        if (va >= vb) hess.add(va, vb, scale * h * ca * cb);
  };
  for (int c = 0; c < sp.cols; ++c)
    for (int k = sp.col_start[c]; k < sp.col_start[c + 1]; ++k) {
      visit(sp.row_index[k], c, values[k]);
      if (sp.row_index[k] != c) visit(c, sp.row_index[k], values[k]);
    }
}

bool CollocationNlp::exact_hessian_possible() const {
  for (const auto& term : objective_)
    if (!term->has_hessian(*this)) return false;
  for (const auto& block : blocks_)
    if (!block->has_hessian(*this)) return false;
  return true;
}

int CollocationNlp::num_constraints() const {
  int m = 0;
  for (const auto& block : blocks_) m += block->rows();
  return m;
}

void CollocationNlp::variable_bounds(std::span<double> lo, std::span<double> hi) const {
  std::copy(lower_.begin(), lower_.end(), lo.begin());
  std::copy(upper_.begin(), upper_.end(), hi.begin());
}

void CollocationNlp::constraint_bounds(std::span<double> lo, std::span<double> hi) const {
  std::size_t row = 0;
  for (const auto& block : blocks_) {
    auto n = std::size_t(block->rows());
    block->bounds(lo.subspan(row, n), hi.subspan(row, n));
    row += n;
  }
}

void CollocationNlp::constraint_scaling(std::span<double> s) const {
  std::size_t row = 0;
  for (const auto& block : blocks_) {
    auto n = std::size_t(block->rows());
    block->scaling(s.subspan(row, n));
    row += n;
  }
}

double CollocationNlp::objective(std::span<const double> v) {
  double f = 0.0;
  for (const auto& term : objective_) f += term->value(*this, v);
  return f;
}

void CollocationNlp::objective_gradient(std::span<const double> v, std::span<double> g) {
  std::fill(g.begin(), g.end(), 0.0);
  for (const auto& term : objective_) term->gradient(*this, v, g);
}

void CollocationNlp::constraints(std::span<const double> v, std::span<double> g) {
  std::size_t row = 0;
  for (const auto& block : blocks_) {
    auto n = std::size_t(block->rows());
    block->values(*this, v, g.subspan(row, n));
    row += n;
  }
}

void CollocationNlp::constraint_jacobian(std::span<const double> v, SparseAssembler& jac) {
  int row = 0;
  for (const auto& block : blocks_) {
    block->jacobian(*this, v, row, jac);
    row += block->rows();
  }
}

void CollocationNlp::lagrangian_hessian(std::span<const double> v, double obj_factor,
                                        std::span<const double> lambda, SparseAssembler& hess) {
  for (const auto& term : objective_) term->hessian(*this, v, obj_factor, hess);
  std::size_t row = 0;
  for (const auto& block : blocks_) {
    auto n = std::size_t(block->rows());
    block->hessian(*this, v, lambda.subspan(row, n), hess);
    row += n;
  }
}

void CollocationNlp::start_values(int e, std::span<const double> v, std::span<const double> p,
                                  std::span<double> x0) {
  const PointRef pt = point(e, 0, 0.0);
  std::vector<double> u(info().inputs.size());
  point_inputs(v, pt, u);
  model(e).initial_state(pt.time, u, p, x0);
}

void CollocationNlp::initial_guess_from_simulation(int e) {
  const ExperimentSetup& s = experiments_[e].setup;
  const ModelInfo& info = this->info();
  Inputs inputs;
  std::vector<std::shared_ptr<const InputSignal>> signals(info.inputs.size());
  for (const auto& [input, signal] : s.fixed_inputs) signals[input] = signal;
  for (std::size_t c = 0; c < s.controls.size(); ++c) {
    const FreeControl& fc = s.controls[c];
    signals[fc.input] = fc.initial_guess ? fc.initial_guess
                                         : std::shared_ptr<const InputSignal>(constant_input(
                                               std::clamp(0.0, fc.bounds.lo, fc.bounds.hi)));
    for (int i = 0; i < num_elements() && fc.per_point; ++i)  // at each collocation point
      for (int j = 0; j < num_points(); ++j) {
        const double t = element_start(e, i) + poly_.tau[std::size_t(j) + 1] * element_length(e, i);
        initial_[std::size_t(control_point_var(e, int(c), i, j))] =
            std::clamp(signals[fc.input]->value(t), fc.bounds.lo, fc.bounds.hi);
      }
    for (int i = 0; i < num_elements() && !fc.per_point; ++i) {  // the signal at the block's midpoint
      double mid = element_start(e, i) + 0.5 * element_length(e, i);
      initial_[std::size_t(control_var(e, int(c), i))] =
          std::clamp(signals[fc.input]->value(mid), fc.bounds.lo, fc.bounds.hi);
    }
  }
  for (auto& sig : signals) inputs.add(shared_input(sig));
  std::vector<double> times;
  for (int i = 0; i < num_elements(); ++i)
    for (double tau : poly_.tau) times.push_back(element_start(e, i) + tau * element_length(e, i));
  times.push_back(s.tf);
  std::vector<double> p(info.parameters.size());
  parameters(initial_, p);
  std::vector<double> x0(info.states.size());
  if (!setup_.collocation.init_traj) {  // states at their start values x0(p)
    start_values(e, initial_, p, x0);
    for (int i = 0; i <= num_elements(); ++i)
      for (int k = 0; k < (i < num_elements() ? num_points() + 1 : 1); ++k)
        for (std::size_t st = 0; st < x0.size(); ++st)
          initial_[std::size_t(state_var(e, i, k, int(st)))] = x0[st];
    apply_state_guesses(e);
    return;
  }
  SimulationOptions options;
  options.relative_tolerance = 1e-8;
  SimulationResult sim = simulate(model(e), inputs, p, OutputGrid::at(times), options);
  const std::size_t nx = info.states.size();
  for (std::size_t row = 0; row < times.size() && sim.trajectory.rows() > 0; ++row) {
    auto values = sim.trajectory.row(std::min(row, sim.trajectory.rows() - 1));
    int i = int(row) / (num_points() + 1), k = int(row) % (num_points() + 1);
    for (std::size_t st = 0; st < nx; ++st)
      initial_[std::size_t(state_var(e, i, k, int(st)))] = values[st];
  }
  start_values(e, initial_, p, x0);  // reset the discrete variables
  if (setup_.collocation.nominal_traj) scale_by_trajectory(e, sim.trajectory);
  apply_state_guesses(e);
}

void CollocationNlp::apply_state_guesses(int e) {
  const auto& guesses = setup_.collocation.state_guesses;
  for (std::size_t st = 0; st < guesses.size() && st < info().states.size(); ++st) {
    if (!guesses[st]) continue;
    for (int i = 0; i <= num_elements(); ++i)
      for (int k = 0; k < (i < num_elements() ? num_points() + 1 : 1); ++k) {
        const double t = i < num_elements() ? element_start(e, i) + poly_.tau[std::size_t(k)] * element_length(e, i)
                                            : experiments_[std::size_t(e)].setup.tf;
        initial_[std::size_t(state_var(e, i, k, int(st)))] = guesses[st]->value(t);
      }
  }
}

void CollocationNlp::scale_by_trajectory(int e, const ResultTable& trajectory) {
  Experiment& ex = experiments_[std::size_t(e)];
  const std::size_t nx = info().states.size();
  for (std::size_t st = 0; st < nx; ++st) {
    double largest = 0.0;
    for (std::size_t row = 0; row < trajectory.rows(); ++row)
      largest = std::max(largest, std::abs(trajectory.row(row)[st]));
    const double attribute = info().states[st].nominal;
    // A state the start hardly moves (the input guess may excite nothing) keeps
    // its attribute: its magnitude at the optimum is unknown.
    ex.nominal[st] = std::isfinite(largest) && largest >= 1e-2 * attribute ? largest : attribute;
  }
  for (int i = 0; i <= num_elements(); ++i)
    for (int k = 0; k < (i < num_elements() ? num_points() + 1 : 1); ++k)
      for (std::size_t st = 0; st < nx; ++st)
        scale_[std::size_t(state_var(e, i, k, int(st)))] = 1.0 / ex.nominal[st];
}

}  // namespace mo::runtime::detail
