// Small open-addressing containers keyed by node id, for traversals that
// touch a part of a large arena: no allocation per entry, O(1) expected.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "mo/symbolic/expr.hpp"

namespace mo::symbolic::detail {

/// A set of node ids. insert() returns true if the id was not yet present.
class NodeSet {
public:
  explicit NodeSet(std::size_t expected = 16) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.assign(capacity, empty);
  }

  bool insert(Expr e) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    return place(slots_, e.id());
  }

  bool contains(Expr e) const {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t s = mix(e.id()) & mask; slots_[s] != empty; s = (s + 1) & mask)
      if (slots_[s] == e.id()) return true;
    return false;
  }

  std::size_t size() const { return size_; }

private:
  static constexpr std::uint32_t empty = 0xFFFFFFFFu;

  static std::size_t mix(std::uint32_t id) {
    std::uint64_t h = id * 0x9E3779B97F4A7C15ull;
    return static_cast<std::size_t>(h ^ (h >> 32));
  }

  bool place(std::vector<std::uint32_t>& slots, std::uint32_t id) {
    const std::size_t mask = slots.size() - 1;
    std::size_t s = mix(id) & mask;
    for (; slots[s] != empty; s = (s + 1) & mask)
      if (slots[s] == id) return false;
    slots[s] = id;
    ++size_;
    return true;
  }

  void grow() {
    std::vector<std::uint32_t> bigger(slots_.size() * 2, empty);
    size_ = 0;
    for (std::uint32_t id : slots_)
      if (id != empty) place(bigger, id);
    slots_.swap(bigger);
  }

  std::vector<std::uint32_t> slots_;
  std::size_t size_ = 0;
};

/// Position of each node of a topological order (sorted by id), so that
/// per-node data can live in vectors parallel to the order. A dense table
/// over the id range when the order covers most of it (O(1), e.g. one deep
/// graph); binary search otherwise (a small part of a large arena).
class OrderIndex {
public:
  explicit OrderIndex(const std::vector<Expr>& order) : order_(order) {
    if (order.empty()) return;
    first_id_ = order.front().id();
    const std::size_t range = std::size_t(order.back().id()) - first_id_ + 1;
    if (range > 4 * order.size()) return;
    dense_.assign(range, not_in_order);
    for (std::size_t p = 0; p < order.size(); ++p)
      dense_[order[p].id() - first_id_] = static_cast<std::uint32_t>(p);
  }

  /// Position of `e`, which must be in the order (checked by the caller).
  std::size_t position(Expr e) const {
    if (!dense_.empty()) return dense_[e.id() - first_id_];
    return static_cast<std::size_t>(
        std::lower_bound(order_.begin(), order_.end(), e) - order_.begin());
  }

  /// True if `e` is in the order.
  bool contains(Expr e) const {
    if (order_.empty() || e < order_.front() || order_.back() < e) return false;
    const std::size_t p = position(e);
    return p < order_.size() && order_[p] == e;
  }

private:
  static constexpr std::uint32_t not_in_order = 0xFFFFFFFFu;
  const std::vector<Expr>& order_;
  std::uint32_t first_id_ = 0;
  std::vector<std::uint32_t> dense_;
};

} // namespace mo::symbolic::detail
