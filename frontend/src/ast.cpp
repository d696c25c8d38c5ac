#include "mo/frontend/ast.hpp"

#include <cmath>

#include <vector>

namespace mo::frontend::ast {

const char *op_text(Op op) {
  switch (op) {
  case Op::Add: return "+";
  case Op::Sub: return "-";
  case Op::Mul: return "*";
  case Op::Div: return "/";
  case Op::Pow: return "^";
  case Op::ElemAdd: return ".+";
  case Op::ElemSub: return ".-";
  case Op::ElemMul: return ".*";
  case Op::ElemDiv: return "./";
  case Op::ElemPow: return ".^";
  case Op::Lt: return "<";
  case Op::Le: return "<=";
  case Op::Gt: return ">";
  case Op::Ge: return ">=";
  case Op::Eq: return "==";
  case Op::Ne: return "<>";
  case Op::And: return "and";
  case Op::Or: return "or";
  case Op::Neg: return "-";
  case Op::Plus: return "+";
  case Op::Not: return "not";
  }
  return "?";
}

const char *variability_text(Variability v) {
  switch (v) {
  case Variability::Continuous: return "";
  case Variability::Discrete: return "discrete";
  case Variability::Parameter: return "parameter";
  case Variability::Constant: return "constant";
  }
  return "";
}

const char *restriction_text(Restriction r) {
  switch (r) {
  case Restriction::Class: return "class";
  case Restriction::Model: return "model";
  case Restriction::Record: return "record";
  case Restriction::OperatorRecord: return "operator record";
  case Restriction::Block: return "block";
  case Restriction::Connector: return "connector";
  case Restriction::ExpandableConnector: return "expandable connector";
  case Restriction::Type: return "type";
  case Restriction::Package: return "package";
  case Restriction::Function: return "function";
  case Restriction::Operator: return "operator";
  case Restriction::Optimization: return "optimization";
  }
  return "class";
}

/// Moves every child out of `e` into `out` (used by the iterative destructor
/// and clone).
static void take_children(Expr &e, std::vector<ExprPtr> &out) {
  for (auto &a : e.args)
    if (a) out.push_back(std::move(a));
  for (auto &n : e.named)
    if (n.value) out.push_back(std::move(n.value));
  for (auto &it : e.iterators)
    if (it.range) out.push_back(std::move(it.range));
  for (auto &row : e.rows)
    for (auto &x : row)
      if (x) out.push_back(std::move(x));
  for (auto &p : e.ref.parts)
    for (auto &s : p.subscripts)
      if (s) out.push_back(std::move(s));
}

// Deep trees (long flow sums, nested ifs) must not overflow the stack when
// freed: children are detached and freed from an explicit work list.
Expr::~Expr() {
  std::vector<ExprPtr> pending;
  take_children(*this, pending);
  while (!pending.empty()) {
    ExprPtr e = std::move(pending.back());
    pending.pop_back();
    take_children(*e, pending);
  }
}

ExprPtr Expr::clone() const {
  // Iterative deep copy: a work list of (source, destination) pairs.
  auto root = std::make_unique<Expr>(kind, range);
  std::vector<std::pair<const Expr *, Expr *>> work{{this, root.get()}};
  auto copy = [&work](const ExprPtr &src) -> ExprPtr {
    if (!src) return nullptr;
    auto dst = std::make_unique<Expr>(src->kind, src->range);
    work.emplace_back(src.get(), dst.get());
    return dst;
  };
  while (!work.empty()) {
    auto [src, dst] = work.back();
    work.pop_back();
    dst->op = src->op;
    dst->number = src->number;
    dst->var = src->var;
    dst->resolved = src->resolved;
    dst->text = src->text;
    dst->ref.global = src->ref.global;
    for (const auto &p : src->ref.parts) {
      RefPart part{p.name, {}};
      for (const auto &s : p.subscripts)
        part.subscripts.push_back(copy(s));
      dst->ref.parts.push_back(std::move(part));
    }
    for (const auto &a : src->args)
      dst->args.push_back(copy(a));
    for (const auto &n : src->named)
      dst->named.push_back(NamedArg{n.name, copy(n.value)});
    for (const auto &it : src->iterators)
      dst->iterators.push_back(ForIndex{it.name, copy(it.range), it.loc});
    for (const auto &row : src->rows) {
      std::vector<ExprPtr> r;
      for (const auto &x : row)
        r.push_back(copy(x));
      dst->rows.push_back(std::move(r));
    }
  }
  return root;
}

bool same_expr(const Expr &a, const Expr &b) {
  // Iterative, like clone(): pairs still to compare.
  std::vector<std::pair<const Expr *, const Expr *>> work{{&a, &b}};
  auto push = [&work](const ExprPtr &x, const ExprPtr &y) {
    if (!x || !y)
      return !x && !y;
    work.emplace_back(x.get(), y.get());
    return true;
  };
  while (!work.empty()) {
    auto [x, y] = work.back();
    work.pop_back();
    if (x->kind != y->kind || x->op != y->op || x->var != y->var || x->text != y->text ||
        x->ref.global != y->ref.global || x->ref.parts.size() != y->ref.parts.size() ||
        x->args.size() != y->args.size() || x->named.size() != y->named.size() ||
        x->iterators.size() != y->iterators.size() || x->rows.size() != y->rows.size())
      return false;
    if (!(x->number == y->number) && !(std::isnan(x->number) && std::isnan(y->number)))
      return false;
    for (std::size_t i = 0; i < x->ref.parts.size(); ++i) {
      const RefPart &p = x->ref.parts[i], &q = y->ref.parts[i];
      if (p.name != q.name || p.subscripts.size() != q.subscripts.size())
        return false;
      for (std::size_t k = 0; k < p.subscripts.size(); ++k)
        if (!push(p.subscripts[k], q.subscripts[k]))
          return false;
    }
    for (std::size_t i = 0; i < x->args.size(); ++i)
      if (!push(x->args[i], y->args[i]))
        return false;
    for (std::size_t i = 0; i < x->named.size(); ++i)
      if (x->named[i].name != y->named[i].name || !push(x->named[i].value, y->named[i].value))
        return false;
    for (std::size_t i = 0; i < x->iterators.size(); ++i)
      if (x->iterators[i].name != y->iterators[i].name || !push(x->iterators[i].range, y->iterators[i].range))
        return false;
    for (std::size_t i = 0; i < x->rows.size(); ++i) {
      if (x->rows[i].size() != y->rows[i].size())
        return false;
      for (std::size_t k = 0; k < x->rows[i].size(); ++k)
        if (!push(x->rows[i][k], y->rows[i][k]))
          return false;
    }
  }
  return true;
}

ExprPtr make_real(double v, SourceRange r) {
  auto e = std::make_unique<Expr>(ExprKind::Real, r);
  e->number = v;
  return e;
}
ExprPtr make_integer(double v, SourceRange r) {
  auto e = std::make_unique<Expr>(ExprKind::Integer, r);
  e->number = v;
  return e;
}
ExprPtr make_bool(bool v, SourceRange r) {
  auto e = std::make_unique<Expr>(ExprKind::Boolean, r);
  e->number = v ? 1 : 0;
  return e;
}
ExprPtr make_ref(std::string name, SourceRange r) {
  auto e = std::make_unique<Expr>(ExprKind::Ref, r);
  e->ref.parts.push_back(RefPart{std::move(name), {}});
  return e;
}
ExprPtr make_unary(Op op, ExprPtr a, SourceRange r) {
  auto e = std::make_unique<Expr>(ExprKind::Unary, r);
  e->op = op;
  e->args.push_back(std::move(a));
  return e;
}
ExprPtr make_binary(Op op, ExprPtr a, ExprPtr b, SourceRange r) {
  auto e = std::make_unique<Expr>(ExprKind::Binary, r);
  e->op = op;
  e->args.push_back(std::move(a));
  e->args.push_back(std::move(b));
  return e;
}
ExprPtr make_call(std::string fn, std::vector<ExprPtr> args, SourceRange r) {
  auto e = std::make_unique<Expr>(ExprKind::Call, r);
  e->resolved = true;
  e->ref.parts.push_back(RefPart{std::move(fn), {}});
  e->args = std::move(args);
  return e;
}

ExprPtr make_call1(std::string fn, ExprPtr a, SourceRange r) {
  std::vector<ExprPtr> args;
  args.push_back(std::move(a));
  return make_call(std::move(fn), std::move(args), r);
}

std::string TypeName::str() const {
  std::string s = global ? "." : "";
  for (std::size_t i = 0; i < parts.size(); ++i)
    s += (i ? "." : "") + parts[i];
  return s;
}

std::string unescape_string(std::string_view body) {
  std::string out;
  out.reserve(body.size());
  for (std::size_t i = 0; i < body.size(); ++i) {
    char c = body[i];
    if (c != '\\' || i + 1 == body.size()) {
      out += c;
      continue;
    }
    char n = body[++i];
    switch (n) {
    case 'n': out += '\n'; break;
    case 't': out += '\t'; break;
    case 'r': out += '\r'; break;
    case 'a': out += '\a'; break;
    case 'b': out += '\b'; break;
    case 'f': out += '\f'; break;
    case 'v': out += '\v'; break;
    default: out += n; break; // \" \' \? \\ and anything else: the character
    }
  }
  return out;
}

std::string escape_string(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
    case '"': out += "\\\""; break;
    case '\\': out += "\\\\"; break;
    case '\n': out += "\\n"; break;
    case '\t': out += "\\t"; break;
    case '\r': out += "\\r"; break;
    case '\a': out += "\\a"; break;
    case '\b': out += "\\b"; break;
    case '\f': out += "\\f"; break;
    case '\v': out += "\\v"; break;
    default: out += c; break; // other bytes are valid inside a Modelica string
    }
  }
  return out;
}

} // namespace mo::frontend::ast
