// The external "C" functions of Modelica.Math.Random (ModelicaExternalC's
// ModelicaRandom.c), which mocompile provides instead of linking the library:
//
// - the generators xorshift64*, xorshift128+ and xorshift1024*
//   (`random(stateIn) -> (result, stateOut)`): a call whose state is known
//   now (numbers, or parameters: evaluated now, with a warning) gives
//   numbers; one whose state varies (`generator.random(pre(state))` at a
//   sample) becomes the flat calls `ModelicaRandom_xorshift128plus(k,
//   state...)`, one per output k (0: the Real; 1..n: the new state), that
//   lowering keeps as ExprKind::External and the generated code evaluates
//   (mo/runtime/modelica_random.hpp, the same code for both);
// - the impure generator's hidden state (`initializeImpureRandom(seed)` stores
//   it with ModelicaRandom_setInternalState_xorshift1024star) and its draws
//   (`impureRandom(id)`), and `automaticGlobalSeed()`: evaluated once, when
//   the model is translated. So the draws of initial equations and bindings
//   (the noise blocks' automatic local seeds) come in the order the model is
//   flattened, and a changed seed needs a new translation. A draw in a
//   when-clause differs at every event: the hidden state becomes discrete
//   Integers of the model (ModelicaRandom.impureState[1..33], starting where
//   the translation's draws left it) that the clause steps once per draw
//   (at most two); draws in more than one clause are refused.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "flattener.hpp"
#include "mo/runtime/modelica_random.hpp"

namespace mo::frontend::detail {

namespace random = runtime::modelica_random;
using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;

namespace {

/// The position of the formal that argument `k` of the external call names.
int formal(const ast::ClassDef &def, std::size_t k, const std::vector<std::string> &names) {
  if (k >= def.external_args.size())
    return -1;
  const Expr &a = *def.external_args[k];
  if (a.kind != ExprKind::Ref || a.ref.parts.size() != 1 || !a.ref.parts[0].subscripts.empty())
    return -1;
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == a.ref.parts[0].name)
      return static_cast<int>(i);
  return -1;
}

} // namespace

std::vector<std::int32_t> Flattener::random_integers(const Tensor &t, SourceRange where) {
  std::vector<std::int32_t> out;
  for (const auto &e : t.elems) {
    if (!e)
      fail(DiagId::NotConstant, where, "a random generator's state has an element without a value");
    const double v = eval(*e, where);
    if (!(v >= -2147483648.0 && v <= 2147483647.0) || v != std::floor(v))
      fail(DiagId::NotConstant, where, fmt::format("a random generator's state element {} is not an Integer", v));
    out.push_back(static_cast<std::int32_t>(v));
  }
  return out;
}

void Flattener::evaluated_random(const std::string &fn_name, SourceRange where, const std::string &why) {
  if (!random_warned_.insert(fn_name).second)
    return;
  diags_.report(DiagId::EvaluatedAtTranslation, where, "'" + fn_name + "' " + why);
}

bool Flattener::provided_random(const ast::ClassDef &def, const std::string &fn_name,
                                const std::vector<std::string> &inputs, const std::vector<std::string> &outputs,
                                const std::vector<const Expr *> &args, const Expr &call, const Scope &s,
                                std::vector<Tensor> &out) {
  const std::string &c = def.external_function;
  auto input = [&](int i) -> Tensor {
    if (i < 0 || !args[static_cast<std::size_t>(i)])
      fail(DiagId::Unsupported, call.range,
           "'" + fn_name + "' does not pass its inputs to '" + c + "' as ModelicaRandom.h declares them");
    return expr(*args[static_cast<std::size_t>(i)], s);
  };
  auto output_slot = [&](int o) {
    if (o < 0)
      fail(DiagId::Unsupported, call.range,
           "'" + fn_name + "' does not receive the outputs of '" + c + "' as ModelicaRandom.h declares them");
    out.resize(outputs.size());
    return static_cast<std::size_t>(o);
  };
  const bool at_events = s.in_when || calls_in_when_ > 0;
  if (const int g = random::generator_named(c)) {
    // void f(int state_in[], int state_out[], double* y)
    const Tensor state = input(formal(def, 0, inputs));
    const std::size_t to_state = output_slot(formal(def, 1, outputs)), to_y = output_slot(formal(def, 2, outputs));
    const std::size_t n = random::state_size(static_cast<random::Generator>(g));
    if (state.elems.size() != n)
      fail(DiagId::TypeMismatch, call.range,
           fmt::format("'{}' needs a state of {} Integers, not {}", c, n, state.elems.size()));
    Tensor next;
    next.dims = {static_cast<int>(n)};
    const bool known = std::all_of(state.elems.begin(), state.elems.end(), [&](const ExprPtr &e) {
      return e && is_constant(*e);
    });
    if (known) {
      if (!std::all_of(state.elems.begin(), state.elems.end(),
                       [](const ExprPtr &e) { return e->kind == ExprKind::Integer || e->kind == ExprKind::Real; }))
        evaluated_random(fn_name, call.range,
                         "is evaluated now with its parameters' values (a random generator's state of "
                         "parameters); changing those parameters later does not change its result");
      const std::vector<std::int32_t> in = random_integers(state, call.range);
      std::vector<std::int32_t> result(n);
      const double y = random::step(static_cast<random::Generator>(g), in, result);
      for (const std::int32_t v : result)
        next.elems.push_back(ast::make_integer(v, call.range));
      out[to_y] = Tensor::scalar(ast::make_real(y, call.range));
      out[to_state] = std::move(next);
      return true;
    }
    auto output = [&](std::size_t k) {
      auto e = std::make_unique<Expr>(ExprKind::Call, call.range);
      e->resolved = true;
      e->ref.parts.push_back(ast::RefPart{c, {}});
      e->args.push_back(ast::make_integer(static_cast<long long>(k), call.range));
      for (const auto &x : state.elems)
        e->args.push_back(x->clone());
      return e;
    };
    out[to_y] = Tensor::scalar(output(0));
    for (std::size_t k = 1; k <= n; ++k)
      next.elems.push_back(output(k));
    out[to_state] = std::move(next);
    return true;
  }
  if (c == "ModelicaRandom_automaticGlobalSeed") {
    // int f(double dummy): from the clock and the process id, once per translation
    if (!automatic_seed_) {
      const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                          std::chrono::system_clock::now().time_since_epoch())
                          .count();
      automatic_seed_ = static_cast<std::int32_t>(static_cast<std::uint32_t>(ms) ^
                                                  (static_cast<std::uint32_t>(::getpid()) << 16));
    }
    evaluated_random(fn_name, call.range,
                     "is evaluated when the model is translated: every simulation of this translation "
                     "uses the same automatic seed");
    const auto it = std::find(outputs.begin(), outputs.end(), def.external_result);
    out.resize(outputs.size());
    out[output_slot(it == outputs.end() ? -1 : static_cast<int>(it - outputs.begin()))] =
        Tensor::scalar(ast::make_integer(*automatic_seed_, call.range));
    return true;
  }
  if (c == "ModelicaRandom_impureRandom_xorshift1024star") {
    // double f(int id); the id only orders the calls after the initialisation
    const auto it = std::find(outputs.begin(), outputs.end(), def.external_result);
    out.resize(outputs.size());
    const std::size_t slot = output_slot(it == outputs.end() ? -1 : static_cast<int>(it - outputs.begin()));
    if (at_events) {  // the state at run time: wherever the translation's draws leave it
      out[slot] = Tensor::scalar(impure_event_draw(call.range));
      return true;
    }
    if (impure_state_.empty())
      fail(DiagId::Unsupported, call.range,
           "'" + fn_name + "' is called before the impure generator is initialised (initializeImpureRandom)");
    const Tensor id = input(formal(def, 0, inputs));
    if (id.elems.size() != 1 || random_integers(id, call.range)[0] != impure_id_)
      fail(DiagId::Unsupported, call.range, "'" + fn_name + "' is called with another id than initializeImpureRandom gave");
    evaluated_random(fn_name, call.range,
                     "draws its numbers when the model is translated, in the order the model is flattened");
    std::vector<std::int32_t> next(impure_state_.size());
    const double y = random::step(random::Generator::Xorshift1024star, impure_state_, next);
    impure_state_ = std::move(next);
    impure_starts();
    out[slot] = Tensor::scalar(ast::make_real(y, call.range));
    return true;
  }
  return false;
}

bool Flattener::provided_random_statement(const ast::ClassDef &def, const std::vector<std::string> &inputs,
                                          const std::vector<const Expr *> &args, const Expr &call, const Scope &s) {
  if (def.external_function != "ModelicaRandom_setInternalState_xorshift1024star")
    return false;
  // void f(int* state, size_t nState, int id): the impure generator's state
  const int state_at = formal(def, 0, inputs), id_at = formal(def, 2, inputs);
  if (state_at < 0 || id_at < 0 || !args[static_cast<std::size_t>(state_at)] || !args[static_cast<std::size_t>(id_at)])
    fail(DiagId::Unsupported, call.range,
         "the call of '" + def.external_function + "' does not pass its inputs as ModelicaRandom.h declares them");
  const Tensor state = expr(*args[static_cast<std::size_t>(state_at)], s);
  const Tensor id = expr(*args[static_cast<std::size_t>(id_at)], s);
  if (state.elems.size() != random::state_size(random::Generator::Xorshift1024star) || id.elems.size() != 1)
    fail(DiagId::TypeMismatch, call.range, "the impure generator's state needs 33 Integers and one id");
  impure_state_ = random_integers(state, call.range);
  impure_id_ = random_integers(id, call.range)[0];
  impure_starts();
  return true;
}

ExprPtr Flattener::impure_event_draw(SourceRange where) {
  const std::size_t n = random::state_size(random::Generator::Xorshift1024star);
  if (impure_vars_.empty()) {
    for (std::size_t k = 0; k < n; ++k) {
      flat::Variable v;
      v.name = fmt::format("ModelicaRandom.impureState[{}]", k + 1);
      if (model_->find(v.name) >= 0)
        fail(DiagId::Unsupported, where, "the model has a variable '" + v.name + "' of its own");
      v.type = flat::BaseType::Integer;
      v.variability = ast::Variability::Discrete;
      v.description = "the impure random generator's state (ModelicaRandom.c's hidden state)";
      v.attr.fixed = ast::make_bool(true, where);
      v.range = where;
      impure_vars_.push_back(model_->add(std::move(v)));
    }
    impure_starts();
  }
  if (impure_branch_ >= 0 && impure_branch_ != when_branch_serial_)
    fail(DiagId::Unsupported, where,
         "the impure random generator is drawn in more than one when-clause; one clause is supported");
  // Each draw's flat state repeats the previous draw's 33 expressions in
  // each of its own: two draws stay small, more would not.
  if (impure_branch_ == when_branch_serial_ && ++impure_branch_draws_ > 2)
    fail(DiagId::Unsupported, where, "a when-clause draws more than twice from the impure random generator");
  if (impure_branch_ < 0) {
    impure_branch_draws_ = 1;
    impure_branch_ = when_branch_serial_;
    for (const std::int32_t var : impure_vars_) {
      auto pre = std::make_unique<Expr>(ExprKind::Call, where);
      pre->resolved = true;
      pre->ref.parts.push_back(ast::RefPart{"pre", {}});
      pre->args.push_back(variable_expr(var, where));
      impure_branch_state_.push_back(std::move(pre));
    }
  }
  // One xorshift1024* step of the state so far in this clause.
  auto output = [&](std::size_t k) {
    auto e = std::make_unique<Expr>(ExprKind::Call, where);
    e->resolved = true;
    e->ref.parts.push_back(ast::RefPart{std::string(random::c_name(random::Generator::Xorshift1024star)), {}});
    e->args.push_back(ast::make_integer(static_cast<double>(k), where));
    for (const auto &x : impure_branch_state_)
      e->args.push_back(x->clone());
    return e;
  };
  ExprPtr y = output(0);
  std::vector<ExprPtr> next;
  for (std::size_t k = 1; k <= n; ++k)
    next.push_back(output(k));
  impure_branch_state_ = std::move(next);
  return y;
}

void Flattener::impure_draws_of_branch(std::vector<ast::Equation> &body) {
  if (impure_branch_ != when_branch_serial_ || impure_branch_state_.empty())
    return;  // no draw in this branch (after a draw the state is the stepped one)
  for (std::size_t k = 0; k < impure_vars_.size(); ++k) {
    ast::Equation eq;
    eq.kind = ast::EquationKind::Simple;
    eq.range = impure_branch_state_[k]->range;
    eq.lhs = variable_expr(impure_vars_[k], eq.range);
    eq.rhs = std::move(impure_branch_state_[k]);
    body.push_back(std::move(eq));
  }
  impure_branch_state_.clear();
}

void Flattener::impure_starts() {
  for (std::size_t k = 0; k < impure_vars_.size() && k < impure_state_.size(); ++k)
    model_->variables[static_cast<std::size_t>(impure_vars_[k])].attr.start =
        ast::make_integer(impure_state_[k], model_->variables[static_cast<std::size_t>(impure_vars_[k])].range);
}

} // namespace mo::frontend::detail
