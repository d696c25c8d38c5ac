// `a[i]` where the subscript i varies in time (an Integer variable, an index
// an algorithm computes): the element is chosen at run time, so the reference
// becomes the if-expression `if i == 1 then a[1] else if i == 2 then a[2] ...
// else a[n]` over the n elements of that dimension. Modelica makes an index
// out of 1..n an error; here it takes a[n].
#include "flattener.hpp"

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;

namespace {

/// True if `e` holds `end` (which only the subscripted array gives a value).
bool has_end(const Expr &root) {
  std::vector<const Expr *> work{&root};
  while (!work.empty()) {
    const Expr *e = work.back();
    work.pop_back();
    if (e->kind == ExprKind::End)
      return true;
    for (const auto &a : e->args)
      if (a)
        work.push_back(a.get());
  }
  return false;
}

} // namespace

bool Flattener::varying_subscript(const Expr &e, const Scope &s, Tensor &out) {
  for (std::size_t p = 0; p < e.ref.parts.size(); ++p) {
    const auto &subs = e.ref.parts[p].subscripts;
    for (std::size_t j = 0; j < subs.size(); ++j) {
      if (subs[j]->kind == ExprKind::Colon || has_end(*subs[j]))
        continue;
      Tensor index = expr(*subs[j], s);
      if (!index.is_scalar() || is_constant(*index.elems[0]))
        continue;
      ExprPtr all = e.clone();
      all->ref.parts[p].subscripts[j] = std::make_unique<Expr>(ExprKind::Colon, subs[j]->range);
      Tensor choices = expr(*all, s);
      if (choices.dims.size() != 1 || choices.elems.empty())
        fail(DiagId::Unsupported, subs[j]->range,
             "a subscript that varies in time is supported only where the reference is otherwise a scalar");
      const std::size_t n = choices.elems.size();
      if (on_varying_index)
        on_varying_index(*index.elems[0], static_cast<int>(n));
      ExprPtr chosen = std::move(choices.elems[n - 1]);
      for (std::size_t k = n - 1; k-- > 0;) {
        auto pick = std::make_unique<Expr>(ExprKind::If, e.range);
        pick->args.push_back(ast::make_binary(ast::Op::Eq, index.elems[0]->clone(),
                                              ast::make_integer(static_cast<double>(k + 1), e.range), e.range));
        pick->args.push_back(std::move(choices.elems[k]));
        pick->args.push_back(std::move(chosen));
        chosen = std::move(pick);
      }
      out = Tensor::scalar(std::move(chosen));
      return true;
    }
  }
  return false;
}

} // namespace mo::frontend::detail
