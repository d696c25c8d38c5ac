// Structural analysis of equation systems: maximum bipartite matching
// (Hopcroft–Karp, O(E·√V)) and block-lower-triangular ordering (Tarjan's
// strongly connected components). Both iterative: any model size is safe.
#pragma once

#include <vector>

namespace mo::symbolic {

/// Incidence of equations (rows) on unknowns (columns), CSR by equation.
struct Incidence {
  int equations = 0;
  int unknowns = 0;
  std::vector<int> start;  ///< size equations + 1
  std::vector<int> index;  ///< unknowns of equation i: index[start[i] .. start[i+1])

  /// Builds from per-equation unknown lists.
  static Incidence from_lists(int unknowns, const std::vector<std::vector<int>>& lists);
};

/// A matching: unknown_of[eq] and equation_of[unknown], -1 where unmatched.
struct Matching {
  std::vector<int> unknown_of;
  std::vector<int> equation_of;
  int size = 0;  ///< number of matched pairs
};

/// A maximum matching (Hopcroft–Karp after a greedy start).
Matching maximum_matching(const Incidence& g);

/// The equations of a perfect (or any) matching grouped into strongly
/// connected blocks, in an order where each block only needs unknowns matched
/// in earlier blocks or itself. Unmatched equations are left out.
std::vector<std::vector<int>> blt_blocks(const Incidence& g, const Matching& m);

}  // namespace mo::symbolic
