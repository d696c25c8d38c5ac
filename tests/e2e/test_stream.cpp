// Stream connectors (MLS 15): inStream() and actualStream() from the
// connection sets, through connectors at several levels of the hierarchy, and
// a flow that reverses. tests/e2e/data/StreamMixing.mo against closed forms.
#include <cmath>
#include <numbers>
#include <string>

#include "e2e/support.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// A tank of mass 2 fed 4 kg/s of a 1:3 mixing of h = 100 and h = 200
/// (175), the same 4 kg/s drawn at its own h, from U = 0.
double fed_tank_h(double t) { return 175 * (1 - std::exp(-2 * t)); }

}  // namespace

TEST_CASE("inStream mixes the flows that enter a connection set of inside connectors", "[stream]") {
  const auto r = run_data_model("e2e_stream_junction", "StreamMixing.mo", "StreamMixing.Junction", 3, 30);
  const auto t = r->times();
  const auto h = (*r)("tank.h");
  const auto h_sink = (*r)("sink.h_in");
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    CHECK(h[k] == Approx(fed_tank_h(t[k])).margin(1e-6));
    CHECK(h_sink[k] == Approx(h[k]).margin(1e-9));  // one-to-one: the other side's outflow
  }
}

TEST_CASE("stream variables of outside connectors carry the mixing through the hierarchy", "[stream]") {
  const auto r = run_data_model("e2e_stream_hierarchy", "StreamMixing.mo", "StreamMixing.Hierarchy", 3, 30);
  const auto t = r->times();
  const auto h = (*r)("tank.h");
  const auto mixed = (*r)("h_mixed");
  const auto pipe_b = (*r)("line.pipe.b.h_outflow");
  const auto pipe_a = (*r)("line.pipe.a.h_outflow");
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    CHECK(h[k] == Approx(fed_tank_h(t[k])).margin(1e-6));
    CHECK(mixed[k] == Approx(175).epsilon(1e-12));   // mixer.out: the mixing of its two outside ports
    CHECK(pipe_b[k] == Approx(175).epsilon(1e-12));  // inStream(pipe.a.h) through line.a
    CHECK(pipe_a[k] == Approx(h[k]).margin(1e-9));   // inStream(pipe.b.h) through line.b: the tank's
  }
}

TEST_CASE("actualStream follows the flow's direction, and an unconnected port's inStream is its own outflow",
          "[stream]") {
  const double pi = std::numbers::pi;
  const auto r = run_data_model("e2e_stream_reversal", "StreamMixing.mo", "StreamMixing.Reversal", 2 * pi, 40);
  const auto t = r->times();
  const auto U = (*r)("tank.U");
  const auto h = (*r)("tank.h");
  const auto h_b = (*r)("h_b");
  // q = sin t enters at hb = 50 until pi, then leaves at the tank's h = U/M.
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    const double exact = t[k] <= pi ? 50 * (1 - std::cos(t[k])) : 100 * std::exp(-(1 + std::cos(t[k])) / 2);
    CHECK(U[k] == Approx(exact).margin(1e-6));
    CHECK(h_b[k] == Approx(h[k]).margin(1e-9));
  }
}
