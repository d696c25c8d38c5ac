// The history behind delay() (delay_lines.hpp), recorded and read by hand.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "mo/runtime/delay_lines.hpp"

using mo::runtime::DelayLines;

TEST_CASE("DelayLines: the start before t0 + T, a cubic through the history after it") {
  DelayLines d;
  d.reset(1);
  d.set_times(0, 1.0, 3.0);  // Tmax 3: everything recorded is kept
  d.set_start(0, 7.0);
  CHECK(d.value(0, 0.5) == 7.0);  // no record yet: the start being settled
  // e(t) = t^3 - t at uneven times from t0 = 0: a cubic reads it exactly.
  for (double t : {0.0, 0.1, 0.25, 0.5, 0.6, 0.9, 1.3, 1.4, 2.0}) d.record(0, t, t * t * t - t);
  CHECK(d.value(0, 0.7) == 0.0);  // t - T < t0: e(t0)
  for (double q : {0.05, 0.3, 0.55, 0.77, 1.1, 1.35, 1.8}) {
    INFO("t - T = " << q);
    CHECK(d.value(0, q + 1.0) == Approx(q * q * q - q).margin(1e-12));
  }
}

TEST_CASE("DelayLines: a jump is read before it until its event, after it from then on") {
  DelayLines d;
  d.reset(1);
  d.set_times(0, 0.5, 2.0);
  d.record(0, 0.0, 0.0);
  d.record(0, 0.1, 0.0);
  d.record(0, 0.2, 0.0);  // the event at 0.2: before the handler ...
  d.record(0, 0.2, 1.0);  // ... and after it
  d.record(0, 0.3, 1.0);
  d.record(0, 0.4, 1.0);
  // Breaks: t0 + T = 0.5 and the jump's 0.2 + T = 0.7 (level 1).
  CHECK(d.next_event(0.0) == Approx(0.5));
  CHECK(d.next_event(0.5) == Approx(0.7));
  CHECK(d.value(0, 0.65) == 0.0);  // no cubic overshoot across the jump
  CHECK(d.value(0, 0.75) == 1.0);
  const double at = d.next_event(0.5);
  CHECK(d.value(0, at) == 0.0);  // integrating up to the event: the value before
  d.at_event(at);
  CHECK(d.value(0, at) == 1.0);  // at and after the event: the value after
  // The level-1 break at 0.7 scheduled 0.7 + T = 1.2 (level 2); 1.2 + T is level 3: none.
  CHECK(d.next_event(at) == Approx(1.2));
  d.at_event(1.2);
  CHECK(d.next_event(1.2) == std::numeric_limits<double>::infinity());
}

TEST_CASE("DelayLines: a delay time must be positive and at most delayMax") {
  DelayLines d;
  d.reset(2);
  d.set_times(0, 0.3, 1.0);
  d.set_times(1, 0.2, 0.2);
  CHECK(d.shortest() == 0.2);
  d.set_times(1, 0.0, 0.2);
  CHECK(std::isnan(d.shortest()));
  d.set_times(1, 0.5, 0.2);
  CHECK(std::isnan(d.shortest()));
}

TEST_CASE("DelayLines: old history is dropped, what t - Tmax reads is kept") {
  DelayLines d;
  d.reset(1);
  d.set_times(0, 0.5, 1.0);
  for (int k = 0; k <= 10000; ++k) {
    const double t = k * 1e-3;
    d.record(0, t, std::sin(t));
  }
  // t = 10: reads 9.5; Tmax = 1 keeps from 9.0 on.
  CHECK(d.value(0, 10.0) == Approx(std::sin(9.5)).margin(1e-12));
  CHECK(d.value(0, 9.6) == Approx(std::sin(9.1)).margin(1e-12));
}

TEST_CASE("DelayLines: a varying delay time is given at each read and schedules no breaks") {
  DelayLines d;
  d.reset(1);
  d.set_varying(0, 0.0, 2.0);  // T = 0 at the start: the step is bounded by Tmax
  CHECK(d.shortest() == 2.0);
  for (int k = 0; k <= 300; ++k) {
    const double t = k * 0.01;
    d.record(0, t, 2 * t);
  }
  CHECK(d.next_event(0.0) == std::numeric_limits<double>::infinity());
  CHECK(d.value(0, 3.0, 0.55) == Approx(2 * 2.45).margin(1e-12));
  CHECK(d.value(0, 3.0, 1.7) == Approx(2 * 1.3).margin(1e-12));
  CHECK(d.value(0, 3.0, 0.0) == 6.0);  // t - T at the last record
}
