// The tables of the MSL's ModelicaStandardTables library, which mocompile
// provides itself: a call of one of its C functions with an external object
// (flatten_external_objects.cpp) becomes an expression of the object's
// table, so that the symbolic stages differentiate it like any other
// (sensitivities to table entries included) and nothing external is linked:
//
// - CombiTimeTable: the value (`_getValue`) is a balanced tree of
//   noEvent(x < key) over the rows, in the row's segment constant or linear,
//   outside the table held, continued through the last two points, or
//   periodic; `_nextTimeEvent` is the next row time that is a time event
//   (each row for constant segments, a repeated time for linear ones, the
//   table's end). As in the C library, between the instant the integrator
//   reaches that time and the table block's when-clause updating it (that
//   is, while t >= nextTimeEvent = pre(nextTimeEvent)), the value is the one
//   from the left, so that the step up to a jump is smooth.
// - CombiTable1D: the same tree in the input u, continued linearly outside.
// - CombiTable2D: bilinear, continued linearly outside.
//
// Akima splines (smoothness = ContinuousDerivative) in 1-D and time tables
// follow the C library's coefficients; 2-D splines are not provided.
#include "external_object.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <optional>
#include <functional>
#include <limits>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;
using ast::Op;


namespace {

constexpr double kNoEvent = std::numeric_limits<double>::max(); // DBL_MAX: no further time event

ExprPtr num(double v) { return ast::make_real(v); }
ExprPtr bin(Op op, ExprPtr a, ExprPtr b) { return ast::make_binary(op, std::move(a), std::move(b)); }
ExprPtr no_event(ExprPtr e) { return ast::make_call1("noEvent", std::move(e)); }
ExprPtr if_then(ExprPtr c, ExprPtr a, ExprPtr b) {
  auto e = std::make_unique<Expr>(ExprKind::If);
  e->args.push_back(std::move(c));
  e->args.push_back(std::move(a));
  e->args.push_back(std::move(b));
  return e;
}
/// noEvent(x < k), or noEvent(x <= k) for the limit from the left.
ExprPtr below(const Expr &x, double k, bool left) { return no_event(bin(left ? Op::Le : Op::Lt, x.clone(), num(k))); }

/// The line through rows (r0, key0) and (r1, key1) of column `c` at x.
ExprPtr line(const Flattener::ExternalObject &t, const std::vector<double> &key, int r0, int r1, int c,
             const Expr &x) {
  if (key[r1] == key[r0])
    return t.at(r1, c);
  ExprPtr slope = bin(Op::Div, bin(Op::Sub, t.at(r1, c), t.at(r0, c)), num(key[r1] - key[r0]));
  return bin(Op::Add, t.at(r0, c), bin(Op::Mul, std::move(slope), bin(Op::Sub, x.clone(), num(key[r0]))));
}

/// Akima's spline through column c (Akima 1970, as the C library computes
/// it: divided differences continued by two on each side, a node's slope
/// the weighted mean of its neighbours' differences): per segment i, y =
/// y_i + ((c0 s + c1) s + c2) s with s = x - key_i. Expressions of the
/// table's entries, so sensitivities to them follow.
struct Akima {
  std::vector<std::array<ExprPtr, 3>> c;
  /// The slope at the last key (for continuing the spline beyond it).
  ExprPtr end_slope(const Flattener::ExternalObject &t) const {
    const std::size_t i = c.size() - 1;
    const double dx = t.key[i + 1] - t.key[i];
    ExprPtr cubic = bin(Op::Mul, bin(Op::Add, bin(Op::Mul, num(3 * dx), c[i][0]->clone()),
                                     bin(Op::Mul, num(2.0), c[i][1]->clone())),
                        num(dx));
    return bin(Op::Add, std::move(cubic), c[i][2]->clone());
  }
};

Akima akima(const Flattener::ExternalObject &t, int col) {
  const int n = t.rows; // >= 3
  std::vector<ExprPtr> d(static_cast<std::size_t>(n + 3));
  auto D = [&](int i) { return d[static_cast<std::size_t>(i)]->clone(); };
  for (int i = 0; i < n - 1; ++i)
    d[static_cast<std::size_t>(i + 2)] =
        bin(Op::Div, bin(Op::Sub, t.at(i + 1, col), t.at(i, col)), num(t.key[i + 1] - t.key[i]));
  auto combine = [&](double a, int i, double b, int j) {
    return bin(Op::Sub, bin(Op::Mul, num(a), D(i)), bin(Op::Mul, num(b), D(j)));
  };
  d[0] = combine(3, 2, 2, 3);
  d[1] = combine(2, 2, 1, 3);
  d[static_cast<std::size_t>(n + 1)] = combine(2, n, 1, n - 1);
  d[static_cast<std::size_t>(n + 2)] = combine(3, n, 2, n - 1);
  // The slope at key i: weights |d[i+3] - d[i+2]| and |d[i+1] - d[i]|.
  auto slope = [&](int i) {
    auto w = [&](int a, int b) { return ast::make_call1("abs", bin(Op::Sub, D(a), D(b))); };
    ExprPtr total = bin(Op::Add, w(i + 3, i + 2), w(i + 1, i));
    ExprPtr weighted = bin(Op::Div, bin(Op::Add, bin(Op::Mul, w(i + 3, i + 2), D(i + 1)), bin(Op::Mul, w(i + 1, i), D(i + 2))),
                           total->clone());
    ExprPtr mean = bin(Op::Mul, num(0.5), bin(Op::Add, D(i + 1), D(i + 2)));
    return if_then(no_event(bin(Op::Gt, std::move(total), num(0.0))), std::move(weighted), std::move(mean));
  };
  Akima out;
  for (int i = 0; i < n - 1; ++i) {
    const double dx = t.key[i + 1] - t.key[i];
    ExprPtr c2 = slope(i), next = slope(i + 1);
    ExprPtr c1 = bin(Op::Div,
                     bin(Op::Sub, bin(Op::Sub, bin(Op::Mul, num(3.0), D(i + 2)), bin(Op::Mul, num(2.0), c2->clone())),
                         next->clone()),
                     num(dx));
    ExprPtr c0 = bin(Op::Div, bin(Op::Sub, bin(Op::Add, c2->clone(), std::move(next)), bin(Op::Mul, num(2.0), D(i + 2))),
                     num(dx * dx));
    out.c.push_back({std::move(c0), std::move(c1), std::move(c2)});
  }
  return out;
}

/// Segment i of column c at x: constant, linear or the spline's cubic.
ExprPtr segment(const Flattener::ExternalObject &t, int c, int i, const Expr &x, const Akima *spline) {
  if (t.smoothness == 3)
    return t.at(i, c);
  if (!spline)
    return line(t, t.key, i, i + 1, c, x);
  const auto &k = spline->c[static_cast<std::size_t>(i)];
  ExprPtr s = bin(Op::Sub, x.clone(), num(t.key[i]));
  ExprPtr poly = bin(Op::Add, bin(Op::Mul, k[0]->clone(), s->clone()), k[1]->clone());
  poly = bin(Op::Add, bin(Op::Mul, std::move(poly), s->clone()), k[2]->clone());
  return bin(Op::Add, t.at(i, c), bin(Op::Mul, std::move(poly), std::move(s)));
}

/// Rows' values along `key` (1-D and time tables): segments lo..hi-1 as a
/// balanced tree; segment i is [key_i, key_i+1) (left: (key_i, key_i+1]).
ExprPtr segments(const Flattener::ExternalObject &t, int c, const Expr &x, bool left, int lo, int hi,
                 const Akima *spline) {
  if (hi - lo == 1)
    return segment(t, c, lo, x, spline);
  const int mid = (lo + hi) / 2;
  return if_then(below(x, t.key[mid], left), segments(t, c, x, left, lo, mid, spline),
                 segments(t, c, x, left, mid, hi, spline));
}

/// Column c of a 1-D or time table at x, with its extrapolation (periodic
/// tables: x already mapped into the period).
ExprPtr column_at(const Flattener::ExternalObject &t, int c, const Expr &x, bool left, int extrapolation) {
  const int n = t.rows;
  if (n == 1)
    return t.at(0, c);
  std::optional<Akima> spline;
  if (t.smoothness == 2)
    spline = akima(t, c);
  ExprPtr inside = segments(t, c, x, left, 0, n - 1, spline ? &*spline : nullptr);
  ExprPtr before, after;
  if (extrapolation == 2 && spline) { // the spline continued with its end slopes
    ExprPtr from_first = bin(Op::Sub, x.clone(), num(t.key[0])), from_last = bin(Op::Sub, x.clone(), num(t.key[n - 1]));
    before = bin(Op::Add, t.at(0, c), bin(Op::Mul, spline->c.front()[2]->clone(), std::move(from_first)));
    after = bin(Op::Add, t.at(n - 1, c), bin(Op::Mul, spline->end_slope(t), std::move(from_last)));
  } else if (extrapolation == 2) { // through the last two points
    before = line(t, t.key, 0, 1, c, x);
    after = line(t, t.key, n - 2, n - 1, c, x);
  } else {
    before = t.at(0, c);
    after = t.at(n - 1, c);
  }
  // At the last key itself the table's own value (from the left: the
  // segment before it).
  ExprPtr beyond = left ? no_event(bin(Op::Gt, x.clone(), num(t.key[n - 1])))
                        : no_event(bin(Op::Ge, x.clone(), num(t.key[n - 1])));
  return if_then(below(x, t.key[0], left), std::move(before),
                 if_then(std::move(beyond), std::move(after), std::move(inside)));
}

/// x mapped into one period [k0, kn) (left: (k0, kn]).
ExprPtr periodic(const Flattener::ExternalObject &t, const Expr &x, bool left) {
  const double k0 = t.key.front(), period = t.key.back() - k0;
  ExprPtr cycles = ast::make_call1(left ? "ceil" : "floor", bin(Op::Div, bin(Op::Sub, x.clone(), num(k0)), num(period)));
  ExprPtr shifted = bin(Op::Sub, x.clone(), bin(Op::Mul, num(period), no_event(std::move(cycles))));
  return left ? bin(Op::Add, std::move(shifted), num(period)) : std::move(shifted);
}

/// A time table's column c at shifted time s (0 before the start time).
ExprPtr time_value(const Flattener::ExternalObject &t, int c, const Expr &s, bool left) {
  ExprPtr value;
  if (t.extrapolation == 3 && t.rows > 1) {
    ExprPtr p = periodic(t, s, left);
    value = column_at(t, c, *p, left, 1);
  } else {
    value = column_at(t, c, s, left, t.extrapolation);
  }
  return if_then(below(s, 0.0, left), num(0.0), std::move(value));
}

/// The time events of one pass through the table after its first key:
/// each new row time (constant segments) or each repeated one (a jump of
/// linear segments), then the last key.
std::vector<double> event_keys(const Flattener::ExternalObject &t) {
  std::vector<double> out;
  const int n = t.rows;
  for (int i = 1; i < n - 1; ++i) {
    const bool event = t.smoothness == 3 ? t.key[i] > t.key[i - 1] : t.key[i] == t.key[i + 1];
    if (event && (out.empty() || t.key[i] > out.back()) && t.key[i] < t.key[n - 1])
      out.push_back(t.key[i]);
  }
  out.push_back(t.key[n - 1]);
  return out;
}

/// The first of `keys` after x (a chain: the events are few).
ExprPtr next_key(const std::vector<double> &keys, const Expr &x, ExprPtr otherwise) {
  ExprPtr e = std::move(otherwise);
  for (std::size_t i = keys.size(); i-- > 0;)
    e = if_then(below(x, keys[i], false), num(keys[i]), std::move(e));
  return e;
}


/// A time table's column c at time `time`. With the block's next time event
/// and its pre() (the MSL's CombiTimeTable passes both): once time reaches
/// that event and the block's when-clause has not moved it yet, the value
/// from the left of it.
ExprPtr time_table_value(const Flattener::ExternalObject &t, int c, const Expr &time, const Expr *next,
                         const Expr *pre_next) {
  ExprPtr s_now = bin(Op::Sub, time.clone(), num(t.start_time));
  ExprPtr now = time_value(t, c, *s_now, false);
  if (!next || !pre_next)
    return now;
  ExprPtr s_next = bin(Op::Sub, next->clone(), num(t.start_time));
  ExprPtr pending = bin(Op::And, bin(Op::Le, next->clone(), pre_next->clone()), bin(Op::Lt, next->clone(), num(kNoEvent)));
  ExprPtr reached = no_event(bin(Op::And, bin(Op::Ge, time.clone(), next->clone()), std::move(pending)));
  return if_then(std::move(reached), time_value(t, c, *s_next, true), std::move(now));
}

/// The time event of a time table after `time`: its start time, its first
/// row, its events (event_keys), period after period if periodic; DBL_MAX
/// when none is left.
ExprPtr time_table_next_event(const Flattener::ExternalObject &t, const Expr &time) {
  ExprPtr s_now = bin(Op::Sub, time.clone(), num(t.start_time));
  ExprPtr next;
  if (t.rows == 1) {
    next = num(kNoEvent);
  } else if (t.extrapolation == 3) {
    const double k0 = t.key.front(), period = t.key.back() - k0;
    ExprPtr cycles = no_event(ast::make_call1("floor", bin(Op::Div, bin(Op::Sub, s_now->clone(), num(k0)), num(period))));
    ExprPtr offset = bin(Op::Mul, num(period), std::move(cycles));
    ExprPtr within = bin(Op::Sub, s_now->clone(), offset->clone());
    next = bin(Op::Add, std::move(offset), next_key(event_keys(t), *within, num(t.key.back())));
    next = bin(Op::Add, std::move(next), num(t.start_time));
  } else {
    std::vector<double> keys{t.key.front()};
    for (double k : event_keys(t))
      keys.push_back(k);
    for (double &k : keys)
      k += t.start_time;
    next = next_key(keys, time, num(kNoEvent));
  }
  return if_then(below(*s_now, 0.0, false), num(t.start_time), std::move(next));
}

/// A 2-D table at (u1, u2): bilinear in the cell of (u1, u2), found by a
/// balanced tree on each key; outside, the border cells continued.
ExprPtr bilinear(const Flattener::ExternalObject &t, const Expr &u1, const Expr &u2) {
  const int n1 = static_cast<int>(t.key.size()), n2 = static_cast<int>(t.key2.size());
  auto cell = [&](int i, int j) {
    auto y = [&](int a, int b) { return t.at(a + 1, b + 1); };
    auto w = [](const Expr &u, double lo, double hi) { return bin(Op::Div, bin(Op::Sub, u.clone(), num(lo)), num(hi - lo)); };
    ExprPtr a = w(u1, t.key[i], t.key[i + 1]), b = w(u2, t.key2[j], t.key2[j + 1]);
    // y00 + a (y10 - y00) + b (y01 - y00) + a b (y11 - y10 - y01 + y00)
    ExprPtr e = y(i, j);
    e = bin(Op::Add, std::move(e), bin(Op::Mul, a->clone(), bin(Op::Sub, y(i + 1, j), y(i, j))));
    e = bin(Op::Add, std::move(e), bin(Op::Mul, b->clone(), bin(Op::Sub, y(i, j + 1), y(i, j))));
    ExprPtr twist = bin(Op::Add, bin(Op::Sub, bin(Op::Sub, y(i + 1, j + 1), y(i + 1, j)), y(i, j + 1)), y(i, j));
    return bin(Op::Add, std::move(e), bin(Op::Mul, bin(Op::Mul, std::move(a), std::move(b)), std::move(twist)));
  };
  std::function<ExprPtr(int, int, int)> over_u2 = [&](int i, int lo, int hi) -> ExprPtr {
    if (hi - lo == 1)
      return cell(i, lo);
    const int mid = (lo + hi) / 2;
    return if_then(below(u2, t.key2[mid], false), over_u2(i, lo, mid), over_u2(i, mid, hi));
  };
  std::function<ExprPtr(int, int)> over_u1 = [&](int lo, int hi) -> ExprPtr {
    if (hi - lo == 1)
      return over_u2(lo, 0, n2 - 1);
    const int mid = (lo + hi) / 2;
    return if_then(below(u1, t.key[mid], false), over_u1(lo, mid), over_u1(mid, hi));
  };
  return over_u1(0, n1 - 1);
}

} // namespace

bool Flattener::provided_external(const std::string &c_name, const std::vector<const Expr *> &args,
                                  const Expr &call, const Scope &s, Tensor &out) {
  static const std::string kPrefix = "ModelicaStandardTables_";
  if (c_name.rfind(kPrefix, 0) != 0)
    return false;
  const std::string fn = c_name.substr(kPrefix.size());
  auto arg = [&](std::size_t i) -> const Expr & {
    if (i >= args.size() || !args[i])
      fail(DiagId::WrongArgumentCount, call.range, fmt::format("'{}' needs argument {}", c_name, i + 1));
    return *args[i];
  };
  auto value = [&](std::size_t i) { return scalar_expr(arg(i), s); };
  auto column = [&](const ExternalObject &t) {
    const double i = eval(*value(1), arg(1).range);
    if (i < 1 || i > static_cast<double>(t.columns.size()) || i != std::floor(i))
      fail(DiagId::BadSubscript, arg(1).range,
           fmt::format("output {} of table '{}' is not among its {} columns", i, t.name, t.columns.size()));
    return t.columns[static_cast<std::size_t>(i) - 1] - 1;
  };
  using Kind = ExternalObject::Kind;
  auto object = [&](Kind kind) {
    std::shared_ptr<ExternalObject> t = external_object(arg(0), s);
    if (t->kind != kind)
      fail(DiagId::TypeMismatch, arg(0).range, "'" + t->name + "' is another kind of table than '" + c_name + "' reads");
    return t;
  };
  if (fn == "CombiTimeTable_read" || fn == "CombiTable1D_read" || fn == "CombiTable2D_read") {
    out = Tensor::scalar(num(1.0)); // read when flattened
    return true;
  }
  if (fn == "CombiTimeTable_minimumTime" || fn == "CombiTimeTable_maximumTime") {
    auto t = object(Kind::TimeTable);
    out = Tensor::scalar(num(fn == "CombiTimeTable_minimumTime" ? t->key.front() : t->key.back()));
    return true;
  }
  if (fn == "CombiTimeTable_getValue") {
    auto t = object(Kind::TimeTable);
    const int c = column(*t);
    ExprPtr time = value(2);
    const bool with_events = args.size() >= 5 && args[3] && args[4];
    ExprPtr next = with_events ? value(3) : nullptr, pre_next = with_events ? value(4) : nullptr;
    out = Tensor::scalar(time_table_value(*t, c, *time, next.get(), pre_next.get()));
    return true;
  }
  if (fn == "CombiTimeTable_nextTimeEvent") {
    auto t = object(Kind::TimeTable);
    out = Tensor::scalar(time_table_next_event(*t, *value(1)));
    return true;
  }
  if (fn == "CombiTable1D_getValue") {
    auto t = object(Kind::Table1D);
    const int c = column(*t);
    out = Tensor::scalar(column_at(*t, c, *value(2), false, 2));
    return true;
  }
  if (fn == "CombiTable2D_getValue") {
    auto t = object(Kind::Table2D);
    if (t->key.size() == 1 || t->key2.size() == 1)
      fail(DiagId::Unsupported, call.range,
           "2-D table '" + t->name + "' needs at least two rows and two columns of values");
    out = Tensor::scalar(bilinear(*t, *value(1), *value(2)));
    return true;
  }
  return false; // another function of the library: reported by the caller
}

} // namespace mo::frontend::detail
