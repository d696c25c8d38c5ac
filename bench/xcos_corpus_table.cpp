// Prints the pass table of the Xcos corpus (issue 10): one row per diagram,
// one column per step (see xcos_corpus.hpp). Usage: xcos_corpus_table [NAME...]
// Exit status 0 when every diagram passes, 1 otherwise, 77 without the corpus.
#include <iostream>

#include "xcos_corpus.hpp"

int main(int argc, char** argv) {
  using namespace mo::xcos_corpus;
  const auto corpus = corpus_dir(MO_SOURCE_DIR);
  if (!corpus) {
    std::cerr << "xcos_corpus: no corpus (set MO_SHARED_DIR or put shared/ beside the checkout)\n";
    return 77;
  }
  std::vector<std::string> names(argv + 1, argv + argc);
  if (names.empty()) names = diagrams(*corpus);
  const Libraries libs{*corpus + "/../third_party/coselica/Coselica.mo", MO_SCILAB_MACROS};
  std::cout << table_header();
  std::size_t passed = 0;
  for (const auto& name : names) {
    const DiagramResult r = check_diagram(*corpus, name, libs);
    passed += r.passed();
    std::cout << table_row(r) << std::endl;
  }
  std::cout << "\n" << passed << " of " << names.size() << " diagrams pass every step\n";
  return passed == names.size() ? 0 : 1;
}
