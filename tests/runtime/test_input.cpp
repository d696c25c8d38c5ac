// Input signals: values, left limits at jumps, breakpoints; CSV tables and
// their error messages (file:line: error: ...).
#include "mo/runtime/input.hpp"

#include <catch2/catch.hpp>

#include <memory>
#include <numbers>

using namespace mo::runtime;

TEST_CASE("Constant and sine inputs", "[input]") {
  auto c = constant_input(2.5);
  CHECK(c->value(-3.0) == 2.5);
  CHECK(c->breakpoints(0, 10).empty());
  auto s = sine_input(3.0, 2.0, 0.5, 1.0);
  CHECK(s->value(0.1) == Approx(1.0 + 3.0 * std::sin(2 * std::numbers::pi * 2.0 * 0.1 + 0.5)));
  CHECK(s->breakpoints(0, 10).empty());
}

TEST_CASE("Step input: jump at its start time, left limit before", "[input]") {
  auto s = step_input(2.0, 1.0, -1.0);
  CHECK(s->value(0.5) == -1.0);
  CHECK(s->value(1.0) == 1.0);
  CHECK(s->value_before(1.0) == -1.0);
  CHECK(s->breakpoints(0, 2) == std::vector<double>{1.0});
  CHECK(s->breakpoints(1, 2).empty());  // open interval
}

TEST_CASE("Pulse input: periodic edges from its start", "[input]") {
  auto p = pulse_input(5.0, 1.0, 0.25, 0.5);
  CHECK(p->value(0.4) == 0.0);
  CHECK(p->value(0.5) == 5.0);
  CHECK(p->value(0.74) == 5.0);
  CHECK(p->value(0.75) == 0.0);
  CHECK(p->value_before(0.75) == 5.0);
  CHECK(p->value_before(1.5) == 0.0);
  CHECK(p->value(1.6) == 5.0);
  CHECK(p->breakpoints(0.0, 2.0) == std::vector<double>{0.5, 0.75, 1.5, 1.75});
  CHECK(p->breakpoints(0.6, 1.6) == std::vector<double>{0.75, 1.5});
  CHECK_THROWS_AS(pulse_input(1.0, 1.0, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(pulse_input(1.0, 1.0, 2.0), std::invalid_argument);
}

TEST_CASE("Piecewise constant input", "[input]") {
  auto p = piecewise_constant_input({0.0, 1.0, 3.0}, {1.0, 2.0, 3.0});
  CHECK(p->value(-1.0) == 1.0);
  CHECK(p->value(0.5) == 1.0);
  CHECK(p->value(1.0) == 2.0);
  CHECK(p->value_before(1.0) == 1.0);
  CHECK(p->value(10.0) == 3.0);
  CHECK(p->breakpoints(-5, 5) == std::vector<double>{1.0, 3.0});
  CHECK_THROWS_AS(piecewise_constant_input({0.0, 0.0}, {1.0, 2.0}), std::invalid_argument);
  CHECK_THROWS_AS(piecewise_constant_input({0.0}, {1.0, 2.0}), std::invalid_argument);
  CHECK_THROWS_AS(piecewise_constant_input({}, {}), std::invalid_argument);
}

TEST_CASE("CSV table: linear interpolation, hold at ends, jumps at repeated times", "[input]") {
  auto table = std::make_shared<const InputTable>(read_input_csv(MO_TEST_DATA_DIR "/inputs.csv"));
  CHECK(table->names == std::vector<std::string>{"F", "G"});
  auto f = table_input(table, "F");
  auto g = table_input(table, 1);
  CHECK(f->value(-1.0) == 0.0);
  CHECK(f->value(0.5) == Approx(1.0));
  CHECK(f->value(1.5) == 2.0);
  CHECK(f->value_before(2.0) == 2.0);  // jump at t = 2
  CHECK(f->value(2.0) == -1.0);
  CHECK(f->value(3.0) == Approx(0.0));
  CHECK(f->value(9.0) == 1.0);
  CHECK(g->value(1.5) == Approx(15.0));
  CHECK(f->breakpoints(0.0, 5.0) == std::vector<double>{1.0, 2.0, 4.0});
  CHECK_THROWS_AS(table_input(table, "H"), std::out_of_range);
  CHECK_THROWS_AS(table_input(table, 2), std::out_of_range);

  Inputs inputs;
  inputs.add(table_input(table, "F"));
  inputs.add(step_input(1.0, 0.5));
  CHECK(inputs.breakpoints(0.0, 5.0) == std::vector<double>{0.5, 1.0, 2.0, 4.0});
  std::vector<double> u(2);
  inputs.evaluate_before(2.0, u);
  CHECK(u == std::vector<double>{2.0, 1.0});
}

namespace {
std::string parse_error(std::string_view text) {
  try {
    parse_input_csv(text, "in.csv");
  } catch (const InputFileError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST_CASE("CSV table errors name file and line", "[input][errors]") {
  CHECK(parse_error("") == "in.csv:1: error: no header line 'time,<input>,...'");
  CHECK(parse_error("t,F\n0,1\n") ==
        "in.csv:1: error: header must be 'time,<input>,...' with at least one input column");
  CHECK(parse_error("time\n0\n") ==
        "in.csv:1: error: header must be 'time,<input>,...' with at least one input column");
  CHECK(parse_error("time,F,F\n") == "in.csv:1: error: duplicate column 'F'");
  CHECK(parse_error("time,F,\n") == "in.csv:1: error: empty name of column 3");
  CHECK(parse_error("# comment\ntime,F\n") == "in.csv:2: error: no data rows after the header");
  CHECK(parse_error("time,F\n0,1\n\n1,2,3\n") == "in.csv:4: error: expected 2 fields, found 3");
  CHECK(parse_error("time,F\n0,abc\n") == "in.csv:2: error: field 2 ('abc') is not a number");
  CHECK(parse_error("time,F\n0,1.5x\n") == "in.csv:2: error: field 2 ('1.5x') is not a number");
  CHECK(parse_error("time,F\n0,\n") == "in.csv:2: error: field 2 ('') is not a number");
  CHECK(parse_error("time,F\n0,inf\n") == "in.csv:2: error: field 2 is not finite");
  CHECK(parse_error("time,F\n1,0\n0.5,1\n") ==
        "in.csv:3: error: time 0.5 is less than the previous time");
  CHECK(parse_error("time,F\n1,0\n1,1\n1,2\n") == "in.csv:4: error: time 1 appears more than twice");
  CHECK(parse_error("time,F\r\n0, 1\r\n1,2\r\n") == "no error");  // CRLF and spaces are fine
  try {
    read_input_csv("/nonexistent/dir/in.csv");
    FAIL("no error");
  } catch (const InputFileError& e) {
    CHECK(std::string(e.what()) == "/nonexistent/dir/in.csv:1: error: cannot open file");
  }
}

TEST_CASE("Collocated input: the polynomial through each element's points", "[input]") {
  // Two elements [0, 1), [1, 3]; points τ = 1/3, 1: values of t² on the first
  // (a line through them), of 5 − t on the second.
  const std::vector<double> points{1.0 / 3.0, 1.0};
  const double a = 1.0 / 9.0, b = 1.0;  // t² at t = 1/3 and 1
  const auto s = collocated_input({0.0, 1.0}, 3.0, points, {a, b, 5.0 - 5.0 / 3.0, 2.0});
  CHECK(s->value(1.0 / 3.0) == Approx(a));
  CHECK(s->value(0.0) == Approx(a - (b - a) / 2));       // extrapolated to τ = 0
  CHECK(s->value_before(1.0) == Approx(b));             // left of the boundary: the first element
  CHECK(s->value(1.0) == Approx(5.0 - 1.0));            // the second element's line at τ = 0
  CHECK(s->value(2.0) == Approx(3.0));
  CHECK(s->breakpoints(0.0, 3.0) == std::vector<double>{1.0});
  const auto w = lagrange_weights(points, 0.5);
  CHECK(w[0] + w[1] == Approx(1.0));
  CHECK_THROWS_AS(collocated_input({0.0}, 1.0, points, {1.0}), std::invalid_argument);
}

TEST_CASE("Input derivatives just before a time: exact slopes, a difference by default", "[input]") {
  CHECK(constant_input(2.5)->derivative_before(1.0) == 0.0);
  const double w = 2 * std::numbers::pi * 2.0;
  CHECK(sine_input(3.0, 2.0, 0.5, 1.0)->derivative_before(0.1) == Approx(3.0 * w * std::cos(w * 0.1 + 0.5)));
  CHECK(step_input(2.0, 1.0)->derivative_before(1.0) == 0.0);
  CHECK(pulse_input(1.0, 1.0, 0.5)->derivative_before(0.25) == 0.0);
  CHECK(piecewise_constant_input({0.0, 1.0}, {1.0, 2.0})->derivative_before(0.5) == 0.0);
  // A table: the slope of the segment that ends at or after t; 0 where held.
  auto table = std::make_shared<InputTable>(InputTable{{"u"}, {0.0, 1.0, 3.0}, {{0.0, 2.0, 1.0}}});
  const auto u = table_input(table, "u");
  CHECK(u->derivative_before(0.5) == Approx(2.0));
  CHECK(u->derivative_before(1.0) == Approx(2.0));  // the kink: the slope from the left
  CHECK(u->derivative_before(2.0) == Approx(-0.5));
  CHECK(u->derivative_before(5.0) == 0.0);
  CHECK(u->derivative_before(-1.0) == 0.0);
  // The default (a collocated input): a one-sided difference, from the left
  // at an element boundary. t² on [0, 1) (slope 2 at 1), 5 − t after.
  const std::vector<double> points{1.0 / 3.0, 2.0 / 3.0, 1.0};
  std::vector<double> values;
  for (double tau : points) values.push_back(tau * tau);
  for (double tau : points) values.push_back(5.0 - (1.0 + 2.0 * tau));
  const auto s = collocated_input({0.0, 1.0}, 3.0, points, values);
  CHECK(s->derivative_before(1.0) == Approx(2.0).epsilon(1e-5));
  CHECK(s->derivative_before(2.0) == Approx(-1.0).epsilon(1e-5));
  Inputs both;
  both.add(table_input(table, "u"));
  both.add(shared_input(std::shared_ptr<const InputSignal>(sine_input(1.0, 1.0))));
  std::vector<double> udot(2);
  both.derivative_before(2.0, udot);
  CHECK(udot[0] == Approx(-0.5));
  CHECK(udot[1] == Approx(2 * std::numbers::pi));
}
