#include "ipopt_tnlp.hpp"

#include <IpIpoptCalculatedQuantities.hpp>
#include <IpIpoptData.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <span>

namespace mo::runtime::detail {
namespace {

using Clock = std::chrono::steady_clock;

bool all_finite(std::span<const double> values) {
  return std::all_of(values.begin(), values.end(), [](double x) { return std::isfinite(x); });
}

}  // namespace

CollocationTnlp::CollocationTnlp(CollocationNlp& nlp, bool exact_hessian, bool user_scaling,
                                 ProgressCallback progress)
    : nlp_(nlp), exact_hessian_(exact_hessian), user_scaling_(user_scaling),
      progress_(std::move(progress)), last_x_(nlp.initial_guess()) {
  jac_.begin_record();
  nlp_.constraint_jacobian(last_x_, jac_);
  jac_.finish_record();
  if (exact_hessian_) {
    std::vector<double> ones(std::size_t(nlp_.num_constraints()), 1.0);
    hess_.begin_record();
    nlp_.lagrangian_hessian(last_x_, 1.0, ones, hess_);
    hess_.finish_record();
  }
}

template <class F> bool CollocationTnlp::guarded(const char* what, F&& body) {
  auto start = Clock::now();
  bool ok = false;
  try {
    ok = body();
    if (!ok && evaluation_error_.empty())
      evaluation_error_ = std::string("non-finite value in ") + what;
  } catch (const std::exception& e) {
    evaluation_error_ = std::string(what) + ": " + e.what();
  }
  evaluation_seconds_ += std::chrono::duration<double>(Clock::now() - start).count();
  return ok;
}

bool CollocationTnlp::get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac,
                                   Ipopt::Index& nnz_h, IndexStyleEnum& style) {
  n = nlp_.num_variables();
  m = nlp_.num_constraints();
  nnz_jac = jac_.nnz();
  nnz_h = exact_hessian_ ? hess_.nnz() : 0;
  style = C_STYLE;
  return true;
}

bool CollocationTnlp::get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u,
                                      Ipopt::Index m, Ipopt::Number* g_l, Ipopt::Number* g_u) {
  nlp_.variable_bounds({x_l, std::size_t(n)}, {x_u, std::size_t(n)});
  nlp_.constraint_bounds({g_l, std::size_t(m)}, {g_u, std::size_t(m)});
  auto to_ipopt = [](double* v, Ipopt::Index count) {  // Ipopt's infinity is ±1e19
    for (Ipopt::Index k = 0; k < count; ++k) v[k] = std::clamp(v[k], -1e19, 1e19);
  };
  to_ipopt(x_l, n), to_ipopt(x_u, n), to_ipopt(g_l, m), to_ipopt(g_u, m);
  return true;
}

bool CollocationTnlp::get_scaling_parameters(Ipopt::Number& obj_scaling, bool& use_x_scaling,
                                             Ipopt::Index n, Ipopt::Number* x_scaling,
                                             bool& use_g_scaling, Ipopt::Index m,
                                             Ipopt::Number* g_scaling) {
  obj_scaling = 1.0;
  use_x_scaling = use_g_scaling = user_scaling_;
  if (user_scaling_) {
    nlp_.variable_scaling({x_scaling, std::size_t(n)});
    nlp_.constraint_scaling({g_scaling, std::size_t(m)});
  }
  return true;
}

bool CollocationTnlp::get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool,
                                         Ipopt::Number*, Ipopt::Number*, Ipopt::Index, bool,
                                         Ipopt::Number*) {
  if (init_x) std::copy(nlp_.initial_guess().begin(), nlp_.initial_guess().end(), x);
  return n == nlp_.num_variables();
}

bool CollocationTnlp::eval_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number& obj) {
  return guarded("objective", [&] {
    last_x_.assign(x, x + n);
    obj = nlp_.objective({x, std::size_t(n)});
    last_objective_ = obj;
    return std::isfinite(obj);
  });
}

bool CollocationTnlp::eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool,
                                  Ipopt::Number* grad) {
  return guarded("objective gradient", [&] {
    nlp_.objective_gradient({x, std::size_t(n)}, {grad, std::size_t(n)});
    return all_finite({grad, std::size_t(n)});
  });
}

bool CollocationTnlp::eval_g(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Index m,
                             Ipopt::Number* g) {
  return guarded("constraints", [&] {
    nlp_.constraints({x, std::size_t(n)}, {g, std::size_t(m)});
    return all_finite({g, std::size_t(m)});
  });
}

bool CollocationTnlp::eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Index,
                                 Ipopt::Index nele, Ipopt::Index* rows, Ipopt::Index* cols,
                                 Ipopt::Number* values) {
  if (!values) {
    std::copy(jac_.rows().begin(), jac_.rows().end(), rows);
    std::copy(jac_.cols().begin(), jac_.cols().end(), cols);
    return true;
  }
  return guarded("constraint Jacobian", [&] {
    jac_.begin_values({values, std::size_t(nele)});
    nlp_.constraint_jacobian({x, std::size_t(n)}, jac_);
    jac_.finish_values();
    return all_finite({values, std::size_t(nele)});
  });
}

bool CollocationTnlp::eval_h(Ipopt::Index n, const Ipopt::Number* x, bool,
                             Ipopt::Number obj_factor, Ipopt::Index m,
                             const Ipopt::Number* lambda, bool, Ipopt::Index nele,
                             Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* values) {
  if (!exact_hessian_) return false;
  if (!values) {
    std::copy(hess_.rows().begin(), hess_.rows().end(), rows);
    std::copy(hess_.cols().begin(), hess_.cols().end(), cols);
    return true;
  }
  return guarded("Lagrangian Hessian", [&] {
    hess_.begin_values({values, std::size_t(nele)});
    nlp_.lagrangian_hessian({x, std::size_t(n)}, obj_factor, {lambda, std::size_t(m)}, hess_);
    hess_.finish_values();
    return all_finite({values, std::size_t(nele)});
  });
}

void CollocationTnlp::finalize_solution(Ipopt::SolverReturn, Ipopt::Index n,
                                        const Ipopt::Number* x, const Ipopt::Number*,
                                        const Ipopt::Number*, Ipopt::Index, const Ipopt::Number*,
                                        const Ipopt::Number*, Ipopt::Number obj,
                                        const Ipopt::IpoptData*,
                                        Ipopt::IpoptCalculatedQuantities* cq) {
  if (x && n == nlp_.num_variables()) {
    last_x_.assign(x, x + n);
    last_objective_ = obj;
    finalized_ = true;
  }
  if (!cq) return;
  try {  // Ipopt's own unscaled max-norm residuals of its final iterate
    kkt_.primal_infeasibility = cq->unscaled_curr_nlp_constraint_violation(Ipopt::NORM_MAX);
    kkt_.dual_infeasibility = cq->unscaled_curr_dual_infeasibility(Ipopt::NORM_MAX);
    kkt_.complementarity = cq->unscaled_curr_complementarity(0.0, Ipopt::NORM_MAX);
  } catch (...) {  // no iterate to measure (e.g. a failure before the first one): stay NaN
    kkt_ = KktResiduals{};
  }
}

bool CollocationTnlp::intermediate_callback(Ipopt::AlgorithmMode mode, Ipopt::Index iter,
                                            Ipopt::Number obj, Ipopt::Number inf_pr,
                                            Ipopt::Number inf_du, Ipopt::Number, Ipopt::Number,
                                            Ipopt::Number, Ipopt::Number, Ipopt::Number,
                                            Ipopt::Index, const Ipopt::IpoptData*,
                                            Ipopt::IpoptCalculatedQuantities*) {
  if (!progress_) return true;
  return progress_(IterationInfo{int(iter), obj, inf_pr, inf_du,
                                 mode == Ipopt::RestorationPhaseMode});
}

}  // namespace mo::runtime::detail
