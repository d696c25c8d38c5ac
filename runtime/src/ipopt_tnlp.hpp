// Ipopt's TNLP view of a CollocationNlp: sizes, bounds, scaling, start, and
// the evaluation callbacks (exceptions and non-finite values become `false`).
#pragma once

#include "collocation_nlp.hpp"

#include <IpTNLP.hpp>

#include <chrono>

namespace mo::runtime::detail {

/// Adapter from CollocationNlp to Ipopt::TNLP.
class CollocationTnlp final : public Ipopt::TNLP {
public:
  /// Records the Jacobian (and with exact_hessian the Hessian) pattern at the initial guess.
  CollocationTnlp(CollocationNlp& nlp, bool exact_hessian, bool user_scaling,
                  ProgressCallback progress);

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac,
                    Ipopt::Index& nnz_h, IndexStyleEnum& style) override;
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m,
                       Ipopt::Number* g_l, Ipopt::Number* g_u) override;
  bool get_scaling_parameters(Ipopt::Number& obj_scaling, bool& use_x_scaling, Ipopt::Index n,
                              Ipopt::Number* x_scaling, bool& use_g_scaling, Ipopt::Index m,
                              Ipopt::Number* g_scaling) override;
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z,
                          Ipopt::Number* z_L, Ipopt::Number* z_U, Ipopt::Index m,
                          bool init_lambda, Ipopt::Number* lambda) override;
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number& obj) override;
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x,
                   Ipopt::Number* grad) override;
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m,
              Ipopt::Number* g) override;
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m,
                  Ipopt::Index nele, Ipopt::Index* rows, Ipopt::Index* cols,
                  Ipopt::Number* values) override;
  bool eval_h(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number obj_factor,
              Ipopt::Index m, const Ipopt::Number* lambda, bool new_lambda, Ipopt::Index nele,
              Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* values) override;
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x,
                         const Ipopt::Number* z_L, const Ipopt::Number* z_U, Ipopt::Index m,
                         const Ipopt::Number* g, const Ipopt::Number* lambda,
                         Ipopt::Number obj, const Ipopt::IpoptData* data,
                         Ipopt::IpoptCalculatedQuantities* cq) override;
  bool intermediate_callback(Ipopt::AlgorithmMode mode, Ipopt::Index iter, Ipopt::Number obj,
                             Ipopt::Number inf_pr, Ipopt::Number inf_du, Ipopt::Number mu,
                             Ipopt::Number d_norm, Ipopt::Number regularization,
                             Ipopt::Number alpha_du, Ipopt::Number alpha_pr, Ipopt::Index ls,
                             const Ipopt::IpoptData* data,
                             Ipopt::IpoptCalculatedQuantities* cq) override;

  [[nodiscard]] int jacobian_nonzeros() const { return jac_.nnz(); }
  [[nodiscard]] int hessian_nonzeros() const { return exact_hessian_ ? hess_.nnz() : 0; }
  [[nodiscard]] const std::vector<double>& last_iterate() const { return last_x_; }
  [[nodiscard]] double last_objective() const { return last_objective_; }
  [[nodiscard]] double evaluation_seconds() const { return evaluation_seconds_; }
  [[nodiscard]] bool finalized() const { return finalized_; }
  [[nodiscard]] const std::string& evaluation_error() const { return evaluation_error_; }
  /// Unscaled KKT residuals at the final point (NaN if Ipopt gave none).
  [[nodiscard]] const KktResiduals& kkt() const { return kkt_; }

private:
  template <class F> bool guarded(const char* what, F&& body);

  CollocationNlp& nlp_;
  bool exact_hessian_, user_scaling_;
  ProgressCallback progress_;
  SparseAssembler jac_, hess_;
  std::vector<double> last_x_;
  double last_objective_ = 0.0, evaluation_seconds_ = 0.0;
  bool finalized_ = false;
  std::string evaluation_error_;
  KktResiduals kkt_;
};

}  // namespace mo::runtime::detail
