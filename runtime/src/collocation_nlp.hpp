// The collocation NLP shared by optimal control, input design and estimation.
//
// Per experiment e, on elements [t_i, t_i + h_i], i = 0..n_e−1, with the
// collocation polynomials of collocation_scheme.hpp:
//   variables    b_i = x(t_i) (i = 0..n_e), X_ij = x(t_i + τ_j h_i) (j = 1..K),
//                u_c,β (one per control and block β), shared free parameters p_f,
//                plus extra variables that terms may add (e.g. an epigraph s);
//   collocation  Σ_k D_jk X_ik − h_i f(X_ij, u_i, p, t_ij) = 0   (X_i0 = b_i)
//   continuity   b_{i+1} − Σ_k ℓ_k(1) X_ik = 0
//   initial      b_0 − x0(p) = 0
//   bounds       state bounds on b and X, final-state bounds on b_{n_e};
// objective terms and further constraint blocks are added by the callers.
// A "point" is (experiment, element, τ): its state is Σ_k ℓ_k(τ) X_ik, linear
// in the variables, so derivatives of model outputs map through the ℓ_k.
#pragma once

#include "collocation_scheme.hpp"
#include "mo/runtime/optimize.hpp"
#include "sparse_assembler.hpp"

#include <Eigen/Sparse>
#include <memory>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

namespace mo::runtime::detail {

/// A problem description the NLP cannot transcribe; becomes invalid_problem.
class ProblemError : public std::invalid_argument {
public:
  using std::invalid_argument::invalid_argument;
};

/// What varies between experiments sharing the parameters.
struct ExperimentSetup {
  double t0 = 0.0, tf = 1.0;
  std::vector<FreeControl> controls;
  std::map<std::size_t, std::shared_ptr<const InputSignal>> fixed_inputs;
  std::map<std::size_t, Bounds> state_bounds;
  std::vector<FinalStateConstraint> final_state;
};

/// What is shared by all experiments.
struct NlpSetup {
  std::vector<double> parameters;  ///< all values; empty = model defaults
  std::vector<FreeParameter> free_parameters;
  CollocationOptions collocation;
};

/// An instant inside one element: its time and the interpolation weights ℓ_k(τ).
struct PointRef {
  int experiment = 0;
  int element = 0;
  double tau = 0.0;
  double time = 0.0;
  std::vector<double> basis;  ///< ℓ_k(τ), k = 0..K
  std::vector<double> point_basis;  ///< per-point controls: Lagrange weights of τ_1..τ_K at τ
};

/// z = (x, u, p) of a point mapped to NLP variables: z_a = Σ coeff·v[var] (+ constants).
using VariableMap = std::vector<std::vector<std::pair<int, double>>>;

class CollocationNlp;

/// A contribution to the objective.
class ObjectiveTerm {
public:
  virtual ~ObjectiveTerm() = default;
  /// The term's value at v (NaN makes Ipopt treat the point as an evaluation error).
  virtual double value(CollocationNlp& nlp, std::span<const double> v) = 0;
  /// Adds ∇ to `gradient`.
  virtual void gradient(CollocationNlp& nlp, std::span<const double> v,
                        std::span<double> gradient) = 0;
  /// True if hessian() is exact; otherwise the NLP uses L-BFGS.
  [[nodiscard]] virtual bool has_hessian(const CollocationNlp& nlp) const = 0;
  /// Adds factor·∇² (lower triangle) through `hessian`.
  virtual void hessian(CollocationNlp& nlp, std::span<const double> v, double factor,
                       SparseAssembler& hessian) = 0;
};

/// A block of constraint rows lo ≤ g(v) ≤ hi.
class ConstraintBlock {
public:
  virtual ~ConstraintBlock() = default;
  /// Number of rows.
  [[nodiscard]] virtual int rows() const = 0;
  /// lo and hi per row (equal for equalities).
  virtual void bounds(std::span<double> lo, std::span<double> hi) const = 0;
  /// g(v), rows() values.
  virtual void values(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) = 0;
  /// Adds the Jacobian entries with rows offset by `row0`.
  virtual void jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                        SparseAssembler& jac) = 0;
  /// True if hessian() is exact; otherwise the NLP uses L-BFGS.
  [[nodiscard]] virtual bool has_hessian(const CollocationNlp& nlp) const = 0;
  /// Adds Σ λ_r ∇² g_r (lower triangle).
  virtual void hessian(CollocationNlp& nlp, std::span<const double> v,
                       std::span<const double> lambda, SparseAssembler& hessian) = 0;
  /// Row scaling factors (default 1).
  virtual void scaling(std::span<double> s) const { std::fill(s.begin(), s.end(), 1.0); }
};

/// The variables, points and derivative mapping of the collocation NLP.
class CollocationNlp {
public:
  /// Transcribes the dynamics of every experiment; throws ProblemError on an
  /// inconsistent description.
  CollocationNlp(const Model& model, NlpSetup setup, std::vector<ExperimentSetup> experiments);

  // --- layout ------------------------------------------------------------------
  /// Number of NLP variables so far.
  [[nodiscard]] int num_variables() const { return static_cast<int>(lower_.size()); }
  /// Experiments sharing the parameters; elements and points per element.
  [[nodiscard]] int num_experiments() const { return static_cast<int>(experiments_.size()); }
  [[nodiscard]] int num_elements() const { return setup_.collocation.n_e; }
  [[nodiscard]] int num_points() const { return setup_.collocation.n_cp; }
  /// Nodes, derivative matrix, quadrature weights of the scheme.
  [[nodiscard]] const CollocationPolynomials& polynomials() const { return poly_; }
  /// The model's metadata (all experiments use clones of one model).
  [[nodiscard]] const ModelInfo& info() const { return models_.front()->info(); }
  /// The shared setup and experiment e's setup, as given.
  [[nodiscard]] const NlpSetup& setup() const { return setup_; }
  [[nodiscard]] const ExperimentSetup& experiment(int e) const { return experiments_[e].setup; }
  /// Experiment e's model instance (evaluation is non-const).
  [[nodiscard]] Model& model(int e) { return *models_[static_cast<std::size_t>(e)]; }
  [[nodiscard]] const Model& model(int e) const { return *models_[static_cast<std::size_t>(e)]; }
  /// Variable of state s at node k (0 = element start) of element i; i = n_e, k = 0 is b_{n_e}.
  [[nodiscard]] int state_var(int e, int i, int k, int s) const;
  /// Variable of control c on element i (of a per-point control: its first point).
  [[nodiscard]] int control_var(int e, int c, int i) const;
  /// Variable of per-point control c at collocation point j (0..n_cp−1) of element i.
  [[nodiscard]] int control_point_var(int e, int c, int i, int j) const;
  /// The collocation points τ_1..τ_K (without τ_0 = 0).
  [[nodiscard]] std::vector<double> collocation_points() const {
    return {poly_.tau.begin() + 1, poly_.tau.end()};
  }
  /// Variable of parameter j, or −1 if it is fixed.
  [[nodiscard]] int parameter_var(std::size_t j) const { return parameter_var_[j]; }
  /// Appends `count` variables; returns the first index.
  int add_variables(int count, Bounds bounds, double initial, double scale = 1.0);
  /// Scaling magnitude of each state of experiment e (nominal_traj or the attribute).
  [[nodiscard]] const std::vector<double>& state_nominal(int e) const {
    return experiments_[static_cast<std::size_t>(e)].nominal;
  }
  /// Start time and length of element i of experiment e.
  [[nodiscard]] double element_start(int e, int i) const;
  [[nodiscard]] double element_length(int e, int i) const;

  // --- points ------------------------------------------------------------------
  /// The point at τ ∈ [0, 1] of element i.
  [[nodiscard]] PointRef point(int e, int i, double tau) const;
  /// The point at time t (t0 ≤ t ≤ tf), in the element to its left at boundaries.
  [[nodiscard]] PointRef point_at(int e, double t) const;
  /// x at the point: Σ_k ℓ_k(τ) X_ik.
  void point_state(std::span<const double> v, const PointRef& pt, std::span<double> x) const;
  /// u at the point: element controls and fixed signals (left limit at τ = 1).
  void point_inputs(std::span<const double> v, const PointRef& pt, std::span<double> u) const;
  /// All parameter values: free ones from v, the others fixed.
  void parameters(std::span<const double> v, std::span<double> p) const;
  /// x0 of experiment e: the initial system at its start time with the
  /// inputs there (point_inputs at τ = 0 of the first element).
  void start_values(int e, std::span<const double> v, std::span<const double> p, std::span<double> x0);
  /// z = (x, u, p) → NLP variables at `pt`.
  [[nodiscard]] VariableMap variable_map(const PointRef& pt) const;
  /// Outputs y at the point.
  std::vector<double> outputs(std::span<const double> v, const PointRef& pt);
  /// ∂y/∂z at the point (ny × (nx+nu+np)) with the model's structural
  /// nonzeros only: a multi-phase model's dense one would be (outputs of all
  /// phases) × (states, inputs and parameters of all phases).
  Eigen::SparseMatrix<double, Eigen::RowMajor> output_jacobian(std::span<const double> v, const PointRef& pt);
  /// Adds scale·∇²_z(wᵀf or wᵀh) at the point, mapped to NLP variables.
  void add_model_hessian(Hessian which, std::span<const double> v, const PointRef& pt,
                         std::span<const double> weights, double scale, SparseAssembler& hess);

  // --- terms -------------------------------------------------------------------
  /// Adds a term to the objective (summed) / a block of constraint rows (appended).
  void add_objective(std::unique_ptr<ObjectiveTerm> term) { objective_.push_back(std::move(term)); }
  void add_constraints(std::unique_ptr<ConstraintBlock> block) {
    blocks_.push_back(std::move(block));
  }
  /// True if every term and block has an exact Hessian.
  [[nodiscard]] bool exact_hessian_possible() const;
  /// Factor Ipopt applies to the objective internally (obj_scaling_factor); default 1.
  [[nodiscard]] double objective_scaling() const { return objective_scaling_; }
  void set_objective_scaling(double factor) { objective_scaling_ = factor; }

  // --- the NLP -----------------------------------------------------------------
  /// Total rows of all constraint blocks.
  [[nodiscard]] int num_constraints() const;
  /// Bounds of the variables (±inf for none) and of the constraint rows.
  void variable_bounds(std::span<double> lo, std::span<double> hi) const;
  void constraint_bounds(std::span<double> lo, std::span<double> hi) const;
  /// The start point (from the initial-guess simulation); replaceable.
  [[nodiscard]] const std::vector<double>& initial_guess() const { return initial_; }
  void set_initial_guess(std::vector<double> v) { initial_ = std::move(v); }
  /// Ipopt user-scaling factors: 1/nominal for states, 1 otherwise; rows likewise.
  void variable_scaling(std::span<double> s) const { std::copy(scale_.begin(), scale_.end(), s.begin()); }
  void constraint_scaling(std::span<double> s) const;
  /// Objective, its gradient (overwritten), and the constraint values.
  double objective(std::span<const double> v);
  void objective_gradient(std::span<const double> v, std::span<double> g);
  void constraints(std::span<const double> v, std::span<double> g);
  /// Records (begin_record … finish_record) or fills the constraint Jacobian.
  void constraint_jacobian(std::span<const double> v, SparseAssembler& jac);
  /// Records or fills the lower triangle of the Lagrangian's Hessian.
  void lagrangian_hessian(std::span<const double> v, double obj_factor,
                          std::span<const double> lambda, SparseAssembler& hess);

private:
  struct Experiment {
    ExperimentSetup setup;
    std::vector<double> element_start, element_length;
    std::vector<std::vector<int>> control_block;  // per control: block of each element
    std::vector<int> control_offset;              // per control: first variable
    std::vector<double> nominal;                  // per state: scaling magnitude
    int state_offset = 0;
  };
  void check_setup();
  void layout_experiment(Experiment& ex);
  void initial_guess_from_simulation(int e);
  void apply_state_guesses(int e);
  void scale_by_trajectory(int e, const ResultTable& trajectory);

  NlpSetup setup_;
  CollocationPolynomials poly_;
  std::vector<std::unique_ptr<Model>> models_;
  std::vector<Experiment> experiments_;
  std::vector<int> parameter_var_;
  std::vector<double> lower_, upper_, initial_, scale_;
  double objective_scaling_ = 1.0;
  std::vector<std::unique_ptr<ObjectiveTerm>> objective_;
  std::vector<std::unique_ptr<ConstraintBlock>> blocks_;
};

}  // namespace mo::runtime::detail
