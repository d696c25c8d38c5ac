// Every Jacobian block of a Model against central differences (Richardson
// extrapolated) of rhs, outputs and initial_state (at the initial point
// (t, u)); entries outside the pattern must be zero too.
#pragma once

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "mo/runtime/model.hpp"

namespace mo::codegen::test {

inline void check_jacobians(runtime::Model& model, double t, std::vector<double> x,
                            std::vector<double> u, std::vector<double> p, double tol = 1e-6) {
  using runtime::Jacobian;
  const auto& info = model.info();
  const std::size_t nx = info.states.size(), ny = info.outputs.size();
  auto function = [&](Jacobian b, const std::vector<double>& xs, const std::vector<double>& us,
                      const std::vector<double>& ps) {
    std::vector<double> out;
    switch (b) {
    case Jacobian::f_x:
    case Jacobian::f_u:
    case Jacobian::f_p: out.resize(nx), model.rhs(t, xs, us, ps, out); break;
    case Jacobian::h_x:
    case Jacobian::h_u:
    case Jacobian::h_p: out.resize(ny), model.outputs(t, xs, us, ps, out); break;
    case Jacobian::x0_p: out.resize(nx), model.initial_state(t, us, ps, out); break;
    }
    return out;
  };
  for (Jacobian b : {Jacobian::f_x, Jacobian::f_u, Jacobian::f_p, Jacobian::h_x, Jacobian::h_u,
                     Jacobian::h_p, Jacobian::x0_p}) {
    const runtime::Sparsity& sp = model.jacobian_sparsity(b);
    REQUIRE(sp.is_valid());
    std::vector<double> values(static_cast<std::size_t>(sp.nnz()));
    model.jacobian_values(b, t, x, u, p, values);
    const bool wrt_x = b == Jacobian::f_x || b == Jacobian::h_x;
    const bool wrt_u = b == Jacobian::f_u || b == Jacobian::h_u;
    std::vector<double>& arg = wrt_x ? x : wrt_u ? u : p;
    REQUIRE(static_cast<std::size_t>(sp.cols) == arg.size());
    for (int c = 0; c < sp.cols; ++c) {
      const double at = arg[static_cast<std::size_t>(c)];
      const double h = 1e-3 * std::max(1.0, std::fabs(at));
      auto central = [&](double step) {
        arg[static_cast<std::size_t>(c)] = at + step;
        const auto plus = function(b, x, u, p);
        arg[static_cast<std::size_t>(c)] = at - step;
        const auto minus = function(b, x, u, p);
        arg[static_cast<std::size_t>(c)] = at;
        std::vector<double> d(plus.size());
        for (std::size_t i = 0; i < d.size(); ++i) d[i] = (plus[i] - minus[i]) / (2 * step);
        return d;
      };
      const auto d1 = central(h), d2 = central(h / 2);
      for (int r = 0; r < sp.rows; ++r) {
        const double numeric = (4 * d2[static_cast<std::size_t>(r)] - d1[static_cast<std::size_t>(r)]) / 3;
        const int k = sp.find(r, c);
        const double exact = k < 0 ? 0.0 : values[static_cast<std::size_t>(k)];
        INFO("block " << static_cast<int>(b) << " entry (" << r << ", " << c << ")"
                      << (k < 0 ? " outside the pattern" : ""));
        CHECK(std::fabs(exact - numeric) <= tol * std::max({1.0, std::fabs(exact), std::fabs(numeric)}));
      }
    }
  }
}

}  // namespace mo::codegen::test
