#include "ipopt_solve.hpp"

#include "ipopt_tnlp.hpp"

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>

#include <chrono>
#include <cstdio>
#include <optional>
#include <cstdlib>
#include <functional>

namespace mo::runtime::detail {
namespace {

OptimizationStatus map_status(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
  case Ipopt::Solve_Succeeded: return OptimizationStatus::success;
  case Ipopt::Solved_To_Acceptable_Level: return OptimizationStatus::acceptable;
  case Ipopt::Infeasible_Problem_Detected: return OptimizationStatus::infeasible;
  case Ipopt::Maximum_Iterations_Exceeded: return OptimizationStatus::iteration_limit;
  case Ipopt::Maximum_CpuTime_Exceeded: return OptimizationStatus::time_limit;
  case Ipopt::Invalid_Number_Detected: return OptimizationStatus::evaluation_error;
  case Ipopt::Error_In_Step_Computation:
  case Ipopt::Insufficient_Memory: return OptimizationStatus::linear_solver_failure;
  case Ipopt::Restoration_Failed: return OptimizationStatus::restoration_failure;
  case Ipopt::User_Requested_Stop: return OptimizationStatus::user_stop;
  case Ipopt::Not_Enough_Degrees_Of_Freedom:
  case Ipopt::Invalid_Problem_Definition:
  case Ipopt::Invalid_Option: return OptimizationStatus::invalid_problem;
  case Ipopt::Search_Direction_Becomes_Too_Small: return OptimizationStatus::stalled;
  case Ipopt::Diverging_Iterates:
  case Ipopt::Feasible_Point_Found:
  case Ipopt::Unrecoverable_Exception:
  case Ipopt::NonIpopt_Exception_Thrown:
  case Ipopt::Internal_Error: return OptimizationStatus::solver_error;
  }
  return OptimizationStatus::solver_error;
}

std::string describe(Ipopt::ApplicationReturnStatus s) {
  return "Ipopt returned " + std::to_string(int(s)) + " (" +
         std::string(to_string(map_status(s))) + ")";
}

// One change of options tried after a linear-solver/restoration failure.
struct Retry {
  std::string what;
  std::function<void(Ipopt::OptionsList&, bool& user_scaling)> apply;
};

std::vector<Retry> retries(bool mumps_scaling) {
  Retry other_scaling =
      mumps_scaling
          ? Retry{"mumps_scaling 0 (no MUMPS scaling)",
                  [](Ipopt::OptionsList& o, bool&) { o.SetIntegerValue("mumps_scaling", 0); }}
          : Retry{"mumps_scaling 77 (MUMPS's automatic scaling)",
                  [](Ipopt::OptionsList& o, bool&) { o.SetIntegerValue("mumps_scaling", 77); }};
  return {
      std::move(other_scaling),
      {"mumps_mem_percent 5000 (more MUMPS working memory)",
       [](Ipopt::OptionsList& o, bool&) { o.SetIntegerValue("mumps_mem_percent", 5000); }},
      {"other NLP scaling (user-scaling <-> gradient-based)",
       [](Ipopt::OptionsList& o, bool& user) {
         user = !user;
         o.SetStringValue("nlp_scaling_method", user ? "user-scaling" : "gradient-based");
       }},
  };
}

// Whether the first attempt uses MUMPS's scaling (`ipopt_options` may override it).
bool mumps_scaling_in(const SolverOptions& options) {
  auto it = options.ipopt_options.find("mumps_scaling");
  if (it == options.ipopt_options.end()) return options.mumps_scaling;
  return std::strtol(it->second.c_str(), nullptr, 10) != 0;
}

bool retryable(OptimizationStatus s) {
  return s == OptimizationStatus::linear_solver_failure ||
         s == OptimizationStatus::restoration_failure;
}

void set_options(Ipopt::OptionsList& o, const SolverOptions& options, bool exact_hessian,
                 bool user_scaling) {
  o.SetNumericValue("tol", options.tolerance);
  o.SetIntegerValue("max_iter", options.max_iterations);
  o.SetNumericValue("acceptable_tol", options.acceptable_tolerance);
  o.SetIntegerValue("acceptable_iter", options.acceptable_iterations);
  o.SetNumericValue("acceptable_obj_change_tol", options.acceptable_objective_change);
  o.SetNumericValue("max_cpu_time", options.max_cpu_seconds);
  o.SetIntegerValue("print_level", options.print_level);
  o.SetStringValue("sb", "yes");  // no banner
  o.SetStringValue("hessian_approximation", exact_hessian ? "exact" : "limited-memory");
  o.SetStringValue("nlp_scaling_method", user_scaling ? "user-scaling" : "gradient-based");
  o.SetIntegerValue("mumps_scaling", options.mumps_scaling ? 77 : 0);
}

/// Sets `ipopt_options` by the type Ipopt registered for each; the first
/// option Ipopt does not know or whose value it rejects, as a message (empty
/// if all were set).
std::string set_user_options(Ipopt::IpoptApplication& app, const SolverOptions& options) {
  Ipopt::OptionsList& o = *app.Options();
  for (const auto& [name, value] : options.ipopt_options) {
    const Ipopt::SmartPtr<const Ipopt::RegisteredOption> registered = app.RegOptions()->GetOption(name);
    if (Ipopt::IsNull(registered)) return "ipopt_options: '" + name + "' is not an option of Ipopt";
    char* end = nullptr;
    bool set = false;
    const char* expected = "";
    switch (registered->Type()) {
    case Ipopt::OT_Integer: {
      const long as_int = std::strtol(value.c_str(), &end, 10);
      set = !value.empty() && *end == '\0' && o.SetIntegerValue(name, Ipopt::Index(as_int));
      expected = "an integer";
      break;
    }
    case Ipopt::OT_Number: {
      const double as_real = std::strtod(value.c_str(), &end);
      set = !value.empty() && *end == '\0' && o.SetNumericValue(name, as_real);
      expected = "a number";
      break;
    }
    default:
      set = o.SetStringValue(name, value);
      expected = "one of the settings Ipopt lists for it";
      break;
    }
    if (!set)
      return "ipopt_options: '" + value + "' is not a valid value of Ipopt's option '" + name + "' (" + expected +
             " expected)";
  }
  return {};
}

}  // namespace

namespace {

// Ipopt's default constr_viol_tol: a restoration failure at a point this
// feasible is a stall, not an infeasibility.
constexpr double kFeasible = 1e-4;

// One Ipopt run on `nlp` from its initial guess.
IpoptOutcome run_once(Ipopt::IpoptApplication& app, CollocationNlp& nlp, bool exact,
                      bool user_scaling, const SolverOptions& options) {
  IpoptOutcome out;
  Ipopt::SmartPtr<CollocationTnlp> tnlp =
      new CollocationTnlp(nlp, exact, user_scaling, options.progress);
  Ipopt::ApplicationReturnStatus status = app.OptimizeTNLP(Ipopt::GetRawPtr(tnlp));
  out.status = map_status(status);
  out.message = describe(status);
  out.kkt = tnlp->kkt();
  const bool converged = out.status == OptimizationStatus::success ||
                         out.status == OptimizationStatus::acceptable;
  // A trial point rejected on the way (e.g. a step to a non-positive-definite F)
  // is part of the normal search: name it only when the solve failed.
  if (!converged && !tnlp->evaluation_error().empty()) out.message += "; " + tnlp->evaluation_error();
  out.solution = tnlp->last_iterate();
  out.objective = tnlp->last_objective();
  out.iterations = IsValid(app.Statistics()) ? int(app.Statistics()->IterationCount()) : 0;
  out.size = {nlp.num_variables(), nlp.num_constraints(), tnlp->jacobian_nonzeros(),
              tnlp->hessian_nonzeros()};
  out.evaluation_seconds = tnlp->evaluation_seconds();
  return out;
}

std::string kkt_text(const KktResiduals& k) {
  char text[160];
  std::snprintf(text, sizeof text, "; KKT residuals: primal %.2e, dual %.2e, complementarity %.2e",
                k.primal_infeasibility, k.dual_infeasibility, k.complementarity);
  return text;
}

}  // namespace

IpoptOutcome solve_with_ipopt(CollocationNlp& nlp, const SolverOptions& options) {
  IpoptOutcome out;
  const bool exact_possible = nlp.exact_hessian_possible();
  bool exact = options.hessian != HessianMode::limited_memory && exact_possible;
  if (options.hessian == HessianMode::exact && !exact) {
    out.status = OptimizationStatus::invalid_problem;
    out.message = "exact Hessian requested, but the model or an objective term provides none";
    out.solution = nlp.initial_guess();
    return out;
  }
  bool user_scaling = options.scale_by_nominal;
  auto start = std::chrono::steady_clock::now();
  std::vector<Retry> changes = retries(mumps_scaling_in(options));
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->RethrowNonIpoptException(false);
  set_options(*app->Options(), options, exact, user_scaling);
  if (std::string refused = set_user_options(*app, options); !refused.empty()) {
    out.status = OptimizationStatus::invalid_problem;
    out.message = std::move(refused);
    out.solution = nlp.initial_guess();
    return out;
  }
  app->Options()->SetNumericValue("obj_scaling_factor", nlp.objective_scaling());
  double evaluation_seconds = 0.0;
  bool restarted = false;
  std::optional<IpoptOutcome> stalled;
  for (std::size_t attempt = 0;; ++attempt) {
    if (app->Initialize("") != Ipopt::Solve_Succeeded) {
      out.status = OptimizationStatus::invalid_problem;
      out.message = "Ipopt rejected its options";
      break;
    }
    if (attempt == 0 && !options.log_file.empty())  // the journal stays open: one log, all attempts
      app->OpenOutputFile(options.log_file, Ipopt::J_ITERSUMMARY);
    std::vector<std::string> earlier = std::move(out.retries);
    out = run_once(*app, nlp, exact, user_scaling, options);
    out.retries = std::move(earlier);
    evaluation_seconds += out.evaluation_seconds;
    const bool more_changes =
        options.retry_on_solver_failure && retryable(out.status) && attempt < changes.size();
    // A restoration failure is first retried with the changes below (without
    // MUMPS's scaling the cart-pendulum designs converge); when they are spent,
    // one at a feasible point is a stall.
    if (!more_changes && out.status == OptimizationStatus::restoration_failure &&
        out.kkt.primal_infeasibility <= kFeasible) {
      out.status = OptimizationStatus::stalled;
      out.message += ", at a feasible point: stalled";
    }
    if (out.status == OptimizationStatus::stalled && !restarted && options.retry_on_solver_failure) {
      // The fallback for a stall: restart once from the last iterate, with the
      // other Hessian mode where both exist (a fresh L-BFGS memory otherwise).
      restarted = true;
      stalled = out;
      exact = exact_possible && !exact;
      app->Options()->SetStringValue("hessian_approximation", exact ? "exact" : "limited-memory");
      nlp.set_initial_guess(out.solution);
      out.retries.push_back("after " + out.message + ": restarting from the last iterate with the " +
                            (exact ? "exact" : "limited-memory") + " Hessian");
      continue;
    }
    if (!more_changes) break;
    out.retries.push_back("after " + out.message + ": retrying with " + changes[attempt].what);
    changes[attempt].apply(*app->Options(), user_scaling);
  }
  const bool converged = out.status == OptimizationStatus::success ||
                         out.status == OptimizationStatus::acceptable;
  if (stalled && !converged) {  // the restart did not help: report the stall
    const std::string ended(to_string(out.status));
    std::vector<std::string> tried = std::move(out.retries);
    out = *stalled;
    out.retries = std::move(tried);
    out.message += " (the restart ended " + ended + ")";
  }
  out.evaluation_seconds = evaluation_seconds;
  out.solve_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (out.status == OptimizationStatus::stalled) out.message += kkt_text(out.kkt);
  if (!out.retries.empty()) out.message += " after " + std::to_string(out.retries.size()) + " retries";
  return out;
}

}  // namespace mo::runtime::detail
