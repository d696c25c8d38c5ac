#include "xcos_blocks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace fs = std::filesystem;

namespace mo::tools {

namespace {

constexpr std::size_t kMaxValues = 1'000'000;  ///< per field: a diagram's parameters are far fewer

// ---------------------------------------------------------------- reading

struct LineReader {
  std::string file;
  std::size_t line = 0;
  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error(fmt::format("{}:{}: error: {}", file, line, why));
  }
};

bool plain_name(const std::string& s) {
  if (s.empty() || s.size() > 200 || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isalnum(c) || c == '_'; });
}

double number(const LineReader& r, const std::string& token) {
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (token.empty() || end != token.c_str() + token.size()) r.fail("'" + token.substr(0, 40) + "' is not a number");
  return v;
}

int integer(const LineReader& r, const std::string& token) {
  const double v = number(r, token);
  if (v != std::floor(v) || std::abs(v) > 1e9) r.fail("'" + token.substr(0, 40) + "' is not an integer");
  return static_cast<int>(v);
}

/// `tag N v1 ... vN` (N = -1: not a real matrix) into `block`.
void read_field(const LineReader& r, const std::vector<std::string>& tokens, XcosBlock& block) {
  if (tokens.size() < 2) r.fail("'" + tokens[0] + "' without a count");
  const int n = integer(r, tokens[1]);
  if (n == -1 && tokens.size() == 2) {
    block.not_real.push_back(tokens[0]);
    return;
  }
  if (n < 0 || static_cast<std::size_t>(n) > kMaxValues || tokens.size() != static_cast<std::size_t>(n) + 2)
    r.fail(fmt::format("'{}' should list {} numbers", tokens[0], n));
  std::vector<double> values;
  for (std::size_t i = 2; i < tokens.size(); ++i) values.push_back(number(r, tokens[i]));
  block.fields[tokens[0]] = std::move(values);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> tokens;
  std::istringstream in(line);
  for (std::string t; in >> t;) tokens.push_back(t);
  return tokens;
}

XcosLink read_link(const LineReader& r, const std::vector<std::string>& t) {
  if (t.size() != 5) r.fail("a link has 4 numbers");
  return {integer(r, t[1]), integer(r, t[2]), integer(r, t[3]), integer(r, t[4])};
}

const std::set<std::string> kFields{"in", "out", "evtin", "nzcross", "nmode", "rpar",
                                    "ipar", "opar", "firing", "state", "dstate"};

// --------------------------------------------------------------- writing

std::string num(double v) {
  const std::string s = fmt::format("{:.17g}", v);
  return v < 0 ? "(" + s + ")" : s;
}

/// What one block contributes, or why it cannot.
struct Translation {
  std::string declarations, equations, why_not;
};

/// The translation context: names and sources of signals.
class Translator {
public:
  Translator(const XcosBlocks& blocks, std::string prefix) : b_(blocks), prefix_(std::move(prefix)) {}

  std::string output(int block, int port) const {
    if (block == b_.modelica) return fmt::format("`OutPutPort{}.vo`", port);
    return fmt::format("{}b{}_y{}", prefix_, block, port);
  }
  /// The signal into `block`'s input `port`, or nullopt when unconnected.
  std::optional<std::string> input(int block, int port) const {
    for (const auto& l : b_.links)
      if (l.to == block && l.to_port == port) return output(l.from, l.from_port);
    return std::nullopt;
  }
  /// Activation links into `block` from other blocks than itself.
  bool activated_from_outside(int block) const {
    return std::any_of(b_.events.begin(), b_.events.end(),
                       [&](const XcosLink& l) { return l.to == block && l.from != block; });
  }
  bool activated(int block) const {
    return std::any_of(b_.events.begin(), b_.events.end(), [&](const XcosLink& l) { return l.to == block; });
  }
  Translation translate(const XcosBlock& block) const;

private:
  const XcosBlocks& b_;
  std::string prefix_;
};

const std::vector<double>& field(const XcosBlock& b, const std::string& name) {
  static const std::vector<double> none;
  const auto it = b.fields.find(name);
  return it == b.fields.end() ? none : it->second;
}

/// Scalar ports only: every declared port size is 1 or inherited (negative).
std::string port_problem(const XcosBlock& b) {
  for (const char* f : {"in", "out"})
    for (double n : field(b, f))
      if (n > 1) return fmt::format("a port of size {:g} (only scalar signals are translated)", n);
  return {};
}

std::string finite_problem(const XcosBlock& b) {
  for (const char* f : {"rpar", "ipar", "opar", "firing", "state"})
    for (double v : field(b, f))
      if (!std::isfinite(v)) return std::string("a parameter (") + f + ") that is not finite";
  return {};
}

/// Kinds: the computational function decides, so a block's variants for
/// integer types (gainblk_i32n, ...) are not taken for the double one.
enum class Kind {
  Constant, ConstantOpar, Gain, Summation, WeightedSum, PlainSum, Product, PlainProduct, Hysteresis,
  Saturation, Sign, Abs, Step, Ramp, Sine, Curve, Split, Integrator, Unknown
};

Kind kind_of(const std::string& sim) {
  static const std::map<std::string, Kind> kinds{
      {"cstblk4", Kind::Constant},       {"cstblk", Kind::Constant},      {"cstblk4_m", Kind::ConstantOpar},
      {"gainblk", Kind::Gain},           {"gain", Kind::Gain},            {"summation", Kind::Summation},
      {"sum", Kind::WeightedSum},        {"plusblk", Kind::PlainSum},     {"product", Kind::Product},
      {"prod", Kind::PlainProduct},      {"hystheresis", Kind::Hysteresis}, {"satur", Kind::Saturation},
      {"signum", Kind::Sign},            {"absolute_value", Kind::Abs},   {"step_func", Kind::Step},
      {"ramp", Kind::Ramp},              {"gensin", Kind::Sine},          {"intplt", Kind::Curve},
      {"lsplit", Kind::Split},           {"integr", Kind::Integrator},    {"integral_func", Kind::Integrator}};
  const auto it = kinds.find(sim);
  return it == kinds.end() ? Kind::Unknown : it->second;
}

Translation fail(const std::string& why) { return {"", "", why}; }

/// The inputs 1..n of `block`, each a signal, or the first unconnected one's number.
struct Inputs {
  std::vector<std::string> signals;
  int missing = 0;
};

Inputs inputs_of(const Translator& t, int block, std::size_t n) {
  Inputs in;
  for (std::size_t p = 1; p <= n; ++p) {
    const auto s = t.input(block, static_cast<int>(p));
    if (!s) {
      in.missing = static_cast<int>(p);
      return in;
    }
    in.signals.push_back(*s);
  }
  return in;
}

/// y = c0 + Σ w_k u_k, written with signs.
std::string weighted(const std::vector<std::string>& u, const std::vector<double>& w) {
  std::string e;
  for (std::size_t k = 0; k < u.size(); ++k) {
    if (w[k] == 1) e += (e.empty() ? "" : " + ") + u[k];
    else if (w[k] == -1) e += (e.empty() ? "-" : " - ") + u[k];
    else e += (e.empty() ? "" : " + ") + num(w[k]) + "*" + u[k];
  }
  return e.empty() ? "0" : e;
}

/// The piecewise-linear curve of CURV_f (Scicos' intplt): clamped to the
/// first and last values outside the abscissae, linear between.
std::string curve(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  std::string e = "if time <= " + num(x[0]) + " then " + num(y[0]);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (!(x[i + 1] > x[i])) continue;  // never chosen by intplt
    const double slope = (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
    e += fmt::format(" elseif time < {} then {} + {}*(time - {})", num(x[i + 1]), num(y[i]), num(slope), num(x[i]));
  }
  return e + " else " + num(y[n - 1]);
}

Translation Translator::translate(const XcosBlock& b) const {
  const Kind kind = kind_of(b.sim);
  if (kind == Kind::Unknown)
    return fail("its computational function '" + b.sim + "' is not among the blocks translated to Modelica");
  if (auto p = port_problem(b); !p.empty()) return fail("it has " + p);
  if (auto p = finite_problem(b); !p.empty()) return fail("it has " + p);
  if (kind != Kind::Step && activated(b.index))
    return fail("it is activated by events (only always-active blocks are translated)");
  const auto& rpar = field(b, "rpar");
  const auto& ipar = field(b, "ipar");
  const std::string y = output(b.index, 1);
  const std::string decl = "  Real " + y + ";\n";
  auto n_inputs = [&](std::size_t n) { return inputs_of(*this, b.index, n); };
  auto unconnected = [&](int p) { return fail(fmt::format("its input {} is not connected", p)); };
  auto simple = [&](const std::string& rhs) { return Translation{decl, "  " + y + " = " + rhs + ";\n", ""}; };
  switch (kind) {
    case Kind::Constant:
    case Kind::ConstantOpar: {
      // CONST_m keeps its value in opar (cstblk4_m) or, in older diagrams, in rpar.
      const auto& c = field(b, kind == Kind::ConstantOpar || rpar.empty() ? "opar" : "rpar");
      if (c.size() != 1) return fail("its constant is not one real number");
      return simple(num(c[0]));
    }
    case Kind::Gain: {
      if (rpar.size() != 1) return fail("its gain is not one real number");
      const Inputs in = n_inputs(1);
      if (in.missing) return unconnected(in.missing);
      return simple(num(rpar[0]) + "*" + in.signals[0]);
    }
    case Kind::Summation:
    case Kind::WeightedSum: {
      const auto& w = kind == Kind::Summation ? ipar : rpar;
      if (w.empty()) return fail("it has no input signs");
      const Inputs in = n_inputs(w.size());
      if (in.missing) return unconnected(in.missing);
      // One input: Scicos sums the components of the vector (a scalar: itself).
      if (w.size() == 1 && kind == Kind::Summation) return simple(in.signals[0]);
      return simple(weighted(in.signals, w));
    }
    case Kind::PlainSum: {
      std::vector<std::string> u;
      for (std::size_t p = 1; p <= std::max<std::size_t>(field(b, "in").size(), 1); ++p)
        if (auto s = input(b.index, static_cast<int>(p))) u.push_back(*s);  // SUM_f: unconnected inputs are dropped
      return simple(weighted(u, std::vector<double>(u.size(), 1.0)));
    }
    case Kind::Product:
    case Kind::PlainProduct: {
      const std::vector<double> s = kind == Kind::Product ? ipar : std::vector<double>(field(b, "in").size(), 1.0);
      if (s.empty()) return fail("it has no inputs");
      const Inputs in = n_inputs(s.size());
      if (in.missing) return unconnected(in.missing);
      if (s.size() == 1) return simple(in.signals[0]);
      std::string e = "1";
      for (std::size_t k = 0; k < s.size(); ++k) e += (s[k] > 0 ? "*" : "/") + in.signals[k];
      return simple(e);
    }
    case Kind::Hysteresis: {
      // Scicos' hystheresis: the output is out_high once u >= high, out_low
      // once u <= low, held in between (out_low when it starts in between);
      // the switches are events at the crossings.
      if (rpar.size() != 4) return fail("it does not have 4 real parameters");
      const Inputs in = n_inputs(1);
      if (in.missing) return unconnected(in.missing);
      const std::string& u = in.signals[0];
      const std::string hi = num(rpar[0]), lo = num(rpar[1]), on = num(rpar[2]), off = num(rpar[3]);
      return {"  discrete Real " + y + ";\n",
              fmt::format("  when initial() then\n    {y} = if {u} >= {hi} then {on} else {off};\n"
                          "  elsewhen {u} >= {hi} then\n    {y} = {on};\n"
                          "  elsewhen {u} <= {lo} then\n    {y} = {off};\n  end when;\n",
                          fmt::arg("y", y), fmt::arg("u", u), fmt::arg("hi", hi), fmt::arg("lo", lo),
                          fmt::arg("on", on), fmt::arg("off", off)),
              ""};
    }
    case Kind::Saturation: {
      if (rpar.size() != 2) return fail("it does not have 2 real parameters");
      const Inputs in = n_inputs(1);
      if (in.missing) return unconnected(in.missing);
      const std::string& u = in.signals[0];
      return simple(fmt::format("if {0} >= {1} then {1} elseif {0} <= {2} then {2} else {0}", u, num(rpar[0]),
                                num(rpar[1])));
    }
    case Kind::Sign:
    case Kind::Abs: {
      const Inputs in = n_inputs(1);
      if (in.missing) return unconnected(in.missing);
      const std::string& u = in.signals[0];
      return simple(kind == Kind::Sign ? fmt::format("if {0} > 0 then 1 elseif {0} < 0 then -1 else 0", u)
                                       : fmt::format("if {0} >= 0 then {0} else -{0}", u));
    }
    case Kind::Step: {
      // STEP (inside STEP_FUNCTION): the initial value until its first event
      // (firing), the final value from then on; it must schedule itself.
      const auto& firing = field(b, "firing");
      if (rpar.size() != 2 || firing.size() != 1) return fail("it is not a scalar step with one step time");
      if (activated_from_outside(b.index)) return fail("it is activated by other blocks' events");
      return simple(fmt::format("if time >= {} then {} else {}", num(firing[0]), num(rpar[1]), num(rpar[0])));
    }
    case Kind::Ramp: {
      if (rpar.size() != 3) return fail("it does not have 3 real parameters");
      return simple(fmt::format("if time >= {1} then {2} + {0}*(time - {1}) else {2}", num(rpar[0]), num(rpar[1]),
                                num(rpar[2])));
    }
    case Kind::Sine: {
      if (rpar.size() != 3) return fail("it does not have 3 real parameters");
      return simple(fmt::format("{}*sin({}*time + {})", num(rpar[0]), num(rpar[1]), num(rpar[2])));
    }
    case Kind::Curve: {
      if (ipar.empty() || ipar[0] < 1 || rpar.size() < 2 * static_cast<std::size_t>(ipar[0]))
        return fail("its curve is not given by n abscissae and n ordinates");
      const auto n = static_cast<std::size_t>(ipar[0]);
      return simple(curve({rpar.begin(), rpar.begin() + static_cast<long>(n)},
                          {rpar.begin() + static_cast<long>(n), rpar.begin() + static_cast<long>(2 * n)}));
    }
    case Kind::Split: {
      const Inputs in = n_inputs(1);
      if (in.missing) return unconnected(in.missing);
      Translation t;
      for (std::size_t p = 1; p <= std::max<std::size_t>(field(b, "out").size(), 1); ++p) {
        const std::string yp = output(b.index, static_cast<int>(p));
        t.declarations += "  Real " + yp + ";\n";
        t.equations += "  " + yp + " = " + in.signals[0] + ";\n";
      }
      return t;
    }
    case Kind::Integrator: {
      const auto& x0 = field(b, "state");
      if (x0.size() != 1 || !rpar.empty()) return fail("it is not a plain scalar integrator (no limits, no reset)");
      const Inputs in = n_inputs(1);
      if (in.missing) return unconnected(in.missing);
      return {"  Real " + y + "(start = " + num(x0[0]) + ");\n", "  der(" + y + ") = " + in.signals[0] + ";\n", ""};
    }
    case Kind::Unknown: break;
  }
  return fail("unknown kind");
}

/// A prefix for the new names that no name of the flat model starts with.
std::string fresh_prefix(const std::string& flat_text) {
  std::string prefix = "xcos_";
  while (flat_text.find(prefix) != std::string::npos) prefix.insert(0, "_");
  return prefix;
}

std::string block_label(const XcosBlock& b) { return fmt::format("{} (block {})", b.gui, b.index); }

}  // namespace

XcosBlocks read_xcos_blocks(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": error: cannot read the diagram's block list");
  LineReader r{file.string()};
  XcosBlocks out;
  bool header = false, ended = false;
  for (std::string line; std::getline(in, line);) {
    ++r.line;
    if (line.size() > 64'000'000) r.fail("line too long");
    const auto t = split(line);
    if (t.empty()) continue;
    if (ended) r.fail("text after 'end'");
    if (!header) {
      if (t.size() != 2 || t[0] != "mo-xcos-blocks" || t[1] != "1") r.fail("not a block list of version 1");
      header = true;
    } else if (t[0] == "modelica" && t.size() == 4) {
      out.modelica = integer(r, t[1]);
      out.inputs = integer(r, t[2]);
      out.outputs = integer(r, t[3]);
    } else if (t[0] == "block") {
      if (t.size() != 4) r.fail("a block line is 'block K GUI SIM'");
      XcosBlock b;
      b.index = integer(r, t[1]);
      if (b.index != static_cast<int>(out.blocks.size()) + 1) r.fail("blocks are not numbered 1, 2, ...");
      b.gui = plain_name(t[2]) ? t[2] : "?";
      b.sim = plain_name(t[3]) ? t[3] : "?";
      out.blocks.push_back(std::move(b));
    } else if (kFields.contains(t[0])) {
      if (out.blocks.empty()) r.fail("'" + t[0] + "' before any block");
      read_field(r, t, out.blocks.back());
    } else if (t[0] == "link") {
      out.links.push_back(read_link(r, t));
    } else if (t[0] == "event") {
      out.events.push_back(read_link(r, t));
    } else if (t[0] == "end" && t.size() == 1) {
      ended = true;
    } else {
      r.fail("unexpected '" + t[0].substr(0, 40) + "'");
    }
  }
  if (!ended) r.fail("the block list is incomplete (no 'end')");
  if (out.modelica != static_cast<int>(out.blocks.size()) + 1) r.fail("the Modelica part is not the block after the others");
  const int n = out.modelica;
  for (const auto& l : out.links)
    if (l.from < 1 || l.from > n || l.to < 1 || l.to > n || l.from_port < 1 || l.to_port < 1)
      r.fail("a link names a block or port that does not exist");
  return out;
}

ClosedLoop close_xcos_loop(const XcosBlocks& blocks, const std::string& flat_text) {
  const Translator t(blocks, fresh_prefix(flat_text));
  std::map<int, Translation> done;  // block index -> translation
  ClosedLoop loop;
  std::set<int> emitted;
  for (int k = 1; k <= blocks.inputs; ++k) {
    const std::string port = fmt::format("`InPutPort{}.vi`", k);
    if (flat_text.find("input Real " + port) == std::string::npos) {
      loop.warnings.push_back(fmt::format("the flat model has no input {}; the diagram's blocks are not joined to it",
                                          port));
      continue;
    }
    // The blocks reached backwards from the input (a worklist, no recursion).
    std::vector<int> reached, work;
    std::set<int> seen;
    std::string problem;
    const auto source = t.input(blocks.modelica, k);
    if (!source) continue;  // nothing of the diagram drives it
    for (const auto& l : blocks.links)
      if (l.to == blocks.modelica && l.to_port == k) work.push_back(l.from);
    while (!work.empty() && problem.empty()) {
      const int b = work.back();
      work.pop_back();
      if (b == blocks.modelica) continue;
      if (!seen.insert(b).second) continue;
      reached.push_back(b);
      const XcosBlock& block = blocks.blocks[static_cast<std::size_t>(b - 1)];
      auto it = done.find(b);
      if (it == done.end()) it = done.emplace(b, t.translate(block)).first;
      if (!it->second.why_not.empty()) {
        problem = fmt::format("block {} is not translated: {}", block_label(block), it->second.why_not);
        break;
      }
      for (const auto& l : blocks.links)
        if (l.to == b) work.push_back(l.from);
    }
    for (int p = 1; p <= blocks.outputs && problem.empty(); ++p)
      if (flat_text.find(fmt::format("output Real `OutPutPort{}.vo`", p)) == std::string::npos &&
          std::any_of(blocks.links.begin(), blocks.links.end(), [&](const XcosLink& l) {
            return l.from == blocks.modelica && l.from_port == p && seen.contains(l.to);
          }))
        problem = fmt::format("the flat model has no output `OutPutPort{}.vo`", p);
    if (!problem.empty()) {
      loop.warnings.push_back(fmt::format("input {} stays open: {}", port, problem));
      continue;
    }
    std::sort(reached.begin(), reached.end());
    for (int b : reached)
      if (emitted.insert(b).second) {
        loop.declarations += done[b].declarations;
        loop.equations += done[b].equations;
      }
    loop.equations += "  " + port + " = " + *source + ";\n";
    loop.closed.push_back(k);
  }
  for (int b : emitted) loop.translated.push_back(block_label(blocks.blocks[static_cast<std::size_t>(b - 1)]));
  return loop;
}

std::string with_closed_loop(const std::string& flat_text, const ClosedLoop& loop) {
  if (loop.closed.empty()) return flat_text;
  const auto equation = flat_text.find("\nequation\n");
  const auto end = flat_text.rfind("\nend ");
  if (equation == std::string::npos || end == std::string::npos || end < equation)
    throw std::runtime_error("the flat model is not shaped as Xcos writes it (a class with one 'equation' section)");
  std::string out = flat_text.substr(0, equation + 1);
  out += loop.declarations;
  out += flat_text.substr(equation + 1, end + 1 - (equation + 1));
  out += loop.equations;
  out += flat_text.substr(end + 1);
  return out;
}

}  // namespace mo::tools
