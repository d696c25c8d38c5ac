// Node storage, the hash-consing table and the symbol table of ExprArena.
// The rewriting factories are in factories.cpp.
#include "mo/symbolic/expr_arena.hpp"

#include <array>
#include <bit>
#include <stdexcept>
#include <string>

namespace mo::symbolic {

namespace {

constexpr std::uint32_t empty_slot = 0xFFFFFFFFu;

struct KindInfo {
  std::size_t arity;
  std::string_view name;
  std::string_view spelling;
};

constexpr std::array<KindInfo, expr_kind_count> kind_infos = {{
#define MO_EXPR_KIND(Name, arity, spelling) {arity, #Name, spelling},
#include "mo/symbolic/expr_kinds.def"
}};

const KindInfo& info(ExprKind kind) {
  return kind_infos.at(static_cast<std::size_t>(kind));
}

} // namespace

std::size_t arity(ExprKind kind) { return info(kind).arity; }
std::string_view kind_name(ExprKind kind) { return info(kind).name; }
std::string_view kind_spelling(ExprKind kind) { return info(kind).spelling; }

ExprArena::ExprArena() : table_(1024, empty_slot) {}

const ExprArena::Node& ExprArena::node(Expr e) const {
  if (!e.valid() || e.id() >= nodes_.size())
    throw std::out_of_range("expression handle " + std::to_string(e.id()) +
                            " is not a node of this arena");
  return nodes_[e.id()];
}

std::uint64_t ExprArena::hash(const Node& n) {
  // splitmix64-style mixing of the four words.
  std::uint64_t h = static_cast<std::uint64_t>(n.kind) * 0x9E3779B97F4A7C15ull;
  for (std::uint32_t w : n.word) {
    h ^= w + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 31;
  }
  return h;
}

void ExprArena::grow_table() {
  std::vector<std::uint32_t> bigger(table_.size() * 2, empty_slot);
  const std::size_t mask = bigger.size() - 1;
  for (std::uint32_t id : table_) {
    if (id == empty_slot) continue;
    std::size_t slot = hash(nodes_[id]) & mask;
    while (bigger[slot] != empty_slot) slot = (slot + 1) & mask;
    bigger[slot] = id;
  }
  table_.swap(bigger);
}

Expr ExprArena::intern(const Node& n) {
  const std::size_t mask = table_.size() - 1;
  std::size_t slot = hash(n) & mask;
  while (table_[slot] != empty_slot) {
    if (nodes_[table_[slot]] == n) return Expr(table_[slot]);
    slot = (slot + 1) & mask;
  }
  if (nodes_.size() >= empty_slot - 1)
    throw std::length_error("expression arena is full (2^32 - 2 nodes)");
  const auto id = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back(n);
  table_[slot] = id;
  // Keep the load factor at most 1/2 so that probes stay short.
  if (2 * nodes_.size() > table_.size()) grow_table();
  return Expr(id);
}

Expr ExprArena::intern(ExprKind kind, Expr a, Expr b, Expr c) {
  Node n{kind, {0, 0, 0}};
  const std::array<Expr, 3> operands{a, b, c};
  for (std::size_t i = 0; i < arity(kind); ++i) {
    node(operands[i]); // throws for a foreign or invalid handle
    n.word[i] = operands[i].id();
  }
  return intern(n);
}

Expr ExprArena::constant(double value) {
  const auto bits = std::bit_cast<std::uint64_t>(value);
  return intern(Node{ExprKind::Constant,
                     {static_cast<std::uint32_t>(bits),
                      static_cast<std::uint32_t>(bits >> 32), 0}});
}

Expr ExprArena::symbol(std::string_view name, SymbolRole role,
                       std::int32_t index) {
  if (name.empty()) throw std::invalid_argument("symbol name is empty");
  const auto found = symbol_by_name_.find(std::string(name));
  if (found != symbol_by_name_.end()) {
    const SymbolInfo& existing = symbol_infos_[found->second];
    if (existing.role != role || existing.index != index)
      throw std::invalid_argument("symbol '" + std::string(name) +
                                  "' already exists with another role or index");
    return symbol_exprs_[found->second];
  }
  const auto entry = static_cast<std::uint32_t>(symbol_infos_.size());
  const Expr e = intern(Node{ExprKind::Symbol, {entry, 0, 0}});
  symbol_infos_.push_back(SymbolInfo{std::string(name), role, index});
  symbol_exprs_.push_back(e);
  symbol_by_name_.emplace(std::string(name), entry);
  return e;
}

Expr ExprArena::der(Expr x) {
  if (kind(x) != ExprKind::Symbol)
    throw std::invalid_argument("der() needs a variable symbol as operand");
  return intern(ExprKind::Der, x);
}

Expr ExprArena::pre(Expr x) {
  if (kind(x) != ExprKind::Symbol)
    throw std::invalid_argument("pre() needs a variable symbol as operand");
  return intern(ExprKind::Pre, x);
}

Expr ExprArena::operand(Expr e, std::size_t i) const {
  const Node& n = node(e);
  if (i >= arity(n.kind))
    throw std::out_of_range("operand " + std::to_string(i) + " of a " +
                            std::string(kind_name(n.kind)) + " node");
  return Expr(n.word[i]);
}

double ExprArena::constant_value(Expr e) const {
  const Node& n = node(e);
  if (n.kind != ExprKind::Constant)
    throw std::invalid_argument("constant_value() of a " +
                                std::string(kind_name(n.kind)) + " node");
  return std::bit_cast<double>(static_cast<std::uint64_t>(n.word[0]) |
                               (static_cast<std::uint64_t>(n.word[1]) << 32));
}

bool ExprArena::is_constant(Expr e, double value) const {
  return is_constant(e) && constant_value(e) == value;
}

bool ExprArena::is_leaf(Expr e) const {
  const ExprKind k = kind(e);
  return k == ExprKind::Symbol || k == ExprKind::Der || k == ExprKind::Pre || k == ExprKind::Delay;
}

const SymbolInfo& ExprArena::symbol_info(Expr e) const {
  const Node& n = node(e);
  if (n.kind != ExprKind::Symbol)
    throw std::invalid_argument("symbol_info() of a " +
                                std::string(kind_name(n.kind)) + " node");
  return symbol_infos_[n.word[0]];
}

std::optional<Expr> ExprArena::find_symbol(std::string_view name) const {
  const auto found = symbol_by_name_.find(std::string(name));
  if (found == symbol_by_name_.end()) return std::nullopt;
  return symbol_exprs_[found->second];
}

} // namespace mo::symbolic
