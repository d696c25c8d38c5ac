// The Xcos corpus check; see xcos_corpus.hpp.
#include "xcos_corpus.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <set>
#include <sstream>

#include <sys/wait.h>
#include <unistd.h>

#include "common.hpp"
#include "mo/frontend/diagnostics.hpp"
#include "mo/runtime/input.hpp"
#include "mo/runtime/simulate.hpp"
#include "pipeline.hpp"
#include "xcos_blocks.hpp"
#include "xcos_diagram.hpp"

namespace fs = std::filesystem;

namespace mo::xcos_corpus {

std::optional<std::string> corpus_dir(const std::string& source_dir) {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("MO_SHARED_DIR")) candidates.push_back(fs::path(env) / "xcos-corpus");
  candidates.push_back(fs::path(source_dir) / ".." / "shared" / "xcos-corpus");
  for (const auto& c : candidates)
    if (fs::is_directory(c / "ref")) return fs::weakly_canonical(c).string();
  return std::nullopt;
}

std::vector<std::string> diagrams(const std::string& corpus) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(fs::path(corpus) / "ref"))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

namespace {

/// Diagnostics as text, first `max_lines` lines.
std::string first_lines(const std::string& text, std::size_t max_lines = 1) {
  std::istringstream in(text);
  std::string line, out;
  for (std::size_t k = 0; k < max_lines && std::getline(in, line); ++k) out += (k ? " / " : "") + line;
  return out;
}

struct Loaded {
  std::unique_ptr<frontend::flat::Model> model;
  std::string errors;
};

Loaded load(const tools::ModelSource& source) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  Loaded out;
  out.model = tools::load_flat_model(source, sources, diags);
  std::ostringstream err;
  diags.print(err);
  out.errors = err.str();
  return out;
}

std::vector<std::string> aux_files(const std::string& corpus, const std::string& name) {
  std::vector<std::string> files;
  const fs::path dir = fs::path(corpus) / "flat" / "aux" / name;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".mo") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

/// modelicat names a scalarised array element `a.[2]` (a matrix element
/// `a.[1].[2]`), mocompile `a[2]` (`a[1,2]`).
std::string scalar_name(std::string name) {
  for (std::size_t k; (k = name.find(".[")) != std::string::npos;) name.erase(k, 1);
  for (std::size_t k; (k = name.find("][")) != std::string::npos;) name.replace(k, 2, ",");
  return name;
}

std::set<std::string> unknown_names(const frontend::flat::Model& m) {
  std::set<std::string> names;
  for (const auto& v : m.variables)
    if (v.variability != frontend::ast::Variability::Parameter && v.variability != frontend::ast::Variability::Constant)
      names.insert(scalar_name(v.name));
  return names;
}

/// The reference trajectory: times and named columns.
struct Reference {
  runtime::InputTable table;  // names, times, columns
  nlohmann::json meta;
};

/// Hier: the hierarchical file's unknowns are the flat file's (by name).
StepResult compare_unknowns(const frontend::flat::Model& hier, const frontend::flat::Model& flat) {
  const auto a = unknown_names(hier), b = unknown_names(flat);
  std::vector<std::string> missing, extra;
  std::set_difference(b.begin(), b.end(), a.begin(), a.end(), std::back_inserter(missing));
  std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(extra));
  StepResult r{true, missing.empty() && extra.empty(), ""};
  if (r.passed) {
    r.detail = fmt::format("{} variables", a.size());
  } else {
    r.detail = fmt::format("{} missing, {} extra", missing.size(), extra.size());
    if (!missing.empty()) r.detail += " (missing " + missing.front() + ")";
    if (!extra.empty()) r.detail += " (extra " + extra.front() + ")";
  }
  return r;
}

/// A recorded input column as a signal: cubic (Catmull-Rom) between the
/// samples of a smooth column, so that a sampled sine is not flattened into
/// chords; linear when the column takes few values (a relay, a step), where a
/// cubic would overshoot.
class RecordedInput : public runtime::InputSignal {
public:
  RecordedInput(std::vector<double> t, std::vector<double> u) : t_(std::move(t)), u_(std::move(u)) {
    std::set<double> distinct(u_.begin(), u_.end());
    cubic_ = distinct.size() > 10;
  }
  [[nodiscard]] double value(double t) const override {
    if (t <= t_.front()) return u_.front();
    if (t >= t_.back()) return u_.back();
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
    const double h = t_[k + 1] - t_[k], s = (t - t_[k]) / h;
    if (!cubic_) return u_[k] + s * (u_[k + 1] - u_[k]);
    const double m0 = slope(k) * h, m1 = slope(k + 1) * h, s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * u_[k] + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * u_[k + 1] + (s3 - s2) * m1;
  }

private:
  [[nodiscard]] double slope(std::size_t k) const {
    const std::size_t a = k == 0 ? 0 : k - 1, b = std::min(k + 1, t_.size() - 1);
    return (u_[b] - u_[a]) / (t_[b] - t_[a]);
  }
  std::vector<double> t_, u_;
  bool cubic_ = false;
};

/// Every algebraic and eliminated variable becomes an output, so that any
/// column of the reference can be found in the trajectory.
void expose_all(symbolic::OdeModel& ode) {
  std::set<std::string> have;
  for (const auto& y : ode.outputs) have.insert(y.info.name);
  for (const auto& a : ode.algebraics)
    if (have.insert(a.info.name).second) ode.outputs.push_back({a.info, a.symbol});
  for (const auto& e : ode.eliminated)
    if (have.insert(e.info.name).second) ode.outputs.push_back(e);
}

/// The column of `trajectory` (or the model's discrete values are not there) named `name`.
std::optional<std::vector<double>> column(const runtime::ResultTable& t, const std::string& name) {
  const auto& names = t.names();
  for (std::size_t j = 0; j < names.size(); ++j) {
    if (names[j] != name) continue;
    std::vector<double> c(t.rows());
    for (std::size_t k = 0; k < t.rows(); ++k) c[k] = t.at(k, j);
    return c;
  }
  return std::nullopt;
}

/// The kind of a reference column ("state", "algebraic", "output", "input",
/// "time"), "" when the json does not list it.
std::string column_kind(const Reference& ref, const std::string& name) {
  const auto& kinds = ref.meta["column_kinds"];
  const auto& cols = ref.meta["columns"];
  for (std::size_t c = 0; c < cols.size(); ++c)
    if (cols[c] == name) return kinds[c].get<std::string>();
  return "";
}

/// The reference columns compared: states, algebraic variables, outputs.
bool compared_column(const Reference& ref, const std::string& name) {
  const std::string kind = column_kind(ref, name);
  return !kind.empty() && kind != "input" && kind != "time";
}

/// Whether Scilab ran looser than 1e-6: its states are then known to about
/// 1e-2 of their range (the tolerance for such runs), and an
/// algebraic variable only to that error times the model's gain from the
/// states to it (the Clutch's acceleration is the spring's torque over the
/// inertia: 42 times the angle's error). Such a run's algebraic columns are
/// measured and reported, but only its states and outputs must match: the
/// columns the issue names.
bool loose_reference(const Reference& ref) { return ref.meta.value("rtol", 1e-6) > 1e-6; }

/// The largest magnitude over the reference's compared columns: what the
/// model's signals are made of.
double model_magnitude(const Reference& ref) {
  double m = 0.0;
  for (std::size_t j = 0; j < ref.table.names.size(); ++j)
    if (compared_column(ref, ref.table.names[j]))
      for (double x : ref.table.columns[j]) m = std::max(m, std::abs(x));
  return m;
}

/// A column's scale: its range (or 1e-3 of its magnitude when nearly
/// constant), but never below what the reference resolves: Scilab integrated
/// to rtol·M + atol (M the model's largest signal), so a column that is zero
/// up to that noise (a force that cancels, 1e-10 against signals of 1) is
/// compared to that accuracy, not to its own noise (tol of the scale is then
/// rtol·M + atol).
double scale_of(const Reference& ref, const std::vector<double>& v, double tol) {
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  double magnitude = 0.0;
  for (double x : v) magnitude = std::max(magnitude, std::abs(x));
  const double resolved = (ref.meta.value("rtol", 1e-6) * model_magnitude(ref) +
                           ref.meta.value("atol", 1e-6)) / tol;
  return std::max({*hi - *lo, 1e-3 * magnitude, resolved, 1e-12});
}

/// The first reference row where our runs at two tolerances (`got` and
/// `fine`, 100 times tighter) differ by more than tol/2 of a column's range:
/// beyond it a chaotic model is not predictable at the reference's tolerance.
std::size_t predictable_rows(const Reference& ref, const runtime::ResultTable& got,
                             const runtime::ResultTable& fine, double tol) {
  std::size_t rows = ref.table.times.size();
  for (std::size_t j = 0; j < ref.table.names.size(); ++j) {
    const std::string& name = ref.table.names[j];
    if (!compared_column(ref, name)) continue;
    const auto a = column(got, name), b = column(fine, name);
    if (!a || !b || b->size() != a->size()) continue;
    const double scale = scale_of(ref, ref.table.columns[j], tol);
    for (std::size_t k = 1; k < rows; ++k)
      if (std::abs((*a)[k + 1] - (*b)[k + 1]) / scale > tol / 2) rows = k;
  }
  return rows;
}

StepResult compare(const Reference& ref, const runtime::ResultTable& got, const runtime::ResultTable& fine) {
  const double rtol = ref.meta.value("rtol", 1e-6);
  const double tol = rtol <= 1e-6 ? 1e-3 : 1e-2;
  const std::size_t all = ref.table.times.size();
  const std::size_t n = std::min(all, predictable_rows(ref, got, fine, tol) + 1);
  double worst = 0.0, worst_reported = 0.0;
  std::string worst_name, worst_reported_name, missing;
  std::size_t compared = 0, reported = 0;
  for (std::size_t j = 0; j < ref.table.names.size(); ++j) {
    const std::string& name = ref.table.names[j];
    if (!compared_column(ref, name)) continue;
    const auto mine = column(got, name);
    if (!mine) {
      if (missing.empty()) missing = name;
      continue;
    }
    const bool only_reported = loose_reference(ref) && column_kind(ref, name) == "algebraic";
    double& w = only_reported ? worst_reported : worst;
    std::string& w_name = only_reported ? worst_reported_name : worst_name;
    const auto& theirs = ref.table.columns[j];
    const double scale = scale_of(ref, theirs, tol);
    for (std::size_t k = 1; k + 1 < n; ++k) {
      const double e = std::abs((*mine)[k + 1] - theirs[k]) / scale;  // row 0 of ours is t = 0
      if (!(e <= w)) {
        w = std::isnan(e) ? INFINITY : e;
        w_name = fmt::format("{} at t={:.4g}", name, ref.table.times[k]);
      }
    }
    ++(only_reported ? reported : compared);
  }
  StepResult r{true, missing.empty() && worst <= tol, ""};
  if (!missing.empty())
    r.detail = "no column " + missing;
  else
    r.detail = fmt::format("{} columns, max err {:.1e} of range{}", compared, worst,
                           worst > tol ? " (" + worst_name + ")" : "");
  if (reported > 0)
    r.detail += fmt::format("; {} algebraic columns of a run at rtol {:g}: max err {:.1e} ({})", reported,
                            ref.meta.value("rtol", 1e-6), worst_reported, worst_reported_name);
  if (n < all)
    r.detail += fmt::format("; to t={:.4g}, where runs at rtol and rtol/100 part (chaotic)", ref.table.times[n - 1]);
  return r;
}

/// Lowering: no more states than modelicac.
StepResult lower(const frontend::flat::Model& flat, const Reference& ref, std::optional<symbolic::OdeModel>& ode) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  ode = tools::lower_model(flat, diags);
  if (!ode) {
    std::ostringstream err;
    diags.print(err);
    return {true, false, first_lines(err.str())};
  }
  const std::size_t mine = ode->num_base_states(), theirs = ref.meta.value("n_states_modelicac", 0);
  return {true, mine <= theirs, fmt::format("{} states (modelicac {})", mine, theirs)};
}

StepResult simulate(symbolic::OdeModel& ode, const Reference& ref, runtime::ResultTable& trajectory,
                    runtime::ResultTable& fine) {
  expose_all(ode);
  try {
    tools::BuiltModel built = tools::build_model(ode, 2, "xcos_corpus");
    const runtime::ModelInfo& info = built.model->info();
    std::vector<std::unique_ptr<runtime::InputSignal>> signals;
    for (const auto& u : info.inputs) {
      const auto it = std::find(ref.table.names.begin(), ref.table.names.end(), u.name);
      if (it == ref.table.names.end()) return {true, false, "input " + u.name + " not recorded"};
      signals.push_back(std::make_unique<RecordedInput>(
          ref.table.times, ref.table.columns[static_cast<std::size_t>(it - ref.table.names.begin())]));
    }
    std::vector<double> times{0.0};
    times.insert(times.end(), ref.table.times.begin(), ref.table.times.end());
    runtime::SimulationOptions so;
    so.relative_tolerance = std::min(1e-8, ref.meta.value("rtol", 1e-6));
    so.absolute_tolerance = 1e-10;
    const runtime::Inputs inputs(std::move(signals));
    const auto result = runtime::simulate(*built.model, inputs, info.default_parameters(),
                                          runtime::OutputGrid::at(times), so);
    trajectory = result.trajectory;
    so.relative_tolerance /= 100;
    so.absolute_tolerance /= 100;
    fine = runtime::simulate(*built.model, inputs, info.default_parameters(), runtime::OutputGrid::at(times), so)
               .trajectory;
    if (!result.ok())
      return {true, false, fmt::format("{}: {}", runtime::to_string(result.status), first_lines(result.message))};
    return {true, true, fmt::format("{:.2f} s", result.statistics.wall_time_seconds)};
  } catch (const std::exception& e) {
    return {true, false, first_lines(e.what())};
  }
}

Reference read_reference(const std::string& corpus, const std::string& name) {
  Reference ref;
  ref.table = runtime::read_input_csv((fs::path(corpus) / "ref" / (name + ".csv")).string());
  std::ifstream in(fs::path(corpus) / "ref" / (name + ".json"));
  ref.meta = nlohmann::json::parse(in);
  return ref;
}

/// The class of a hierarchical file: its last class.
tools::ModelSource hier_source(const std::string& corpus, const std::string& name, const Libraries& libs) {
  tools::ModelSource s;
  s.file = (fs::path(corpus) / "flat" / (name + "_hier.mo")).string();
  s.libs = {libs.coselica, (fs::path(libs.scilab_macros) / "Electrical" / "Electrical.mo").string(),
            (fs::path(libs.scilab_macros) / "Hydraulics" / "Hydraulics.mo").string()};
  for (auto& f : aux_files(corpus, name)) s.libs.push_back(f);
  return s;
}

DiagramResult check_diagram_in_process(const std::string& corpus, const std::string& name, const Libraries& libs,
                                       bool hier_only, const std::string& closed_flat);

/// A diagram whose recorded inputs are driven by non-Modelica blocks, closed
/// through them (tools/xcos_blocks.hpp): Scilab lists the diagram's blocks
/// (its first compile pass, no block library needed), the supported ones
/// become Modelica equations in a copy of the flat file.
struct Closing {
  std::unique_ptr<tools::ExtractedDiagram> listing;  ///< holds the temporary folder
  std::string file;                                  ///< the closed flat file, or empty
  std::string note;                                  ///< what was closed, or why not
};

Closing close_inputs(const std::string& corpus, const std::string& name, const Reference& ref) {
  Closing c;
  const auto kinds = ref.meta.value("column_kinds", std::vector<std::string>{});
  if (std::find(kinds.begin(), kinds.end(), "input") == kinds.end()) return c;
  fs::path diagram = fs::path(corpus) / "diagrams" / (name + ".zcos");
  if (!fs::exists(diagram)) diagram.replace_extension(".xcos");
  tools::DiagramOptions options;
  options.blocks_only = true;
  options.quiet = true;
  options.timeout_seconds = 300;
  try {
    c.listing = tools::extract_flat_model(diagram.string(), options);
    const auto blocks = tools::read_xcos_blocks(c.listing->blocks_file());
    std::ifstream in(fs::path(corpus) / "flat" / (name + ".mo"), std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    const auto loop = tools::close_xcos_loop(blocks, text.str());
    if (loop.closed.empty()) {
      c.note = "inputs driven from the recording" + (loop.warnings.empty() ? "" : " (" + loop.warnings[0] + ")");
      return c;
    }
    c.file = (c.listing->work_dir() / (name + "_closed.mo")).string();
    std::ofstream(c.file, std::ios::binary) << tools::with_closed_loop(text.str(), loop);
    std::string names;
    for (const auto& t : loop.translated) names += (names.empty() ? "" : ", ") + t;
    c.note = fmt::format("closed through {}{}", names, loop.warnings.empty() ? "" : " (" + loop.warnings[0] + ")");
  } catch (const std::exception& e) {
    c.file.clear();
    c.note = "inputs driven from the recording (" + first_lines(e.what()) + ")";
  }
  return c;
}

/// Runs `steps` in a child process, so that a crash of the front end is a
/// failed step (named by its signal), not the end of the whole check.
std::vector<StepResult> in_child(std::size_t count, const std::function<std::vector<StepResult>()>& steps) {
  int fd[2];
  std::cout.flush();  // the child must not print the parent's buffered output again
  std::cerr.flush();
  if (::pipe(fd) != 0) return steps();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fd[0]);
    std::string text;
    for (const StepResult& s : steps()) {
      std::string detail = s.detail;
      std::replace(detail.begin(), detail.end(), '\n', ' ');
      text += fmt::format("{}{}{}\n", s.ran ? 1 : 0, s.passed ? 1 : 0, detail);
    }
    for (std::size_t done = 0; done < text.size();) {
      const auto n = ::write(fd[1], text.data() + done, text.size() - done);
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    ::_exit(0);
  }
  ::close(fd[1]);
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = ::read(fd[0], buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<std::size_t>(n));
  ::close(fd[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  std::vector<StepResult> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line) && line.size() >= 2;)
    out.push_back({line[0] == '1', line[1] == '1', line.substr(2)});
  const std::string crash = WIFSIGNALED(status) ? fmt::format("CRASH (signal {})", WTERMSIG(status)) : "no result";
  for (std::size_t k = out.size(); k < count; ++k) out.push_back({k == out.size(), false, k == out.size() ? crash : ""});
  return out;
}

}  // namespace

DiagramResult check_diagram(const std::string& corpus, const std::string& name, const Libraries& libs) {
  DiagramResult r;
  r.name = name;
  r.hier =
      in_child(1, [&] { return std::vector<StepResult>{check_diagram_in_process(corpus, name, libs, true, "").hier}; })[0];
  Closing closing;
  try {
    closing = close_inputs(corpus, name, read_reference(corpus, name));
  } catch (const std::exception&) {
    // the reference is unreadable: the flat step says so
  }
  const auto rest = in_child(4, [&] {
    const DiagramResult d = check_diagram_in_process(corpus, name, libs, false, closing.file);
    return std::vector<StepResult>{d.flat, d.lower, d.simulate, d.compare};
  });
  r.flat = rest[0];
  r.lower = rest[1];
  r.simulate = rest[2];
  r.compare = rest[3];
  if (!closing.note.empty() && r.simulate.ran) r.simulate.detail += "; " + closing.note;
  return r;
}

namespace {

DiagramResult check_diagram_in_process(const std::string& corpus, const std::string& name, const Libraries& libs,
                                       bool hier_only, const std::string& closed_flat) {
  DiagramResult r;
  r.name = name;
  Reference ref;
  try {
    ref = read_reference(corpus, name);
  } catch (const std::exception& e) {
    r.flat = {true, false, std::string("reference: ") + e.what()};
    return r;
  }
  tools::ModelSource flat_source;
  flat_source.file = (fs::path(corpus) / "flat" / (name + ".mo")).string();
  if (!hier_only && !closed_flat.empty()) flat_source.file = closed_flat;
  flat_source.libs = aux_files(corpus, name);
  Loaded flat = load(flat_source);
  r.flat = {true, flat.model != nullptr, flat.model ? fmt::format("{} variables", flat.model->variables.size())
                                                    : first_lines(flat.errors)};
  if (hier_only) {
    Loaded hier = load(hier_source(corpus, name, libs));
    r.hier = hier.model ? (flat.model ? compare_unknowns(*hier.model, *flat.model) : StepResult{true, true, ""})
                        : StepResult{true, false, first_lines(hier.errors)};
    return r;
  }
  if (!flat.model) return r;
  std::optional<symbolic::OdeModel> ode;
  r.lower = lower(*flat.model, ref, ode);
  if (!ode) return r;
  runtime::ResultTable trajectory, fine;
  r.simulate = simulate(*ode, ref, trajectory, fine);
  if (trajectory.rows() != ref.table.times.size() + 1) {
    if (r.simulate.passed) r.simulate = {true, false, "incomplete trajectory"};
    return r;
  }
  r.compare = compare(ref, trajectory, fine);
  return r;
}

}  // namespace

StepResult check_closed_loop(const std::string& corpus, const std::string& name, const std::string& loop_file,
                             const std::string& component) {
  return in_child(1, [&] {
    Reference ref;
    try {
      ref = read_reference(corpus, name);
    } catch (const std::exception& e) {
      return std::vector<StepResult>{{true, false, std::string("reference: ") + e.what()}};
    }
    tools::ModelSource source;
    source.file = loop_file;
    source.libs = aux_files(corpus, name);
    source.libs.push_back((fs::path(corpus) / "flat" / (name + ".mo")).string());
    Loaded loop = load(source);
    if (!loop.model) return std::vector<StepResult>{{true, false, first_lines(loop.errors)}};
    std::optional<symbolic::OdeModel> ode;
    const StepResult lowered = lower(*loop.model, ref, ode);
    if (!ode) return std::vector<StepResult>{lowered};
    runtime::ResultTable trajectory, fine;
    const StepResult simulated = simulate(*ode, ref, trajectory, fine);
    if (!simulated.passed || trajectory.rows() != ref.table.times.size() + 1)
      return std::vector<StepResult>{{true, false, "simulate: " + simulated.detail}};
    // The component's columns under the flat file's names.
    const std::string prefix = component + ".";
    auto renamed = [&](const runtime::ResultTable& t) {
      std::vector<std::string> names = t.names();
      for (auto& n : names)
        if (n.starts_with(prefix)) n = n.substr(prefix.size());
      runtime::ResultTable out(std::move(names));
      for (std::size_t k = 0; k < t.rows(); ++k) out.add_row(t.times()[k], t.row(k));
      return out;
    };
    return std::vector<StepResult>{compare(ref, renamed(trajectory), renamed(fine))};
  })[0];
}

std::string table_header() {
  return "| diagram | flat | hier | lower | simulate | compare |\n|---|---|---|---|---|---|\n";
}

std::string table_row(const DiagramResult& r) {
  auto cell = [](const StepResult& s) {
    if (!s.ran) return std::string("–");
    return std::string(s.passed ? "pass" : "FAIL") + (s.detail.empty() ? "" : ": " + s.detail);
  };
  std::string row = "| " + r.name;
  for (const StepResult* s : {&r.flat, &r.hier, &r.lower, &r.simulate, &r.compare}) row += " | " + cell(*s);
  return row + " |";
}

}  // namespace mo::xcos_corpus
