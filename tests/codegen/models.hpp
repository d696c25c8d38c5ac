// Lowered models built by hand (standing in for the lowering until it lands):
//
//   cart_pendulum()   docs/cart-pendulum.md, der(v), der(w) from a 2×2 linear block
//   bouncing_ball()   h' = v, v' = -g; when h < 0: bounces := pre(bounces) + 1, reinit(v, -e pre(v))
//   cubic_root()      x' = -z with z³ + z = x (nonlinear block), y = z² + x
//   spring_chain(n)   n masses between springs/dampers (for benchmarks)
#pragma once

#include <string>

#include "mo/symbolic/ode.hpp"

namespace mo::codegen::test {

using symbolic::Expr;
using symbolic::OdeModel;
using symbolic::SymbolRole;

/// Appends variables and steps to an OdeModel.
struct OdeBuilder {
  OdeModel m;
  symbolic::ExprArena& a = m.arena;

  explicit OdeBuilder(std::string name) {
    m.name = std::move(name);
    m.time = a.symbol("time", SymbolRole::Time, 0);
  }
  static symbolic::VariableInfo info(std::string name, std::string unit = {},
                                     std::string description = {}) {
    symbolic::VariableInfo i;
    i.name = std::move(name), i.unit = std::move(unit), i.description = std::move(description);
    return i;
  }
  Expr c(double v) { return a.constant(v); }
  Expr state(const std::string& name, Expr start, std::string unit = {}, std::string desc = {}) {
    const auto i = static_cast<std::int32_t>(m.states.size());
    symbolic::OdeState s;
    s.info = info(name, std::move(unit), std::move(desc));
    s.symbol = a.symbol(name, SymbolRole::State, i);
    s.derivative = a.symbol("der(" + name + ")", SymbolRole::Derivative, i);
    s.start = start;
    s.fixed = true;
    m.states.push_back(s);
    return s.symbol;
  }
  Expr der(std::size_t i) const { return m.states[i].derivative; }
  Expr input(const std::string& name, std::string unit = {}, std::string desc = {}) {
    const Expr s = a.symbol(name, SymbolRole::Input, static_cast<std::int32_t>(m.inputs.size()));
    m.inputs.push_back({info(name, std::move(unit), std::move(desc)), s});
    return s;
  }
  Expr parameter(const std::string& name, double value, std::string unit = {},
                 std::string desc = {}) {
    const Expr s = a.symbol(name, SymbolRole::Parameter, static_cast<std::int32_t>(m.parameters.size()));
    m.parameters.push_back({info(name, std::move(unit), std::move(desc)), s, value});
    return s;
  }
  Expr algebraic(const std::string& name) {
    const Expr s = a.symbol(name, SymbolRole::Algebraic, static_cast<std::int32_t>(m.algebraics.size()));
    m.algebraics.push_back({info(name), s});
    return s;
  }
  Expr discrete(const std::string& name, double start) {
    const Expr s = a.symbol(name, SymbolRole::Discrete, static_cast<std::int32_t>(m.discrete.size()));
    m.discrete.push_back({info(name), s, start});
    return s;
  }
  void assign(Expr target, Expr value) { m.steps.emplace_back(symbolic::Assignment{target, value}); }
  void output(const std::string& name, Expr value, std::string unit = {}, std::string desc = {}) {
    m.outputs.push_back({info(name, std::move(unit), std::move(desc)), value});
  }
};

/// The cart-pendulum plant; g is the constant 9.81, p = (m1, d1, m2, d2, l).
inline OdeModel cart_pendulum() {
  OdeBuilder b("CartPendulumODE");
  auto& a = b.a;
  const Expr zero = b.c(0);
  const Expr x = b.state("x", zero, "m", "Cart position (m)");
  const Expr phi = b.state("phi", zero, "rad", "Pendulum angle");
  const Expr v = b.state("v", zero, "m/s");
  const Expr w = b.state("w", zero, "rad/s");
  const Expr F = b.input("F", "N", "Force on the cart (N)");
  const Expr m1 = b.parameter("m1", 2, "kg"), d1 = b.parameter("d1", 15), m2 = b.parameter("m2", 1, "kg"),
             d2 = b.parameter("d2", 0.5), l = b.parameter("l", 0.5, "m");
  const Expr g = b.c(9.81), half = b.c(0.5);
  b.assign(b.der(0), v);
  b.assign(b.der(1), w);
  const Expr a11 = a.add(m1, m2);
  const Expr a12 = a.mul(a.mul(m2, l), a.mul(a.cos(phi), half));
  const Expr a22 = a.div(a.mul(m2, a.pow(l, b.c(2))), b.c(3));
  const Expr b1 = a.add(a.sub(a.mul(a.mul(a.mul(m2, l), a.sin(phi)), a.mul(a.pow(w, b.c(2)), half)),
                              a.mul(d1, v)),
                        F);
  const Expr b2 = a.sub(a.neg(a.mul(a.mul(a.mul(m2, g), l), a.mul(a.sin(phi), half))), a.mul(d2, w));
  symbolic::EquationBlock blk;
  blk.linear = true;
  blk.unknowns = {b.der(2), b.der(3)};
  blk.offset = {a.neg(b1), a.neg(b2)};
  blk.jacobian = {{0, 0, a11}, {0, 1, a12}, {1, 0, a12}, {1, 1, a22}};
  blk.residuals = {a.add(a.add(a.mul(a11, b.der(2)), a.mul(a12, b.der(3))), blk.offset[0]),
                   a.add(a.add(a.mul(a12, b.der(2)), a.mul(a22, b.der(3))), blk.offset[1])};
  b.m.steps.emplace_back(blk);
  b.output("y_x", x, "m", "Measured cart position (m)");
  b.output("y_phi", phi, "rad");
  return std::move(b.m);
}

/// h' = v, v' = -g, h(0) = h0; when h < 0: reinit(v, -e pre(v)), bounces := pre(bounces) + 1.
inline OdeModel bouncing_ball() {
  OdeBuilder b("BouncingBall");
  auto& a = b.a;
  const Expr g = b.parameter("g", 9.81), e = b.parameter("e", 0.8), h0 = b.parameter("h0", 1.0);
  const Expr h = b.state("h", h0, "m");
  const Expr v = b.state("v", b.c(0), "m/s");
  const Expr bounces = b.discrete("bounces", 0);
  b.assign(b.der(0), v);
  b.assign(b.der(1), a.neg(g));
  b.output("height", h, "m");
  b.output("bounce_count", bounces);
  b.m.zero_crossings = {h};
  symbolic::WhenClause when;
  when.condition = a.lt(h, b.c(0));
  when.assignments = {{bounces, a.add(a.pre(bounces), b.c(1))}};
  when.reinits = {{1, a.neg(a.mul(e, a.pre(v)))}};
  b.m.whens.push_back(when);
  return std::move(b.m);
}

/// x' = -z, z³ + k z = x (nonlinear block in z), q = z² + x; y = (q, z); p = (k, x0).
inline OdeModel cubic_root() {
  OdeBuilder b("CubicRoot");
  auto& a = b.a;
  const Expr k = b.parameter("k", 1.0), x0 = b.parameter("x0", 2.0);
  const Expr x = b.state("x", a.mul(x0, x0));
  const Expr z = b.algebraic("z");
  const Expr q = b.algebraic("q");
  symbolic::EquationBlock blk;
  blk.linear = false;
  blk.unknowns = {z};
  blk.residuals = {a.sub(a.add(a.pow(z, b.c(3)), a.mul(k, z)), x)};
  blk.jacobian = {{0, 0, a.add(a.mul(b.c(3), a.pow(z, b.c(2))), k)}};
  blk.start = {0.5};
  b.m.steps.emplace_back(blk);
  b.assign(b.der(0), a.neg(z));
  b.assign(q, a.add(a.mul(z, z), x));
  b.output("q", q);
  b.output("z", z);
  return std::move(b.m);
}

/// n masses in a chain: ground — (spring c, damper d) — m_1 — ... — m_n, a
/// force F on the last mass. Per unit: states s_i, v_i, parameters m_i, c_i, d_i.
inline OdeModel spring_chain(int n) {
  OdeBuilder b("Chain");
  auto& a = b.a;
  std::vector<Expr> s, v, m, c, d, f;
  for (int i = 0; i < n; ++i) {
    const std::string u = "u[" + std::to_string(i + 1) + "].";
    s.push_back(b.state(u + "mass.s", b.c(0.01 * (i + 1))));
    v.push_back(b.state(u + "mass.v", b.c(0)));
  }
  const Expr force = b.input("F");
  for (int i = 0; i < n; ++i) {
    const std::string u = "u[" + std::to_string(i + 1) + "].";
    m.push_back(b.parameter(u + "mass.m", 0.5));
    c.push_back(b.parameter(u + "sd.c", 200));
    d.push_back(b.parameter(u + "sd.d", 1));
  }
  for (int i = 0; i < n; ++i) {
    const std::string u = "u[" + std::to_string(i + 1) + "].";
    f.push_back(b.algebraic(u + "sd.f"));
    const Expr ds = i == 0 ? a.neg(s[0]) : a.sub(s[i - 1], s[i]);
    const Expr dv = i == 0 ? a.neg(v[0]) : a.sub(v[i - 1], v[i]);
    b.assign(f.back(), a.add(a.mul(c[i], ds), a.mul(d[i], dv)));
  }
  for (int i = 0; i < n; ++i) {
    b.assign(b.der(2 * i), v[i]);
    const Expr next = i + 1 < n ? f[i + 1] : a.neg(force);
    b.assign(b.der(2 * i + 1), a.div(a.sub(f[i], next), m[i]));
  }
  b.output("tip", s.back());
  return std::move(b.m);
}

}  // namespace mo::codegen::test
