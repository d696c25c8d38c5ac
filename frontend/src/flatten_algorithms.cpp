// Algorithm sections of models and blocks that are not plain equations
// (algorithm_equations.cpp takes those), flattened by executing their
// statements on flat expressions, in SSA style: each assignment gives its
// variable a new value expression, which later statements read in its place;
// an `if` on a condition that varies runs both branches and joins the values
// they assign into if-expressions (φ = `if c then v_then else v_else`); a
// `for` is unrolled over its range, a `while` runs while its condition is
// known now. What the section finally gives each variable it assigns becomes
// the equation `v = value`. A variable read before the section assigns it
// has its value at the section's start (MLS 11.1.2): pre(v) for a discrete
// variable, its start value otherwise (at initialisation always the start
// value). Every element of an array counts as assigned once one is.
//
// A `when` statement (at the top of the section only, as Modelica requires)
// becomes a when-clause: each branch's statements run on their own, starting
// from pre() of the variables the statement assigns, and a variable a branch
// leaves alone keeps pre(v) there. After the statement its variables read as
// themselves; before it, as pre(v).
#include "flattener.hpp"
#include "mo/frontend/printer.hpp"

#include <fmt/format.h>

namespace mo::frontend::detail {

using ast::EquationKind;
using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;
using ast::Statement;
using ast::StatementKind;

namespace {

constexpr long kMaxWhileIterations = 100'000;

using Values = std::map<std::int32_t, ExprPtr>;

Values clone_values(const Values &v) {
  Values out;
  for (const auto &[k, e] : v)
    out.emplace(k, e->clone());
  return out;
}

/// The names a statement list assigns (first part of each target), with
/// `when` statements' apart; iterative.
void assigned_names(const std::vector<Statement> &body, std::vector<const Expr *> &plain,
                    std::vector<const Expr *> &in_when) {
  std::vector<std::pair<const std::vector<Statement> *, bool>> work{{&body, false}};
  while (!work.empty()) {
    auto [list, when] = work.back();
    work.pop_back();
    for (const Statement &st : *list) {
      switch (st.kind) {
      case StatementKind::Assign:
        for (const auto &t : st.targets)
          if (t)
            (when ? in_when : plain).push_back(t.get());
        break;
      case StatementKind::If:
        for (const auto &b : st.branches)
          work.emplace_back(&b.body, when);
        break;
      case StatementKind::When:
        for (const auto &b : st.branches)
          work.emplace_back(&b.body, true);
        break;
      case StatementKind::For:
      case StatementKind::While:
        work.emplace_back(&st.body, when);
        break;
      case StatementKind::Call:
      case StatementKind::Break:
      case StatementKind::Return:
        break;
      }
    }
  }
}

/// A target without its subscripts: the whole variable (array) it assigns into.
ExprPtr whole(const Expr &target) {
  ExprPtr e = target.clone();
  for (auto &p : e->ref.parts)
    p.subscripts.clear();
  return e;
}

class SectionRunner {
public:
  SectionRunner(Flattener &f, const ast::AlgorithmSection &alg, const Scope &s, std::vector<ast::Equation> &out)
      : f_(f), m_(*f.model_), alg_(alg), out_(out) {
    scope_ = s;
    scope_.env = &env_;
  }

  void run() {
    std::vector<const Expr *> plain, in_when;
    assigned_names(alg_.body, plain, in_when);
    for (const Expr *t : plain)
      for (std::int32_t v : vars_of(*whole(*t)))
        if (plain_.insert(v).second)
          order_.push_back(v);
    for (const Expr *t : in_when)
      for (std::int32_t v : vars_of(*whole(*t))) {
        if (plain_.count(v))
          f_.fail(DiagId::Unsupported, t->range,
                  "'" + m_.variables[v].name + "' is assigned both inside and outside a when-statement");
        when_vars_.insert(v);
      }
    exec(alg_.body, values_);
    for (std::int32_t v : order_) {
      auto it = values_.find(v);
      emit(v, it == values_.end() ? start_value(v) : std::move(it->second), alg_.range, out_);
    }
  }

private:
  Flattener &f_;
  flat::Model &m_;
  const ast::AlgorithmSection &alg_;
  std::vector<ast::Equation> &out_;
  Scope scope_;
  LoopEnv env_;
  std::set<std::int32_t> plain_, when_vars_, when_done_;
  std::vector<std::int32_t> order_;
  Values values_;
  /// Inside a when-branch: the when-statement's variables (read as pre(v)
  /// until assigned); null outside.
  const std::set<std::int32_t> *branch_vars_ = nullptr;
  unsigned varying_ifs_ = 0; ///< varying `if`s around the statement being run
  bool broke_ = false;
  unsigned loops_ = 0;      ///< for- and while-loops around the statement being run
  /// When the innermost loop has left by a `break` under varying conditions:
  /// the statements after it run under `not loop_broken_`; null: it has not.
  ExprPtr loop_broken_;

  [[noreturn]] void unsupported(SourceRange r, const std::string &what) {
    f_.fail(DiagId::Unsupported, r, "this algorithm section cannot be flattened: " + what);
  }

  /// Reports value `e` of variable `v` beyond kMaxValueDepth or max_value_nodes().
  void check_size(const Expr &e, std::int32_t v, SourceRange r) {
    if (too_large_value(e, f_.max_value_nodes()))
      unsupported(r, fmt::format("the value of '{}' grows beyond {} levels or {} terms (a loop that "
                                 "accumulates an expression?)",
                                 m_.variables[v].name, kMaxValueDepth, f_.max_value_nodes()));
  }

  std::vector<std::int32_t> vars_of(const Expr &target) {
    Tensor t = f_.expr(target, scope_);
    std::vector<std::int32_t> out;
    for (const auto &e : t.elems) {
      if (!e || e->kind != ExprKind::Ref || e->var < 0)
        unsupported(target.range, "only variables (or elements of them) can be assigned");
      const ast::Variability k = m_.variables[e->var].variability;
      // An initial algorithm computes parameters declared fixed = false,
      // as initial equations do (the MSL's CombiTimeTable: t_min).
      const bool computed = alg_.initial && m_.variables[e->var].free_parameter();
      if ((k == ast::Variability::Parameter && !computed) || k == ast::Variability::Constant)
        unsupported(target.range, "'" + m_.variables[e->var].name + "' is a parameter or constant");
      out.push_back(e->var);
    }
    return out;
  }

  bool is_discrete(std::int32_t v) const {
    const flat::Variable &x = m_.variables[v];
    return x.variability == ast::Variability::Discrete || x.type != flat::BaseType::Real || when_vars_.count(v);
  }

  /// The value of `v` at the start of the section (or of a when-branch).
  ExprPtr start_value(std::int32_t v) {
    const flat::Variable &x = m_.variables[v];
    if (!alg_.initial && is_discrete(v))
      return ast::make_call1("pre", var_ref(m_, v, alg_.range), alg_.range);
    if (x.attr.start)
      return x.attr.start->clone();
    return x.type == flat::BaseType::Boolean ? ast::make_bool(false, alg_.range) : ast::make_real(0, alg_.range);
  }

  /// Replaces the references in `t` to variables the section has assigned
  /// by their values in `vals` (or their start values when the section
  /// assigns them later); arguments of pre() and der() are kept.
  void substitute(Tensor &t, const Values &vals) {
    for (auto &root : t.elems) {
      std::vector<ExprPtr *> work{&root};
      while (!work.empty()) {
        ExprPtr *slot = work.back();
        work.pop_back();
        Expr &e = **slot;
        if (e.kind == ExprKind::Ref && e.var >= 0) {
          if (ExprPtr r = read(e.var, vals, e.range))
            *slot = std::move(r);
          continue;
        }
        if (e.kind == ExprKind::Call && e.var < 0 && e.ref.parts.size() == 1 &&
            (e.ref.parts[0].name == "pre" || e.ref.parts[0].name == "der"))
          continue;
        for (auto &a : e.args)
          if (a)
            work.push_back(&a);
      }
    }
  }

  /// The value `v` reads as here, or null when it reads as itself.
  ExprPtr read(std::int32_t v, const Values &vals, SourceRange r) {
    auto it = vals.find(v);
    if (it != vals.end())
      return it->second->clone();
    if (branch_vars_ && branch_vars_->count(v))
      return ast::make_call1("pre", var_ref(m_, v, r), r);
    if (plain_.count(v))
      return start_value(v);
    if (when_vars_.count(v) && !when_done_.count(v))
      return alg_.initial ? start_value(v) : ast::make_call1("pre", var_ref(m_, v, r), r);
    return nullptr;
  }

  Tensor value(const Expr &e, const Values &vals) {
    Tensor t = f_.expr(e, scope_);
    substitute(t, vals);
    return t;
  }

  ExprPtr condition(const Expr &e, const Values &vals) {
    Tensor t = value(e, vals);
    if (!t.is_scalar())
      unsupported(e.range, "a condition must be a scalar");
    return std::move(t.elems[0]);
  }

  /// 1 or 0 when `c` is decided now (literals, parameters), -1 when it varies.
  int decided(const Expr &c, SourceRange r) {
    if (c.kind == ExprKind::Boolean)
      return c.number != 0;
    if (f_.is_constant(c))
      return f_.eval(c, r) != 0;
    return -1;
  }

  void exec(const std::vector<Statement> &body, Values &vals) {
    for (const Statement &st : body) {
      if (broke_)
        return;
      if (loop_broken_)
        exec_unless_broken(st, vals);
      else
        exec_one(st, vals);
    }
  }

  /// `st` after a break under varying conditions in the same loop: as if
  /// written `if not broken then st end if`, and breaks inside it join.
  void exec_unless_broken(const Statement &st, Values &vals) {
    ExprPtr broken = std::move(loop_broken_);
    ExprPtr running = ast::make_unary(ast::Op::Not, broken->clone(), st.range);
    Values other = clone_values(vals);
    ++varying_ifs_;
    guards_.push_back(running->clone());
    exec_one(st, vals);
    guards_.pop_back();
    --varying_ifs_;
    join(*running, vals, other, st.range);
    loop_broken_ = loop_broken_ ? ast::make_binary(ast::Op::Or, std::move(broken), std::move(loop_broken_), st.range)
                                : std::move(broken);
  }

  void exec_one(const Statement &st, Values &vals) {
    switch (st.kind) {
    case StatementKind::Assign:
      assign(st, vals);
      return;
    case StatementKind::Call:
      call(st, vals);
      return;
    case StatementKind::Break:
      if (varying_ifs_ > 0 && loops_ > 0) {
        // Left where the varying conditions around hold: the rest of this
        // branch is skipped (exec_if clears broke_ after it), what follows
        // in the loop runs where they do not (exec_unless_broken).
        ExprPtr held = guards_[0]->clone();
        for (std::size_t g = 1; g < guards_.size(); ++g)
          held = ast::make_binary(ast::Op::And, std::move(held), guards_[g]->clone(), st.range);
        loop_broken_ = loop_broken_ ? ast::make_binary(ast::Op::Or, std::move(loop_broken_), std::move(held), st.range)
                                    : std::move(held);
        broke_ = true;
        return;
      }
      if (varying_ifs_ > 0)
        unsupported(st.range, "'break' under a condition that varies in time, outside a loop");
      broke_ = true;
      return;
    case StatementKind::Return:
      unsupported(st.range, "'return' is only allowed in functions");
    case StatementKind::If:
      exec_if(st.branches, 0, vals);
      return;
    case StatementKind::For:
      exec_for(st, 0, vals);
      return;
    case StatementKind::While:
      exec_while(st, vals);
      return;
    case StatementKind::When:
      exec_when(st, vals);
      return;
    }
  }

  void assign(const Statement &st, Values &vals) {
    std::vector<Tensor> results;
    ClassNode *fn = st.value->kind == ExprKind::Call ? f_.lookup_function(*st.value, scope_) : nullptr;
    if (st.targets.size() > 1 || (fn && st.targets.size() == 1 && !st.targets[0])) {
      if (!fn)
        unsupported(st.value->range, "the right side of a multiple assignment must call a user function");
      results = f_.call_function(fn, *st.value, scope_, st.targets.size());
      for (Tensor &t : results)
        substitute(t, vals);
    } else {
      results.push_back(value(*st.value, vals));
    }
    for (std::size_t k = 0; k < st.targets.size() && k < results.size(); ++k) {
      if (!st.targets[k])
        continue;
      std::vector<std::int32_t> vars = vars_of(*st.targets[k]);
      Tensor &r = results[k];
      if (r.elems.size() != vars.size())
        f_.fail(DiagId::TypeMismatch, st.range,
                fmt::format("'{}' has {} element(s) but the assigned value {}", st.targets[k]->ref.str(),
                            vars.size(), r.elems.size()));
      f_.fold_numbers(r);
      for (std::size_t i = 0; i < vars.size(); ++i) {
        if (!branch_vars_ && when_vars_.count(vars[i]))
          unsupported(st.range, "'" + m_.variables[vars[i]].name + "' is assigned inside and outside a when-statement");
        check_size(*r.elems[i], vars[i], st.range);
        vals[vars[i]] = std::move(r.elems[i]);
      }
    }
  }

  void call(const Statement &st, Values &vals) {
    const Expr &c = *st.value;
    const std::string n = c.ref.str();
    if (n != "assert" && n != "terminate" && n != "reinit")
      unsupported(st.range, "the statement '" + n + "(...)' is not supported in a model's algorithm");
    if (n == "reinit" && !branch_vars_)
      unsupported(st.range, "reinit() is only allowed inside a when-statement");
    if (n != "assert" && varying_ifs_ > 0)
      unsupported(st.range, "'" + n + "(...)' under a condition that varies in time");
    auto flat_call = std::make_unique<Expr>(ExprKind::Call, c.range);
    flat_call->resolved = true;
    flat_call->ref.parts.push_back(ast::RefPart{n, {}});
    for (std::size_t i = 0; i < c.args.size(); ++i) {
      if (n == "reinit" && i == 0) {
        Tensor t = f_.expr(*c.args[0], scope_);
        if (!t.is_scalar() || t.elems[0]->kind != ExprKind::Ref || t.elems[0]->var < 0)
          f_.fail(DiagId::TypeMismatch, c.args[0]->range, "the first argument of reinit() must be a variable");
        flat_call->args.push_back(std::move(t.elems[0]));
        continue;
      }
      Tensor t = value(*c.args[i], vals);
      if (!t.is_scalar())
        unsupported(c.args[i]->range, "array arguments of '" + n + "' are not supported in an algorithm");
      flat_call->args.push_back(std::move(t.elems[0]));
    }
    // An assert under varying conditions checks only where they hold.
    if (n == "assert" && !guards_.empty() && !flat_call->args.empty()) {
      ExprPtr held = guards_[0]->clone();
      for (std::size_t g = 1; g < guards_.size(); ++g)
        held = ast::make_binary(ast::Op::And, std::move(held), guards_[g]->clone(), c.range);
      flat_call->args[0] = ast::make_binary(ast::Op::Or, ast::make_unary(ast::Op::Not, std::move(held), c.range),
                                            std::move(flat_call->args[0]), c.range);
    }
    ast::Equation eq;
    eq.kind = EquationKind::Call;
    eq.range = st.range;
    eq.lhs = std::move(flat_call);
    (branch_out_ ? *branch_out_ : out_).push_back(std::move(eq));
  }

  std::vector<ExprPtr> guards_; ///< conditions of the varying `if` branches around (negated for else)
  std::vector<ast::Equation> *branch_out_ = nullptr; ///< a when-branch's equations, while one runs

  void exec_if(const std::vector<ast::StatementBranch> &branches, std::size_t i, Values &vals) {
    if (i == branches.size())
      return;
    const auto &b = branches[i];
    if (!b.condition) {
      exec(b.body, vals);
      return;
    }
    ExprPtr c = condition(*b.condition, vals);
    const int known = decided(*c, b.condition->range);
    if (known >= 0) {
      if (known)
        exec(b.body, vals);
      else
        exec_if(branches, i + 1, vals);
      return;
    }
    Values other = clone_values(vals);
    ++varying_ifs_;
    guards_.push_back(c->clone());
    // A break in a branch ends it (broke_) and leaves the loop where the
    // branch's conditions hold (loop_broken_, null on entry: exec() calls
    // no statement while it is set); the other branches do not see it.
    exec(b.body, vals);
    broke_ = false;
    ExprPtr broken_here = std::move(loop_broken_);
    guards_.back() = ast::make_unary(ast::Op::Not, c->clone(), c->range);
    exec_if(branches, i + 1, other);
    broke_ = false;
    guards_.pop_back();
    --varying_ifs_;
    join(*c, vals, other, b.range);
    if (broken_here)
      loop_broken_ = loop_broken_ ? ast::make_binary(ast::Op::Or, std::move(broken_here), std::move(loop_broken_), b.range)
                                  : std::move(broken_here);
  }

  /// vals := if c then vals else other, per variable either side assigned.
  void join(const Expr &c, Values &vals, Values &other, SourceRange r) {
    std::set<std::int32_t> keys;
    for (const auto &[v, e] : vals)
      keys.insert(v);
    for (const auto &[v, e] : other)
      keys.insert(v);
    for (std::int32_t v : keys) {
      ExprPtr yes = vals.count(v) ? std::move(vals[v]) : read(v, {}, r);
      ExprPtr no = other.count(v) ? std::move(other[v]) : read(v, {}, r);
      if (!yes)
        yes = var_ref(m_, v, r);
      if (!no)
        no = var_ref(m_, v, r);
      if (print_expr(*yes) == print_expr(*no)) {
        vals[v] = std::move(yes);
        continue;
      }
      auto e = std::make_unique<Expr>(ExprKind::If, r);
      e->args.push_back(c.clone());
      e->args.push_back(std::move(yes));
      e->args.push_back(std::move(no));
      check_size(*e, v, r);
      vals[v] = std::move(e);
    }
  }

  void exec_for(const Statement &st, std::size_t index, Values &vals) {
    if (index == st.indices.size()) {
      f_.count_statement_loop_run(st.range);
      exec(st.body, vals);
      return;
    }
    const ast::ForIndex &fi = st.indices[index];
    if (!fi.range)
      unsupported(fi.loc, "a for-loop without a range");
    if (index == 0)
      ++loops_;
    for (double v : f_.eval_range(*fi.range, scope_)) {
      env_.values.emplace_back(fi.name, v);
      exec_for(st, index + 1, vals);
      env_.values.pop_back();
      if (broke_)
        break;
    }
    if (index == 0) {
      --loops_;
      broke_ = false;
      loop_broken_.reset(); // a break leaves this loop only
    }
  }

  void exec_while(const Statement &st, Values &vals) {
    ++loops_;
    exec_while_body(st, vals);
    --loops_;
    loop_broken_.reset();
  }

  void exec_while_body(const Statement &st, Values &vals) {
    for (long n = 0;; ++n) {
      if (n > kMaxWhileIterations)
        unsupported(st.range, "the while-loop runs more than 100000 times");
      f_.count_statement_loop_run(st.range);
      ExprPtr c = condition(*st.value, vals);
      const int known = decided(*c, st.value->range);
      if (known < 0)
        unsupported(st.value->range, "a while-loop whose condition varies in time");
      if (!known)
        return;
      exec(st.body, vals);
      if (broke_) {
        broke_ = false;
        return;
      }
    }
  }

  void exec_when(const Statement &st, Values &vals) {
    if (branch_vars_ || varying_ifs_ > 0 || !env_.values.empty())
      unsupported(st.range, "a when-statement must be at the top of the algorithm section");
    std::vector<const Expr *> plain, targets;
    for (const auto &b : st.branches)
      assigned_names(b.body, targets, plain);
    std::set<std::int32_t> mine;
    std::vector<std::int32_t> order;
    for (const Expr *t : targets)
      for (std::int32_t v : vars_of(*whole(*t)))
        if (mine.insert(v).second)
          order.push_back(v);
    ast::Equation eq;
    eq.kind = EquationKind::When;
    eq.range = st.range;
    for (const auto &b : st.branches) {
      Tensor c = value(*b.condition, vals);
      ExprPtr cond;
      if (c.is_scalar()) {
        cond = std::move(c.elems[0]);
      } else {
        cond = std::make_unique<Expr>(ExprKind::Array, b.condition->range);
        for (auto &x : c.elems)
          cond->args.push_back(std::move(x));
      }
      ast::EquationBranch fb{std::move(cond), {}, b.range};
      Values branch = clone_values(vals);
      for (std::int32_t v : mine)
        branch.erase(v);
      branch_vars_ = &mine;
      branch_out_ = &fb.body;
      exec(b.body, branch);
      branch_vars_ = nullptr;
      branch_out_ = nullptr;
      for (std::int32_t v : order) {
        auto it = branch.find(v);
        emit(v, it == branch.end() ? ast::make_call1("pre", var_ref(m_, v, b.range), b.range) : std::move(it->second), b.range,
             fb.body);
      }
      eq.branches.push_back(std::move(fb));
    }
    out_.push_back(std::move(eq));
    for (std::int32_t v : order)
      when_done_.insert(v);
  }

  void emit(std::int32_t v, ExprPtr value, SourceRange r, std::vector<ast::Equation> &out) {
    ast::Equation eq;
    eq.kind = EquationKind::Simple;
    eq.range = r;
    Tensor l = Tensor::scalar(var_ref(m_, v, r));
    Tensor rhs = Tensor::scalar(std::move(value));
    f_.equal_elements(eq, l, rhs, out);
  }
};

} // namespace

ExprPtr var_ref(const flat::Model &m, std::int32_t v, SourceRange r) {
  ExprPtr e = ast::make_ref(m.variables[static_cast<std::size_t>(v)].name, r);
  e->var = v;
  return e;
}

void Flattener::algorithm_section(const ast::AlgorithmSection &alg, const Scope &s, std::vector<ast::Equation> &out) {
  SectionRunner(*this, alg, s, out).run();
}

} // namespace mo::frontend::detail
