// Building sections: slots on demand and each node computed once per section
// chain (see program.hpp).
#pragma once

#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "mo/codegen/program.hpp"

namespace mo::codegen::detail {

/// Slots of expression nodes, allocated on first use.
class SlotMap {
public:
  /// For an arena that no longer grows, of `arena_size` nodes.
  explicit SlotMap(std::size_t arena_size) : slot_(arena_size, none) {}
  /// The slot of `e`, allocated now if it has none.
  Slot of(symbolic::Expr e);
  /// True if `e` already has a slot.
  bool has(symbolic::Expr e) const { return slot_.at(e.id()) != none; }
  /// A slot belonging to no node (a materialised constant).
  Slot fresh() { return next_++; }
  /// Number of slots so far.
  Slot count() const { return next_; }
  /// Slot of every node, no_slot if none.
  const std::vector<Slot>& all() const { return slot_; }

private:
  static constexpr Slot none = no_slot;
  std::vector<Slot> slot_;
  Slot next_ = 0;
};

/// Which nodes hold their current value at a point of a section chain.
using Validity = std::vector<std::uint8_t>;

/// Appends instructions to sections, computing each node at most once given
/// what the earlier sections of the chain computed (`valid`).
class SectionBuilder {
public:
  /// Starts from `valid` (size = arena size); leaves are always valid.
  SectionBuilder(const symbolic::ExprArena& arena, SlotMap& slots, Program& program, Validity valid);

  /// Makes relation `e` take its value from crossing `indicator` (event sections).
  /// Nodes above it that were valid are recomputed. Call before any emission.
  void override_relation(symbolic::Expr e, int indicator, double value_if_down);
  /// Emits what `e` needs into `s`; returns the slot holding e (a constant
  /// gets a fresh slot and a Copy).
  Slot root(symbolic::Expr e, Section& s);
  /// Emits `target := value` (target a symbol slot).
  void assign(Slot target, symbolic::Expr value, Section& s);
  /// Emits an equation block: its inputs, then the solve.
  void block(const symbolic::EquationBlock& b, const std::string& description, Section& s);
  /// Validity after everything emitted so far.
  const Validity& valid() const { return valid_; }

private:
  void require(symbolic::Expr e, Section& s);
  bool is_valid(symbolic::Expr e) const;
  /// A delay() node whose delay time varies (DelayCode::varying): computed, not loaded.
  bool varying_delay(symbolic::Expr e) const;
  void emit_node(symbolic::Expr e, Section& s);
  void nonlinear(const symbolic::EquationBlock& b, BlockCode& code, Section& s);

  const symbolic::ExprArena& a_;
  SlotMap& slots_;
  Program& program_;
  Validity valid_;
  std::vector<std::uint8_t> tainted_;  // depends on an overridden relation
  std::unordered_map<std::uint32_t, std::pair<int, double>> overrides_;
};

}  // namespace mo::codegen::detail
