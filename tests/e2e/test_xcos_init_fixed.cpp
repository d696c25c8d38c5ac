// --init-fixed on the Xcos corpus (slow). Scilab's translator (modelicat, run
// as Xcos runs it) writes each diagram's init file from its hierarchical
// model, and a stand-in Scilab hands the translation to morun. Coselica
// declares its initial values as expressions of the blocks' initType
// (guesses by default), which the translator marks fixed whatever their
// value; checked against the model's own flags, the run with --init-fixed
// equals the one from start values alone, which matches Scilab's
// (test_xcos_corpus.cpp). Before, the cart with pendulum failed at t = 0 and
// the simple pendulum started elsewhere. Each runs to Scilab's tf. Skipped
// without the corpus or modelicat.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <fstream>
#include <string>
#include <vector>

#include "e2e/cli.hpp"
#include "xcos_corpus.hpp"

using namespace mo::e2e;

namespace {

/// The diagram's title: `model <title>_im` on the hierarchical file's first line.
std::string title_of(const fs::path& hier) {
  std::ifstream in(hier);
  std::string word, name;
  in >> word >> name;
  return word == "model" && name.ends_with("_im") ? name.substr(0, name.size() - 3) : "";
}

/// Writes into `dir` what Scilab's translator writes for the corpus diagram
/// `name`, and the list of what it read; false when modelicat fails.
bool translate(const fs::path& corpus, const std::string& name, const std::string& title, const fs::path& dir) {
  const fs::path coselica = corpus / ".." / "third_party" / "coselica" / "Coselica.mo";
  const fs::path macros = MO_SCILAB_MACROS;
  fs::copy_file(corpus / "flat" / (name + "_hier.mo"), dir / (title + "_im.mo"));
  std::vector<fs::path> libs{coselica, macros / "Electrical" / "Electrical.mo",
                             macros / "Hydraulics" / "Hydraulics.mo"};
  std::ofstream list(dir / "translator_libs.txt");
  list << coselica.string() << "\n"
       << (macros / "Electrical").string() << "\n"
       << (macros / "Hydraulics").string() << "\n";
  // A generic block's text (Scilab's demos): beside the translation, listed by name, as the script does.
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(corpus / "flat" / "aux" / name, ec)) {
    const std::string file = entry.path().filename().string();
    if (file.ends_with("_imf_functions.mo")) continue;  // the translator's output
    fs::copy_file(entry.path(), dir / file);
    libs.push_back(dir / file);
    list << file << "\n";
  }
  list.close();
  libs.push_back(dir / (title + "_im.mo"));
  std::string cmd = "cd " + quoted(dir.string()) + " && " + quoted(MO_MODELICAT);
  for (const fs::path& lib : libs) cmd += " -lib " + quoted(lib.string());
  cmd += " -o " + quoted(title + "_imf.mo") + " -with-init -command " + quoted(title + "_im " + title + "_imf;") +
         " >modelicat.log 2>&1";
  return std::system(cmd.c_str()) == 0;
}

/// morun on the translation in `fake`, to `stop`, results in dir/out_<tag>.
Run run(const fs::path& dir, const fs::path& fake, double stop, const std::string& tag, bool init_fixed) {
  const fs::path err = dir / ("stderr_" + tag + ".txt");
  const std::string cmd = "env XDG_CACHE_HOME=" + quoted(std::string(MO_TEST_CACHE_DIR) + "/morun-test-cache") +
                          " MO_SCILAB=" + quoted(std::string(MO_TEST_DATA_DIR) + "/xcos/translating-scilab.sh") +
                          " DISPLAY=:0 MO_FAKE_TRANSLATION=" + quoted(fake.string()) + " " + quoted(kMorun) + " " +
                          quoted(std::string(MO_TEST_DATA_DIR) + "/xcos/SeriesRLC.zcos") +
                          " --open-loop --stop-time " + std::to_string(stop) + " -o " +
                          quoted((dir / ("out_" + tag)).string()) +
                          (init_fixed ? " --init-fixed" : "") + " >/dev/null 2>" + quoted(err.string());
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(err)};
}

}  // namespace

TEST_CASE("the corpus's diagrams with --init-fixed start as their start values do", "[xcos][corpus]") {
  const auto corpus = mo::xcos_corpus::corpus_dir(MO_SOURCE_DIR);
  if (!corpus) {
    WARN("SKIPPED: no xcos-corpus beside the checkout (set MO_SHARED_DIR)");
    return;
  }
  if (std::string(MO_MODELICAT).empty() || !fs::exists(MO_MODELICAT)) {
    WARN("SKIPPED: Scilab's modelicat is not installed (scripts/install-deps.sh)");
    return;
  }
  int checked = 0;
  for (const auto& name : mo::xcos_corpus::diagrams(*corpus)) {
    const fs::path hier = fs::path(*corpus) / "flat" / (name + "_hier.mo");
    const std::string title = title_of(hier);
    INFO(name);
    REQUIRE(!title.empty());
    const fs::path dir = scratch("xcos-init-fixed-" + name);
    fs::create_directories(dir / "fake");
    REQUIRE(translate(*corpus, name, title, dir / "fake"));
    const double tf = nlohmann::json::parse(slurp(fs::path(*corpus) / "ref" / (name + ".json"))).at("tf");
    const Run plain = run(dir, dir / "fake", tf, "plain", false);
    const Run fixed = run(dir, dir / "fake", tf, "fixed", true);
    INFO(plain.err << fixed.err);
    REQUIRE(plain.status == 0);
    REQUIRE(fixed.status == 0);
    CHECK(fixed.err.find("unchecked") == std::string::npos);
    CHECK(slurp(dir / "out_fixed" / "result.csv") == slurp(dir / "out_plain" / "result.csv"));
    ++checked;
  }
  CHECK(checked == static_cast<int>(mo::xcos_corpus::diagrams(*corpus).size()));
}
