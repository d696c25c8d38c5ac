// Conversion of flat ast::Expr trees into the symbolic arena.
#pragma once

#include <functional>
#include <string>

#include "mo/frontend/ast.hpp"
#include "mo/frontend/diagnostics.hpp"
#include "mo/symbolic/expr_arena.hpp"

namespace mo::symbolic::detail {

/// Converts expressions; references to flat variables and der() go through
/// callbacks so the caller decides what a variable stands for. Unsupported
/// constructs are reported once (the first) and convert to 0.
class ExprConverter {
public:
  using RefFn = std::function<Expr(const frontend::ast::Expr& ref)>;
  using DerFn = std::function<Expr(const frontend::ast::Expr& argument)>;

  ExprConverter(ExprArena& arena, Expr time, frontend::DiagnosticEngine& diags, RefFn refs,
                DerFn der)
      : a_(arena), time_(time), diags_(diags), refs_(std::move(refs)), der_(std::move(der)) {}

  /// The symbolic form of `e` (recursive over the tree; flat trees are shallow).
  Expr convert(const frontend::ast::Expr& e);
  /// `initial()` converts to the symbol `initial` returns (the caller's
  /// discrete flag, true only while the model initialises).
  void on_initial(std::function<Expr()> initial) { initial_ = std::move(initial); }
  /// `sample(start, interval)` converts to what `sample` returns for the
  /// call (the caller's discrete flag, true only at the call's time events).
  void on_sample(std::function<Expr(const frontend::ast::Expr& call)> sample) {
    sample_ = std::move(sample);
  }
  /// False once something could not be converted (and was reported).
  [[nodiscard]] bool ok() const { return ok_; }
  /// Reports `what` at e's range (once) and returns 0.
  Expr fail(const frontend::ast::Expr& e, const std::string& what);

private:
  Expr call(const frontend::ast::Expr& e);

  ExprArena& a_;
  Expr time_;
  frontend::DiagnosticEngine& diags_;
  RefFn refs_;
  DerFn der_;
  std::function<Expr()> initial_;
  std::function<Expr(const frontend::ast::Expr&)> sample_;
  bool ok_ = true;
};

}  // namespace mo::symbolic::detail
