// The random generators of ModelicaExternalC that mocompile provides
// (runtime/include/mo/runtime/modelica_random.hpp, frontend/src/
// flatten_random.cpp), on tests/e2e/data/RandomNoise.mo: a state seeded at
// translation, draws at samples, against Vigna's generators written here
// once more on plain 64-bit words.
#include <cstdint>
#include <fstream>
#include <sstream>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

std::uint64_t word(std::int32_t low, std::int32_t high) {
  return std::uint64_t{static_cast<std::uint32_t>(low)} | std::uint64_t{static_cast<std::uint32_t>(high)} << 32;
}
double unit(std::uint64_t x) { return static_cast<double>(static_cast<std::int64_t>(x)) / 18446744073709551616.0 + 0.5; }

/// xorshift64* (xorshift.di.unimi.it) on the word {s[0], s[1]}.
double star64(std::int32_t s[2]) {
  std::uint64_t x = word(s[0], s[1]);
  x ^= x >> 12;
  x ^= x << 25;
  x ^= x >> 27;
  x *= 2685821657736338717ULL;
  s[0] = static_cast<std::int32_t>(x & 0xffffffffu);
  s[1] = static_cast<std::int32_t>(x >> 32);
  return unit(x);
}

/// xorshift128+ on the words {s[0], s[1]} and {s[2], s[3]}.
double plus128(std::int32_t s[4]) {
  std::uint64_t a = word(s[0], s[1]);
  const std::uint64_t b = word(s[2], s[3]);
  a ^= a << 23;
  const std::uint64_t c = a ^ b ^ (a >> 17) ^ (b >> 26);
  const std::uint64_t next = c + b;
  s[0] = s[2];
  s[1] = s[3];
  s[2] = static_cast<std::int32_t>(next & 0xffffffffu);
  s[3] = static_cast<std::int32_t>(next >> 32);
  return unit(next);
}

/// xorshift1024* on 16 words and the index p.
double star1024(std::uint64_t words[16], int& p) {
  const std::uint64_t s0 = words[p];
  p = (p + 1) & 15;
  std::uint64_t s1 = words[p];
  s1 ^= s1 << 31;
  words[p] = s1 ^ s0 ^ (s1 >> 11) ^ (s0 >> 30);
  return unit(words[p] * 1181783497276652981ULL);
}

tools::ModelSource source(const std::string& name) { return {kData + "RandomNoise.mo", name, {}, true}; }

}  // namespace

TEST_CASE("xorshift128+ draws at samples from a state seeded when the model is translated") {
  // RandomNoise.seeded(5, 67867967): five xorshift64* steps, then one more.
  std::int32_t s[2] = {5, 67867967};
  for (int i = 0; i < 5; ++i) star64(s);
  std::int32_t state[4] = {s[0], s[1], 0, 0};
  star64(s);
  state[2] = s[0];
  state[3] = s[1];
  // r at initialisation reads the initial state without stepping it (as the
  // MSL's noise blocks do), so the tick at t = 0.1 draws the same number.
  std::int32_t copy[4] = {state[0], state[1], state[2], state[3]};
  std::vector<double> draws{plus128(copy)};  // on [0, 0.1), then [0.1, 0.2), ...
  for (int k = 1; k <= 10; ++k) draws.push_back(plus128(state));

  auto model = compiled_model("e2e_random_sampled", {source("RandomNoise.SampledNoise"), {}});
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 1.05, 21);  // 0.05 apart: between the samples
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto x = column(r.trajectory, "x");
  double integral = 0;
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k];
    const int ticks = static_cast<int>(std::floor(t / 0.1 + 1e-9));
    INFO("t = " << t);
    CHECK(x[k] == Approx(integral + draws[static_cast<std::size_t>(ticks)] * (t - 0.1 * ticks)).margin(1e-9));
    if (k + 1 < grid.times.size() && std::floor(grid.times[k + 1] / 0.1 + 1e-9) > ticks)
      integral += draws[static_cast<std::size_t>(ticks)] * 0.1;
  }
  // After the last sample (t = 1.0, the tenth): r and the state it left.
  CHECK(discrete_value(*model, "r") == draws[10]);
  for (int i = 0; i < 4; ++i) CHECK(discrete_value(*model, "state[" + std::to_string(i + 1) + "]") == state[i]);
}

TEST_CASE("xorshift1024* steps its 16 words and index at each sample") {
  std::uint64_t words[16];
  for (int i = 0; i < 16; ++i) words[i] = word(3 + 2 * i + 1, 3 + 2 * i + 2);
  int p = 0;
  double last = 0;
  for (int draw = 0; draw < 4; ++draw) last = star1024(words, p);  // t = 0.25, 0.5, 0.75, 1
  auto model = compiled_model("e2e_random_long", {source("RandomNoise.LongStateNoise"), {}});
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), runtime::OutputGrid::uniform(0, 1.1, 11), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(discrete_value(*model, "r") == last);
  CHECK(discrete_value(*model, "state[33]") == p);
  for (int i = 0; i < 16; ++i) {
    CHECK(discrete_value(*model, "state[" + std::to_string(2 * i + 1) + "]") ==
          static_cast<std::int32_t>(words[i] & 0xffffffffu));
    CHECK(discrete_value(*model, "state[" + std::to_string(2 * i + 2) + "]") == static_cast<std::int32_t>(words[i] >> 32));
  }
}

TEST_CASE("the impure generator: drawn at translation in initial equations, stepped by its when-clause at events") {
  std::uint64_t words[16];
  for (int i = 0; i < 16; ++i) words[i] = word(11 + 2 * i + 1, 11 + 2 * i + 2);
  int p = 0;
  auto draw = [&] { return star1024(words, p); };
  const double first = draw();
  std::vector<double> y;  // at initialisation, t = 0.5, 1.0
  for (int k = 0; k < 3; ++k) y.push_back(draw());

  auto model = compiled_model("e2e_random_impure", {source("RandomNoise.ImpureDraws"), {}});
  const auto& names = model->info().parameters;
  const auto at = std::find_if(names.begin(), names.end(), [](const auto& q) { return q.name == "first"; });
  REQUIRE(at != names.end());
  CHECK(model->info().default_parameters()[static_cast<std::size_t>(at - names.begin())] == first);
  const auto p0 = model->info().default_parameters();
  std::vector<double> x0(model->info().states.size());
  model->initial_state(0.0, {}, p0, x0);
  CHECK(discrete_value(*model, "y") == y[0]);
  for (const double stop : {0.7, 1.2}) {
    const auto r = runtime::simulate(*model, {}, p0, runtime::OutputGrid::uniform(0, stop, 7), tight());
    INFO(r.message);
    REQUIRE(r.ok());
    CHECK(discrete_value(*model, "y") == y[stop < 1 ? 1 : 2]);
  }
}

TEST_CASE("the impure generator: two draws in one when-clause - three, or draws in two clauses, refused") {
  std::uint64_t words[16];
  for (int i = 0; i < 16; ++i) words[i] = word(11 + 2 * i + 1, 11 + 2 * i + 2);
  int p = 0;
  std::vector<double> d;
  for (int k = 0; k < 4; ++k) d.push_back(star1024(words, p));
  auto model = compiled_model("e2e_random_impure_twice", {source("RandomNoise.ImpureTwice"), {}});
  const auto p0 = model->info().default_parameters();
  for (const double stop : {0.7, 1.2}) {
    const auto r = runtime::simulate(*model, {}, p0, runtime::OutputGrid::uniform(0, stop, 7), tight());
    INFO(r.message);
    REQUIRE(r.ok());
    const std::size_t first = stop < 1 ? 0 : 2;
    CHECK(discrete_value(*model, "y1") == d[first]);
    CHECK(discrete_value(*model, "y2") == d[first + 1]);
  }
  for (const auto& [name, message] : std::vector<std::pair<std::string, std::string>>{
           {"RandomNoise.ImpureThrice", "a when-clause draws more than twice from the impure random generator"},
           {"RandomNoise.ImpureTwoClauses", "the impure random generator is drawn in more than one when-clause"}}) {
    frontend::SourceManager sources;
    frontend::DiagnosticEngine diags(sources);
    CHECK_FALSE(tools::load_flat_model(source(name), sources, diags));
    std::ostringstream printed;
    diags.print(printed);
    INFO(printed.str());
    CHECK(printed.str().find(message) != std::string::npos);
  }
}

TEST_CASE("the generators' calls: flat calls per output, the translation-time warning, wrong sizes refused") {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  auto flat = tools::load_flat_model(source("RandomNoise.SampledNoise"), sources, diags);
  REQUIRE(flat);
  std::ostringstream printed;
  diags.print(printed);
  CHECK(printed.str().find("warning: 'RandomNoise.xorshift64star' is evaluated now with its parameters' values") !=
        std::string::npos);
  const std::string text = flat->print();
  CHECK(text.find("r = ModelicaRandom_xorshift128plus(0, pre(`state[1]`), pre(`state[2]`), pre(`state[3]`), "
                  "pre(`state[4]`));") != std::string::npos);
  CHECK(text.find("`state[4]` = ModelicaRandom_xorshift128plus(4, pre(`state[1]`)") != std::string::npos);

  // What --emit flat prints flattens again to the same text.
  const std::string path = (scratch("random_flat") / "RandomNoiseFlat.mo").string();
  std::ofstream(path) << text;
  frontend::DiagnosticEngine again_diags(sources);
  auto again = tools::load_flat_model({path, "", {}, true}, sources, again_diags);
  std::ostringstream again_printed;
  again_diags.print(again_printed);
  INFO(again_printed.str());
  REQUIRE(again);
  CHECK(again->print() == text);

  frontend::DiagnosticEngine bad_diags(sources);
  CHECK_FALSE(tools::load_flat_model(source("RandomNoise.WrongStateSize"), sources, bad_diags));
  std::ostringstream bad;
  bad_diags.print(bad);
  CHECK(bad.str().find("error: 'ModelicaRandom_xorshift128plus' needs a state of 4 Integers, not 3") != std::string::npos);
}
