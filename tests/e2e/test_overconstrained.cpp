// Overdetermined connectors (MLS 9.4, frontend/src/flatten_overconstrained.cpp):
// our planar frames (data/PlanarFrames.mo) with Connections.root, branch and
// potentialRoot, rooted() choosing each joint's equations, against the
// pendulum's equation of motion; a loop's broken connection gets the
// equalityConstraint residue, a graph without a root is reported. The MSL's MultiBody Pendulum against the same equation, and its
// PointGravity's free bodies against their Kepler orbits.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <sstream>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// phi(t) of J phi'' = -m g L cos(phi) - d phi' from (phi0, 0), by RK4
/// with 1e-5 s steps, at each of `times`.
std::vector<double> pendulum(double J, double mgL, double d, double phi0, const std::vector<double> &times) {
  const auto f = [&](double phi, double w) { return (-mgL * std::cos(phi) - d * w) / J; };
  std::vector<double> out;
  double phi = phi0, w = 0, t = 0;
  const double h = 1e-5;
  for (double target : times) {
    while (t < target - h / 2) {
      const double k1p = w, k1w = f(phi, w);
      const double k2p = w + h / 2 * k1w, k2w = f(phi + h / 2 * k1p, w + h / 2 * k1w);
      const double k3p = w + h / 2 * k2w, k3w = f(phi + h / 2 * k2p, w + h / 2 * k2w);
      const double k4p = w + h * k3w, k4w = f(phi + h * k3p, w + h * k3w);
      phi += h / 6 * (k1p + 2 * k2p + 2 * k3p + k4p);
      w += h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
      t += h;
    }
    out.push_back(phi);
  }
  return out;
}

ModelSpec planar(const std::string &name) { return {{kData + "PlanarFrames.mo", "PlanarFrames." + name, {}, true}, {}}; }

/// The diagnostics of flattening PlanarFrames.`name`, which must fail.
std::string flatten_errors(const std::string &name) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  CHECK_FALSE(tools::load_flat_model(planar(name).source, sources, diags));
  std::ostringstream printed;
  diags.print(printed);
  return printed.str();
}

} // namespace

TEST_CASE("overdetermined connectors: rooted() picks each joint's equations, either way round") {
  const auto grid = runtime::OutputGrid::uniform(0, 2, 40);
  // Body: m = 1, I = 0.01, L = 0.5 about the joint: J = I + m L².
  const std::vector<double> exact = pendulum(0.01 + 0.25, 9.81 * 0.5, 0, 0.3, grid.times);
  for (const bool reversed : {false, true}) {
    INFO((reversed ? "ReversedPendulum" : "Pendulum"));
    auto model = compiled_model(reversed ? "e2e_planar_reversed" : "e2e_planar_pendulum",
                                planar(reversed ? "ReversedPendulum" : "Pendulum"));
    const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
    INFO(r.message);
    REQUIRE(r.ok());
    // Turned round, the joint's angle is the body's turned back.
    const auto phi = column(r.trajectory, "joint.phi");
    for (std::size_t k = 0; k < grid.times.size(); ++k) {
      INFO("t = " << grid.times[k]);
      CHECK((reversed ? -phi[k] : phi[k]) == Approx(exact[k]).margin(1e-6));
    }
    const auto p = model->info().default_parameters();
    const std::string name = reversed ? "e2e_planar_reversed" : "e2e_planar_pendulum";
    CHECK(variable(name, r.trajectory, p, "joint.aRooted").front() == (reversed ? 0.0 : 1.0));
    CHECK(variable(name, r.trajectory, p, "body.root").front() == 0.0);  // the ground is the root
  }
}

// MLS 9.4.1: the connection that closes the loop (the last, joint2 to the
// body) is broken: equalityConstraint's residue replaces its R equation.
TEST_CASE("overdetermined connectors: a loop's broken connection gets the equalityConstraint residue") {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  const auto flat = tools::load_flat_model(planar("TwoJointsLoop").source, sources, diags);
  std::ostringstream printed;
  diags.print(printed);
  INFO(printed.str());
  REQUIRE(flat);
  const std::string text = flat->print();
  INFO(text);
  CHECK(text.find("  0. = `joint2.frame_b.R.phi` - `body.frame_a.R.phi`;\n") != std::string::npos);
  CHECK(text.find("`joint2.frame_b.R.phi` = `body.frame_a.R.phi`") == std::string::npos);
  CHECK(text.find("`body.frame_a.R.phi` = `joint2.frame_b.R.phi`") == std::string::npos);
  CHECK(text.find("`joint1.frame_b.R.phi` = `body.frame_a.R.phi`") != std::string::npos);
}

TEST_CASE("overdetermined connectors: a part without a root is reported") {
  CHECK_THAT(flatten_errors("Revolute"),
             Catch::Contains("error: 'frame_a.R' is in a part of the connection graph without a root"));
}

TEST_CASE("the MSL's MultiBody Pendulum swings as its equation of motion says", "[msl]") {
  auto model = msl_compiled_model("e2e_msl_multibody_pendulum", {{kData + "MslMultiBody.mo", "Pendulum", {}, true}, {}});
  if (!model) return;
  const auto grid = runtime::OutputGrid::uniform(0, 5, 100);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  // Body m = 1, r_CM = 0.5, I_33 = 0.001; damper d = 0.1; from phi = 0, w = 0.
  const std::vector<double> exact = pendulum(0.001 + 0.25, 9.81 * 0.5, 0.1, 0, grid.times);
  const auto phi = column(r.trajectory, "rev.phi");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    INFO("t = " << grid.times[k]);
    CHECK(phi[k] == Approx(exact[k]).margin(1e-6));
  }
}

// The phasor current of the series circuit: I = V / (R + j(ωL − 1/(ωC)))
// with ωL = f and 1/(ωC) = 1/f here, so |I| = 1/√(0.01 + (f − 1/f)²) and
// arg I = −atan((f − 1/f)/0.1).
TEST_CASE("the MSL's QuasiStationary SeriesResonance draws its phasor current", "[msl]") {
  const std::string name = "e2e_msl_qs_series_resonance";
  auto model = msl_compiled_model(name, {{kData + "MslQuasiStationary.mo", "SeriesResonance", {}, true}, {}});
  if (!model) return;
  const auto grid = runtime::OutputGrid::uniform(0, 1, 50);
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto magnitude = variable(name, r.trajectory, p, "I_abs");
  const auto angle = variable(name, r.trajectory, p, "I_arg");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double f = 1e-6 + 2 * grid.times[k], x = f - 1 / f;
    INFO("t = " << grid.times[k]);
    CHECK(magnitude[k] == Approx(1 / std::sqrt(0.01 + x * x)).epsilon(1e-9));
    CHECK(angle[k] == Approx(-std::atan(x / 0.1)).epsilon(1e-9).margin(1e-12));
  }
}

// In per unit of the transformer's rating the load is 1 (resistive) and the
// short-circuit impedance r + jx with r = P_sc/S = 0.01 and |r + jx| = v_sc
// = 0.05, so the load's line voltage is 100 V / |1 + r + jx|, and the vector
// group 1 turns it by −30° besides the impedance's −atan(x / (1 + r)).
// Before the connect()s inside the Deltas' if-equations were edges of the
// connection graph, the model had 9 equations too many.
TEST_CASE("the MSL's QuasiStationary TransformerTestbench: a Yd01 transformer at rated load", "[msl]") {
  const std::string name = "e2e_msl_qs_transformer_testbench";
  auto model =
      msl_compiled_model(name, {{kData + "MslQuasiStationary.mo", "TransformerTestbench", {}, true}, {}, true});
  if (!model) return;
  const auto grid = runtime::OutputGrid::uniform(0, 1, 4);
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const double pu_r = 0.01, pu_x = std::sqrt(0.05 * 0.05 - pu_r * pu_r);
  const auto vs = variable(name, r.trajectory, p, "VS");
  const auto vl = variable(name, r.trajectory, p, "VL");
  const auto phi_s = variable(name, r.trajectory, p, "phiS");
  const auto phi_l = variable(name, r.trajectory, p, "phiL");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    CHECK(vs[k] == Approx(100).epsilon(1e-12));
    CHECK(vl[k] == Approx(100 / std::hypot(1 + pu_r, pu_x)).epsilon(1e-9));
    CHECK(phi_l[k] - phi_s[k] == Approx(-std::numbers::pi / 6 - std::atan(pu_x / (1 + pu_r))).epsilon(1e-9));
  }
}

namespace {

/// r(t_end) of r'' = -mue r / |r|^3 from (r, v), by RK4 with 1e-4 s steps.
std::array<double, 3> kepler(std::array<double, 3> r, std::array<double, 3> v, double mue, double t_end) {
  using V = std::array<double, 3>;
  const auto acc = [&](const V &x) {
    const double d = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    return V{-mue * x[0] / (d * d * d), -mue * x[1] / (d * d * d), -mue * x[2] / (d * d * d)};
  };
  const auto axpy = [](const V &x, double a, const V &y) { return V{x[0] + a * y[0], x[1] + a * y[1], x[2] + a * y[2]}; };
  const double h = 1e-4;
  for (long k = 0, n = std::lround(t_end / h); k < n; ++k) {
    const V k1r = v, k1v = acc(r);
    const V k2r = axpy(v, h / 2, k1v), k2v = acc(axpy(r, h / 2, k1r));
    const V k3r = axpy(v, h / 2, k2v), k3v = acc(axpy(r, h / 2, k2r));
    const V k4r = axpy(v, h, k3v), k4v = acc(axpy(r, h, k3r));
    for (int i = 0; i < 3; ++i) {
      r[i] += h / 6 * (k1r[i] + 2 * k2r[i] + 2 * k3r[i] + k4r[i]);
      v[i] += h / 6 * (k1v[i] + 2 * k2v[i] + 2 * k3v[i] + k4v[i]);
    }
  }
  return r;
}

} // namespace

TEST_CASE("the MSL's MultiBody PointGravity: two free bodies fly their Kepler orbits", "[msl]") {
  auto model =
      msl_compiled_model("e2e_msl_multibody_point_gravity", {{kData + "MslMultiBody.mo", "PointGravity", {}, true}, {}});
  if (!model) return;
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 5, 50);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  // mue = 1; body1 from (0, 0.6, 0) at (1, 0, 0), body2 from (0.6, 0.6, 0) at (0.6, 0, 0).
  const struct {
    const char *name;
    std::array<double, 3> r0, v0;
  } bodies[] = {{"body1", {0, 0.6, 0}, {1, 0, 0}}, {"body2", {0.6, 0.6, 0}, {0.6, 0, 0}}};
  for (const auto &b : bodies) {
    const std::array<double, 3> exact = kepler(b.r0, b.v0, 1.0, 5.0);
    for (int i = 0; i < 3; ++i) {
      const std::string name = std::string(b.name) + ".r_0[" + std::to_string(i + 1) + "]";
      INFO(name);
      CHECK(variable("e2e_msl_multibody_point_gravity", r.trajectory, p, name).back() ==
            Approx(exact[static_cast<std::size_t>(i)]).margin(1e-6));
    }
  }
}

TEST_CASE("the MSL's MultiBody ThreeSprings: a free body on springs keeps its energy", "[msl]") {
  auto model = msl_compiled_model("e2e_msl_multibody_three_springs",
                                  {{kData + "MslMultiBody.mo", "ThreeSprings", {}, true}, {}, true});
  if (!model) return;
  const auto grid = runtime::OutputGrid::uniform(0, 10, 200);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto col = [&](const std::string &name) { return column(r.trajectory, name); };
  const auto at = [](const std::string &base, int i) { return base + "[" + std::to_string(i) + "]"; };
  // body1: m = 0.8, I = 0.1 on the diagonal, r_CM = (0, -0.2, 0) in frame_a;
  // gravity 9.81 along -y; springs of c = 20, 40, 20 N/m, unstretched 0.1 m, massless.
  const double m = 0.8, inertia = 0.1, g = 9.81, s0 = 0.1;
  const std::array<double, 3> r_cm{0, -0.2, 0};
  std::array<std::array<std::vector<double>, 3>, 3> T;
  std::array<std::vector<double>, 3> w, v0, r0;
  for (int i = 1; i <= 3; ++i) {
    for (int j = 1; j <= 3; ++j)
      T[i - 1][j - 1] = col("body1.frame_a.R.T[" + std::to_string(i) + "," + std::to_string(j) + "]");
    w[i - 1] = col(at("body1.w_a", i));
    v0[i - 1] = col(at("body1.v_0", i));
    r0[i - 1] = col(at("body1.frame_a.r_0", i));
  }
  const std::array<std::pair<const char *, double>, 3> springs{{{"spring1", 20}, {"spring2", 40}, {"spring3", 20}}};
  std::vector<double> energy;
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const std::array<double, 3> wa{w[0][k], w[1][k], w[2][k]};
    const std::array<double, 3> wxr{wa[1] * r_cm[2] - wa[2] * r_cm[1], wa[2] * r_cm[0] - wa[0] * r_cm[2],
                                    wa[0] * r_cm[1] - wa[1] * r_cm[0]};
    double kinetic = 0, y_cm = r0[1][k];
    for (std::size_t i = 0; i < 3; ++i) {
      double v = v0[i][k];  // v_CM = v_0 + Tᵀ (w × r_CM), T resolving world vectors in frame_a
      for (std::size_t j = 0; j < 3; ++j) v += T[j][i][k] * wxr[j];
      kinetic += 0.5 * m * v * v + 0.5 * inertia * wa[i] * wa[i];
      y_cm += T[i][1][k] * r_cm[i];
    }
    double potential = m * g * y_cm;
    for (const auto &[name, c] : springs) {
      const double stretch = col(std::string(name) + ".spring.s_rel")[k] - s0;
      potential += 0.5 * c * stretch * stretch;
    }
    energy.push_back(kinetic + potential);
  }
  double drift = 0, swing = 0;
  for (std::size_t k = 0; k < energy.size(); ++k) {
    drift = std::max(drift, std::fabs(energy[k] - energy[0]));
    swing = std::max(swing, std::fabs(m * g * (r0[1][k] - r0[1][0])));
  }
  CHECK(swing > 0.1);  // the body moves: its weight's potential changes by more than 0.1 J
  CHECK(drift < 1e-6);
}

TEST_CASE("the MSL's MultiBody PlanarLoops_analytic: three loops stay closed as the drive turns", "[msl]") {
  const std::string name = "e2e_msl_multibody_planar_loops";
  auto model = msl_compiled_model(name, {{kData + "MslMultiBody.mo", "PlanarLoops_analytic", {}, true}, {}, true});
  if (!model) return;
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 5, 50);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  std::map<std::string, std::vector<double>> columns;
  const auto position = [&](const std::string &frame, std::size_t k) {
    std::array<double, 3> x{};
    for (int i = 0; i < 3; ++i) {
      const std::string v = frame + ".r_0[" + std::to_string(i + 1) + "]";
      if (!columns.contains(v)) columns[v] = variable(name, r.trajectory, p, v);
      x[static_cast<std::size_t>(i)] = columns[v][k];
    }
    return x;
  };
  const auto distance = [](const std::array<double, 3> &a, const std::array<double, 3> &b) {
    return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  };
  // The example's rods: r1a = r1b + rh - rv = (0.6, 0, 0), r1b = (0.1, 0.5, 0),
  // r2a = r2b + rh - r1b = (0.5, 0.1, 0), r2b = (0.1, 0.6, 0),
  // r3a = r3b + rh - r2b = (0.4, -0.05, 0), r3b = (0, 0.55, 0).
  const struct {
    const char *joint;
    double rod1, rod2;
  } joints[] = {{"jointRRR1", 0.6, std::hypot(0.1, 0.5)},
                {"jointRRR2", std::hypot(0.5, 0.1), std::hypot(0.1, 0.6)},
                {"jointRRR3", std::hypot(0.4, 0.05), 0.55}};
  const auto drive = variable(name, r.trajectory, p, "rev.phi");
  // The sine's amplitude is 0.7 rad, through the position source's filter.
  CHECK(*std::max_element(drive.begin(), drive.end()) > 0.6);
  CHECK(*std::min_element(drive.begin(), drive.end()) < -0.6);
  for (const auto &j : joints)
    for (std::size_t k = 0; k < grid.times.size(); ++k) {
      const std::string J = j.joint;
      INFO(J << " at t = " << grid.times[k]);
      CHECK(distance(position(J + ".frame_im", k), position(J + ".frame_ia", k)) == Approx(j.rod1).epsilon(1e-9));
      CHECK(distance(position(J + ".frame_im", k), position(J + ".frame_ib", k)) == Approx(j.rod2).epsilon(1e-9));
      CHECK(distance(position(J + ".frame_a", k), position(J + ".frame_ia", k)) == Approx(0).margin(1e-12));
    }
}
