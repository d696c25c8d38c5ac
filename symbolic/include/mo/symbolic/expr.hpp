// An expression is a node of a directed acyclic graph owned by an ExprArena:
// a constant, a variable symbol, der(x) or pre(x) of a symbol, or an operator
// or built-in function applied to operand expressions. Expr is the handle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <unordered_map>

namespace mo::symbolic {

/// The operation of a node; one enumerator per line of expr_kinds.def.
enum class ExprKind : std::uint8_t {
#define MO_EXPR_KIND(Name, arity, spelling) Name,
#include "mo/symbolic/expr_kinds.def"
};

/// Number of ExprKind enumerators.
inline constexpr std::size_t expr_kind_count = 0
#define MO_EXPR_KIND(Name, arity, spelling) +1
#include "mo/symbolic/expr_kinds.def"
    ;

/// Number of operands a node of `kind` has (0 to 3).
std::size_t arity(ExprKind kind);

/// The enumerator's name, e.g. "Atan2"; used by debug dumps and tests.
std::string_view kind_name(ExprKind kind);

/// The Modelica spelling, e.g. "+", "atan2", "noEvent"; empty for leaves.
std::string_view kind_spelling(ExprKind kind);

/// What a variable symbol stands for in `0 = F(der(x), x, y, u, p, t)`.
enum class SymbolRole : std::uint8_t {
  State,      ///< x: a differentiated variable.
  Derivative, ///< der(x) introduced as a variable of its own by the caller.
  Algebraic,  ///< y: an algebraic variable.
  Input,      ///< u: an input, given over time.
  Parameter,  ///< p: constant during a simulation.
  Time,       ///< t: the independent variable.
  Discrete,   ///< d: changes only at events (when-clauses).
};

/// The side-table entry of a symbol: its name, role and the caller's index.
struct SymbolInfo {
  std::string name;   ///< Unique within the arena, e.g. "pendulum.phi".
  SymbolRole role;    ///< What the symbol stands for.
  std::int32_t index; ///< Caller's number, e.g. position in the state vector.
};

/// A cheap handle to a node of one ExprArena: a 32-bit node index.
/// Equal handles from the same arena mean structurally equal expressions.
/// A default-constructed Expr is invalid; arena functions reject it.
class Expr {
public:
  /// The invalid handle.
  constexpr Expr() = default;
  /// The handle of node `id`; only ExprArena should need this.
  constexpr explicit Expr(std::uint32_t id) : id_(id) {}

  /// The node index in its arena. Children always have smaller ids than
  /// their parents, so sorting by id is a topological order.
  constexpr std::uint32_t id() const { return id_; }
  /// False for the default-constructed handle.
  constexpr bool valid() const { return id_ != invalid_id; }

  /// Same node (within one arena: structurally equal expressions).
  friend constexpr bool operator==(Expr, Expr) = default;
  /// Order by id: operands before their users.
  friend constexpr auto operator<=>(Expr, Expr) = default;

private:
  static constexpr std::uint32_t invalid_id = 0xFFFFFFFFu;
  std::uint32_t id_ = invalid_id;
};

/// Hash of a handle, for unordered containers keyed by Expr.
struct ExprHash {
  /// Hash of the node id.
  std::size_t operator()(Expr e) const noexcept {
    return std::hash<std::uint32_t>{}(e.id());
  }
};

/// A map from expressions to expressions: derivative seeds, substitutions.
using ExprMap = std::unordered_map<Expr, Expr, ExprHash>;

} // namespace mo::symbolic

/// Lets std::unordered_map<Expr, ...> work without naming ExprHash.
template <> struct std::hash<mo::symbolic::Expr> : mo::symbolic::ExprHash {};
