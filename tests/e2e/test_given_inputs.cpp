// Study option `inputs` in optimal_control: the inputs it names follow their
// signals (JModelica's ExternalData `eliminated`), the others stay controls.
// A disturbance given as a signal must give the same optimum as the same
// disturbance written into the model; naming an unknown input, or giving
// two experiments' inputs, is refused.
#include <cmath>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// der(x) = -x + u + d, tracking x = 1 with a cheap control u ∈ [-5, 5]: d is
/// an input (`inside` false) or 0.5 sin(2πt) in the model's equations.
void write_study(const fs::path& dir, bool inside, const std::string& options) {
  std::ofstream f(dir / "Track.mop");
  f << "model Disturbed\n"
       "  input Real u(min = -5, max = 5);\n"
    << (inside ? "  Real d = 0.5 * sin(2 * 3.141592653589793 * time);\n" : "  input Real d;\n")
    << "  Real x(start = 0, fixed = true);\n"
       "equation\n"
       "  der(x) = -x + u + d;\n"
       "end Disturbed;\n"
       "optimization Track(objectiveIntegrand = (x - 1)^2 + 0.1 * u^2, startTime = 0, finalTime = 2)\n"
       "  extends Disturbed;\n"
       "annotation(__mocompile(n_e = 40, n_cp = 3, plot = false"
    << options << "));\n"
    << "end Track;\n";
}

struct Solved {
  Run run;
  nlohmann::json summary;
  std::string trajectories;
};

Solved solve(const std::string& name, bool inside, const std::string& options) {
  const fs::path dir = scratch(name);
  write_study(dir, inside, options);
  Solved s;
  s.run = morun(quoted((dir / "Track.mop").string()) + " -o " + quoted((dir / "out").string()), dir);
  if (fs::exists(dir / "out" / "summary.json")) {
    s.summary = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
    s.trajectories = slurp(dir / "out" / "trajectories.csv");
  }
  return s;
}

}  // namespace

TEST_CASE("optimal control: an input given a signal follows it, the others stay controls") {
  const Solved given = solve("given_input_sine", false, ", inputs = {\"d=sine:0.5,1\"}");
  const Solved inside = solve("given_input_inside", true, "");
  const Solved zero = solve("given_input_zero", false, ", inputs = {\"d=const:0\"}");
  for (const Solved* s : {&given, &inside, &zero}) {
    INFO(s->run.err);
    REQUIRE(s->run.status == 0);
    CHECK(s->summary["status"] == "success");
    // The re-simulation replays the given signal beside the optimal control.
    CHECK(s->summary["resimulation"]["max_state_difference"].get<double>() < 1e-6);
  }
  const double j = given.summary["objective"].get<double>();
  CHECK(j == Approx(inside.summary["objective"].get<double>()).epsilon(1e-8));
  CHECK(std::fabs(j - zero.summary["objective"].get<double>()) > 1e-3 * j);  // the signal matters
  // d is no NLP variable: one control of 40 values, not two.
  CHECK(given.summary["nlp"]["variables"].get<int>() == inside.summary["nlp"]["variables"].get<int>());
  CHECK(given.trajectories.substr(0, given.trajectories.find('\n')).find(",d") != std::string::npos);
}

TEST_CASE("optimal control: a given input the model lacks, or two experiments' inputs, is refused") {
  const Solved unknown = solve("given_input_unknown", false, ", inputs = {\"q=const:1\"}");
  INFO(unknown.run.err);
  CHECK(unknown.run.status == 2);
  CHECK(unknown.run.err.find("the model has no input 'q'") != std::string::npos);
  const Solved two = solve("given_input_two", false, ", inputs = {\"d=const:0\", \"d=const:1\"}");
  INFO(two.run.err);
  CHECK(two.run.status == 2);
  CHECK(two.run.err.find("optimal_control has one experiment") != std::string::npos);
}
