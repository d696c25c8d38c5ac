// Named intermediate values of inlined functions.
//
// Functions are inlined into the equations as expression trees, and a tree
// copies a local each time it is read: a local read twice per statement
// doubles per statement (the MSL's Fluid.Utilities.regFun3 merges nested
// `if`-statements on its own intermediates; MoistAir's h_pTX reads its
// saturation pressure through three locals), and a few dozen statements
// reach millions of terms. Where a continuous equation is being flattened,
// a value past kIntermediateNodes that varies in time becomes a variable of
// the model instead, with its defining equation (one of parameters only, a
// parameter with that binding); the value read from then on is a reference
// to it. A value computed under varying conditions (a branch of an `if` in
// the function) is defined only where they hold (else 0), so that a value
// the branch guards (a division by what is zero elsewhere) is never computed
// outside it and neither is its derivative.
#include "flattener.hpp"
#include "mo/frontend/printer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;
using ast::Op;

namespace {

/// Calls whose value is not a function of the present values of their
/// arguments, which an intermediate may not hold: it is computed as a plain
/// continuous equation. (inStream and actualStream are: the intermediates'
/// equations join the model's before flatten_stream.cpp resolves them.)
bool operator_on_time(const std::string &n) {
  static const char *const kNames[] = {
      "der", "pre", "initial", "terminal", "sample", "edge", "change", "delay", "reinit", "cardinality",
      "spatialDistribution", "previous", "hold", "subSample", "superSample", "shiftSample", "backSample",
      "noClock", "interval", "firstTick", "Clock"};
  for (const char *k : kNames)
    if (n == k)
      return true;
  return false;
}

bool is_relation(const Expr &e) {
  return e.kind == ExprKind::Binary && (e.op == Op::Lt || e.op == Op::Le || e.op == Op::Gt || e.op == Op::Ge ||
                                        e.op == Op::Eq || e.op == Op::Ne);
}

} // namespace

Flattener::IntermediateKind Flattener::intermediate_kind(const Expr &value) const {
  using K = IntermediateKind;
  // A number, not a Boolean or a String.
  const Expr *top = &value;
  while (top->kind == ExprKind::If)
    top = top->args[1].get();
  if (top->kind == ExprKind::Boolean || top->kind == ExprKind::String || is_relation(*top) ||
      (top->kind == ExprKind::Binary && (top->op == Op::And || top->op == Op::Or)) ||
      (top->kind == ExprKind::Unary && top->op == Op::Not))
    return K::None;
  if (top->kind == ExprKind::Ref && top->var >= 0 && model_->variables[top->var].type != flat::BaseType::Real)
    return K::None;
  bool varying = false, parameters = false;
  std::vector<const Expr *> work{&value};
  while (!work.empty()) {
    const Expr *x = work.back();
    work.pop_back();
    switch (x->kind) {
    case ExprKind::Ref:
      if (x->var < 0) {
        varying = true; // time
      } else {
        const flat::Variable &v = model_->variables[x->var];
        if (v.type == flat::BaseType::String)
          return K::None;
        varying = varying || v.is_unknown() || v.top_level_input;
        parameters = parameters || v.variability == ast::Variability::Parameter;
      }
      break;
    case ExprKind::Call:
      if (x->var >= 0 || x->ref.parts.empty() || operator_on_time(x->ref.parts[0].name))
        return K::None;
      break;
    case ExprKind::Binary:
      // A relation of a function that generates events is left where it
      // is: an intermediate's equation is not under the caller's noEvent().
      if (no_event_depth_ == 0 && is_relation(*x))
        return K::None;
      break;
    case ExprKind::String:
      return K::None;
    default:
      break;
    }
    for (const auto &a : x->args)
      if (a)
        work.push_back(a.get());
  }
  return varying ? K::Varying : parameters ? K::Parameter : K::None;
}

ExprPtr Flattener::intermediate(ExprPtr value, ClassNode *fn_class, const std::string &local, SourceRange where) {
  // Inside a call of parameters only, a value that grows is a reason to
  // evaluate the call instead (inline_or_evaluate), not to keep it.
  if (!intermediates_on_ || decided_paths_ > 0 || value_nodes_cap_ <= kEvaluableValueNodes || !value ||
      !too_large_value(*value, kIntermediateNodes))
    return value;
  const IntermediateKind kind = intermediate_kind(*value);
  if (kind == IntermediateKind::None)
    return value;
  if (!inline_guards_.empty() && no_event_depth_ == 0)
    return value; // the guards' relations would generate events (see intermediate_kind)
  const bool parameter = kind == IntermediateKind::Parameter;
  if (parameter && !std::all_of(inline_guards_.begin(), inline_guards_.end(),
                                [this](const ExprPtr &g) { return is_constant(*g); }))
    return value; // a parameter's value under a varying condition
  if (!inline_guards_.empty()) {
    ExprPtr guard = inline_guards_.front()->clone();
    for (std::size_t k = 1; k < inline_guards_.size(); ++k)
      guard = ast::make_binary(Op::And, std::move(guard), inline_guards_[k]->clone(), where);
    auto guarded = std::make_unique<Expr>(ExprKind::If, where);
    guarded->args.push_back(std::move(guard));
    guarded->args.push_back(std::move(value));
    guarded->args.push_back(ast::make_real(0.0, where));
    value = std::move(guarded);
  }
  // The same value (a function called twice with the same arguments, a
  // path run again by inline_call) is the same variable.
  std::string text = print_expr(*value);
  if (auto it = intermediate_by_text_.find(text); it != intermediate_by_text_.end())
    return var_ref(*model_, it->second, where);
  const std::string fn = fn_class->path();
  std::string short_fn = fn.substr(fn.rfind('.') + 1), name;
  std::string tidy;
  for (char c : local)
    tidy += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  do
    name = fmt::format("_fn{}.{}.{}", ++intermediate_count_, short_fn, tidy);
  while (model_->find(name) >= 0);
  flat::Variable v;
  v.name = name;
  v.description = fmt::format("intermediate value '{}' of function {}", local, fn);
  v.range = where;
  if (parameter) { // computed from the other parameters, as a binding
    v.variability = ast::Variability::Parameter;
    v.binding = std::move(value);
  }
  const std::int32_t id = model_->add(std::move(v));
  intermediate_by_text_.emplace(std::move(text), id);
  if (!parameter) {
    ast::Equation eq;
    eq.kind = ast::EquationKind::Simple;
    eq.range = where;
    eq.lhs = var_ref(*model_, id, where);
    eq.rhs = std::move(value);
    intermediate_equations_.push_back(std::move(eq));
  }
  return var_ref(*model_, id, where);
}

void Flattener::flush_intermediates() {
  for (auto &eq : intermediate_equations_)
    model_->equations.push_back(std::move(eq));
  intermediate_equations_.clear();
}

} // namespace mo::frontend::detail
