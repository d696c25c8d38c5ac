// The arena that owns every expression node of one model, and the factories
// that create nodes. Nodes are immutable and hash-consed: building a node that
// is structurally equal to an existing one returns the existing handle.
//
// Rewrite semantics ("finite-value semantics"): factories fold constants and
// apply cheap rewrites that never change a result that is finite and defined.
// A rewrite may turn a NaN or an infinity into a finite value (x*0 -> 0 even
// for x = Inf), and may change the sign of a zero result (x + 0 -> x for
// x = -0). A valid Modelica model never evaluates to Inf or NaN, so this
// never changes a valid model's results, and it keeps derivatives sparse.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "mo/symbolic/expr.hpp"

namespace mo::symbolic {

/// Owns the nodes of one model. Not thread-safe; handles from another arena
/// are not detected unless their id is out of range (std::out_of_range).
class ExprArena {
public:
  /// An empty arena.
  ExprArena();
  /// Not copyable: handles would silently refer to either copy.
  ExprArena(const ExprArena&) = delete;
  ExprArena& operator=(const ExprArena&) = delete;
  /// Movable; handles stay valid for the moved-to arena.
  ExprArena(ExprArena&&) noexcept = default;
  ExprArena& operator=(ExprArena&&) noexcept = default;

  // --- Leaves -------------------------------------------------------------

  /// The constant `value`; constants are distinct by bit pattern (-0 != +0).
  Expr constant(double value);
  /// The symbol `name`, created on first use. Throws std::invalid_argument if
  /// `name` is empty or already names a symbol with another role or index.
  Expr symbol(std::string_view name, SymbolRole role, std::int32_t index);
  /// der(x) of a symbol x, a leaf the caller seeds when differentiating.
  /// Throws std::invalid_argument if `x` is not a Symbol.
  Expr der(Expr x);
  /// pre(x) of a symbol x, the value of x before an event; a leaf.
  /// Throws std::invalid_argument if `x` is not a Symbol.
  Expr pre(Expr x);

  // --- Arithmetic ---------------------------------------------------------

  /// a + b, with constant folding and rewrites (see the file comment).
  Expr add(Expr a, Expr b);
  /// a - b.
  Expr sub(Expr a, Expr b);
  /// a * b.
  Expr mul(Expr a, Expr b);
  /// a / b.
  Expr div(Expr a, Expr b);
  /// -a.
  Expr neg(Expr a);
  /// a ^ b; pow(x, 2) is kept as a power (code generation may square it).
  Expr pow(Expr a, Expr b);

  // --- Built-in functions -------------------------------------------------

  /// f(a) for a one-operand function kind (Sin ... Ceil, NoEvent).
  /// Throws std::invalid_argument for any other kind.
  Expr apply(ExprKind function, Expr a);
  Expr sin(Expr a) { return apply(ExprKind::Sin, a); }     ///< sin(a).
  Expr cos(Expr a) { return apply(ExprKind::Cos, a); }     ///< cos(a).
  Expr tan(Expr a) { return apply(ExprKind::Tan, a); }     ///< tan(a).
  Expr asin(Expr a) { return apply(ExprKind::Asin, a); }   ///< asin(a).
  Expr acos(Expr a) { return apply(ExprKind::Acos, a); }   ///< acos(a).
  Expr atan(Expr a) { return apply(ExprKind::Atan, a); }   ///< atan(a).
  Expr sinh(Expr a) { return apply(ExprKind::Sinh, a); }   ///< sinh(a).
  Expr cosh(Expr a) { return apply(ExprKind::Cosh, a); }   ///< cosh(a).
  Expr tanh(Expr a) { return apply(ExprKind::Tanh, a); }   ///< tanh(a).
  Expr exp(Expr a) { return apply(ExprKind::Exp, a); }     ///< exp(a).
  Expr log(Expr a) { return apply(ExprKind::Log, a); }     ///< Natural log.
  Expr log10(Expr a) { return apply(ExprKind::Log10, a); } ///< log10(a).
  Expr sqrt(Expr a) { return apply(ExprKind::Sqrt, a); }   ///< sqrt(a).
  Expr abs(Expr a) { return apply(ExprKind::Abs, a); }     ///< |a|.
  /// sign(a): 1 if a > 0, -1 if a < 0, 0 if a == 0, NaN for NaN.
  Expr sign(Expr a) { return apply(ExprKind::Sign, a); }
  Expr floor(Expr a) { return apply(ExprKind::Floor, a); } ///< floor(a).
  Expr ceil(Expr a) { return apply(ExprKind::Ceil, a); }   ///< ceil(a).
  /// noEvent(a): relations inside a generate no events.
  Expr no_event(Expr a) { return apply(ExprKind::NoEvent, a); }
  /// atan2(a, b), the angle of the point (b, a).
  Expr atan2(Expr a, Expr b);
  /// min(a, b); evaluates as `if a < b then a else b`.
  Expr min(Expr a, Expr b);
  /// max(a, b); evaluates as `if a > b then a else b`.
  Expr max(Expr a, Expr b);
  /// smooth(order, a): a is `order` times continuously differentiable.
  /// Throws std::invalid_argument if order < 0.
  Expr smooth(int order, Expr a);
  /// Output `code` of a provided external function of `args` (ExprKind::
  /// External); folded to its value when every argument is a constant.
  /// Throws std::invalid_argument for a code no function has.
  Expr external(int code, std::span<const Expr> args);
  /// The arguments of an External node `e`, in order.
  std::vector<Expr> external_args(Expr e) const;
  /// delay(e, delay_time, delay_max) (ExprKind::Delay); a constant `e` is
  /// its own delayed value.
  Expr delay(Expr e, Expr delay_time, Expr delay_max);

  // --- Conditionals, relations, logic -------------------------------------

  /// if condition then a else b; the condition is Boolean (0 or 1).
  Expr select(Expr condition, Expr a, Expr b);
  Expr lt(Expr a, Expr b); ///< a < b, 0 or 1.
  Expr le(Expr a, Expr b); ///< a <= b.
  Expr gt(Expr a, Expr b); ///< a > b.
  Expr ge(Expr a, Expr b); ///< a >= b.
  Expr eq(Expr a, Expr b); ///< a == b.
  Expr ne(Expr a, Expr b); ///< a <> b.
  /// a and b; operands must be Boolean (0/1) as Modelica typing ensures.
  Expr logical_and(Expr a, Expr b);
  /// a or b; operands must be Boolean (0/1).
  Expr logical_or(Expr a, Expr b);
  /// not a; the operand must be Boolean (0/1).
  Expr logical_not(Expr a);

  /// The node `kind(operands...)` through the matching factory (so rewrites
  /// apply); used to rebuild nodes. Throws std::invalid_argument for
  /// Constant/Symbol, a wrong operand count or operands a factory rejects.
  Expr make(ExprKind kind, std::span<const Expr> operands);

  // --- Inspection ---------------------------------------------------------

  /// Number of nodes; ids run from 0 to size() - 1.
  std::size_t size() const { return nodes_.size(); }
  /// The kind of `e`. Throws std::out_of_range for an invalid handle.
  ExprKind kind(Expr e) const { return node(e).kind; }
  /// Operand `i` of `e`. Throws std::out_of_range if i >= arity(kind(e)).
  Expr operand(Expr e, std::size_t i) const;
  /// The value of a Constant. Throws std::invalid_argument otherwise.
  double constant_value(Expr e) const;
  /// True if `e` is a Constant.
  bool is_constant(Expr e) const { return kind(e) == ExprKind::Constant; }
  /// True if `e` is a Constant equal (==) to `value`.
  bool is_constant(Expr e, double value) const;
  /// True if `e` is a Symbol, Der, Pre or Delay: a value supplied by the caller
  /// (a Delay from recorded history; its delay time is an ordinary operand).
  bool is_leaf(Expr e) const;
  /// The symbol table entry of a Symbol. Throws std::invalid_argument if `e`
  /// is not a Symbol. The reference is valid until the next symbol().
  const SymbolInfo& symbol_info(Expr e) const;
  /// The symbol named `name`, if one exists.
  std::optional<Expr> find_symbol(std::string_view name) const;
  /// Every symbol in creation order.
  const std::vector<Expr>& symbols() const { return symbol_exprs_; }

private:
  // 16 bytes: kind plus three 32-bit words. Operator nodes hold operand ids;
  // a Constant holds the double's bits in words 0-1; a Symbol holds its
  // index into symbols_ in word 0. Unused words are zero.
  struct Node {
    ExprKind kind;
    std::uint32_t word[3];
    friend bool operator==(const Node&, const Node&) = default;
  };

  const Node& node(Expr e) const;
  Expr intern(const Node& n);
  Expr intern(ExprKind kind, Expr a, Expr b = Expr(0), Expr c = Expr(0));
  Expr fold_or_intern(ExprKind kind, Expr a, Expr b = Expr(0), Expr c = Expr(0));
  Expr relation(ExprKind kind, Expr a, Expr b);
  void grow_table();
  static std::uint64_t hash(const Node& n);

  std::vector<Node> nodes_;
  std::vector<std::uint32_t> table_; // open addressing; holds node ids
  std::vector<SymbolInfo> symbol_infos_;
  std::vector<Expr> symbol_exprs_;
  std::unordered_map<std::string, std::uint32_t> symbol_by_name_;
};

} // namespace mo::symbolic
