// `a[i]` where the subscript i varies in time (an Integer variable, an index
// an algorithm computes): the element is chosen at run time, so the reference
// becomes the if-expression `if i == 1 then a[1] else if i == 2 then a[2] ...
// else a[n]` over the n elements of that dimension; with several varying
// subscripts (`T[a, b]`, the MSL's Digital logic tables indexed by two
// signals) the if-expressions nest, one level per subscript. Modelica makes
// an index out of 1..n an error; here it takes a[n].
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

namespace {

/// `if i1 == 1 then ... else if i1 == 2 then ...` over the first of
/// `indices` (the varying subscripts, in order), each branch the same over
/// the others: the element of `choices` (row-major over the indices' dims,
/// from `offset` with `stride` elements per value of the first) they select.
ExprPtr pick(std::vector<ExprPtr> &choices, const std::vector<int> &dims, const std::vector<ExprPtr> &indices,
             std::size_t level, std::size_t offset, SourceRange where) {
  if (level == dims.size())
    return std::move(choices[offset]);
  std::size_t stride = 1;
  for (std::size_t d = level + 1; d < dims.size(); ++d)
    stride *= static_cast<std::size_t>(dims[d]);
  const std::size_t n = static_cast<std::size_t>(dims[level]);
  ExprPtr chosen = pick(choices, dims, indices, level + 1, offset + (n - 1) * stride, where);
  for (std::size_t k = n - 1; k-- > 0;) {
    auto e = std::make_unique<Expr>(ExprKind::If, where);
    e->args.push_back(ast::make_binary(ast::Op::Eq, indices[level]->clone(),
                                       ast::make_integer(static_cast<double>(k + 1), where), where));
    e->args.push_back(pick(choices, dims, indices, level + 1, offset + k * stride, where));
    e->args.push_back(std::move(chosen));
    chosen = std::move(e);
  }
  return chosen;
}

} // namespace

bool Flattener::varying_subscript(const Expr &e, const Scope &s, Tensor &out) {
  ExprPtr all = e.clone();
  std::vector<ExprPtr> indices;
  SourceRange first;
  for (std::size_t p = 0; p < e.ref.parts.size(); ++p) {
    const auto &subs = e.ref.parts[p].subscripts;
    for (std::size_t j = 0; j < subs.size(); ++j) {
      if (subs[j]->kind == ExprKind::Colon || has_end(*subs[j]))
        continue;
      Tensor index = expr(*subs[j], s);
      if (!index.is_scalar() || is_constant(*index.elems[0]))
        continue;
      if (indices.empty())
        first = subs[j]->range;
      indices.push_back(std::move(index.elems[0]));
      all->ref.parts[p].subscripts[j] = std::make_unique<Expr>(ExprKind::Colon, subs[j]->range);
    }
  }
  if (indices.empty())
    return false;
  Tensor choices = expr(*all, s);
  if (choices.dims.size() != indices.size() || choices.elems.empty() || choices.record)
    fail(DiagId::Unsupported, first,
         "a subscript that varies in time is supported only where the reference is otherwise a scalar");
  if (on_varying_index)
    for (std::size_t k = 0; k < indices.size(); ++k)
      on_varying_index(*indices[k], choices.dims[k]);
  out = Tensor::scalar(pick(choices.elems, choices.dims, indices, 0, 0, e.range));
  return true;
}

} // namespace mo::frontend::detail
