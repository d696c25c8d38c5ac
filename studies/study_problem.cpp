// Objective and constraints as outputs; see study_problem.hpp.
#include "study_problem.hpp"

#include <cmath>
#include <fmt/format.h>

namespace mo::tools {

namespace ast = frontend::ast;
namespace flat = frontend::flat;
using frontend::DiagId;

namespace {

/// The time of a point value `v(T)` on the study's horizon: T itself, or with
/// a free final time τ = 1 for `finalTime` and τ = 0 for startTime. Nullopt
/// after reporting a time that is not constant (or, with a free final time,
/// neither startTime nor finalTime).
std::optional<double> point_time(const flat::Model& m, const ast::Expr& at, const ProblemOutputs& out,
                                 frontend::DiagnosticEngine& diags) {
  const auto& free = out.free_final_time;
  if (free && at.kind == ast::ExprKind::Ref && at.var == free->var) return 1.0;
  const auto t = constant_value(m, at);
  if (!t) {
    diags.report(DiagId::BadOptimization, at.range,
                 free ? "the time of this point value is not constant (with a free finalTime, "
                        "point values are at startTime or finalTime)"
                      : "the time of this point value is not constant");
    return std::nullopt;
  }
  if (!free) return t;
  if (*t == free->start) return 0.0;
  diags.report(DiagId::BadOptimization, at.range,
               "with a free finalTime, point values may only be at startTime or finalTime");
  return std::nullopt;
}

/// Replaces every `v(T)` (a Call with a resolved variable) in `e` by `v` and
/// collects the times T (see point_time). False after reporting a bad time.
bool strip_times(const flat::Model& m, ast::Expr& e, std::vector<double>& times,
                 const ProblemOutputs& out, frontend::DiagnosticEngine& diags) {
  if (e.kind == ast::ExprKind::Call && e.var >= 0 && e.args.size() == 1) {
    const auto t = point_time(m, *e.args[0], out, diags);
    if (!t) return false;
    times.push_back(*t);
    e.kind = ast::ExprKind::Ref;
    e.args.clear();
    return true;
  }
  for (auto& a : e.args)
    if (!strip_times(m, *a, times, out, diags)) return false;
  return true;
}

/// Adds `name = expr` as a top-level output of the flat model.
void add_output(flat::Model& m, const std::string& name, ast::ExprPtr expr,
                frontend::SourceRange range) {
  flat::Variable v;
  v.name = name;
  v.causality = ast::Causality::Output;
  v.range = range;
  v.description = "added by mocompile for the optimization problem";
  const std::int32_t index = m.add(std::move(v));
  ast::Equation eq;
  eq.kind = ast::EquationKind::Simple;
  eq.range = range;
  eq.lhs = ast::make_ref(name, range);
  eq.lhs->var = index;
  eq.rhs = std::move(expr);
  m.equations.push_back(std::move(eq));
}

/// The single time of a point expression, nullopt for none; false on a mix.
bool common_time(const std::vector<double>& times, std::optional<double>& t) {
  for (double x : times) {
    if (t && *t != x) return false;
    t = x;
  }
  return true;
}

bool add_constraint(flat::Model& m, const ast::Equation& eq, std::size_t k, ProblemOutputs& out,
                    frontend::DiagnosticEngine& diags) {
  ast::ExprPtr lhs = eq.lhs->clone(), rhs = eq.rhs->clone();
  std::vector<double> times;
  if (!strip_times(m, *lhs, times, out, diags) || !strip_times(m, *rhs, times, out, diags))
    return false;
  ProblemConstraint c;
  c.range = eq.range;
  if (!common_time(times, c.time)) {
    diags.report(DiagId::BadOptimization, eq.range,
                 "a constraint may refer to one time instant only");
    return false;
  }
  double bound = 0.0;
  ast::ExprPtr value;
  ast::Op rel = eq.rel;
  if (auto r = constant_value(m, *rhs)) {
    bound = *r;
    value = std::move(lhs);
  } else if (auto l = constant_value(m, *lhs)) {  // c rel e  ⇔  e rel' c
    bound = *l;
    value = std::move(rhs);
    rel = rel == ast::Op::Le ? ast::Op::Ge : rel == ast::Op::Ge ? ast::Op::Le : rel;
  } else {
    value = std::make_unique<ast::Expr>(ast::ExprKind::Binary, eq.range);
    value->op = ast::Op::Sub;
    value->args.push_back(std::move(lhs));
    value->args.push_back(std::move(rhs));
  }
  if (rel != ast::Op::Ge) c.hi = bound;
  if (rel != ast::Op::Le) c.lo = bound;
  if (value->kind == ast::ExprKind::Ref && value->var >= 0)
    c.variable = m.variables[static_cast<std::size_t>(value->var)].name;
  c.output = fmt::format("$constraint[{}]", k + 1);
  add_output(m, c.output, std::move(value), eq.range);
  out.constraints.push_back(c);
  return true;
}

}  // namespace

std::optional<ProblemOutputs> add_problem_outputs(flat::Model& m,
                                                  frontend::DiagnosticEngine& diags) {
  if (!m.optimization) return std::nullopt;
  flat::Optimization& opt = *m.optimization;
  ProblemOutputs out;
  if (opt.start_time) out.t0 = constant_value(m, *opt.start_time).value_or(0.0);
  if (opt.final_time) out.tf = constant_value(m, *opt.final_time).value_or(1.0);
  if (opt.free_final_time >= 0) {  // the horizon becomes τ ∈ [0, 1]
    const auto var = static_cast<std::size_t>(opt.free_final_time);
    out.free_final_time = FreeFinalTime{opt.free_final_time, m.variables[var].name, out.t0};
    out.t0 = 0.0;
    out.tf = 1.0;
  }
  if (out.tf <= out.t0) {
    diags.report(DiagId::BadOptimization, opt.range,
                 fmt::format("finalTime ({}) must be after startTime ({})", out.tf, out.t0));
    return std::nullopt;
  }
  if (opt.objective) {
    ast::ExprPtr e = opt.objective->clone();
    std::vector<double> times;
    if (!strip_times(m, *e, times, out, diags)) return std::nullopt;
    for (double t : times)
      if (t != out.tf) {
        diags.report(DiagId::BadOptimization, opt.objective->range,
                     "the objective may only use values at finalTime");
        return std::nullopt;
      }
    add_output(m, "$objective", std::move(e), opt.objective->range);
    out.mayer = "$objective";
  }
  if (opt.objective_integrand) {
    add_output(m, "$objective_integrand", opt.objective_integrand->clone(),
               opt.objective_integrand->range);
    out.lagrange = "$objective_integrand";
  }
  for (std::size_t k = 0; k < opt.constraints.size(); ++k)
    if (!add_constraint(m, opt.constraints[k], k, out, diags)) return std::nullopt;
  return out;
}

}  // namespace mo::tools
