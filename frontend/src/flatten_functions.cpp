// Calls of user-defined functions, inlined into the caller's expressions.
//
// The function's algorithm is executed symbolically on the arguments'
// flattened expressions: each assignment replaces the expression bound to
// its target, an `if` whose condition is known (numbers only, or parameters
// whose values already sized an array or chose a branch) picks its branch and
// one that depends on variables merges both branches into if-expressions, a
// `for` over a constant range is unrolled and a `while` runs while its
// condition evaluates to a constant. What cannot be turned into expressions
// (`when`, `return`/`break` under a condition that varies, `error(...)` and
// other statements with effects, external "C" functions, a `while`
// whose condition varies) is, when every argument is a parameter expression,
// run again on the arguments' values (a root search in a parameter binding),
// with a warning that the result no longer follows those parameters;
// otherwise it gets a diagnostic.
// `external "builtin"` functions are the built-ins they name. A record
// input, output or local is a record value (flatten_records.cpp): its fields
// are read and assigned through designate().
#include "flattener.hpp"
#include "mo/frontend/printer.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <set>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::Op;
using ast::ExprPtr;
using ast::Statement;
using ast::StatementKind;

const Expr &without_no_event(const Expr &e) {
  const Expr *x = &e;
  while (x->kind == ExprKind::Call && x->args.size() == 1 && x->ref.is_simple() && x->ref.parts[0].name == "noEvent")
    x = x->args[0].get();
  return *x;
}

namespace {

constexpr unsigned kMaxCallDepth = 64;
constexpr long kMaxWhileIterations = 100'000;
/// Varying conditions met on one way through a function's algorithm.
constexpr std::size_t kMaxDecisions = 128;

bool is_literal(const Expr &e) {
  return e.kind == ExprKind::Real || e.kind == ExprKind::Integer || e.kind == ExprKind::Boolean;
}

/// A call of a pure built-in that Flattener::eval computes (sqrt, abs, ...).
bool foldable_builtin(const Expr &call) {
  static const std::set<std::string> names{"sin",   "cos",  "tan",   "asin", "acos",  "atan",    "sinh", "cosh",
                                           "tanh",  "exp",  "log",   "log10", "sqrt", "abs",     "floor", "ceil",
                                           "integer", "sign", "noEvent", "atan2", "min", "max",    "div",  "mod",
                                           "rem",   "smooth"};
  return call.var < 0 && call.ref.parts.size() == 1 && names.count(call.ref.parts[0].name) > 0;
}

/// True when `e` is built from literals only (no variable, no parameter, no
/// operator on time such as pre or der): it can be folded without fixing the
/// value of anything a user may change.
bool literals_only(const Expr &e) {
  std::vector<const Expr *> work{&e};
  while (!work.empty()) {
    const Expr *x = work.back();
    work.pop_back();
    switch (x->kind) {
    case ExprKind::Real:
    case ExprKind::Integer:
    case ExprKind::Boolean:
      break;
    case ExprKind::Unary:
    case ExprKind::Binary:
    case ExprKind::If:
      for (const auto &a : x->args)
        work.push_back(a.get());
      break;
    case ExprKind::Call:
      if (!foldable_builtin(*x))
        return false;
      for (const auto &a : x->args)
        work.push_back(a.get());
      break;
    case ExprKind::Ref:
    case ExprKind::String:
    case ExprKind::Array:
    case ExprKind::Matrix:
    case ExprKind::Range:
    case ExprKind::Tuple:
    case ExprKind::Colon:
    case ExprKind::End:
      return false;
    }
  }
  return true;
}

/// True if `e`, numbers only, is an Integer: Integer literals joined by
/// + - * and signs, integer(), and min, max, abs, sign, div, mod, rem of
/// Integers (the branches of an if-expression likewise).
bool integer_valued(const Expr &e) {
  static const std::set<std::string> keep_integers{"min", "max", "abs", "sign", "div", "mod", "rem"};
  std::vector<const Expr *> work{&e};
  while (!work.empty()) {
    const Expr *x = work.back();
    work.pop_back();
    switch (x->kind) {
    case ExprKind::Integer:
      break;
    case ExprKind::Unary:
    case ExprKind::Binary:
      if (x->op != Op::Add && x->op != Op::Sub && x->op != Op::Mul && x->op != Op::Neg && x->op != Op::Plus)
        return false;
      for (const auto &a : x->args)
        work.push_back(a.get());
      break;
    case ExprKind::If:
      for (std::size_t i = 1; i < x->args.size(); i += 2)
        work.push_back(x->args[i].get());
      work.push_back(x->args.back().get());
      break;
    case ExprKind::Call:
      if (x->var >= 0 || x->ref.parts.size() != 1)
        return false;
      if (x->ref.parts[0].name == "integer")
        break;
      if (!keep_integers.count(x->ref.parts[0].name))
        return false;
      for (const auto &a : x->args)
        work.push_back(a.get());
      break;
    default:
      return false;
    }
  }
  return true;
}

} // namespace

bool too_large_value(const Expr &e, std::size_t max_nodes) {
  std::vector<std::pair<const Expr *, std::size_t>> work{{&e, 1}};
  std::size_t nodes = 0;
  while (!work.empty()) {
    auto [x, depth] = work.back();
    work.pop_back();
    if (++nodes > max_nodes || depth > kMaxValueDepth)
      return true;
    for (const auto &a : x->args)
      if (a)
        work.emplace_back(a.get(), depth + 1);
  }
  return false;
}

/// The elements and algorithms of a function, bases first.
struct Signature {
  std::vector<std::pair<const ast::Component *, ClassNode *>> inputs, outputs, locals;
  std::vector<std::pair<const std::vector<Statement> *, ClassNode *>> algorithms;
};

namespace {

void collect(Flattener &f, ClassNode *cls, Signature &sig, unsigned depth) {
  if (!cls || !cls->def || depth > 32)
    return;
  for (auto &[ext, base] : f.bases(cls))
    collect(f, base, sig, depth + 1);
  for (const auto &c : cls->def->components) {
    // An element declared again as its base declares it (MixtureGasNasa's
    // `redeclare function extends velocityOfSound` with its own `input
    // ThermodynamicState state`) is one element (MLS 7.3).
    const auto declared = [&](const auto &list) {
      return std::any_of(list.begin(), list.end(), [&](const auto &e) { return e.first->name == c.name; });
    };
    if (declared(sig.inputs) || declared(sig.outputs) || declared(sig.locals))
      continue;
    auto &list = c.causality == ast::Causality::Input    ? sig.inputs
                 : c.causality == ast::Causality::Output ? sig.outputs
                                                         : sig.locals;
    list.emplace_back(&c, cls);
  }
  if (!cls->def->algorithm.empty())
    sig.algorithms.emplace_back(&cls->def->algorithm, cls);
}

/// Row-major flat indices of the elements of `t` that `subs` select, in
/// scope `s`; `out_dims` gets the dimensions of the selection (a scalar
/// subscript drops its dimension).
std::vector<std::size_t> selection(Flattener &f, const std::vector<ExprPtr> &subs, const Tensor &t,
                                   const std::string &name, const Scope &s, SourceRange where,
                                   std::vector<int> &out_dims) {
  if (subs.size() != t.dims.size())
    f.fail(DiagId::BadSubscript, where,
           fmt::format("'{}' has {} dimension(s) but {} subscript(s) are given", name, t.dims.size(),
                       subs.size()));
  std::vector<std::vector<int>> p(subs.size());
  for (std::size_t i = 0; i < subs.size(); ++i) {
    if (subs[i]->kind == ExprKind::Colon) {
      for (int k = 1; k <= t.dims[i]; ++k)
        p[i].push_back(k);
      out_dims.push_back(t.dims[i]);
      continue;
    }
    LoopEnv env = s.env ? *s.env : LoopEnv{};
    env.values.emplace_back("end", t.dims[i]);
    Scope sub = s;
    sub.env = &env;
    Tensor picked = f.expr(*subs[i], sub);
    for (auto &e : picked.elems) {
      double v = f.eval(*e, subs[i]->range);
      if (v != static_cast<int>(v) || v < 1 || v > t.dims[i])
        f.fail(DiagId::BadSubscript, subs[i]->range,
               fmt::format("subscript {} is out of bounds 1..{} of '{}'", v, t.dims[i], name));
      p[i].push_back(static_cast<int>(v));
    }
    if (!picked.is_scalar())
      out_dims.push_back(static_cast<int>(picked.elems.size()));
  }
  std::vector<std::size_t> out;
  for (const auto &v : p)
    if (v.empty())
      return out;
  std::vector<std::size_t> pos(p.size(), 0);
  while (true) {
    std::size_t flat = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      flat = flat * static_cast<std::size_t>(t.dims[i]) + static_cast<std::size_t>(p[i][pos[i]] - 1);
    out.push_back(flat);
    std::size_t i = p.size();
    while (i-- > 0) {
      if (++pos[i] < p[i].size())
        break;
      pos[i] = 0;
    }
    if (i == static_cast<std::size_t>(-1))
      break;
  }
  return out;
}

/// True if `e` is a Boolean by its top operation (a literal, a relation,
/// and/or/not), through noEvent().
bool is_boolean_valued(const Expr &e0) {
  const Expr &e = without_no_event(e0);
  if (e.kind == ExprKind::Boolean)
    return true;
  if (e.kind == ExprKind::Unary)
    return e.op == Op::Not;
  if (e.kind != ExprKind::Binary)
    return false;
  switch (e.op) {
  case Op::Lt: case Op::Le: case Op::Gt: case Op::Ge: case Op::Eq: case Op::Ne: case Op::And: case Op::Or:
    return true;
  case Op::Add: case Op::Sub: case Op::Mul: case Op::Div: case Op::Pow: case Op::ElemAdd: case Op::ElemSub:
  case Op::ElemMul: case Op::ElemDiv: case Op::ElemPow: case Op::Neg: case Op::Plus: case Op::Not:
    return false;
  }
  return false;
}

/// A statement the symbolic inliner cannot express; call_function reports it
/// (or retries with the arguments' values, see there).
struct InlineUnsupported {
  SourceRange range;
  std::string what;
};

/// A condition that varies where the algorithm must take one way only (a
/// `while`, an `if` around `return`/`break`/`while`): the run stops, and
/// inline_call runs the algorithm again once per outcome (see Decisions).
struct NeedDecision {
  ExprPtr condition;
};

/// The outcomes taken so far at the varying conditions of one run, in the
/// order they are met; a run that meets one more throws NeedDecision.
struct Decisions {
  std::vector<bool> taken;
  std::size_t next = 0;
  /// The outcome on this path of each condition met so far, by its text: a
  /// condition met again (a loop's test after the `if` that guards the loop)
  /// is not a new decision, and the ways it rules out are never run.
  std::map<std::string, bool> known;
  /// Closed bounds [lo, hi] on this path of varying values (by their text)
  /// that relations and subscripts have shown: a subscript is within its
  /// dimension, `i < n` decided true bounds i by n. A while-loop that counts
  /// a varying row up (the MSL's TimeTable: `next < nrow and t >= table[next, 1]`)
  /// so has as many ways as rows, not kMaxDecisions.
  std::map<std::string, std::pair<double, double>> bounds;
};

/// `e` as atom + offset, the atom its non-numeric part (by text), through
/// additions and subtractions of numbers; false if `e` is numbers only.
bool atom_plus_offset(Flattener &f, const Expr &e, std::string &atom, double &offset) {
  const Expr *x = &e;
  double c = 0;
  while (x->kind == ExprKind::Binary && (x->op == Op::Add || x->op == Op::Sub)) {
    const bool left_number = literals_only(*x->args[0]), right_number = literals_only(*x->args[1]);
    if (right_number && !left_number) {
      const double v = f.eval(*x->args[1], x->range);
      c += x->op == Op::Add ? v : -v;
      x = x->args[0].get();
    } else if (left_number && !right_number && x->op == Op::Add) {
      c += f.eval(*x->args[0], x->range);
      x = x->args[1].get();
    } else {
      break;
    }
  }
  if (literals_only(*x))
    return false;
  atom = print_expr(*x);
  offset = c;
  return true;
}

/// A relation `atom + c op d` (or `d op atom + c`) as (atom, op, d - c) with
/// the atom on the left; false for other expressions.
bool bound_form(Flattener &f, const Expr &c0, std::string &atom, Op &op, double &value) {
  const Expr &c = without_no_event(c0);
  if (c.kind != ExprKind::Binary || !(c.op == Op::Lt || c.op == Op::Le || c.op == Op::Gt || c.op == Op::Ge))
    return false;
  double offset = 0;
  if (literals_only(*c.args[1]) && atom_plus_offset(f, *c.args[0], atom, offset)) {
    op = c.op;
    value = f.eval(*c.args[1], c.range) - offset;
    return true;
  }
  if (literals_only(*c.args[0]) && atom_plus_offset(f, *c.args[1], atom, offset)) {
    op = c.op == Op::Lt ? Op::Gt : c.op == Op::Le ? Op::Ge : c.op == Op::Gt ? Op::Lt : Op::Le;
    value = f.eval(*c.args[0], c.range) - offset;
    return true;
  }
  return false;
}

/// The value of relation `c` from the bounds of its atom, or -1.
int bounded_value(Flattener &f, const Expr &c, const Decisions &d) {
  std::string atom;
  Op op{};
  double v = 0;
  if (!bound_form(f, c, atom, op, v))
    return -1;
  const auto it = d.bounds.find(atom);
  if (it == d.bounds.end())
    return -1;
  const auto [lo, hi] = it->second;
  switch (op) {
  case Op::Lt: return hi < v ? 1 : lo >= v ? 0 : -1;
  case Op::Le: return hi <= v ? 1 : lo > v ? 0 : -1;
  case Op::Gt: return lo > v ? 1 : hi <= v ? 0 : -1;
  case Op::Ge: return lo >= v ? 1 : hi < v ? 0 : -1;
  default: return -1;
  }
}

/// Narrows the bounds of `atom` to [lo, hi].
void narrow(Decisions &d, const std::string &atom, double lo, double hi) {
  auto [it, fresh] = d.bounds.try_emplace(atom, lo, hi);
  if (!fresh)
    it->second = {std::max(it->second.first, lo), std::min(it->second.second, hi)};
}

/// The value of `c` from `known` outcomes and literals (folded) through and/or/not,
/// or -1 when they do not decide it; iterative over the and/or tree.
int known_value(Flattener &f, const Expr &c, const Decisions &decisions) {
  const std::map<std::string, bool> &known = decisions.known;
  // Post-order over the Boolean connectives only; other nodes are leaves.
  std::vector<std::pair<const Expr *, bool>> work{{&c, false}};
  std::map<const Expr *, int> value;
  while (!work.empty()) {
    auto [e0, expanded] = work.back();
    work.pop_back();
    const Expr *e = &without_no_event(*e0);
    const bool connective = (e->kind == ExprKind::Binary && (e->op == Op::And || e->op == Op::Or)) ||
                            (e->kind == ExprKind::Unary && e->op == Op::Not);
    if (!connective) {
      if (is_literal(*e) || literals_only(*e)) {
        value[e0] = f.eval(*e, e->range) != 0;
      } else {
        auto it = known.find(print_expr(*e));
        value[e0] = it == known.end() ? bounded_value(f, *e, decisions) : it->second;
      }
      continue;
    }
    if (!expanded) {
      work.emplace_back(e0, true);
      for (const auto &a : e->args)
        work.emplace_back(a.get(), false);
      continue;
    }
    if (e->kind == ExprKind::Unary) {
      const int a = value[e->args[0].get()];
      value[e0] = a < 0 ? -1 : 1 - a;
      continue;
    }
    const int a = value[e->args[0].get()], b = value[e->args[1].get()];
    const int absorbing = e->op == Op::And ? 0 : 1;
    if (a == absorbing || b == absorbing)
      value[e0] = absorbing;
    else if (a >= 0 && b >= 0)
      value[e0] = 1 - absorbing;
    else {
      auto it = known.find(print_expr(*e));
      value[e0] = it == known.end() ? -1 : it->second;
    }
  }
  return value[&c];
}

/// Adds to `out` the first name of each target that `body` assigns, nested
/// statements included: the locals an `if` on a varying condition can change.
void assigned_names(const std::vector<Statement> &body, std::set<std::string> &out) {
  for (const Statement &st : body) {
    for (const auto &t : st.targets)
      if (t && t->kind == ExprKind::Ref && !t->ref.parts.empty())
        out.insert(t->ref.parts[0].name);
    assigned_names(st.body, out);
    for (const auto &b : st.branches)
      assigned_names(b.body, out);
  }
}

/// True if `body` holds a `return`, a `while`, or a `break` that leaves the
/// loop enclosing `body` (not one of a loop inside it); iterative.
bool has_jump(const std::vector<Statement> &body) {
  std::vector<std::pair<const std::vector<Statement> *, bool>> work{{&body, false}}; // (list, inside a nested loop)
  while (!work.empty()) {
    auto [list, nested] = work.back();
    work.pop_back();
    for (const Statement &st : *list) {
      switch (st.kind) {
      case StatementKind::Return:
      case StatementKind::While:
        return true;
      case StatementKind::Break:
        if (!nested)
          return true;
        break;
      case StatementKind::If:
      case StatementKind::When:
        for (const auto &b : st.branches)
          work.emplace_back(&b.body, nested);
        break;
      case StatementKind::For:
        work.emplace_back(&st.body, true);
        break;
      case StatementKind::Assign:
      case StatementKind::Call:
        break;
      }
    }
  }
  return false;
}

/// Executes one function's algorithm on symbolic values; every assigned value
/// that is numbers only is folded to one, so loops that iterate to a tolerance
/// or count stay small.
class Inliner {
public:
  Inliner(Flattener &f, ClassNode *fn, Decisions &decisions)
      : f_(f), fn_(fn), decisions_(decisions), guards_at_start_(f.inline_guards_.size()) {}
  /// The guards and decisions of this run hold only in it (also when it
  /// leaves by an exception).
  ~Inliner() {
    f_.inline_guards_.resize(guards_at_start_);
    f_.decided_paths_ -= decided_ ? 1 : 0;
  }
  Inliner(const Inliner &) = delete;
  Inliner &operator=(const Inliner &) = delete;

  FunctionLocals values;

  Scope scope(ClassNode *cls) {
    Scope s;
    s.cls = cls;
    s.env = &env_;
    s.locals = &values;
    return s;
  }

  void run(const std::vector<Statement> &body, ClassNode *cls) {
    cls_ = cls;
    // Subscripts this algorithm takes at varying indices bound them (restored
    // on the way out: a NeedDecision or an error leaves by exception).
    struct Hook {
      Flattener &f;
      std::function<void(const Expr &, int)> saved;
      ~Hook() { f.on_varying_index = std::move(saved); }
    } hook{f_, std::move(f_.on_varying_index)};
    f_.on_varying_index = [this](const Expr &index, int n) {
      std::string atom;
      double offset = 0;
      if (!atom_plus_offset(f_, index, atom, offset))
        return;
      if (pending_)
        pending_->push_back({atom, 1 - offset, n - offset});
      else
        narrow(decisions_, atom, 1 - offset, n - offset);
    };
    exec(body);
  }

private:
  Flattener &f_;
  ClassNode *fn_;
  Decisions &decisions_;
  std::size_t guards_at_start_;
  bool decided_ = false; ///< this run has taken a decision (counted in Flattener::decided_paths_)
  ClassNode *cls_ = nullptr;
  LoopEnv env_;
  bool returned_ = false, broke_ = false;
  /// Bounds that the subscripts of a condition being flattened would give.
  /// A guard before them (`j <= n and x > a[j]`) may keep them from being
  /// evaluated, so they hold only where the condition is decided true and
  /// has no `or` (every part of it was evaluated).
  struct IndexBound {
    std::string atom;
    double lo, hi;
  };
  std::vector<IndexBound> *pending_ = nullptr;

  /// `c` (or `not c`) holds for the statements run while it lives (see
  /// Flattener::inline_guards_).
  struct Guard {
    std::vector<ExprPtr> &guards;
    std::size_t size;
    Guard(std::vector<ExprPtr> &g, const Expr &c, bool holds, SourceRange r) : guards(g), size(g.size()) {
      guards.push_back(holds ? c.clone() : ast::make_unary(Op::Not, c.clone(), r));
    }
    ~Guard() { guards.resize(size); }
    Guard(const Guard &) = delete;
    Guard &operator=(const Guard &) = delete;
  };

  /// condition(c), with the bounds its subscripts give in `out`.
  ExprPtr condition_with_bounds(const Expr &c, std::vector<IndexBound> &out) {
    struct Restore {
      std::vector<IndexBound> *&slot, *saved;
      ~Restore() { slot = saved; }
    } restore{pending_, pending_};
    pending_ = &out;
    return condition(c);
  }

  /// Applies `bounds` of condition `source` if it held (see pending_).
  void condition_held(const Expr &source, bool value, const std::vector<IndexBound> &bounds) {
    if (!value)
      return;
    std::vector<const Expr *> work{&source};
    while (!work.empty()) {
      const Expr *e = work.back();
      work.pop_back();
      if (e->kind == ExprKind::Binary && e->op == Op::Or)
        return;
      for (const auto &a : e->args)
        if (a)
          work.push_back(a.get());
    }
    for (const IndexBound &b : bounds)
      narrow(decisions_, b.atom, b.lo, b.hi);
  }

  [[noreturn]] void unsupported(SourceRange r, const std::string &what) { throw InlineUnsupported{r, what}; }

  /// A condition flattened with `and`/`or` short-circuited where the left
  /// side is known now: `j <= n and a[j] > x` never indexes a[n + 1].
  ExprPtr condition(const Expr &c) {
    if (c.kind != ExprKind::Binary || (c.op != Op::And && c.op != Op::Or))
      return f_.scalar_expr(c, scope(cls_));
    ExprPtr left = condition(*c.args[0]);
    if (is_literal(*left) || literals_only(*left)) {
      const bool value = f_.eval(*left, c.range) != 0;
      if (value == (c.op == Op::Or))
        return ast::make_bool(value, c.range);
      return condition(*c.args[1]);
    }
    return ast::make_binary(c.op, std::move(left), condition(*c.args[1]), c.range);
  }

  /// The outcome of varying condition `c` on this run's path (see Decisions).
  bool decide(const Expr &c) {
    const int known = known_value(f_, c, decisions_);
    if (known >= 0)
      return known != 0;
    if (decisions_.next == decisions_.taken.size()) {
      if (decisions_.next >= kMaxDecisions)
        unsupported(c.range, fmt::format("more than {} conditions that vary decide one way through the "
                                         "algorithm (a while-loop on a varying condition?)", kMaxDecisions));
      // `i < n and x >= a[i]` with i and n known: the decision is on the rest.
      const Expr *rest = &c;
      while (rest->kind == ExprKind::Binary && (rest->op == Op::And || rest->op == Op::Or)) {
        const int left = known_value(f_, *rest->args[0], decisions_);
        const int right = known_value(f_, *rest->args[1], decisions_);
        const int neutral = rest->op == Op::And ? 1 : 0;
        if (left == neutral)
          rest = rest->args[1].get();
        else if (right == neutral)
          rest = rest->args[0].get();
        else
          break;
      }
      throw NeedDecision{rest->clone()};
    }
    const bool outcome = decisions_.taken[decisions_.next++];
    learn(c, outcome);
    if (!decided_) { // this run's values hold on its path only: no intermediates (see decided_paths_)
      decided_ = true;
      ++f_.decided_paths_;
    }
    return outcome;
  }

  /// Records `c` = `outcome`, and for a relation also its complement
  /// (`a >= b` false: `a < b` true), which the other branch of the `if`
  /// around a loop tests.
  void learn(const Expr &c0, bool outcome) {
    const Expr &c = without_no_event(c0);
    decisions_.known[print_expr(c)] = outcome;
    if (c.kind != ExprKind::Binary)
      return;
    if (c.op == Op::And || c.op == Op::Or) {  // what the outcome says of each side
      const bool absorbing = c.op == Op::Or;  // true for or, false for and
      if (outcome != absorbing) {
        learn(*c.args[0], outcome);
        learn(*c.args[1], outcome);
      } else if (known_value(f_, *c.args[0], decisions_) == !absorbing) {
        learn(*c.args[1], outcome);
      } else if (known_value(f_, *c.args[1], decisions_) == !absorbing) {
        learn(*c.args[0], outcome);
      }
      return;
    }
    std::string atom;
    Op op{};
    double v = 0;
    if (bound_form(f_, c, atom, op, v)) {
      const bool upper = (op == Op::Lt || op == Op::Le) == outcome;
      constexpr double inf = std::numeric_limits<double>::infinity();
      narrow(decisions_, atom, upper ? -inf : v, upper ? v : inf);
    }
    Op complement = Op::Eq;
    switch (c.op) {
    case Op::Lt: complement = Op::Ge; break;
    case Op::Le: complement = Op::Gt; break;
    case Op::Gt: complement = Op::Le; break;
    case Op::Ge: complement = Op::Lt; break;
    case Op::Eq: complement = Op::Ne; break;
    case Op::Ne: complement = Op::Eq; break;
    case Op::Add: case Op::Sub: case Op::Mul: case Op::Div: case Op::Pow: case Op::ElemAdd: case Op::ElemSub:
    case Op::ElemMul: case Op::ElemDiv: case Op::ElemPow: case Op::And: case Op::Or: case Op::Neg:
    case Op::Plus: case Op::Not:
      return;
    }
    ExprPtr other = ast::make_binary(complement, c.args[0]->clone(), c.args[1]->clone(), c.range);
    decisions_.known[print_expr(*other)] = !outcome;
  }

  void exec(const std::vector<Statement> &body) {
    for (const Statement &st : body) {
      if (returned_ || broke_)
        return;
      exec_one(st);
    }
  }

  void exec_one(const Statement &st) {
    Scope s = scope(cls_);
    switch (st.kind) {
    case StatementKind::Assign:
      if (st.targets.size() == 1 && st.value->kind != ExprKind::Call) {
        assign(*st.targets[0], f_.expr(*st.value, s));
      } else if (st.targets.size() == 1 && !f_.lookup_function(*st.value, s)) {
        assign(*st.targets[0], f_.expr(*st.value, s)); // a built-in call
      } else {
        ClassNode *callee = f_.lookup_function(*st.value, s);
        if (!callee)
          f_.fail(DiagId::UnknownFunction, st.value->range,
                  "unknown function '" + st.value->ref.str() + "'");
        std::vector<Tensor> outs = f_.call_function(callee, *st.value, s, st.targets.size());
        for (std::size_t i = 0; i < st.targets.size() && i < outs.size(); ++i)
          if (st.targets[i])
            assign(*st.targets[i], std::move(outs[i]));
      }
      return;
    case StatementKind::Call: {
      const std::string n = st.value->ref.str();
      if (n == "assert" || n == "terminate")
        return; // checks only; the flat model keeps the caller's asserts
      if (ClassNode *callee = f_.lookup_function(*st.value, s); callee && f_.call_statement(callee, *st.value, s))
        return;
      unsupported(st.range, "the statement '" + n + "(...)' has effects other than its outputs");
    }
    case StatementKind::Break:
      broke_ = true;
      return;
    case StatementKind::Return:
      returned_ = true;
      return;
    case StatementKind::If:
      exec_if(st.branches, 0);
      return;
    case StatementKind::For:
      exec_for(st, 0);
      return;
    case StatementKind::While:
      exec_while(st);
      return;
    case StatementKind::When:
      unsupported(st.range, "'when' statements are not supported in functions");
    }
  }

  void exec_if(const std::vector<ast::StatementBranch> &branches, std::size_t i) {
    if (i == branches.size())
      return;
    const auto &b = branches[i];
    if (!b.condition) {
      exec(b.body);
      return;
    }
    std::vector<IndexBound> bounds;
    ExprPtr c = condition_with_bounds(*b.condition, bounds);
    // Parameters that already sized arrays (a filter's `order`) decide now:
    // the other branches may index past those sizes.
    if (!is_literal(*c) && (literals_only(*c) || f_.already_evaluated(*c)))
      c = ast::make_bool(f_.eval(*c, b.condition->range) != 0, b.condition->range);
    if (is_literal(*c)) {
      condition_held(*b.condition, c->number != 0, bounds);
      if (c->number != 0)
        exec(b.body);
      else
        exec_if(branches, i + 1);
      return;
    }
    // The condition varies. Around a return, break or while the algorithm
    // takes one way per run (the result is an if-expression over the runs);
    // otherwise both ways run here and merge into if-expressions.
    bool jumps = false;
    for (std::size_t k = i; k < branches.size(); ++k)
      jumps = jumps || has_jump(branches[k].body);
    if (jumps) {
      const bool held = decide(*c);
      condition_held(*b.condition, held, bounds);
      if (held)
        exec(b.body);
      else
        exec_if(branches, i + 1);
      return;
    }
    // Only the locals the branches assign can differ between them: those are
    // copied before the first branch and merged after the last (copying and
    // comparing all of them, device records included, took minutes on
    // Spice3's larger circuits).
    std::set<std::string> assigned;
    for (std::size_t k = i; k < branches.size(); ++k)
      assigned_names(branches[k].body, assigned);
    FunctionLocals before;
    for (const std::string &name : assigned)
      if (auto it = values.find(name); it != values.end())
        before.emplace(name, clone_tensor(it->second));
    const auto bounds_before = decisions_.bounds; // facts in a branch hold only there
    {
      Guard g(f_.inline_guards_, *c, true, b.range);
      exec(b.body);
    }
    decisions_.bounds = bounds_before;
    if (returned_ || broke_)
      unsupported(b.range, "'return' or 'break' under a condition that varies in time");
    FunctionLocals then_values;
    for (auto &[name, t] : before) {
      Tensor &now = values.at(name);
      then_values.emplace(name, std::move(now));
      now = std::move(t);
    }
    {
      Guard g(f_.inline_guards_, *c, false, b.range);
      exec_if(branches, i + 1);
    }
    decisions_.bounds = bounds_before;
    if (returned_ || broke_)
      unsupported(b.range, "'return' or 'break' under a condition that varies in time");
    for (auto &[name, a] : then_values) {
      Tensor &t = values.at(name);
      if (a.dims != t.dims)
        unsupported(b.range, "'" + name + "' gets arrays of different sizes in the branches of an if");
      for (std::size_t k = 0; k < t.elems.size(); ++k) {
        if (!a.elems[k])
          continue;
        if (!t.elems[k] || ast::same_expr(*a.elems[k], *t.elems[k])) {
          t.elems[k] = std::move(a.elems[k]);
          continue;
        }
        auto n = std::make_unique<Expr>(ExprKind::If, b.range);
        n->args.push_back(c->clone());
        n->args.push_back(std::move(a.elems[k]));
        n->args.push_back(std::move(t.elems[k]));
        t.elems[k] = f_.intermediate(std::move(n), fn_, name, b.range);
      }
    }
  }

  void exec_for(const Statement &st, std::size_t index) {
    if (index == st.indices.size()) {
      f_.count_statement_loop_run(st.range);
      exec(st.body);
      return;
    }
    const ast::ForIndex &fi = st.indices[index];
    if (!fi.range)
      unsupported(fi.loc, "a for-loop without a range");
    std::vector<double> range = f_.eval_range(*fi.range, scope(cls_));
    for (double v : range) {
      env_.values.emplace_back(fi.name, v);
      exec_for(st, index + 1);
      env_.values.pop_back();
      if (returned_)
        return;
      if (broke_) {
        broke_ = false;
        return;
      }
    }
  }

  void exec_while(const Statement &st) {
    for (long n = 0;; ++n) {
      if (n > kMaxWhileIterations)
        unsupported(st.range, "the while-loop runs more than 100000 times");
      f_.count_statement_loop_run(st.range);
      std::vector<IndexBound> bounds;
      ExprPtr c = condition_with_bounds(*st.value, bounds);
      if (!is_literal(*c) && f_.is_constant(*c)) // parameters: their values now
        c = ast::make_bool(f_.eval(*c, st.value->range) != 0, st.value->range);
      const bool held = is_literal(*c) ? c->number != 0 : decide(*c);
      condition_held(*st.value, held, bounds);
      if (!held)
        return;
      exec(st.body);
      if (returned_)
        return;
      if (broke_) {
        broke_ = false;
        return;
      }
    }
  }

private:
  void assign(const Expr &target, Tensor value) {
    f_.fold_numbers(value);
    for (auto &e : value.elems)
      e = f_.intermediate(std::move(e), fn_, target.ref.str(), target.range);
    for (const auto &e : value.elems)
      if (e && too_large_value(*e, f_.max_value_nodes()))
        unsupported(target.range, fmt::format("the value assigned to '{}' grows beyond {} levels or {} terms "
                                              "(a loop that accumulates an expression?)",
                                              target.ref.str(), kMaxValueDepth, f_.max_value_nodes()));
    if (target.kind != ExprKind::Ref || target.ref.global)
      unsupported(target.range, "only a local variable, an element or a field of one can be assigned");
    const std::string &name = target.ref.parts[0].name;
    auto it = values.find(name);
    if (it == values.end())
      f_.fail(DiagId::UnknownComponent, target.range,
              "'" + name + "' is not an output or local variable of function '" + fn_->path() + "'");
    Tensor &slot = it->second;
    if (target.ref.is_simple() && !slot.record && !value.record) {
      if (!slot.dims.empty() && !value.dims.empty() && slot.dims != value.dims)
        f_.fail(DiagId::TypeMismatch, target.range,
                "the sizes of '" + name + "' and of the assigned value differ");
      slot = std::move(value); // an array of a size given by its first value
      return;
    }
    Tensor shape;
    const std::vector<std::size_t> idx = f_.designate(slot, target.ref, scope(cls_), target.range, shape);
    if (!same_record_type(shape.record, value.record) || (!value.is_scalar() && value.elems.size() != idx.size()))
      f_.fail(DiagId::TypeMismatch, target.range,
              "the sizes or types of '" + target.ref.str() + "' and of the assigned value differ");
    for (std::size_t k = 0; k < idx.size(); ++k)
      slot.elems[idx[k]] = value.is_scalar() ? value.elems[0]->clone() : std::move(value.elems[k]);
  }
};

} // namespace

void Flattener::fold_numbers(Tensor &t) {
  for (auto &e : t.elems)
    if (e && !is_literal(*e) && literals_only(*e)) {
      const double v = eval(*e, e->range);
      if (!std::isfinite(v)) // 1 / 0 stays as written, for the run to report
        continue;
      e = is_boolean_valued(*e) ? ast::make_bool(v != 0, e->range)
          : integer_valued(*e)  ? ast::make_integer(v, e->range)
                                : ast::make_real(v, e->range);
    }
}

ClassNode *Flattener::lookup_called_class(const Expr &call, const Scope &s) {
  if (call.kind != ExprKind::Call || call.ref.parts.empty())
    return nullptr;
  std::vector<std::string> path;
  for (const auto &part : call.ref.parts) {
    if (!part.subscripts.empty())
      return nullptr;
    path.push_back(part.name);
  }
  ClassNode *cls = call.ref.global ? nullptr : replaced_class(s.inst, path);
  if (!cls)
    cls = lookup_class(s.cls ? s.cls : &lib_.root, path, call.ref.global, call.range, false);
  if (!cls && path.size() >= 2 && !call.ref.global)
    cls = function_of_instance(call, s).second;
  return cls && cls->def ? cls : nullptr;
}

std::pair<Instance *, ClassNode *> Flattener::function_of_instance(const Expr &call, const Scope &s) {
  const auto &parts = call.ref.parts;
  Instance *owner = s.inst;
  for (std::size_t p = 0; owner && p + 1 < parts.size(); ++p)
    owner = parts[p].subscripts.empty() && owner->dims.empty() ? member(*owner, parts[p].name) : nullptr;
  if (!owner || owner == s.inst || !owner->cls || !owner->dims.empty())
    return {nullptr, nullptr};
  const std::string &name = parts.back().name;
  ClassNode *fn = owner->replaced.count(name) ? owner->replaced.at(name) : find_member_class(owner->cls, name);
  if (!fn || !fn->def || fn->def->restriction != ast::Restriction::Function)
    return {nullptr, nullptr};
  return {owner, fn};
}

ClassNode *Flattener::short_function_base(ClassNode *fn, Instance *owner, const Expr &call,
                                          std::vector<std::pair<std::string, Tensor>> &preset) {
  for (unsigned hops = 0; fn && fn->def && fn->def->short_base; ++hops) {
    if (hops > 32)
      fail(DiagId::ExtendsCycle, call.range, "function '" + fn->path() + "' is defined in terms of itself");
    const ast::ClassDef &d = *fn->def;
    // Where it is written: the owner's class (or a base of it), or an
    // enclosing instance's, for a redeclaration in a modifier there
    // (`world(redeclare function gravityAcceleration = f(phi = latitude))`).
    const std::function<bool(ClassNode *, unsigned)> is_or_extends = [&](ClassNode *c, unsigned depth) {
      if (c == fn->parent)
        return true;
      if (!c || depth > 32)
        return false;
      for (auto &[ext, base] : bases(c))
        if (is_or_extends(base, depth + 1))
          return true;
      return false;
    };
    Instance *in = owner;
    while (in && !is_or_extends(in->cls, 0))
      in = in->parent;
    if (!in)
      in = owner;
    const Scope where{in, in ? in->cls : fn->parent, nullptr};
    for (const ast::ElementMod &m : d.class_mod.args) {
      if (m.redeclare || m.path.size() != 1 || !m.mod.binding || !m.mod.args.empty())
        fail(DiagId::Unsupported, m.range,
             "function '" + fn->path() + "': only modifiers that bind an input ('k = e') are supported");
      const bool known = std::any_of(preset.begin(), preset.end(), [&](const auto &v) { return v.first == m.path[0]; });
      if (!known)
        preset.emplace_back(m.path[0], expr(*m.mod.binding, where));
    }
    ClassNode *base = lookup_class(fn->parent, d.short_base->parts, d.short_base->global, d.short_base->range);
    if (!base)
      throw Reported{};
    fn = base;
    owner = nullptr; // a base's own short definition binds in its own package
  }
  return fn;
}

ClassNode *Flattener::lookup_function(const Expr &call, const Scope &s) {
  ClassNode *fn = lookup_called_class(call, s);
  return fn && fn->def->restriction == ast::Restriction::Function ? fn : nullptr;
}

ClassNode *Flattener::enclosing_function(const Expr &call, const Scope &s) {
  if (call.kind != ExprKind::Call || call.resolved || !call.ref.is_simple())
    return nullptr;
  const std::string &name = call.ref.parts[0].name;
  if (name == "Real" || name == "Integer" || name == "Boolean" || name == "String") // reserved, MLS 4.8
    return nullptr;
  if (s.inst && s.inst->member_index.count(name))
    return nullptr;
  ClassNode *scope = s.cls ? s.cls : &lib_.root;
  const auto key = std::make_pair(scope, name);
  if (auto it = enclosing_functions_.find(key); it != enclosing_functions_.end())
    return it->second;
  ClassNode *fn = lookup_function(call, s);
  // Modelica.Math.exp inside Modelica.Math: `external "builtin"` of the same
  // name is the built-in itself, with no inlining to go through.
  if (fn && fn->def->external_language == "builtin" &&
      (fn->def->external_function.empty() ? fn->name : fn->def->external_function) == name)
    fn = nullptr;
  enclosing_functions_.emplace(key, fn);
  return fn;
}

std::vector<std::size_t> Flattener::designate(const Tensor &slot, const ast::ComponentRef &ref, const Scope &s,
                                              SourceRange where, Tensor &shape) {
  // Each step keeps the indices of `slot` that the reference designates so
  // far, grouped by item: an item is one record (stride: its size) or one scalar.
  std::vector<std::size_t> idx;
  const auto stride = [](const Tensor &t) { return t.record ? t.record->size : std::size_t{1}; };
  shape.dims = slot.dims;
  shape.record = slot.record;
  shape.elems.clear();
  for (std::size_t k = 0; k < slot.elems.size(); ++k)
    idx.push_back(k);
  for (std::size_t p = 0; p < ref.parts.size(); ++p) {
    const ast::RefPart &part = ref.parts[p];
    std::vector<int> lead; // dimensions of the items before this part's own ones
    if (p > 0) {
      if (!shape.record)
        fail(DiagId::UnknownComponent, where, "'" + ref.str() + "': '" + ref.parts[p - 1].name + "' is not a record");
      const RecordLayout::Field *f = shape.record->find(part.name);
      if (!f)
        fail(DiagId::UnknownComponent, where,
             "'" + ref.str() + "': record '" + shape.record->cls->path() + "' has no field '" + part.name + "'");
      std::vector<std::size_t> next;
      for (std::size_t g = 0; g < idx.size(); g += shape.record->size)
        for (std::size_t k = 0; k < f->size; ++k)
          next.push_back(idx[g + f->offset + k]);
      idx.swap(next);
      lead = shape.dims;
      shape.dims.insert(shape.dims.end(), f->dims.begin(), f->dims.end());
      shape.record = f->record;
    }
    if (part.subscripts.empty())
      continue;
    // The subscripts select among this part's own dimensions, in every item before it.
    Tensor own;
    own.dims.assign(shape.dims.begin() + static_cast<std::ptrdiff_t>(lead.size()), shape.dims.end());
    std::vector<int> picked_dims;
    const std::vector<std::size_t> picked = selection(*this, part.subscripts, own, part.name, s, where, picked_dims);
    std::size_t per_lead = stride(shape);
    for (int d : own.dims)
      per_lead *= static_cast<std::size_t>(d);
    std::vector<std::size_t> next;
    for (std::size_t g = 0; g < idx.size(); g += per_lead)
      for (std::size_t item : picked)
        for (std::size_t k = 0; k < stride(shape); ++k)
          next.push_back(idx[g + item * stride(shape) + k]);
    idx.swap(next);
    shape.dims = lead;
    shape.dims.insert(shape.dims.end(), picked_dims.begin(), picked_dims.end());
  }
  return idx;
}

bool Flattener::local_value(const ast::ComponentRef &ref, const Scope &s, SourceRange where, Tensor &out) {
  if (!s.locals || ref.global)
    return false;
  auto it = s.locals->find(ref.parts[0].name);
  if (it == s.locals->end())
    return false;
  const Tensor &t = it->second;
  for (std::size_t k : designate(t, ref, s, where, out)) {
    if (!t.elems[k])
      fail(DiagId::EvaluationError, where, "'" + ref.str() + "' is used before it is assigned");
    out.elems.push_back(t.elems[k]->clone());
  }
  return true;
}

Tensor Flattener::string_call(const Expr &call, const Scope &s) {
  if (call.args.size() != 1)
    fail(DiagId::WrongArgumentCount, call.range,
         fmt::format("String() takes 1 positional argument, {} given", call.args.size()));
  std::vector<ExprPtr> args;
  args.push_back(scalar_expr(*call.args[0], s));
  // Formatting options (significantDigits, minimumLength, leftJustified)
  // only shape the text of messages, which the flat model does not keep.
  return Tensor::scalar(ast::make_call("String", std::move(args), call.range));
}

namespace {

/// The argument expression for each input: positional, then named; null
/// where the default applies.
std::vector<const Expr *> match_arguments(Flattener &f, const Signature &sig, const Expr &call,
                                          const std::string &fn_name) {
  std::vector<const Expr *> out(sig.inputs.size(), nullptr);
  if (call.args.size() > sig.inputs.size())
    f.fail(DiagId::WrongArgumentCount, call.range,
           fmt::format("{}() takes {} argument(s), {} given", fn_name, sig.inputs.size(), call.args.size()));
  for (std::size_t i = 0; i < call.args.size(); ++i)
    out[i] = call.args[i].get();
  for (const auto &na : call.named) {
    std::size_t i = 0;
    while (i < sig.inputs.size() && sig.inputs[i].first->name != na.name)
      ++i;
    if (i == sig.inputs.size())
      f.fail(DiagId::WrongArgumentCount, na.value->range,
             "function '" + fn_name + "' has no input named '" + na.name + "'");
    if (out[i])
      f.fail(DiagId::WrongArgumentCount, na.value->range,
             "input '" + na.name + "' of function '" + fn_name + "' is given twice");
    out[i] = na.value.get();
  }
  return out;
}

} // namespace

namespace {

/// The fields of record value `t` (of each element of a record array) that
/// `mod` binds, as in `output Complex result(re = re, im = im)`.
void bind_fields(Flattener &f, Tensor &t, const ast::Modification &mod, const Scope &fs, const std::string &fn_name,
                 const std::string &name) {
  for (const ast::ElementMod &m : mod.args) {
    const auto field = std::find_if(t.record->fields.begin(), t.record->fields.end(), [&](const RecordLayout::Field &x) {
      return m.path.size() == 1 && x.name == m.path[0];
    });
    if (!m.mod.binding || m.redeclare || field == t.record->fields.end())
      f.fail(DiagId::Unsupported, m.range,
             "cannot inline function '" + fn_name + "': of '" + name + "', only fields bound as 'k = e' are supported");
    const Tensor v = f.expr(*m.mod.binding, fs);
    if (v.elems.size() != field->size || !same_record_type(v.record, field->record))
      f.fail(DiagId::TypeMismatch, m.range, "the value of field '" + field->name + "' of '" + name + "' has the wrong size");
    for (std::size_t base = 0; base < t.elems.size(); base += t.record->size)
      for (std::size_t j = 0; j < field->size; ++j)
        t.elems[base + field->offset + j] = v.elems[j]->clone();
  }
}

/// Runs `fn`'s algorithm on `arguments` (the given inputs, expressions or
/// numbers) along the outcomes `decisions` gives; throws
/// NeedDecision at a varying condition past them, InlineUnsupported where it
/// cannot go on.
std::vector<Tensor> inline_path(Flattener &f, ClassNode *fn, const Signature &sig, const std::vector<bool> &given,
                                std::vector<Tensor> arguments, const Expr &call, std::size_t wanted,
                                Decisions &decisions) {
  const std::string fn_name = fn->path();
  Inliner in(f, fn, decisions);
  for (std::size_t i = 0; i < sig.inputs.size(); ++i)
    if (given[i])
      in.values[sig.inputs[i].first->name] = std::move(arguments[i]);
  // Declared sizes, defaults and bindings, in declaration order.
  auto declare = [&](const ast::Component &c, ClassNode *owner, bool is_input, bool has_value) {
    Scope fs = in.scope(owner);
    ResolvedType rt;
    if (!f.resolve_type(owner, c.type, rt))
      throw Reported{};
    std::shared_ptr<const RecordLayout> record;
    if (!rt.is_builtin && !rt.is_enumeration) {
      if (!is_record_class(rt.cls))
        f.fail(DiagId::Unsupported, c.range,
               "cannot inline function '" + fn_name + "': '" + c.name + "' is neither a number nor a record");
      record = f.record_layout(rt.cls, c.range);
    }
    std::vector<int> dims;
    bool sized = true;
    for (const auto &d : c.dims) {
      if (d->kind == ExprKind::Colon) {
        sized = false;
        continue;
      }
      dims.push_back(static_cast<int>(f.eval_int(*d, fs)));
    }
    dims.insert(dims.end(), rt.dims.begin(), rt.dims.end());
    if (has_value) {
      const Tensor &t = in.values.at(c.name);
      if (!same_record_type(t.record, record))
        f.fail(DiagId::TypeMismatch, call.range,
               "argument '" + c.name + "' of function '" + fn_name + "' is not a value of its type '" +
                   c.type.str() + "'");
      if (sized && t.dims != dims)
        f.fail(DiagId::TypeMismatch, call.range,
             "argument '" + c.name + "' of function '" + fn_name + "' has the wrong size");
      return;
    }
    if (c.mod.binding) {
      in.values[c.name] = f.expr(*c.mod.binding, fs);
      return;
    }
    if (is_input)
      f.fail(DiagId::WrongArgumentCount, call.range,
           "input '" + c.name + "' of function '" + fn_name + "' is missing and has no default");
    if (record) {
      if (!sized)
        f.fail(DiagId::Unsupported, c.range,
               "cannot inline function '" + fn_name + "': '" + c.name + "' is a record array of unknown size");
      Tensor t = f.record_defaults(record, dims, c.range);
      bind_fields(f, t, c.mod, fs, fn_name, c.name); // `output Complex result(re = re, im = im)`
      in.values[c.name] = std::move(t);
      return;
    }
    Tensor t;
    t.dims = sized ? dims : std::vector<int>{};
    std::size_t n = 1;
    for (int d : t.dims)
      n *= static_cast<std::size_t>(d);
    t.elems.resize(n);
    in.values[c.name] = std::move(t);
  };
  for (std::size_t i = 0; i < sig.inputs.size(); ++i)
    declare(*sig.inputs[i].first, sig.inputs[i].second, true, given[i]);
  for (const auto &[c, owner] : sig.outputs)
    declare(*c, owner, false, false);
  for (const auto &[c, owner] : sig.locals)
    declare(*c, owner, false, false);
  for (const auto &[body, owner] : sig.algorithms)
    in.run(*body, owner);
  std::vector<Tensor> out;
  for (std::size_t i = 0; i < wanted; ++i) {
    const std::string &name = sig.outputs[i].first->name;
    Tensor &t = in.values.at(name);
    for (const auto &e : t.elems)
      if (!e)
        f.fail(DiagId::EvaluationError, call.range,
             "output '" + name + "' of function '" + fn_name + "' is not assigned");
    out.push_back(std::move(t));
  }
  return out;
}

/// True if every scalar of type `type` (declared in `owner`) is a Real,
/// records through their fields. A type that does not resolve is reported.
bool all_real(Flattener &f, ClassNode *owner, const ast::TypeName &type, SourceRange where, unsigned depth = 0) {
  ResolvedType rt;
  if (depth > 32)
    return false;
  if (!f.resolve_type(owner, type, rt))
    throw Reported{};
  if (rt.is_enumeration)
    return false;
  if (rt.is_builtin)
    return rt.builtin == flat::BaseType::Real;
  if (!rt.cls || !is_record_class(rt.cls))
    return false;
  const std::shared_ptr<const RecordLayout> layout = f.record_layout(rt.cls, where);
  return std::all_of(layout->fields.begin(), layout->fields.end(), [&](const RecordLayout::Field &field) {
    return field.decl && all_real(f, field.owner, field.decl->type, where, depth + 1);
  });
}

/// True if the relations in `fn`'s body generate no events (Modelica's
/// annotation GenerateEvents): unless `fn` asks for them, or an output is an
/// Integer, Boolean or enumeration, which only an event may change.
bool without_events(Flattener &f, ClassNode *fn, const Signature &sig) {
  if (fn->def->generate_events)
    return false;
  return std::all_of(sig.outputs.begin(), sig.outputs.end(), [&](const auto &output) {
    return all_real(f, output.second, output.first->type, output.first->range);
  });
}

constexpr std::size_t kMaxPaths = 4096;

/// Runs `fn`'s algorithm once per way through its varying decisions (a
/// binary tree: each run that meets a new one becomes a node with both
/// outcomes below it) and joins the runs' outputs bottom-up into
/// if-expressions on the decisions' conditions. Throws InlineUnsupported
/// beyond kMaxPaths runs or where the runs' outputs differ in size.
std::vector<Tensor> inline_call(Flattener &f, ClassNode *fn, const Signature &sig, const std::vector<bool> &given,
                                const std::vector<Tensor> &arguments, const Expr &call, std::size_t wanted) {
  struct Node {
    std::vector<bool> path;
    ExprPtr condition; ///< set: a decision, children then_child and then_child + 1
    std::size_t then_child = 0;
    std::vector<Tensor> outs;
  };
  std::vector<Node> nodes(1);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (nodes.size() > 2 * kMaxPaths)
      throw InlineUnsupported{call.range, fmt::format("its varying conditions make more than {} ways through "
                                                      "the algorithm", kMaxPaths)};
    std::vector<Tensor> args;
    for (const Tensor &t : arguments)
      args.push_back(clone_tensor(t));
    Decisions d;
    d.taken = nodes[n].path;
    try {
      nodes[n].outs = inline_path(f, fn, sig, given, std::move(args), call, wanted, d);
    } catch (NeedDecision &need) {
      nodes[n].condition = std::move(need.condition);
      nodes[n].then_child = nodes.size();
      for (bool outcome : {true, false}) {
        Node child;
        child.path = nodes[n].path;
        child.path.push_back(outcome);
        nodes.push_back(std::move(child));
      }
    }
  }
  // Children come after their parent: joining from the back is bottom-up.
  for (std::size_t n = nodes.size(); n-- > 0;) {
    Node &node = nodes[n];
    if (!node.condition)
      continue;
    std::vector<Tensor> &yes = nodes[node.then_child].outs, &no = nodes[node.then_child + 1].outs;
    for (std::size_t k = 0; k < yes.size(); ++k) {
      if (yes[k].dims != no[k].dims)
        throw InlineUnsupported{call.range, "an output has different sizes on different ways through the algorithm"};
      for (std::size_t j = 0; j < yes[k].elems.size(); ++j) {
        if (ast::same_expr(*yes[k].elems[j], *no[k].elems[j]))
          continue;
        auto e = std::make_unique<Expr>(ExprKind::If, call.range);
        e->args.push_back(node.condition->clone());
        e->args.push_back(std::move(yes[k].elems[j]));
        e->args.push_back(std::move(no[k].elems[j]));
        yes[k].elems[j] = f.intermediate(std::move(e), fn, sig.outputs[k].first->name, call.range);
      }
    }
    node.outs = std::move(yes);
  }
  return std::move(nodes[0].outs);
}

} // namespace

/// The dimensions D over which a call is vectorized (MLS 12.4.6): arguments
/// that have more dimensions than their input's declaration, D in front
/// (the same D for all of them), the others as declared; an element is a
/// number or a record as the input declares. Empty when no argument has
/// more, or when such an input is neither; `sliced` marks the
/// arguments that have them. Only the declared number of dimensions is
/// compared here; their sizes are checked per call.
std::vector<int> vectorized_dims(Flattener &f, const Signature &sig, const std::vector<bool> &given,
                                 const std::vector<Tensor> &arguments, const Expr &call, std::vector<bool> &sliced) {
  std::vector<int> over;
  sliced.assign(sig.inputs.size(), false);
  for (std::size_t i = 0; i < sig.inputs.size(); ++i) {
    const auto &[c, owner] = sig.inputs[i];
    if (!given[i] || arguments[i].dims.size() <= c->dims.size())
      continue; // not beyond its declaration (the common case: no type to resolve)
    ResolvedType rt;
    if (!f.resolve_type(owner, c->type, rt) || (!rt.is_builtin && !(rt.cls && is_record_class(rt.cls))))
      return {}; // a number or a record per element (ComplexMath.'abs' of a vector of Complex)
    const std::size_t declared = c->dims.size() + rt.dims.size();
    const std::vector<int> &dims = arguments[i].dims;
    if (dims.size() <= declared)
      continue;
    const std::vector<int> extra(dims.begin(), dims.end() - static_cast<long>(declared));
    if (!over.empty() && extra != over)
      f.fail(DiagId::TypeMismatch, call.range,
             fmt::format("the arguments of a vectorized call have different sizes ([{}] and [{}])",
                         fmt::join(over, ", "), fmt::join(extra, ", ")));
    over = extra;
    sliced[i] = true;
  }
  return over;
}

bool Flattener::call_statement(ClassNode *fn, const Expr &call, const Scope &s) {
  const ast::ClassDef &def = *fn->def;
  if (!def.is_external) {
    // A Modelica function called for its checks (Fluid's checkBoundary):
    // inlined, its outputs unused; its asserts are dropped as any inlined
    // function's are.
    call_function(fn, call, s, 0);
    return true;
  }
  if (def.external_language != "C")
    return false;
  // ModelicaError (Modelica.Utilities.Streams.error) ends the run with a
  // message: a check, dropped like an inlined function's assert.
  if (def.external_function == "ModelicaError")
    return true;
  Signature sig;
  collect(*this, fn, sig, 0);
  const std::vector<const Expr *> args = match_arguments(*this, sig, call, fn->path());
  std::vector<std::string> in_names;
  for (const auto &[c, owner] : sig.inputs)
    in_names.push_back(c->name);
  return provided_random_statement(def, in_names, args, call, s);
}

std::vector<Tensor> Flattener::call_function(ClassNode *fn, const Expr &call, const Scope &s,
                                             std::size_t wanted, std::vector<std::pair<std::string, Tensor>> preset) {
  const ast::ClassDef &def = *fn->def;
  const std::string fn_name = fn->path();
  if (function_depth_ >= kMaxCallDepth)
    fail(DiagId::Unsupported, call.range,
         fmt::format("function calls nested deeper than {} (a recursive function?) cannot be inlined",
                     kMaxCallDepth));
  if (def.short_base) {
    std::vector<std::pair<std::string, Tensor>> bound; // the inputs its modifiers bind
    ClassNode *base = short_function_base(fn, function_of_instance(call, s).first, call, bound);
    for (auto &b : preset) // the caller's own presets are nearer
      bound.insert(bound.begin(), std::move(b));
    return call_function(base, call, s, wanted, std::move(bound));
  }
  Signature sig;
  collect(*this, fn, sig, 0);
  std::vector<const Expr *> args = match_arguments(*this, sig, call, fn_name);
  struct WhenGuard { // the functions a when-clause calls (impure draws are refused there)
    unsigned &n;
    bool on;
    ~WhenGuard() { n -= on ? 1 : 0; }
  } when_guard{calls_in_when_, s.in_when};
  calls_in_when_ += s.in_when ? 1 : 0;
  if (wanted > sig.outputs.size() || (sig.outputs.empty() && wanted > 0)) // 0: called as a statement
    fail(DiagId::WrongArgumentCount, call.range,
         fmt::format("function '{}' has {} output(s); {} are used", fn_name, sig.outputs.size(),
                     std::max<std::size_t>(wanted, 1)));

  if (def.is_external && !preset.empty())
    fail(DiagId::Unsupported, call.range,
         "a short definition that binds inputs of external function '" + fn_name + "' is not supported");
  if (def.is_external) {
    if (def.external_language == "C") {
      std::vector<std::string> in_names, out_names;
      for (const auto &[c, owner] : sig.inputs)
        in_names.push_back(c->name);
      for (const auto &[c, owner] : sig.outputs)
        out_names.push_back(c->name);
      std::vector<Tensor> random_outputs;
      if (provided_random(def, fn_name, in_names, out_names, args, call, s, random_outputs))
        return random_outputs;
      Tensor provided;
      if (provided_external(def.external_function, args, call, s, provided) ||
          provided_string_function(def.external_function, args, call, s, provided)) {
        std::vector<Tensor> out;
        out.push_back(std::move(provided));
        return out;
      }
    }
    if (def.external_language != "builtin")
      fail(DiagId::Unsupported, call.range,
           "external function '" + fn_name + "' (language \"" + def.external_language +
               "\") cannot be evaluated; only external \"builtin\" functions are supported");
    auto builtin = std::make_unique<Expr>(ExprKind::Call, call.range);
    builtin->resolved = true; // the built-in itself, whatever the scope defines
    builtin->ref.parts.push_back(ast::RefPart{def.external_function.empty() ? fn->name : def.external_function, {}});
    for (std::size_t i = 0; i < args.size(); ++i) {
      if (!args[i])
        fail(DiagId::WrongArgumentCount, call.range,
             "input '" + sig.inputs[i].first->name + "' of function '" + fn_name + "' is missing");
      builtin->args.push_back(args[i]->clone());
    }
    ++function_depth_;
    std::vector<Tensor> out;
    try {
      out.push_back(expr(*builtin, s));
    } catch (...) {
      --function_depth_;
      throw;
    }
    --function_depth_;
    return out;
  }

  // Inputs: the caller's arguments, flattened in the caller's scope.
  std::vector<Tensor> arguments(sig.inputs.size());
  std::vector<bool> given(sig.inputs.size());
  for (std::size_t i = 0; i < sig.inputs.size(); ++i)
    if (args[i]) {
      arguments[i] = expr(*args[i], s);
      given[i] = true;
    }
  for (auto &[name, value] : preset) {
    std::size_t i = 0;
    while (i < sig.inputs.size() && sig.inputs[i].first->name != name)
      ++i;
    if (i == sig.inputs.size())
      fail(DiagId::WrongArgumentCount, call.range, "function '" + fn_name + "' has no input named '" + name + "'");
    if (!given[i])
      arguments[i] = std::move(value), given[i] = true;
  }
  std::vector<bool> sliced;
  if (const std::vector<int> over = vectorized_dims(*this, sig, given, arguments, call, sliced); !over.empty()) {
    std::vector<Tensor> out;
    out.push_back(call_elementwise(fn, sig, given, arguments, sliced, call, over));
    return out;
  }
  return inline_or_evaluate(fn, sig, given, std::move(arguments), call, wanted);
}

Tensor clone_tensor(const Tensor &t) {
  Tensor out;
  out.dims = t.dims;
  out.record = t.record;
  for (const auto &e : t.elems)
    out.elems.push_back(e ? e->clone() : nullptr);
  return out;
}

std::optional<Tensor> Flattener::apply_function(ClassNode *fn, std::vector<Tensor> values, const Expr &site) {
  if (!fn || !fn->def || fn->def->restriction != ast::Restriction::Function || fn->def->short_base ||
      fn->def->is_external)
    return std::nullopt;
  Signature sig;
  collect(*this, fn, sig, 0);
  if (values.size() > sig.inputs.size() || sig.outputs.empty())
    return std::nullopt;
  for (std::size_t i = 0; i < sig.inputs.size(); ++i) {
    const ast::Component &c = *sig.inputs[i].first;
    if (i >= values.size()) {
      if (!c.mod.binding) // an input without a default needs a value
        return std::nullopt;
      continue;
    }
    ResolvedType rt;
    if (!resolve_type(sig.inputs[i].second, c.type, rt))
      return std::nullopt;
    const Tensor &v = values[i];
    const bool record_input = !rt.is_builtin && rt.cls && is_record_class(rt.cls);
    if (record_input != static_cast<bool>(v.record) || (record_input && v.record->cls != rt.cls))
      return std::nullopt;
    if (!record_input && (!rt.is_builtin || rt.builtin == flat::BaseType::String))
      return std::nullopt;
    if (v.dims.size() != c.dims.size() + rt.dims.size())
      return std::nullopt;
  }
  std::vector<bool> given(sig.inputs.size(), false);
  std::fill(given.begin(), given.begin() + static_cast<long>(values.size()), true);
  values.resize(sig.inputs.size());
  return std::move(inline_or_evaluate(fn, sig, given, std::move(values), site, 1).front());
}

Tensor Flattener::call_elementwise(ClassNode *fn, const Signature &sig, const std::vector<bool> &given,
                                   const std::vector<Tensor> &arguments, const std::vector<bool> &sliced,
                                   const Expr &call, const std::vector<int> &over) {
  std::size_t count = 1;
  for (int d : over)
    count *= static_cast<std::size_t>(d);
  Tensor out;
  for (std::size_t k = 0; k < count; ++k) {
    std::vector<Tensor> element(arguments.size());
    for (std::size_t i = 0; i < arguments.size(); ++i) {
      if (!given[i])
        continue;
      const Tensor &a = arguments[i];
      if (!sliced[i]) {
        element[i] = clone_tensor(a); // given with its declared size: the same in every call
        continue;
      }
      element[i].dims.assign(a.dims.begin() + static_cast<long>(over.size()), a.dims.end());
      element[i].record = a.record;
      const std::size_t stride = a.elems.size() / count;
      for (std::size_t j = 0; j < stride; ++j)
        element[i].elems.push_back(a.elems[k * stride + j]->clone());
    }
    Tensor r = std::move(inline_or_evaluate(fn, sig, given, std::move(element), call, 1).front());
    if (k == 0)
      out.dims = over, out.dims.insert(out.dims.end(), r.dims.begin(), r.dims.end()), out.record = r.record;
    else if (!same_record_type(out.record, r.record))
      fail(DiagId::TypeMismatch, call.range, "the calls of a vectorized '" + fn->path() + "' return different types");
    for (auto &e : r.elems)
      out.elems.push_back(std::move(e));
  }
  return out;
}

std::vector<Tensor> Flattener::inline_or_evaluate(ClassNode *fn, const Signature &sig, const std::vector<bool> &given,
                                                  std::vector<Tensor> arguments, const Expr &call,
                                                  std::size_t wanted) {
  const std::string fn_name = fn->path();
  const unsigned quiet = without_events(*this, fn, sig) ? 1 : 0; // reports an output type it cannot resolve
  struct DepthGuard {
    unsigned &d;
    unsigned step;
    DepthGuard(unsigned &depth, unsigned s) : d(depth), step(s) { d += step; }
    ~DepthGuard() { d -= step; }
  } guard{function_depth_, 1}, events{no_event_depth_, quiet};
  const auto report = [&](const InlineUnsupported &u) {
    fail(DiagId::Unsupported, u.range, "cannot inline function '" + fn_name + "': " + u.what);
  };
  const bool evaluable = std::all_of(arguments.begin(), arguments.end(), [this](const Tensor &t) {
    return std::all_of(t.elems.begin(), t.elems.end(), [this](const ExprPtr &e) { return !e || is_constant(*e); });
  });
  try {
    struct Cap { // a smaller bound while inlining a call that can be evaluated instead
      std::size_t &cap, saved;
      ~Cap() { cap = saved; }
    } cap{value_nodes_cap_, value_nodes_cap_};
    if (evaluable)
      value_nodes_cap_ = std::min(value_nodes_cap_, kEvaluableValueNodes);
    return inline_call(*this, fn, sig, given, arguments, call, wanted);
  } catch (const InlineUnsupported &u) {
    // A loop to a tolerance, an error() on a bad input, ...: with parameter
    // arguments (a filter's coefficients) the call can still be evaluated now.
    for (const Tensor &t : arguments)
      for (const auto &e : t.elems)
        if (e && !is_constant(*e))
          report(u);
    for (Tensor &t : arguments)
      for (auto &e : t.elems)
        if (e && !is_literal(*e))
          e = ast::make_real(eval(*e, call.range), call.range);
    std::vector<Tensor> out;
    try {
      out = inline_call(*this, fn, sig, given, arguments, call, wanted);
    } catch (const InlineUnsupported &again) {
      report(again);
    }
    diags_.report(DiagId::EvaluatedAtTranslation, call.range,
                  "function '" + fn_name + "' cannot be inlined (" + u.what +
                      "); it is evaluated now with its arguments' parameter values, so changing those parameters "
                      "later does not change its result");
    return out;
  }
}

} // namespace mo::frontend::detail
