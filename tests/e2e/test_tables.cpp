// Tables through external objects (frontend/src/flatten_tables.cpp): the
// functions of ModelicaStandardTables become expressions of the table, so
// a time table's integral, its time events, a 1-D table of a signal and the
// sensitivity to a table entry follow their closed forms (data/Tables.mo).
#include <cmath>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

const std::string kTables = kData + "Tables.mo";

/// Tables.Integrals' closed forms (see the model).
double exact_a(double t) {
  const double s = t - 0.5;
  if (s < 0) return 0;
  if (s <= 1) return s * s;
  if (s <= 3) return 1 + 5 * (s - 1) - (s - 1) * (s - 1);
  return 7 + (s - 3);
}
double exact_b(double t) {
  const double tau = std::fmod(t, 2.0);
  return 4 * std::floor(t / 2) + (tau < 1 ? tau : 1 + 3 * (tau - 1));
}


/// Akima's spline through (xs, ys) with ModelicaStandardTables' end
/// conditions and its continuation by the end slopes, in numbers: the
/// reference for Tables.Spline.
double akima_reference(const std::vector<double>& xs, const std::vector<double>& ys, double u) {
  const std::size_t n = xs.size();
  std::vector<double> d(n + 3);
  for (std::size_t i = 0; i + 1 < n; ++i) d[i + 2] = (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]);
  d[0] = 3 * d[2] - 2 * d[3];
  d[1] = 2 * d[2] - d[3];
  d[n + 1] = 2 * d[n] - d[n - 1];
  d[n + 2] = 3 * d[n] - 2 * d[n - 1];
  auto slope = [&](std::size_t i) {
    const double w1 = std::fabs(d[i + 3] - d[i + 2]), w2 = std::fabs(d[i + 1] - d[i]);
    return w1 + w2 > 0 ? (w1 * d[i + 1] + w2 * d[i + 2]) / (w1 + w2) : 0.5 * (d[i + 1] + d[i + 2]);
  };
  auto cubic = [&](std::size_t i, double s, bool derivative) {
    const double dx = xs[i + 1] - xs[i], c2 = slope(i), next = slope(i + 1);
    const double c1 = (3 * d[i + 2] - 2 * c2 - next) / dx, c0 = (c2 + next - 2 * d[i + 2]) / (dx * dx);
    return derivative ? (3 * c0 * s + 2 * c1) * s + c2 : ys[i] + ((c0 * s + c1) * s + c2) * s;
  };
  if (u < xs.front()) return ys.front() + slope(0) * (u - xs.front());
  if (u > xs.back()) return ys.back() + cubic(n - 2, xs[n - 1] - xs[n - 2], true) * (u - xs.back());
  std::size_t i = 0;
  while (i + 2 < n && u >= xs[i + 1]) ++i;
  return cubic(i, u - xs[i], false);
}

}  // namespace

TEST_CASE("a time table's segments, jump, hold and period integrate exactly", "[tables]") {
  auto model = compiled_model("e2e_tables_integrals", {{kTables, "Tables.Integrals", {}, true}, {}});
  const auto grid = runtime::OutputGrid::uniform(0, 5, 100);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto a = column(r.trajectory, "a"), b = column(r.trajectory, "b");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    INFO("t = " << grid.times[k]);
    CHECK(a[k] == Approx(exact_a(grid.times[k])).margin(1e-8));
    CHECK(b[k] == Approx(exact_b(grid.times[k])).margin(1e-8));
  }
  // The time events: lin's start time, its jump and its end (0.5, 1.5,
  // 3.5); con's every row time, period after period.
  for (double t : {0.5, 1.0, 1.5, 2.0, 3.0, 3.5, 4.0, 5.0}) {
    INFO("event at " << t);
    CHECK(std::any_of(r.event_times.begin(), r.event_times.end(), [&](double e) { return std::abs(e - t) < 1e-9; }));
  }
}

TEST_CASE("the sensitivity to a table entry follows the interpolation", "[tables]") {
  // a' = lin.y; on s in [1, 3] lin.y = 5 + (v - 5)(s - 1)/2 with v =
  // lin.table[4,2], held at v after: da/dv = (s - 1)^2/4, then 1 + (s - 3).
  const std::string par = "lin.table[4,2]";
  auto model = compiled_model("e2e_tables_integrals_d", {{kTables, "Tables.Integrals", {}, true}, {par}});
  const auto grid = runtime::OutputGrid::uniform(0, 5, 50);
  auto options = tight();
  options.sensitivities.method = runtime::SensitivityMethod::model_states;
  options.sensitivities.parameters = {parameter(model->info(), par)};
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, options);
  INFO(r.message);
  REQUIRE(r.ok());
  const auto row = static_cast<Eigen::Index>(*model->info().state_index("a"));
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double s = grid.times[k] - 0.5;
    const double exact = s <= 1 ? 0 : s <= 3 ? (s - 1) * (s - 1) / 4 : 1 + (s - 3);
    INFO("t = " << grid.times[k]);
    CHECK(r.state_sensitivities[k](row, 0) == Approx(exact).margin(1e-7));
  }
}

TEST_CASE("a 1-D table of a signal interpolates and continues its end segments", "[tables]") {
  auto model = compiled_model("e2e_tables_map", {{kTables, "Tables.Map", {}, true}, {}});
  const auto grid = runtime::OutputGrid::uniform(0, 6, 120);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto u = column(r.trajectory, "u"), y = column(r.trajectory, "y");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double v = u[k];
    const double exact = v < 1 ? v : v < 2 ? 1 + 3 * (v - 1) : 4 + 3 * (v - 2);
    INFO("u = " << v);
    CHECK(y[k] == Approx(exact).margin(1e-12));
  }
}

TEST_CASE("the MSL's CombiTimeTable, CombiTable1Ds and CombiTable2D follow their closed forms", "[tables][msl]") {
  // Found by Modelica's lookup on MODELICAPATH, as a user runs it.
  auto model = msl_compiled_model("e2e_tables_msl", {{kData + "MslTables.mo", "MslTables", {}, true}, {}});
  if (!model) return;
  const auto grid = runtime::OutputGrid::uniform(0, 4, 80);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto x = column(r.trajectory, "x");
  const auto triangle = column(r.trajectory, "triangle"), m = column(r.trajectory, "m_y"),
             m2 = column(r.trajectory, "m2_y");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k], tau = std::fmod(t, 2.0), y = tau < 1 ? tau : 2 - tau, u = 3 * y;
    const double s = t - 0.3;
    INFO("t = " << t);
    CHECK(triangle[k] == Approx(y).margin(1e-9));
    CHECK(m[k] == Approx(u < 1 ? u : u < 2 ? 1 + 3 * (u - 1) : 4 + 3 * (u - 2)).margin(1e-9));
    CHECK(m2[k] == Approx(y + 0.5).margin(1e-9));
    CHECK(x[k] == Approx(s < 0 ? t : t + 5 * s + s * s / 4).margin(1e-7));
  }
}

TEST_CASE("Akima splines (ContinuousDerivative) follow the library's coefficients - sensitivities too", "[tables]") {
  // Tables.Spline: a time table and a 1-D table through the same rows,
  // against the spline computed in numbers; dy/d table[3,2] against central
  // differences of that computation.
  const std::vector<double> xs{0, 1, 2, 3, 5}, ys{0, 1, 4, 3, 0};
  const std::string par = "table[3,2]";
  auto model = compiled_model("e2e_tables_spline", {{kTables, "Tables.Spline", {}, true}, {par}});
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 6, 240);
  auto options = tight();
  options.sensitivities.method = runtime::SensitivityMethod::model_states;
  options.sensitivities.parameters = {parameter(model->info(), par)};
  const auto r = runtime::simulate(*model, {}, p, grid, options);
  INFO(r.message);
  REQUIRE(r.ok());
  const auto y = column(r.trajectory, "y"), z = column(r.trajectory, "z");
  const auto y_output = static_cast<Eigen::Index>(*model->info().output_index("y"));
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k];
    INFO("t = " << t);
    CHECK(y[k] == Approx(akima_reference(xs, ys, t)).margin(1e-12));
    CHECK(z[k] == Approx(akima_reference(xs, ys, t - 1)).margin(1e-12));
    std::vector<double> up = ys, down = ys;
    up[2] += 1e-6;
    down[2] -= 1e-6;
    const double fd = (akima_reference(xs, up, t) - akima_reference(xs, down, t)) / 2e-6;
    CHECK(r.output_sensitivities[k](y_output, 0) == Approx(fd).margin(1e-6));
  }
}
