// ast::Expr (flat, resolved references) → symbolic Expr, and d/dt of a
// symbolic expression over DAE variables.
#include "dae_expr.hpp"

#include "dae.hpp"
#include "dae_build.hpp"

#include <cmath>

#include <fmt/format.h>

#include "mo/runtime/modelica_random.hpp"
#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic::detail {

namespace ast = frontend::ast;
using frontend::DiagId;

namespace {

/// A relation with floor(u) (or integer(u)) on one side, rewritten on u so
/// that its event indicator crosses zero where floor(u) jumps (floor(u) - b
/// only steps, and a root finder cannot locate a step):
///   floor(u) > b  ⟺ u >= floor(b) + 1,   floor(u) >= b ⟺ u >= ceil(b),
///   floor(u) < b  ⟺ u < ceil(b),         floor(u) <= b ⟺ u < floor(b) + 1.
/// Exact for every real b (e.g. the MSL sources' integer(t/T) > pre(count)).
Expr floor_relation(ExprArena& a, ast::Op op, Expr l, Expr r) {
  const bool left = a.kind(l) == ExprKind::Floor, right = a.kind(r) == ExprKind::Floor;
  if (left == right) return Expr();
  if (right) {  // b OP floor(u) is floor(u) OP' b
    std::swap(l, r);
    op = op == ast::Op::Lt ? ast::Op::Gt : op == ast::Op::Le ? ast::Op::Ge
       : op == ast::Op::Gt ? ast::Op::Lt : ast::Op::Le;
  }
  const Expr u = a.operand(l, 0);
  const Expr next = a.add(a.floor(r), a.constant(1.0));
  if (op == ast::Op::Gt) return a.ge(u, next);
  if (op == ast::Op::Ge) return a.ge(u, a.ceil(r));
  if (op == ast::Op::Lt) return a.lt(u, a.ceil(r));
  return a.lt(u, next);  // Le
}

Expr binary(ExprArena& a, ast::Op op, Expr l, Expr r) {
  if (op == ast::Op::Lt || op == ast::Op::Le || op == ast::Op::Gt || op == ast::Op::Ge)
    if (const Expr e = floor_relation(a, op, l, r); e.valid()) return e;
  switch (op) {
  case ast::Op::Add: case ast::Op::ElemAdd: return a.add(l, r);
  case ast::Op::Sub: case ast::Op::ElemSub: return a.sub(l, r);
  case ast::Op::Mul: case ast::Op::ElemMul: return a.mul(l, r);
  case ast::Op::Div: case ast::Op::ElemDiv: return a.div(l, r);
  case ast::Op::Pow: case ast::Op::ElemPow: return a.pow(l, r);
  case ast::Op::Lt: return a.lt(l, r);
  case ast::Op::Le: return a.le(l, r);
  case ast::Op::Gt: return a.gt(l, r);
  case ast::Op::Ge: return a.ge(l, r);
  case ast::Op::Eq: return a.eq(l, r);
  case ast::Op::Ne: return a.ne(l, r);
  case ast::Op::And: return a.logical_and(l, r);
  case ast::Op::Or: return a.logical_or(l, r);
  case ast::Op::Neg: case ast::Op::Plus: case ast::Op::Not: break;
  }
  return Expr();
}

/// div(a, b): a/b truncated toward zero.
Expr trunc_div(ExprArena& a, Expr x, Expr y) {
  const Expr q = a.div(x, y);
  return a.mul(a.sign(q), a.floor(a.abs(q)));
}

}  // namespace

Expr ExprConverter::fail(const ast::Expr& e, const std::string& what) {
  if (ok_) diags_.report(DiagId::UnsupportedInLowering, e.range, what);
  ok_ = false;
  return a_.constant(0.0);
}

Expr ExprConverter::convert(const ast::Expr& e) {
  switch (e.kind) {
  case ast::ExprKind::Real:
  case ast::ExprKind::Integer:
  case ast::ExprKind::Boolean: return a_.constant(e.number);
  case ast::ExprKind::Ref:
    if (e.var >= 0) return refs_(e);
    if (e.ref.is_simple() && e.ref.parts[0].name == "time") return time_;
    return fail(e, "reference to '" + e.ref.str() + "' cannot be lowered");
  case ast::ExprKind::Call: return call(e);
  case ast::ExprKind::Unary: {
    const Expr x = convert(*e.args[0]);
    if (e.op == ast::Op::Neg) return a_.neg(x);
    if (e.op == ast::Op::Not) return a_.logical_not(x);
    return x;
  }
  case ast::ExprKind::Binary:
    return binary(a_, e.op, convert(*e.args[0]), convert(*e.args[1]));
  case ast::ExprKind::If: {
    Expr out = convert(*e.args.back());
    for (std::size_t i = e.args.size() - 1; i >= 2; i -= 2)
      out = a_.select(convert(*e.args[i - 2]), convert(*e.args[i - 1]), out);
    return out;
  }
  case ast::ExprKind::String:
  case ast::ExprKind::Array:
  case ast::ExprKind::Matrix:
  case ast::ExprKind::Range:
  case ast::ExprKind::Tuple:
  case ast::ExprKind::Colon:
  case ast::ExprKind::End: break;
  }
  return fail(e, "this expression cannot be lowered (strings, arrays and ranges must be "
                 "scalarised by flattening)");
}

Expr ExprConverter::call(const ast::Expr& e) {
  const std::string name = e.ref.str();
  std::vector<Expr> x;
  if (name == "sample" && sample_) return sample_(e);
  if (name != "der" && name != "pre" && name != "edge" && name != "change")
    for (const auto& arg : e.args) x.push_back(convert(*arg));
  auto need = [&](std::size_t n) { return e.args.size() == n; };
  static const std::pair<const char*, ExprKind> unary[] = {
      {"sin", ExprKind::Sin},     {"cos", ExprKind::Cos},     {"tan", ExprKind::Tan},
      {"asin", ExprKind::Asin},   {"acos", ExprKind::Acos},   {"atan", ExprKind::Atan},
      {"sinh", ExprKind::Sinh},   {"cosh", ExprKind::Cosh},   {"tanh", ExprKind::Tanh},
      {"exp", ExprKind::Exp},     {"log", ExprKind::Log},     {"log10", ExprKind::Log10},
      {"sqrt", ExprKind::Sqrt},   {"abs", ExprKind::Abs},     {"sign", ExprKind::Sign},
      {"floor", ExprKind::Floor}, {"ceil", ExprKind::Ceil},   {"noEvent", ExprKind::NoEvent},
      {"integer", ExprKind::Floor}};
  for (const auto& [n, k] : unary)
    if (name == n && need(1)) return a_.apply(k, x[0]);
  if (name == "Integer" && need(1)) return x[0];  // an enumeration's ordinal: the flat value
  if (name == "atan2" && need(2)) return a_.atan2(x[0], x[1]);
  if (name == "min" && need(2)) return a_.min(x[0], x[1]);
  if (name == "max" && need(2)) return a_.max(x[0], x[1]);
  if (name == "div" && need(2)) return trunc_div(a_, x[0], x[1]);
  if (name == "mod" && need(2))
    return a_.sub(x[0], a_.mul(a_.floor(a_.div(x[0], x[1])), x[1]));
  if (name == "rem" && need(2)) return a_.sub(x[0], a_.mul(trunc_div(a_, x[0], x[1]), x[1]));
  if (name == "smooth" && need(2)) {
    const double p = a_.is_constant(x[0]) ? a_.constant_value(x[0]) : -1;
    if (p >= 0 && p == std::floor(p)) return a_.smooth(static_cast<int>(p), x[1]);
    return fail(e, "smooth() needs a constant order");
  }
  if (const int g = runtime::modelica_random::generator_named(name); g > 0) {
    // ModelicaRandom_xorshift64star(k, state...): output k (flatten_random.cpp)
    namespace random = runtime::modelica_random;
    const std::size_t n = random::state_size(static_cast<random::Generator>(g));
    const double k = x.size() == n + 1 && a_.is_constant(x[0]) ? a_.constant_value(x[0]) : -1;
    if (k < 0 || k > static_cast<double>(n) || k != std::floor(k))
      return fail(e, fmt::format("'{}' needs a constant output index from 0 to {} and {} state values", name, n, n));
    return a_.external(g * random::kCodeBase + static_cast<int>(k), std::span(x).subspan(1));
  }
  // delay(e, T) and delay(e, T, Tmax) (MLS 3.7.2.4): T and Tmax are
  // parameter expressions, except T with a Tmax given; 0 <= T <= Tmax is
  // checked where the values are known (the start, each evaluation).
  if (name == "delay" && (need(2) || need(3))) {
    auto parameters_only = [&](Expr v) {
      for (Expr leaf : leaves(a_, std::span(&v, 1)))
        if (a_.kind(leaf) != ExprKind::Symbol || a_.symbol_info(leaf).role != SymbolRole::Parameter) return false;
      return true;
    };
    if (x.size() == 3 && !parameters_only(x[2]))
      return fail(*e.args[2], "delay(): delayMax must be a parameter expression");
    if (x.size() == 2 && !parameters_only(x[1]))
      return fail(*e.args[1], "delay(): a delay time that varies needs delayMax, a parameter expression: "
                              "delay(expr, delayTime, delayMax)");
    return a_.delay(x[0], x[1], x.size() == 3 ? x[2] : x[1]);
  }
  if (name == "initial" && initial_) return initial_();
  if (name == "initial" || name == "terminal") return a_.constant(0.0);
  if (name == "der" && need(1)) return der_(*e.args[0]);
  if ((name == "pre" || name == "edge" || name == "change") && need(1)) {
    const Expr v = convert(*e.args[0]);
    const Expr p = a_.kind(v) == ExprKind::Symbol &&
                           a_.symbol_info(v).role == SymbolRole::Discrete
                       ? a_.pre(v)
                       : v;  // pre of a continuous variable is its value
    if (name == "pre") return p;
    if (name == "edge") return a_.logical_and(v, a_.logical_not(p));
    return a_.ne(v, p);
  }
  return fail(e, "call of '" + name + "' cannot be lowered");
}

/// The placeholder of der(v) for the initial equations, made on first use.
Expr initial_derivative(Dae& dae, int v) {
  for (const InitialDerivative& d : dae.initial_derivatives)
    if (d.var == v) return d.symbol;
  const std::string name = dae.symbol_prefix + "initial der(" + dae.vars[static_cast<std::size_t>(v)].info.name + ")";
  const Expr s = dae.arena.symbol(name, SymbolRole::Algebraic, -1);
  dae.initial_derivatives.push_back({v, s});
  return s;
}

Expr time_derivative(Dae& dae, Expr e, bool& input_hit, bool initial) {
  ExprArena& a = dae.arena;
  ExprMap seeds;
  for (Expr leaf : leaves(a, std::span(&e, 1))) {
    if (a.kind(leaf) == ExprKind::Delay) {  // d/dt e(t - T(t)) = e'(t - T) (1 - dT/dt)
      const Expr rate = time_derivative(dae, a.operand(leaf, 0), input_hit, initial);
      const Expr delayed = a.delay(rate, a.operand(leaf, 1), a.operand(leaf, 2));
      const Expr t_rate = time_derivative(dae, a.operand(leaf, 1), input_hit, initial);
      seeds[leaf] = a.mul(delayed, a.sub(a.constant(1.0), t_rate));
      continue;
    }
    if (a.kind(leaf) != ExprKind::Symbol) continue;
    const SymbolInfo info = a.symbol_info(leaf);
    if (info.role == SymbolRole::Time) {
      seeds[leaf] = a.constant(1.0);
    } else if (info.role == SymbolRole::Input) {
      input_hit = true;
    } else if (const int v = dae.var_of(leaf); v != none) {
      if (initial && dae.vars[static_cast<std::size_t>(v)].derivative == none) {
        seeds[leaf] = initial_derivative(dae, v);
        continue;
      }
      const int d = dae.derivative_of(v);
      seeds[leaf] = dae.vars[static_cast<std::size_t>(d)].symbol;
    }
  }
  return forward_derivative(a, e, seeds);
}

}  // namespace mo::symbolic::detail
