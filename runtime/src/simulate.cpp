// CVODES driver: segments between stops (input breakpoints, time events, end),
// root finding for state events, event iteration, restarts, sensitivities.
#include "mo/runtime/simulate.hpp"

#include "cvode_jacobian.hpp"
#include "event_sensitivity.hpp"

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>

namespace mo::runtime {

OutputGrid OutputGrid::uniform(double t0, double t_end, std::size_t intervals) {
  OutputGrid grid;
  if (intervals == 0) {
    grid.times = {t0, t_end};
    return grid;
  }
  grid.times.reserve(intervals + 1);
  for (std::size_t k = 0; k <= intervals; ++k)
    grid.times.push_back(k == intervals ? t_end
                                        : t0 + (t_end - t0) * static_cast<double>(k) /
                                                   static_cast<double>(intervals));
  return grid;
}

namespace {

/// How far a held indicator (exactly 0 where the integration started) must
/// leave 0 to be an event (Simulation::hold_zero_indicators).
constexpr double kHeldZero = 1e-12;
// Chattering: this many roots within kChatterSpan of the simulated interval.
constexpr long kChatterRoots = 100000;
constexpr double kChatterSpan = 1e-4;

// --- RAII owners of SUNDIALS objects ----------------------------------------

struct Context {
  SUNContext ctx = nullptr;
  Context() { SUNContext_Create(nullptr, &ctx); }
  ~Context() { SUNContext_Free(&ctx); }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
};

struct Vector {
  N_Vector v = nullptr;
  Vector(sunindextype n, SUNContext ctx) : v(N_VNew_Serial(n, ctx)) {}
  ~Vector() { N_VDestroy(v); }
  Vector(const Vector&) = delete;
  Vector& operator=(const Vector&) = delete;
  double* data() const { return N_VGetArrayPointer(v); }
};

struct VectorArray {
  N_Vector* v = nullptr;
  int count = 0;
  VectorArray(int n, N_Vector like) : v(n > 0 ? N_VCloneVectorArray(n, like) : nullptr), count(n) {}
  ~VectorArray() {
    if (v) N_VDestroyVectorArray(v, count);
  }
  VectorArray(const VectorArray&) = delete;
  VectorArray& operator=(const VectorArray&) = delete;
};

struct Cvode {
  void* mem = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver solver = nullptr;
  ~Cvode() {
    CVodeFree(&mem);
    if (solver) SUNLinSolFree(solver);
    if (matrix) SUNMatDestroy(matrix);
  }
};

SimulationStatus status_of(int flag) {
  switch (flag) {
  case CV_TOO_MUCH_WORK: return SimulationStatus::too_much_work;
  case CV_TOO_MUCH_ACC: return SimulationStatus::too_much_accuracy;
  case CV_ERR_FAILURE: return SimulationStatus::error_test_failure;
  case CV_CONV_FAILURE: return SimulationStatus::convergence_failure;
  case CV_LINIT_FAIL:
  case CV_LSETUP_FAIL:
  case CV_LSOLVE_FAIL: return SimulationStatus::linear_solver_failure;
  case CV_RHSFUNC_FAIL:
  case CV_FIRST_RHSFUNC_ERR:
  case CV_REPTD_RHSFUNC_ERR:
  case CV_UNREC_RHSFUNC_ERR:
  case CV_SRHSFUNC_FAIL:
  case CV_FIRST_SRHSFUNC_ERR:
  case CV_REPTD_SRHSFUNC_ERR:
  case CV_UNREC_SRHSFUNC_ERR: return SimulationStatus::rhs_failure;
  case CV_RTFUNC_FAIL: return SimulationStatus::event_indicator_failure;
  default: return SimulationStatus::solver_error;
  }
}

bool all_finite(std::span<const double> v) {
  return std::all_of(v.begin(), v.end(), [](double a) { return std::isfinite(a); });
}

// One simulate() call: the state CVODES' callbacks need, and the driver loop.
class Simulation {
public:
  Simulation(Model& model, const Inputs& inputs, std::span<const double> p,
             const OutputGrid& grid, const SimulationOptions& options)
      : model_(model), info_(model.info()), inputs_(inputs), p_(p.begin(), p.end()),
        grid_(grid), options_(options), nx_(info_.states.size()), nu_(info_.inputs.size()),
        ny_(info_.outputs.size()), ng_(info_.num_event_indicators), u_(nu_), y_(ny_) {}

  SimulationResult run();

private:
  // CVODES callbacks; user_data is the Simulation.
  static int rhs_callback(double t, N_Vector x, N_Vector xdot, void* self);
  static int jacobian_callback(double t, N_Vector x, N_Vector fx, SUNMatrix jac, void* self,
                               N_Vector, N_Vector, N_Vector);
  int difference_jacobian(double t, N_Vector x, N_Vector fx, SUNMatrix jac);
  static int sensitivity_callback(int ns, double t, N_Vector x, N_Vector xdot, N_Vector* s,
                                  N_Vector* sdot, void* self, N_Vector, N_Vector);
  static int root_callback(double t, N_Vector x, double* g, void* self);
  static void error_callback(int code, const char* module, const char* function, char* msg,
                             void* self);

  std::string validate() const;
  bool set_up();
  void evaluate_inputs(double t);
  void record(double t);
  bool restart(double t, std::span<const int> crossed = {}, bool hold_crossed = false);
  /// True if one of the indicators with a nonzero entry in `roots` enters
  /// the right-hand side (ModelInfo::indicator_in_rhs), or left a held 0
  /// (±2: restart() releases the hold).
  [[nodiscard]] bool crosses_rhs(std::span<const int> roots) const {
    const auto& in_rhs = info_.indicator_in_rhs;
    for (std::size_t i = 0; i < roots.size(); ++i)
      if (roots[i] != 0 && (std::abs(roots[i]) != 1 || i >= in_rhs.size() || in_rhs[i])) return true;
    return false;
  }
  void hold_zero_indicators(double t, std::span<const int> crossed, bool hold_crossed = false);
  bool chattering(double t, std::span<const int> roots);
  void held_crossings(double t, std::vector<int>& roots);
  bool handle_event(double t, std::span<const int> crossings, bool time_event, bool& changed);
  Eigen::MatrixXd sensitivities() const;
  bool apply_jump(double t, detail::SensitivityJump& jump);
  bool discrete_sensitivities_carried(double t, const std::string& unsupported, const std::string& moved);
  void harvest_statistics();
  void fail(SimulationStatus status, std::string message);
  void fail_cvode(int flag, const char* call, double t);
  std::span<const double> states() const { return {x_->data(), nx_}; }

  Model& model_;
  const ModelInfo& info_;
  const Inputs& inputs_;
  std::vector<double> p_;  // CVODES' difference quotients perturb it in place
  const OutputGrid& grid_;
  const SimulationOptions& options_;
  std::size_t nx_, nu_, ny_, ng_;
  std::vector<double> u_, y_;
  double segment_end_ = 0.0;  // inputs are left limits at t >= segment_end_
  // Indicators exactly 0 where the integration (re)started: CVODES would take
  // them as inactive until they leave 0 and report no root then, so they are
  // given to it as |g| - kHeldZero while held (hold_zero_indicators).
  std::vector<char> held_;
  double chatter_start_ = std::numeric_limits<double>::quiet_NaN();  // see chattering()
  long chatter_roots_ = 0;
  std::vector<long> chatter_crossings_;
  std::vector<double> g_;

  SensitivityMethod sens_method_ = SensitivityMethod::none;
  std::vector<int> sens_params_;           // J
  std::vector<std::size_t> sens_states_;   // model_states: state index of S(i, j), row-major
  int ism_ = CV_STAGGERED;
  std::vector<double> fx_values_, fp_values_, hx_values_, hp_values_;
  std::vector<double> event_time_derivatives_;  // dτ/dp_j of the last event handled with sensitivities

  Context context_;
  Cvode cvode_;
  std::optional<detail::CvodeJacobian> jacobian_;  ///< how ∂f/∂x reaches CVODES' matrix
  std::unique_ptr<Vector> x_;
  std::unique_ptr<VectorArray> s_;
  std::vector<double> pbar_;
  std::string last_error_;
  SimulationResult result_;
};

int Simulation::rhs_callback(double t, N_Vector x, N_Vector xdot, void* self) {
  auto& sim = *static_cast<Simulation*>(self);
  sim.evaluate_inputs(t);
  std::span<double> out(N_VGetArrayPointer(xdot), sim.nx_);
  sim.model_.rhs(t, {N_VGetArrayPointer(x), sim.nx_}, sim.u_, sim.p_, out);
  if (sim.nx_ == 0) N_VGetArrayPointer(xdot)[0] = 0.0;  // the placeholder state of a model without states
  if (all_finite(out)) return 0;
  auto& point = sim.result_.non_finite_rhs.emplace();
  point.t = t;
  point.x.assign(N_VGetArrayPointer(x), N_VGetArrayPointer(x) + sim.nx_);
  point.u = sim.u_;
  return 1;  // recoverable: CVODES retries with a smaller step
}

int Simulation::jacobian_callback(double t, N_Vector x, N_Vector fx, SUNMatrix jac, void* self,
                                  N_Vector, N_Vector, N_Vector) {
  auto& sim = *static_cast<Simulation*>(self);
  sim.evaluate_inputs(t);
  sim.model_.jacobian_values(Jacobian::f_x, t, {N_VGetArrayPointer(x), sim.nx_}, sim.u_, sim.p_,
                             sim.fx_values_);
  if (!all_finite(sim.fx_values_)) return sim.difference_jacobian(t, x, fx, jac);
  sim.jacobian_->store(jac, sim.fx_values_);
  return 0;
}

/// The Jacobian by forward differences of the right-hand side, where the
/// model's own is not finite although f is: a formula whose derivative
/// overflows where the function does not (the MSL's regularised sign
/// 2/(1 + exp(z)) - 1 at z = 1000 is -1, its derivative inf/inf). Each state
/// steps by sqrt(eps)·max(|x|, nominal). Returns 1 (recoverable: CVODES
/// retries with a smaller step) if a difference is not finite either.
int Simulation::difference_jacobian(double t, N_Vector x, N_Vector fx, SUNMatrix jac) {
  const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
  const double* f0 = N_VGetArrayPointer(fx);
  std::vector<double> xs(N_VGetArrayPointer(x), N_VGetArrayPointer(x) + nx_), f(nx_), column(nx_);
  jacobian_->begin_columns(jac);
  for (std::size_t c = 0; c < nx_; ++c) {
    const double saved = xs[c];
    xs[c] += root_eps * std::max(std::abs(saved), std::abs(info_.states[c].nominal));
    const double step = xs[c] - saved;
    model_.rhs(t, xs, u_, p_, f);
    xs[c] = saved;
    for (std::size_t r = 0; r < nx_; ++r) {
      column[r] = (f[r] - f0[r]) / step;
      if (!std::isfinite(column[r])) return 1;
    }
    jacobian_->store_column(jac, static_cast<int>(c), column);
  }
  ++result_.statistics.difference_jacobians;
  return 0;
}

int Simulation::sensitivity_callback(int ns, double t, N_Vector x, N_Vector, N_Vector* s,
                                     N_Vector* sdot, void* self, N_Vector, N_Vector) {
  auto& sim = *static_cast<Simulation*>(self);
  sim.evaluate_inputs(t);
  std::span<const double> xs(N_VGetArrayPointer(x), sim.nx_);
  const Sparsity& fx = sim.model_.jacobian_sparsity(Jacobian::f_x);
  const Sparsity& fp = sim.model_.jacobian_sparsity(Jacobian::f_p);
  sim.model_.jacobian_values(Jacobian::f_x, t, xs, sim.u_, sim.p_, sim.fx_values_);
  sim.model_.jacobian_values(Jacobian::f_p, t, xs, sim.u_, sim.p_, sim.fp_values_);
  for (int j = 0; j < ns; ++j) {
    const double* sj = N_VGetArrayPointer(s[j]);
    double* out = N_VGetArrayPointer(sdot[j]);
    std::fill(out, out + sim.nx_, 0.0);
    for (int c = 0; c < fx.cols; ++c) {  // out += f_x · s_j
      if (sj[c] == 0.0) continue;
      for (int k = fx.col_start[c]; k < fx.col_start[c + 1]; ++k)
        out[fx.row_index[k]] += sim.fx_values_[k] * sj[c];
    }
    int pj = sim.sens_params_[j];  // out += f_p(:, p_j)
    for (int k = fp.col_start[pj]; k < fp.col_start[pj + 1]; ++k)
      out[fp.row_index[k]] += sim.fp_values_[k];
    if (!all_finite({out, sim.nx_})) return 1;
  }
  return 0;
}

int Simulation::root_callback(double t, N_Vector x, double* g, void* self) {
  auto& sim = *static_cast<Simulation*>(self);
  sim.evaluate_inputs(t);
  std::span<double> out(g, sim.ng_);
  sim.model_.event_indicators(t, {N_VGetArrayPointer(x), sim.nx_}, sim.u_, sim.p_, out);
  for (std::size_t i = 0; i < sim.ng_; ++i)
    if (sim.held_[i]) out[i] = std::abs(out[i]) - kHeldZero;
  return all_finite(out) ? 0 : -1;
}

// A relation on an indicator that is exactly 0 when the integration starts
// (a ramp's force from t = 2 in `free = fn <= 0`, a speed at rest) changes
// value when the indicator leaves 0 without changing sign: Modelica has an
// event there, CVODES none. Held indicators are watched as |g| - kHeldZero.
// Not an indicator that crossed at the event just handled: its relations
// already took the value of the side it crossed to (CVODES may well return
// the root with g exactly 0), and leaving 0 to that side changes nothing.
// Left to its other side it is lost, as before. A when-condition `a >= b`
// on a held indicator leaving 0 upwards fires once more (its value at 0 was
// already true; the handler takes the value before from the other side).
//
// `hold_crossed`: the crossed indicators are held too if they are within
// kHeldZero of 0 (the same root returned again, see run()).
void Simulation::hold_zero_indicators(double t, std::span<const int> crossed, bool hold_crossed) {
  held_.assign(ng_, 0);
  if (ng_ == 0) return;
  g_.resize(ng_);
  inputs_.evaluate(t, u_);  // a segment starts here: right limits
  model_.event_indicators(t, states(), u_, p_, g_);
  for (std::size_t i = 0; i < ng_; ++i) {
    const bool was_crossed = i < crossed.size() && crossed[i] != 0;
    held_[i] = was_crossed ? hold_crossed && std::abs(g_[i]) < kHeldZero : g_[i] == 0.0;
  }
}

// Roots that follow each other without time moving on end the run: a
// relation that switches its own indicator back (a sliding mode, `der(x) =
// if x > 0 then -1 else 1`) gives a root every few nanoseconds or ulp, most
// of them changing no discrete variable, so max_events never counts them and
// nothing else ends the run. kChatterRoots roots within kChatterSpan of the
// interval (100000 within 0.3 ms of a 3 s run: 10⁹ such roots to reach its
// end) are chattering; the message names the indicator crossed most often.
// A chattering that ends by itself runs on: the MSL's Spice3 CascodeCircuit
// has some 4000 roots within 1e-10 s of its 0.2 s, then none.
bool Simulation::chattering(double t, std::span<const int> roots) {
  const double span = kChatterSpan * (grid_.times.back() - grid_.times.front());
  if (!(t - chatter_start_ <= span)) {
    chatter_start_ = t;
    chatter_roots_ = 0;
    chatter_crossings_.assign(ng_, 0);
  }
  ++chatter_roots_;
  for (std::size_t i = 0; i < ng_ && i < roots.size(); ++i)
    if (roots[i] != 0) ++chatter_crossings_[i];
  if (chatter_roots_ < kChatterRoots) return false;
  const auto most = static_cast<std::size_t>(
      std::max_element(chatter_crossings_.begin(), chatter_crossings_.end()) - chatter_crossings_.begin());
  const auto& texts = info_.indicator_text;
  const std::string which = most < texts.size() && !texts[most].empty()
                                ? fmt::format("of event indicator {}, {}", most, texts[most])
                                : fmt::format("of event indicator {}", most);
  fail(SimulationStatus::event_limit,
       fmt::format("chattering at t = {}: {} state events within {} s, {} of them crossings {}; a relation "
                   "whose switch moves its own indicator back (a sliding mode) has no solution by "
                   "events: smooth the switch, give it hysteresis, or write it in noEvent()",
                   t, chatter_roots_, t - chatter_start_, chatter_crossings_[most], which));
  return true;
}

// CVODES reports a held indicator's |g| - kHeldZero rising through 0; the
// model's crossing direction is the sign g left 0 with.
void Simulation::held_crossings(double t, std::vector<int>& roots) {
  bool any = false;
  for (std::size_t i = 0; i < ng_; ++i) any = any || (held_[i] && roots[i] != 0);
  if (!any) return;
  evaluate_inputs(t);
  model_.event_indicators(t, states(), u_, p_, g_);
  for (std::size_t i = 0; i < ng_; ++i)
    if (held_[i] && roots[i] != 0) roots[i] = g_[i] > 0 ? 2 : -2;  // EventCause: left a held 0
}

void Simulation::error_callback(int code, const char*, const char* function, char* msg,
                                void* self) {
  if (code < 0) static_cast<Simulation*>(self)->last_error_ = fmt::format("{}: {}", function, msg);
}

void Simulation::evaluate_inputs(double t) {
  if (t >= segment_end_)
    inputs_.evaluate_before(t, u_);
  else
    inputs_.evaluate(t, u_);
}

std::string Simulation::validate() const {
  const auto& times = grid_.times;
  if (times.empty()) return "output grid is empty";
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k])) return fmt::format("output time {} is not finite", k);
    if (k > 0 && times[k] < times[k - 1]) return "output times decrease";
  }
  if (inputs_.size() != nu_)
    return fmt::format("{} input signals for {} model inputs", inputs_.size(), nu_);
  if (p_.size() != info_.parameters.size())
    return fmt::format("{} parameter values for {} model parameters", p_.size(),
                       info_.parameters.size());
  if (!(options_.relative_tolerance > 0.0) || !(options_.absolute_tolerance > 0.0))
    return "tolerances must be positive";
  const auto& sens = options_.sensitivities;
  for (std::size_t j : sens.parameters)
    if (j >= p_.size()) return fmt::format("sensitivity parameter index {} out of range", j);
  if ((sens.method == SensitivityMethod::cvodes_analytic ||
       sens.method == SensitivityMethod::cvodes_difference) &&
      sens.parameters.empty())
    return "CVODES sensitivities need a non-empty parameter list";
  // CVODES' f_x s + f_p misses the delayed sensitivities: the compiled
  // sensitivity states carry them (delay(∂e/∂p, T)).
  if (info_.num_delays > 0 && (sens.method == SensitivityMethod::cvodes_analytic ||
                               sens.method == SensitivityMethod::cvodes_difference))
    return fmt::format("model '{}' calls delay(): its sensitivities need the compiled sensitivity "
                       "states (mocompile --sensitivities), not CVODES' own",
                       info_.name);
  return {};
}

void Simulation::fail(SimulationStatus status, std::string message) {
  result_.status = status;
  result_.message = std::move(message);
}

void Simulation::fail_cvode(int flag, const char* call, double t) {
  char* name = CVodeGetReturnFlagName(flag);  // malloc'ed by SUNDIALS: the caller frees it
  std::string flag_name = name ? name : "unknown flag";
  std::free(name);
  fail(status_of(flag), fmt::format("{} failed at t = {} ({}){}{}", call, t, flag_name,
                                    last_error_.empty() ? "" : ": ", last_error_));
}

bool Simulation::set_up() {
  double t0 = grid_.times.front();
  // A model without states (an algebraic model) is integrated with one
  // placeholder state, der = 0, never recorded: every output time and event
  // is then an algebraic solve at that time.
  auto n = static_cast<sunindextype>(std::max<std::size_t>(nx_, 1));
  x_ = std::make_unique<Vector>(n, context_.ctx);
  N_VConst(0.0, x_->v);
  std::span<double> x(x_->data(), nx_);
  model_.initial_state(t0, u_, p_, x);  // u_ holds u(t0)

  const auto& sens = options_.sensitivities;
  sens_method_ = sens.method;
  ism_ = sens.staggered ? CV_STAGGERED : CV_SIMULTANEOUS;
  fx_values_.resize(static_cast<std::size_t>(model_.jacobian_sparsity(Jacobian::f_x).nnz()));
  fp_values_.resize(static_cast<std::size_t>(model_.jacobian_sparsity(Jacobian::f_p).nnz()));
  hx_values_.resize(static_cast<std::size_t>(model_.jacobian_sparsity(Jacobian::h_x).nnz()));
  hp_values_.resize(static_cast<std::size_t>(model_.jacobian_sparsity(Jacobian::h_p).nnz()));

  if (sens_method_ == SensitivityMethod::model_states) {
    // J: the requested parameters, or all that have sensitivity states.
    std::vector<std::size_t> params = sens.parameters;
    if (params.empty()) {
      for (const auto& s : info_.states)
        if (s.sensitivity) params.push_back(s.sensitivity->parameter);
      std::sort(params.begin(), params.end());
      params.erase(std::unique(params.begin(), params.end()), params.end());
    }
    std::size_t nb = info_.num_base_states();
    sens_states_.assign(nb * params.size(), nx_);
    for (std::size_t k = 0; k < nx_; ++k) {
      const auto& s = info_.states[k].sensitivity;
      if (!s) continue;
      auto it = std::find(params.begin(), params.end(), s->parameter);
      if (it != params.end() && s->state < nb)
        sens_states_[s->state * params.size() + static_cast<std::size_t>(it - params.begin())] = k;
    }
    // The compiler emits only structurally nonzero sensitivities: a missing
    // S(i, j) is identically zero. A parameter with none at all is an error.
    for (std::size_t j = 0; j < params.size(); ++j) {
      bool any = false;
      for (std::size_t i = 0; i < nb; ++i) any = any || sens_states_[i * params.size() + j] != nx_;
      if (!any) {
        fail(SimulationStatus::invalid_problem,
             fmt::format("model has no sensitivity states for parameter {}",
                         info_.parameters[params[j]].name));
        return false;
      }
    }
    for (std::size_t j : params) sens_params_.push_back(static_cast<int>(j));
  } else if (sens_method_ != SensitivityMethod::none) {
    for (std::size_t j : sens.parameters) sens_params_.push_back(static_cast<int>(j));
  }
  result_.sensitivity_parameters.assign(sens_params_.begin(), sens_params_.end());

  cvode_.mem = CVodeCreate(CV_BDF, context_.ctx);
  if (!cvode_.mem) {
    fail(SimulationStatus::solver_error, "CVodeCreate failed (out of memory)");
    return false;
  }
  void* cv = cvode_.mem;
  CVodeSetErrHandlerFn(cv, error_callback, this);
  int flag = CVodeInit(cv, rhs_callback, t0, x_->v);
  if (flag != CV_SUCCESS) return fail_cvode(flag, "CVodeInit", t0), false;
  CVodeSetUserData(cv, this);
  Vector atol(n, context_.ctx);
  N_VConst(options_.absolute_tolerance, atol.v);
  for (std::size_t i = 0; i < nx_; ++i)
    atol.data()[i] = options_.absolute_tolerance * std::abs(info_.states[i].nominal);
  CVodeSVtolerances(cv, options_.relative_tolerance, atol.v);
  CVodeSetMaxNumSteps(cv, options_.max_steps);
  double max_step = options_.max_step;
  if (!(max_step > 0.0) && nx_ == 0 && grid_.times.size() > 1) {
    // Without states nothing limits the step: keep the algebraic solves (and
    // their Newton guesses) near the output times, one interval at a time.
    max_step = (grid_.times.back() - t0) / static_cast<double>(grid_.times.size() - 1);
  }
  if (info_.num_delays > 0) {
    // Every point t − T a step reads lies in the recorded past.
    const double shortest = model_.shortest_delay();
    if (!(shortest > 0.0)) {
      fail(SimulationStatus::invalid_problem,
           fmt::format("model '{}': a delay() has a delay time that is not positive, or exceeds its "
                       "delayMax, at these parameters",
                       info_.name));
      return false;
    }
    max_step = max_step > 0.0 ? std::min(max_step, shortest) : shortest;
  }
  if (max_step > 0.0) CVodeSetMaxStep(cv, max_step);

  jacobian_.emplace(model_.jacobian_sparsity(Jacobian::f_x), n, options_.linear_solver, options_.use_model_jacobian);
  result_.statistics.sparse_linear_solver = jacobian_->sparse();
  cvode_.matrix = jacobian_->make_matrix(context_.ctx);
  cvode_.solver = cvode_.matrix ? jacobian_->make_solver(x_->v, cvode_.matrix, context_.ctx) : nullptr;
  if (!cvode_.solver) {
    fail(SimulationStatus::linear_solver_failure, "SUNDIALS could not create the integrator's linear solver");
    return false;
  }
  flag = CVodeSetLinearSolver(cv, cvode_.solver, cvode_.matrix);
  if (flag != CV_SUCCESS) return fail_cvode(flag, "CVodeSetLinearSolver", t0), false;
  if (options_.use_model_jacobian) CVodeSetJacFn(cv, jacobian_callback);

  if (ng_ > 0) {
    flag = CVodeRootInit(cv, static_cast<int>(ng_), root_callback);
    if (flag != CV_SUCCESS) return fail_cvode(flag, "CVodeRootInit", t0), false;
    CVodeSetNoInactiveRootWarn(cv);
  }
  hold_zero_indicators(t0, {});

  if (sens_method_ == SensitivityMethod::cvodes_analytic ||
      sens_method_ == SensitivityMethod::cvodes_difference) {
    int ns = static_cast<int>(sens_params_.size());
    s_ = std::make_unique<VectorArray>(ns, x_->v);
    // S(t0) = ∂x0/∂p_J
    const Sparsity& x0p = model_.jacobian_sparsity(Jacobian::x0_p);
    std::vector<double> x0p_values(static_cast<std::size_t>(x0p.nnz()));
    model_.jacobian_values(Jacobian::x0_p, t0, x, u_, p_, x0p_values);
    for (int j = 0; j < ns; ++j) {
      N_VConst(0.0, s_->v[j]);
      double* sj = N_VGetArrayPointer(s_->v[j]);
      int pj = sens_params_[j];
      for (int k = x0p.col_start[pj]; k < x0p.col_start[pj + 1]; ++k)
        sj[x0p.row_index[k]] = x0p_values[k];
    }
    bool analytic = sens_method_ == SensitivityMethod::cvodes_analytic;
    flag = CVodeSensInit(cv, ns, ism_, analytic ? sensitivity_callback : nullptr, s_->v);
    if (flag != CV_SUCCESS) return fail_cvode(flag, "CVodeSensInit", t0), false;
    pbar_.clear();
    for (int pj : sens_params_) pbar_.push_back(p_[pj] != 0.0 ? std::abs(p_[pj]) : 1.0);
    flag = CVodeSetSensParams(cv, analytic ? nullptr : p_.data(), pbar_.data(),
                              analytic ? nullptr : sens_params_.data());
    if (flag != CV_SUCCESS) return fail_cvode(flag, "CVodeSetSensParams", t0), false;
    CVodeSensEEtolerances(cv);
    CVodeSetSensErrCon(cv, options_.sensitivities.error_control ? SUNTRUE : SUNFALSE);
  }
  // S_d(t0): the when-clauses that fired at initialisation (a sample-and-hold
  // on initial()) set the discrete sensitivities.
  if (sens_method_ != SensitivityMethod::none && !sens_params_.empty() &&
      model_.provides_event_tangents()) {
    std::string moved;
    const std::string unsupported = detail::initial_discrete_sensitivities(
        model_, t0, states(), u_, p_, sensitivities(), sens_params_, moved);
    if (!discrete_sensitivities_carried(t0, unsupported, moved)) return false;
  }
  return true;
}

void Simulation::record(double t) {
  inputs_.evaluate(t, u_);
  std::span<const double> x = states();
  model_.outputs(t, x, u_, p_, y_);
  std::vector<double> row(x.begin(), x.end());
  row.insert(row.end(), y_.begin(), y_.end());
  result_.trajectory.add_row(t, row);
  if (sens_method_ == SensitivityMethod::none) return;

  // S_x: from CVODES' vectors or from the model's sensitivity states.
  auto ns = static_cast<Eigen::Index>(sens_params_.size());
  Eigen::MatrixXd sx;
  if (sens_method_ == SensitivityMethod::model_states) {
    auto nb = static_cast<Eigen::Index>(info_.num_base_states());
    sx.resize(nb, ns);
    for (Eigen::Index i = 0; i < nb; ++i)
      for (Eigen::Index j = 0; j < ns; ++j)
        sx(i, j) = sens_states_[static_cast<std::size_t>(i * ns + j)] == nx_
                       ? 0.0  // structurally zero
                       : x[sens_states_[static_cast<std::size_t>(i * ns + j)]];
  } else {
    sx.resize(static_cast<Eigen::Index>(nx_), ns);
    for (Eigen::Index j = 0; j < ns; ++j)
      sx.col(j) = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(s_->v[j]),
                                                    static_cast<Eigen::Index>(nx_));
  }
  // S_y = ∂h/∂x · S_x + ∂h/∂p_J (columns of h_x beyond S_x's rows are sensitivity states: skipped)
  Eigen::MatrixXd sy = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(ny_), ns);
  const Sparsity& hx = model_.jacobian_sparsity(Jacobian::h_x);
  const Sparsity& hp = model_.jacobian_sparsity(Jacobian::h_p);
  model_.jacobian_values(Jacobian::h_x, t, x, u_, p_, hx_values_);
  model_.jacobian_values(Jacobian::h_p, t, x, u_, p_, hp_values_);
  for (int c = 0; c < std::min<int>(hx.cols, static_cast<int>(sx.rows())); ++c)
    for (int k = hx.col_start[c]; k < hx.col_start[c + 1]; ++k)
      sy.row(hx.row_index[k]) += hx_values_[k] * sx.row(c);
  for (Eigen::Index j = 0; j < ns; ++j) {
    int pj = sens_params_[static_cast<std::size_t>(j)];
    for (int k = hp.col_start[pj]; k < hp.col_start[pj + 1]; ++k)
      sy(hp.row_index[k], j) += hp_values_[k];
  }
  result_.state_sensitivities.push_back(std::move(sx));
  result_.output_sensitivities.push_back(std::move(sy));
}

void Simulation::harvest_statistics() {
  void* cv = cvode_.mem;
  auto& st = result_.statistics;
  long v = 0;
  if (CVodeGetNumSteps(cv, &v) == CV_SUCCESS) st.steps += v;
  if (CVodeGetNumRhsEvals(cv, &v) == CV_SUCCESS) st.rhs_evaluations += v;
  if (CVodeGetNumJacEvals(cv, &v) == CV_SUCCESS) st.jacobian_evaluations += v;
  if (CVodeGetNumErrTestFails(cv, &v) == CV_SUCCESS) st.error_test_failures += v;
  if (CVodeGetNumNonlinSolvConvFails(cv, &v) == CV_SUCCESS)
    st.nonlinear_convergence_failures += v;
  if (s_ && CVodeGetSensNumRhsEvals(cv, &v) == CV_SUCCESS) st.sensitivity_rhs_evaluations += v;
}

// Re-initialises CVODES at t from the current x (and S): its counters restart.
// `crossed`: the crossings of the event just handled (none after a stop);
// `hold_crossed`: see hold_zero_indicators().
bool Simulation::restart(double t, std::span<const int> crossed, bool hold_crossed) {
  harvest_statistics();
  int flag = CVodeReInit(cvode_.mem, t, x_->v);
  if (flag != CV_SUCCESS) return fail_cvode(flag, "CVodeReInit", t), false;
  if (s_) {
    flag = CVodeSensReInit(cvode_.mem, ism_, s_->v);
    if (flag != CV_SUCCESS) return fail_cvode(flag, "CVodeSensReInit", t), false;
  }
  ++result_.statistics.restarts;
  hold_zero_indicators(t, crossed, hold_crossed);
  return true;
}

// Runs the handler (with event iteration) at t; `changed` says whether the
// integrator must restart. Returns false if the simulation must stop.
bool Simulation::handle_event(double t, std::span<const int> crossings, bool time_event,
                              bool& changed) {
  inputs_.evaluate(t, u_);
  std::span<double> x(x_->data(), nx_);
  EventCause cause{t, crossings, time_event};
  changed = false;
  bool terminate = false;
  std::string terminate_message;
  std::optional<detail::SensitivityJump> jump;
  // Without event tangents only an event that changes nothing (a time event
  // of delay(), a model without when-clauses) keeps the sensitivities.
  bool without_tangents = false;
  if (sens_method_ != SensitivityMethod::none && !sens_params_.empty()) {
    if (model_.provides_event_tangents()) {
      std::vector<double> udot(u_.size());  // an input moves with the event time: g_u u̇
      inputs_.derivative_before(t, udot);
      jump.emplace(model_, t, states(), u_, udot, p_, crossings, sensitivities(), sens_params_);
    } else {
      without_tangents = true;
    }
  }
  for (int iteration = 0;; ++iteration) {
    if (iteration == options_.max_event_iterations) {
      fail(SimulationStatus::event_iteration_limit,
           fmt::format("event at t = {}: discrete variables still changing after {} "
                       "handler iterations",
                       t, options_.max_event_iterations));
      return false;
    }
    EventResponse response =
        jump ? jump->handle(cause, x, u_, p_) : model_.handle_event(cause, x, u_, p_);
    changed = changed || response.discrete_changed || response.states_reinit;
    if (response.terminate && !terminate) terminate_message = response.message;
    terminate = terminate || response.terminate;
    if (!response.discrete_changed) break;
    cause = EventCause{t, {}, false};
  }
  if (without_tangents && changed) {
    fail(SimulationStatus::invalid_problem,
         fmt::format("event at t = {}: model '{}' gives no event tangents, so its "
                     "sensitivities cannot be carried through events",
                     t, info_.name));
    return false;
  }
  if (changed || time_event || terminate) {
    result_.event_times.push_back(t);
    if (++result_.statistics.events > options_.max_events) {
      fail(SimulationStatus::event_limit,
           fmt::format("more than {} events by t = {} (chattering or Zeno behaviour?)",
                       options_.max_events, t));
      return false;
    }
  }
  if (!all_finite(states())) {
    fail(SimulationStatus::rhs_failure, fmt::format("event at t = {} set a non-finite state", t));
    return false;
  }
  if (jump && !apply_jump(t, *jump)) return false;
  event_time_derivatives_.clear();
  if (jump) event_time_derivatives_ = jump->event_time_derivatives();
  if (terminate) {
    fail(SimulationStatus::terminated_by_model,
         fmt::format("terminated by the model at t = {}{}", t,
                     terminate_message.empty() ? "" : ": " + terminate_message));
    return false;
  }
  return true;
}

// S⁻ as a matrix: base states × J (model_states) or states × J (CVODES).
Eigen::MatrixXd Simulation::sensitivities() const {
  const auto ns = static_cast<Eigen::Index>(sens_params_.size());
  if (sens_method_ != SensitivityMethod::model_states) {
    Eigen::MatrixXd sx(static_cast<Eigen::Index>(nx_), ns);
    for (Eigen::Index j = 0; j < ns; ++j)
      sx.col(j) = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(s_->v[j]),
                                                    static_cast<Eigen::Index>(nx_));
    return sx;
  }
  const auto nb = static_cast<Eigen::Index>(info_.num_base_states());
  Eigen::MatrixXd sx = Eigen::MatrixXd::Zero(nb, ns);
  for (Eigen::Index i = 0; i < nb; ++i)
    for (Eigen::Index j = 0; j < ns; ++j)
      if (std::size_t k = sens_states_[static_cast<std::size_t>(i * ns + j)]; k != nx_)
        sx(i, j) = x_->data()[k];
  return sx;
}

// A discrete variable that moves with the parameters (a sample-and-hold) has
// its sensitivity carried only by discrete sensitivities, which only the
// model's own sensitivity states read: `unsupported` names one without them,
// `moved` one with them (refused under CVODES). True if neither stops the run.
bool Simulation::discrete_sensitivities_carried(double t, const std::string& unsupported,
                                                const std::string& moved) {
  const bool cvodes = sens_method_ != SensitivityMethod::model_states;
  const std::string& name = unsupported.empty() && cvodes ? moved : unsupported;
  if (name.empty()) return true;
  fail(SimulationStatus::invalid_problem,
       fmt::format("event at t = {}: discrete variable '{}' takes a value that depends on the "
                   "states, parameters or time; sensitivities through it are carried only by "
                   "the sensitivity states of a model compiled with sensitivities to these "
                   "parameters (SensitivityMethod::model_states){}",
                   t, name, cvodes ? ", not by CVODES' sensitivities" : ""));
  return false;
}

// S⁺ after the handler: written back where S⁻ was read from.
bool Simulation::apply_jump(double t, detail::SensitivityJump& jump) {
  if (!jump.failure().empty()) {
    fail(SimulationStatus::invalid_problem,
         fmt::format("event at t = {}: {}; sensitivities through it are not supported", t, jump.failure()));
    return false;
  }
  if (!discrete_sensitivities_carried(t, jump.unsupported(), jump.moved_discrete())) return false;
  jump.finish_discrete();
  const Eigen::MatrixXd sx = jump.finish(t, states(), u_, p_);
  if (!sx.allFinite()) {
    fail(SimulationStatus::rhs_failure,
         fmt::format("event at t = {}: non-finite sensitivity jump", t));
    return false;
  }
  const auto ns = sx.cols();
  for (Eigen::Index j = 0; j < ns; ++j) {
    if (sens_method_ != SensitivityMethod::model_states) {
      Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(s_->v[j]), sx.rows()) = sx.col(j);
      continue;
    }
    for (Eigen::Index i = 0; i < sx.rows(); ++i) {
      const std::size_t k = sens_states_[static_cast<std::size_t>(i * ns + j)];
      if (k != nx_) {
        x_->data()[k] = sx(i, j);
      } else if (sx(i, j) != 0.0) {
        fail(SimulationStatus::invalid_problem,
             fmt::format("event at t = {}: d({})/d({}) jumps to {}, but the model has no "
                         "sensitivity state for it",
                         t, info_.states[static_cast<std::size_t>(i)].name,
                         info_.parameters[static_cast<std::size_t>(sens_params_[static_cast<std::size_t>(j)])].name,
                         sx(i, j)));
        return false;
      }
    }
  }
  return true;
}

SimulationResult Simulation::run() {
  auto wall_start = std::chrono::steady_clock::now();
  std::vector<std::string> names;
  for (const auto& s : info_.states) names.push_back(s.name);
  for (const auto& y : info_.outputs) names.push_back(y.name);
  result_.trajectory = ResultTable(std::move(names));

  auto finish = [&]() -> SimulationResult {
    if (cvode_.mem) harvest_statistics();
    result_.warnings = model_.notes();
    result_.statistics.wall_time_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return std::move(result_);
  };

  if (std::string problem = validate(); !problem.empty()) {
    fail(SimulationStatus::invalid_problem, std::move(problem));
    return finish();
  }
  const std::vector<double>& times = grid_.times;
  const double t0 = times.front(), t_end = times.back();
  segment_end_ = t0;  // no integration yet: set_up() evaluates x0 only
  inputs_.evaluate(t0, u_);
  if (!set_up()) return finish();

  std::size_t next_out = 0;
  // A time within rounding of t counts as reached: CVODES refuses to step to
  // it (CV_TOO_CLOSE), and grids built on phases or elements (τ + s·len)
  // give such neighbours (1.35 and 1.3499999999999999).
  const auto reached = [](double target, double t) {
    return target <= t + 8 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
  };
  auto record_through = [&](double t) {
    while (next_out < times.size() && reached(times[next_out], t)) record(times[next_out++]);
  };
  record_through(t0);
  // A model with delay() takes one step at a time: each accepted step adds
  // to the delays' history, and the output times it passed are read from its
  // interpolant (CVodeGetDky). The history's cubic interpolation is no more
  // accurate than its points are dense: a step of order q adds q - 1 points
  // inside it from the same interpolant (a smooth solution lets BDF take
  // steps far longer than a cubic through their ends can follow). Before and
  // after an event's handler the history gets the values before and after it.
  const bool one_step = info_.num_delays > 0;
  std::vector<double> x_keep;
  auto record_passed = [&](double t) {
    // Output times before t (not within rounding of it: record_through's).
    while (next_out < times.size() && !reached(t, times[next_out])) {
      const double t_out = times[next_out++];
      x_keep.assign(x_->data(), x_->data() + nx_);
      if (CVodeGetDky(cvode_.mem, t_out, 0, x_->v) == CV_SUCCESS) record(t_out);
      std::copy(x_keep.begin(), x_keep.end(), x_->data());
    }
  };
  // At a state event the relations on the crossed indicators take their
  // values from the crossing: before the handler as before it, after as after.
  std::vector<int> relations;
  double recorded = t0;  // the history's last time
  auto record_inside = [&](double t) {
    int order = 1;
    double step = 0.0;
    if (CVodeGetLastOrder(cvode_.mem, &order) != CV_SUCCESS || CVodeGetLastStep(cvode_.mem, &step) != CV_SUCCESS) return;
    const double from = std::max(recorded, t - step);
    x_keep.assign(x_->data(), x_->data() + nx_);
    for (int i = 1; i < order; ++i) {
      const double ti = from + (t - from) * i / order;
      if (CVodeGetDky(cvode_.mem, ti, 0, x_->v) != CV_SUCCESS) continue;
      evaluate_inputs(ti);
      model_.record_delays(ti, states(), u_, p_, {});
    }
    std::copy(x_keep.begin(), x_keep.end(), x_->data());
  };
  auto record_delays = [&](double t, bool after_event, std::span<const int> crossings = {}) {
    if (!one_step) return false;
    if (after_event)
      inputs_.evaluate(t, u_);
    else
      evaluate_inputs(t);
    relations.assign(crossings.size(), 0);
    for (std::size_t i = 0; i < crossings.size(); ++i)
      if (std::abs(crossings[i]) == 1) relations[i] = after_event ? crossings[i] : -crossings[i];
    recorded = t;
    return model_.record_delays(t, states(), u_, p_, relations);
  };

  const std::vector<double> breakpoints = inputs_.breakpoints(t0, t_end);
  std::size_t next_bp = 0;
  std::vector<int> roots(ng_);
  bool continued = false;  // the last root was passed over without a restart
  double last_root = std::numeric_limits<double>::quiet_NaN();
  void* cv = cvode_.mem;
  double t = t0;
  while (next_out < times.size()) {
    while (next_bp < breakpoints.size() && reached(breakpoints[next_bp], t)) ++next_bp;
    double t_break = next_bp < breakpoints.size() ? breakpoints[next_bp] : t_end;
    double t_event = model_.next_time_event(t);
    double t_stop = std::min({t_end, t_break, t_event});
    segment_end_ = t_stop;
    CVodeSetStopTime(cv, t_stop);

    for (;;) {  // integrate until t_stop or a state event
      double t_out = std::min(times[next_out], t_stop);
      double t_ret = t;
      int flag = CVode(cv, t_out, x_->v, &t_ret, one_step ? CV_ONE_STEP : CV_NORMAL);
      // Continued past a root without a restart, CVODES refuses an indicator
      // that is exactly 0 there and just after (CV_ILL_INPUT, "Root found at
      // and very near"): a restart makes it inactive until it leaves 0.
      if (flag == CV_ILL_INPUT && continued) {
        continued = false;
        if (!restart(t, roots)) return finish();
        continue;
      }
      continued = false;
      if (flag < 0) {
        fail_cvode(flag, "CVode", t_ret);
        return finish();
      }
      t = t_ret;
      if (s_) CVodeGetSens(cv, &t_ret, s_->v);
      if (one_step) {
        record_passed(t);
        record_inside(t);
      }
      if (flag != CV_ROOT_RETURN) record_delays(t, false);
      if (flag == CV_ROOT_RETURN) {
        CVodeGetRootInfo(cv, roots.data());
        held_crossings(t, roots);
        if (chattering(t, roots)) {
          record_through(t);
          return finish();
        }
        record_delays(t, false, roots);
        bool changed = false;
        if (!handle_event(t, roots, false, changed)) {
          record_through(t);
          return finish();
        }
        // A delayed expression that jumps at an event whose time moves with
        // p jumps T later at a time that moves too: S would jump there, and
        // the break's time event carries no such jump.
        if (record_delays(t, true, roots)) {
          for (std::size_t j = 0; j < event_time_derivatives_.size(); ++j)
            if (event_time_derivatives_[j] != 0.0) {
              fail(SimulationStatus::invalid_problem,
                   fmt::format("event at t = {}: a delay() of a value that jumps here, at a time that "
                               "depends on parameter {}; the sensitivities of the delayed jump are not "
                               "supported",
                               t, info_.parameters[static_cast<std::size_t>(sens_params_[j])].name));
              record_through(t);
              return finish();
            }
        }
        // Restart even if nothing discrete changed: a relation in the
        // continuous equations switched at this root, and CVODES' last step
        // (already taken past the root) used the right-hand side of before.
        // Not when nothing changed and no crossed indicator enters the
        // right-hand side: a restart (order 1, a tiny first step) per root
        // of an indicator that stays at 0 ± rounding (a switch's quench test
        // `abs(i) <= abs(v)*Goff or pre(quenched)`) costs accuracy.
        // The same root again, and again nothing changed: CVODES does not
        // move past an indicator at 0 ± rounding whose value there flips
        // with its Newton block's start (an idle machine's switch, the
        // MSL's SMEE_LoadDump): it is held like an indicator exactly 0.
        const bool repeated = !changed && t == last_root;
        last_root = t;
        if (repeated || changed || s_ || crosses_rhs(roots)) {
          if (!restart(t, roots, repeated)) return finish();
        } else {
          continued = true;
        }
        record_through(t);
        break;  // a discrete change may move the next time event
      }
      if (t < t_stop) {  // an output time inside the segment
        record_through(t);
        continue;
      }
      // At a stop: time event, input breakpoint, or the end.
      bool changed = false;
      if (t_event <= t && !handle_event(t, {}, true, changed)) {
        record_through(t);
        return finish();
      }
      record_delays(t, true);
      if (t < t_end && !restart(t)) return finish();
      record_through(t);
      break;
    }
  }
  return finish();
}

}  // namespace

SimulationResult simulate(Model& model, const Inputs& inputs, std::span<const double> p,
                          const OutputGrid& grid, const SimulationOptions& options) {
  return Simulation(model, inputs, p, grid, options).run();
}

}  // namespace mo::runtime
