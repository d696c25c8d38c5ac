// Hopcroft–Karp matching and Tarjan BLT; see structure.hpp.
#include "mo/symbolic/structure.hpp"

#include <algorithm>
#include <limits>

namespace mo::symbolic {

Incidence Incidence::from_lists(int unknowns, const std::vector<std::vector<int>>& lists) {
  Incidence g;
  g.equations = static_cast<int>(lists.size());
  g.unknowns = unknowns;
  g.start.reserve(lists.size() + 1);
  g.start.push_back(0);
  for (const auto& l : lists) {
    g.index.insert(g.index.end(), l.begin(), l.end());
    g.start.push_back(static_cast<int>(g.index.size()));
  }
  return g;
}

namespace {

constexpr int kInf = std::numeric_limits<int>::max();

class HopcroftKarp {
public:
  explicit HopcroftKarp(const Incidence& g)
      : g_(g), dist_(static_cast<std::size_t>(g.equations)), next_(dist_.size()) {
    m_.unknown_of.assign(static_cast<std::size_t>(g.equations), -1);
    m_.equation_of.assign(static_cast<std::size_t>(g.unknowns), -1);
  }

  Matching run() {
    greedy();
    while (layer())
      for (int e = 0; e < g_.equations; ++e)
        if (m_.unknown_of[at(e)] == -1 && augment(e)) ++m_.size;
    return std::move(m_);
  }

private:
  static std::size_t at(int i) { return static_cast<std::size_t>(i); }

  void greedy() {
    for (int e = 0; e < g_.equations; ++e)
      for (int k = g_.start[at(e)]; k < g_.start[at(e) + 1]; ++k) {
        const int u = g_.index[at(k)];
        if (m_.equation_of[at(u)] == -1) {
          m_.equation_of[at(u)] = e;
          m_.unknown_of[at(e)] = u;
          ++m_.size;
          break;
        }
      }
  }

  /// BFS from free equations; true if some free unknown is reachable.
  bool layer() {
    std::vector<int> queue;
    for (int e = 0; e < g_.equations; ++e) {
      dist_[at(e)] = m_.unknown_of[at(e)] == -1 ? 0 : kInf;
      if (dist_[at(e)] == 0) queue.push_back(e);
    }
    bool found = false;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int e = queue[q];
      for (int k = g_.start[at(e)]; k < g_.start[at(e) + 1]; ++k) {
        const int owner = m_.equation_of[at(g_.index[at(k)])];
        if (owner == -1) {
          found = true;
        } else if (dist_[at(owner)] == kInf) {
          dist_[at(owner)] = dist_[at(e)] + 1;
          queue.push_back(owner);
        }
      }
    }
    for (int e = 0; e < g_.equations; ++e) next_[at(e)] = g_.start[at(e)];
    return found;
  }

  /// Iterative DFS along the BFS layers from free equation `root`.
  bool augment(int root) {
    std::vector<int> path{root};
    while (!path.empty()) {
      const int e = path.back();
      bool advanced = false;
      while (next_[at(e)] < g_.start[at(e) + 1]) {
        const int u = g_.index[at(next_[at(e)]++)];
        const int owner = m_.equation_of[at(u)];
        if (owner == -1) {
          flip(path, u);
          return true;
        }
        if (dist_[at(owner)] == dist_[at(e)] + 1) {
          path.push_back(owner);
          advanced = true;
          break;
        }
      }
      if (!advanced) {
        dist_[at(e)] = kInf;  // dead end for this phase
        path.pop_back();
      }
    }
    return false;
  }

  /// Rematches along the path ending in free unknown `u`.
  void flip(const std::vector<int>& path, int u) {
    for (std::size_t i = path.size(); i-- > 0;) {
      const int e = path[i];
      const int previous = m_.unknown_of[at(e)];
      m_.unknown_of[at(e)] = u;
      m_.equation_of[at(u)] = e;
      u = previous;
    }
  }

  const Incidence& g_;
  Matching m_;
  std::vector<int> dist_;
  std::vector<int> next_;
};

}  // namespace

Matching maximum_matching(const Incidence& g) { return HopcroftKarp(g).run(); }

std::vector<std::vector<int>> blt_blocks(const Incidence& g, const Matching& m) {
  const auto n = static_cast<std::size_t>(g.equations);
  std::vector<int> index(n, -1), low(n, 0), edge(n, 0), stack;
  std::vector<char> on_stack(n, 0);
  std::vector<std::vector<int>> blocks;
  int counter = 0;
  // Successors of equation e: the equations matched to the unknowns e uses.
  auto successor = [&](int k) {
    return m.equation_of[static_cast<std::size_t>(g.index[static_cast<std::size_t>(k)])];
  };
  for (int root = 0; root < g.equations; ++root) {
    if (index[static_cast<std::size_t>(root)] != -1 ||
        m.unknown_of[static_cast<std::size_t>(root)] == -1)
      continue;
    std::vector<int> call{root};
    while (!call.empty()) {
      const int e = call.back();
      const auto se = static_cast<std::size_t>(e);
      if (index[se] == -1) {
        index[se] = low[se] = counter++;
        edge[se] = g.start[se];
        stack.push_back(e);
        on_stack[se] = 1;
      }
      bool descended = false;
      while (edge[se] < g.start[se + 1]) {
        const int s = successor(edge[se]++);
        if (s == -1 || s == e) continue;
        const auto ss = static_cast<std::size_t>(s);
        if (index[ss] == -1) {
          call.push_back(s);
          descended = true;
          break;
        }
        if (on_stack[ss]) low[se] = std::min(low[se], index[ss]);
      }
      if (descended) continue;
      call.pop_back();
      if (!call.empty()) {
        const auto sp = static_cast<std::size_t>(call.back());
        low[sp] = std::min(low[sp], low[se]);
      }
      if (low[se] == index[se]) {
        std::vector<int> block;
        int w;
        do {
          w = stack.back();
          stack.pop_back();
          on_stack[static_cast<std::size_t>(w)] = 0;
          block.push_back(w);
        } while (w != e);
        std::reverse(block.begin(), block.end());
        blocks.push_back(std::move(block));
      }
    }
  }
  return blocks;
}

}  // namespace mo::symbolic
