// Flattening of array constructs beyond element-wise arithmetic: the array
// built-ins (cat, linspace, diagonal, outerProduct, matrix, ndims, skew,
// symmetric), reductions with iterators (`sum(e for i in r)`), array
// constructors with several iterators, matrix constructors `[a, b; c, d]`
// with array elements, and enumeration types as dimensions and ranges.
// Every result is a Tensor of scalar expressions (row-major).
#include "flattener.hpp"

#include <cmath>
#include <fmt/format.h>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;
using ast::Op;

namespace {

std::string dims_text(const std::vector<int> &dims) {
  std::string s = "[";
  for (std::size_t i = 0; i < dims.size(); ++i)
    s += (i ? ", " : "") + std::to_string(dims[i]);
  return s + "]";
}

std::size_t product_of(const std::vector<int> &dims, std::size_t from, std::size_t to) {
  std::size_t n = 1;
  for (std::size_t i = from; i < to && i < dims.size(); ++i)
    n *= static_cast<std::size_t>(dims[i]);
  return n;
}

/// A number written out (possibly negated): folding it changes nothing a
/// sensitivity or a parameter change could see.
bool is_number(const Expr &e) {
  if (e.kind == ExprKind::Unary && e.op == Op::Neg)
    return is_number(*e.args[0]);
  return e.kind == ExprKind::Real || e.kind == ExprKind::Integer;
}

ExprPtr mul(ExprPtr a, ExprPtr b, SourceRange r) { return ast::make_binary(Op::Mul, std::move(a), std::move(b), r); }

/// `t` with at least `n` dimensions: trailing dimensions of size 1 added
/// (Modelica's promote(): a vector becomes a column).
Tensor promote(Tensor t, std::size_t n) {
  while (t.dims.size() < n)
    t.dims.push_back(1);
  return t;
}

} // namespace

/// Concatenation along dimension `k` (1-based) of tensors with the same
/// number of dimensions and equal sizes elsewhere; reports a mismatch at `r`.
static Tensor cat_tensors(Flattener &f, long long k, std::vector<Tensor> parts, SourceRange r) {
  if (parts.empty())
    f.fail(DiagId::WrongArgumentCount, r, "cat() needs at least one array to concatenate");
  const std::vector<int> &first = parts[0].dims;
  if (k < 1 || k > static_cast<long long>(first.size()))
    f.fail(DiagId::BadSubscript, r,
           fmt::format("cannot concatenate along dimension {} of arrays with {} dimension(s)", k, first.size()));
  const std::size_t kd = static_cast<std::size_t>(k - 1);
  Tensor out;
  out.dims = first;
  out.dims[kd] = 0;
  for (const Tensor &p : parts) {
    bool same = p.dims.size() == first.size();
    for (std::size_t i = 0; same && i < first.size(); ++i)
      same = i == kd || p.dims[i] == first[i];
    if (!same)
      f.fail(DiagId::TypeMismatch, r,
             fmt::format("cannot concatenate arrays of sizes {} and {} along dimension {}", dims_text(first),
                         dims_text(p.dims), k));
    out.dims[kd] += p.dims[kd];
  }
  const std::size_t outer = product_of(first, 0, kd);
  for (std::size_t o = 0; o < outer; ++o)
    for (Tensor &p : parts) {
      const std::size_t block = product_of(p.dims, kd, p.dims.size());
      for (std::size_t i = 0; i < block; ++i)
        out.elems.push_back(std::move(p.elems[o * block + i]));
    }
  return out;
}

int Flattener::enumeration_size(const ast::ComponentRef &ref, const Scope &s, SourceRange where) {
  for (const auto &p : ref.parts)
    if (!p.subscripts.empty())
      return -1;
  if (!ref.global && s.inst && s.inst->member_index.count(ref.parts[0].name))
    return -1; // a component, not a type
  if (s.env && ref.is_simple() && s.env->find(ref.parts[0].name))
    return -1; // a loop index
  std::vector<std::string> path;
  for (const auto &p : ref.parts)
    path.push_back(p.name);
  ClassNode *cls = lookup_class(s.cls ? s.cls : &lib_.root, path, ref.global, where, false);
  // Through short classes: `type Phase3 = Phase;`.
  for (unsigned hops = 0; cls && cls->def && cls->def->short_base && hops < 32; ++hops)
    cls = lookup_class(cls->parent, cls->def->short_base->parts, cls->def->short_base->global, where, false);
  if (!cls || !cls->def || cls->def->enumeration.empty())
    return -1;
  return static_cast<int>(cls->def->enumeration.size());
}

long long Flattener::dimension_size(const Expr &d, const Scope &s) {
  if (d.kind == ExprKind::Ref)
    if (int n = enumeration_size(d.ref, s, d.range); n >= 0)
      return n;
  return eval_int(d, s);
}

Tensor Flattener::comprehension(const Expr &body, const std::vector<ast::ForIndex> &iterators, const Scope &s,
                                SourceRange where) {
  // {e for i in r1, j in r2} = {{e for i in r1} for j in r2}: the last
  // iterator runs along the first dimension.
  const std::size_t n = iterators.size();
  std::vector<std::vector<double>> ranges(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (!iterators[k].range)
      fail(DiagId::Unsupported, iterators[k].loc, "iterators without 'in range' are not supported");
    ranges[k] = eval_range(*iterators[k].range, s);
  }
  Tensor out;
  std::vector<long long> sizes;
  for (std::size_t k = n; k-- > 0;) {
    out.dims.push_back(static_cast<int>(ranges[k].size()));
    sizes.push_back(static_cast<long long>(ranges[k].size()));
  }
  const std::size_t total = element_count(sizes, where, "the array constructor");
  LoopEnv env = s.env ? *s.env : LoopEnv{};
  const std::size_t base = env.values.size();
  for (std::size_t k = 0; k < n; ++k)
    env.values.emplace_back(iterators[k].name, 0.0);
  Scope inner = s;
  inner.env = &env;
  std::vector<int> body_dims;
  for (std::size_t flat = 0; flat < total; ++flat) {
    std::size_t rest = flat; // row-major over (last iterator, ..., first)
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t len = ranges[k].size();
      env.values[base + k].second = ranges[k][rest % len];
      rest /= len;
    }
    Tensor t = expr(body, inner);
    if (flat == 0)
      body_dims = t.dims, out.record = t.record; // {u[k] for k in 1:n} of records: an array of records
    else if (t.dims != body_dims)
      fail(DiagId::TypeMismatch, where, "the elements of this array have different sizes");
    else if (!same_record_type(t.record, out.record))
      fail(DiagId::TypeMismatch, where, "the elements of this array are records of different types");
    for (auto &x : t.elems)
      out.elems.push_back(std::move(x));
  }
  if (total == 0)
    body_dims.clear();
  out.dims.insert(out.dims.end(), body_dims.begin(), body_dims.end());
  return out;
}

Tensor Flattener::matrix_constructor(const Expr &e, const Scope &s) {
  // [a, b; c, d] = cat(1, cat(2, a, b), cat(2, c, d)), each element
  // promoted to at least two dimensions.
  std::vector<Tensor> rows;
  for (const auto &row : e.rows) {
    std::vector<Tensor> cells;
    for (const auto &x : row) {
      Tensor cell = expr(*x, s);
      if (cell.record)
        no_record(cell, x->range, "a matrix constructor");
      cells.push_back(promote(std::move(cell), 2));
    }
    rows.push_back(cat_tensors(*this, 2, std::move(cells), e.range));
  }
  return cat_tensors(*this, 1, std::move(rows), e.range);
}

Tensor reduce_elements(Flattener &f, const std::string &name, Tensor a, SourceRange r) {
  if (a.elems.empty()) {
    if (name == "min" || name == "max")
      f.fail(DiagId::TypeMismatch, r, name + "() of an empty array");
    return Tensor::scalar(ast::make_real(name == "sum" ? 0 : 1, r)); // as sum() of {} does
  }
  return Tensor::scalar(join_terms(std::move(a.elems), [&](ExprPtr x, ExprPtr y) {
    if (name == "sum" || name == "product")
      return ast::make_binary(name == "sum" ? Op::Add : Op::Mul, std::move(x), std::move(y), r);
    std::vector<ExprPtr> v;
    v.push_back(std::move(x));
    v.push_back(std::move(y));
    return ast::make_call(name, std::move(v), r);
  }));
}

bool Flattener::array_function(const Expr &e, const Scope &s, Tensor &out) {
  if (!e.ref.is_simple() || !e.named.empty())
    return false;
  const std::string &name = e.ref.parts[0].name;
  const SourceRange r = e.range;
  if (s.inst && s.inst->member_index.count(name))
    return false; // a component called so (Optimica's `x(t)`)
  auto want_args = [&](std::size_t lo, std::size_t hi) {
    if (e.args.size() < lo || e.args.size() > hi)
      fail(DiagId::WrongArgumentCount, r,
           fmt::format("{}() takes {} argument{}, {} given", name,
                       lo == hi ? std::to_string(lo) : fmt::format("{} to {}", lo, hi), hi == 1 ? "" : "s",
                       e.args.size()));
  };
  auto arg = [&](std::size_t i) {
    Tensor t = expr(*e.args[i], s);
    if (name != "size" && name != "ndims")
      if (t.record)
        no_record(t, e.args[i]->range, name + "()");
    return t;
  };
  if (!e.iterators.empty()) {
    if (name != "sum" && name != "product" && name != "min" && name != "max")
      fail(DiagId::Unsupported, r, "'" + name + "(... for ...)' is not a supported reduction");
    want_args(1, 1);
    out = reduce_elements(*this, name, comprehension(*e.args[0], e.iterators, s, r), r);
    return true;
  }
  if (name == "cat") {
    want_args(2, 1000);
    long long k = eval_int(*e.args[0], s);
    std::vector<Tensor> parts;
    for (std::size_t i = 1; i < e.args.size(); ++i)
      parts.push_back(arg(i));
    out = cat_tensors(*this, k, std::move(parts), r);
    return true;
  }
  if (name == "linspace") {
    want_args(3, 3);
    ExprPtr x1 = scalar_expr(*e.args[0], s), x2 = scalar_expr(*e.args[1], s);
    long long n = eval_int(*e.args[2], s);
    if (n < 2 || n > 1'000'000)
      fail(DiagId::BadSubscript, e.args[2]->range, fmt::format("linspace() needs n >= 2, got {}", n));
    out.dims = {static_cast<int>(n)};
    const bool literal = is_number(*x1) && is_number(*x2);
    for (long long i = 0; i < n; ++i) {
      if (literal) { // fold when both ends are numbers: the flat model reads better
        double a = eval(*x1, r), b = eval(*x2, r);
        out.elems.push_back(ast::make_real(a + (b - a) * static_cast<double>(i) / static_cast<double>(n - 1), r));
        continue;
      }
      ExprPtr step = ast::make_binary(Op::Div, ast::make_binary(Op::Sub, x2->clone(), x1->clone(), r),
                                      ast::make_integer(static_cast<double>(n - 1), r), r);
      out.elems.push_back(ast::make_binary(Op::Add, x1->clone(),
                                           mul(ast::make_integer(static_cast<double>(i), r), std::move(step), r), r));
    }
    return true;
  }
  if (name == "diagonal") {
    want_args(1, 1);
    Tensor v = arg(0);
    if (v.dims.size() != 1)
      fail(DiagId::TypeMismatch, r, "diagonal() needs a vector, got size " + dims_text(v.dims));
    const int n = v.dims[0];
    element_count({n, n}, r, "diagonal()");
    out.dims = {n, n};
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        out.elems.push_back(i == j ? std::move(v.elems[i]) : ast::make_integer(0, r));
    return true;
  }
  if (name == "outerProduct") {
    want_args(2, 2);
    Tensor v = arg(0), w = arg(1);
    if (v.dims.size() != 1 || w.dims.size() != 1)
      fail(DiagId::TypeMismatch, r, "outerProduct() needs two vectors");
    element_count({v.dims[0], w.dims[0]}, r, "outerProduct()");
    out.dims = {v.dims[0], w.dims[0]};
    for (int i = 0; i < v.dims[0]; ++i)
      for (int j = 0; j < w.dims[0]; ++j)
        out.elems.push_back(mul(v.elems[i]->clone(), w.elems[j]->clone(), r));
    return true;
  }
  if (name == "matrix") {
    want_args(1, 1);
    Tensor a = promote(arg(0), 2);
    for (std::size_t i = 2; i < a.dims.size(); ++i)
      if (a.dims[i] != 1)
        fail(DiagId::TypeMismatch, r, "matrix() of an array of size " + dims_text(a.dims));
    a.dims.resize(2);
    out = std::move(a);
    return true;
  }
  if (name == "ndims") {
    want_args(1, 1);
    out = Tensor::scalar(ast::make_integer(static_cast<double>(arg(0).dims.size()), r));
    return true;
  }
  if (name == "skew") {
    want_args(1, 1);
    Tensor x = arg(0);
    if (x.dims != std::vector<int>{3})
      fail(DiagId::TypeMismatch, r, "skew() needs a vector of size 3");
    auto at = [&](int i) { return x.elems[i]->clone(); };
    auto neg = [&](int i) { return ast::make_unary(Op::Neg, at(i), r); };
    out.dims = {3, 3};
    out.elems.push_back(ast::make_integer(0, r));
    out.elems.push_back(neg(2));
    out.elems.push_back(at(1));
    out.elems.push_back(at(2));
    out.elems.push_back(ast::make_integer(0, r));
    out.elems.push_back(neg(0));
    out.elems.push_back(neg(1));
    out.elems.push_back(at(0));
    out.elems.push_back(ast::make_integer(0, r));
    return true;
  }
  if (name == "symmetric") {
    want_args(1, 1);
    Tensor a = arg(0);
    if (a.dims.size() != 2 || a.dims[0] != a.dims[1])
      fail(DiagId::TypeMismatch, r, "symmetric() needs a square matrix");
    const int n = a.dims[0];
    out.dims = a.dims;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        out.elems.push_back(a.elems[i <= j ? i * n + j : j * n + i]->clone());
    return true;
  }
  return false;
}

} // namespace mo::frontend::detail
