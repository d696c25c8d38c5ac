#include "mo/frontend/printer.hpp"

#include <cmath>
#include <fmt/format.h>

namespace mo::frontend {

using namespace ast;

namespace {

// Precedence levels of Modelica's expression grammar, loosest first.
enum Prec : int {
  kIf = 0,       // if-expression, range
  kOr = 1,
  kAnd = 2,
  kNot = 3,
  kRel = 4,
  kAdd = 5,      // binary + -, and unary + - (only leftmost in a sum)
  kMul = 6,
  kPow = 7,
  kPrimary = 8,
};

int binary_prec(Op op) {
  switch (op) {
  case Op::Or: return kOr;
  case Op::And: return kAnd;
  case Op::Lt: case Op::Le: case Op::Gt: case Op::Ge: case Op::Eq: case Op::Ne: return kRel;
  case Op::Add: case Op::Sub: case Op::ElemAdd: case Op::ElemSub: return kAdd;
  case Op::Mul: case Op::Div: case Op::ElemMul: case Op::ElemDiv: return kMul;
  case Op::Pow: case Op::ElemPow: return kPow;
  case Op::Neg: case Op::Plus: return kAdd;
  case Op::Not: return kNot;
  }
  return kPrimary;
}

int prec_of(const Expr &e) {
  switch (e.kind) {
  case ExprKind::If:
  case ExprKind::Range: return kIf;
  case ExprKind::Unary:
  case ExprKind::Binary: return binary_prec(e.op);
  case ExprKind::Real:
  case ExprKind::Integer: return std::signbit(e.number) ? kAdd : kPrimary; // prints with '-'
  case ExprKind::String:
  case ExprKind::Boolean:
  case ExprKind::Ref:
  case ExprKind::Call:
  case ExprKind::Array:
  case ExprKind::Matrix:
  case ExprKind::Tuple:
  case ExprKind::Colon:
  case ExprKind::End: return kPrimary;
  }
  return kPrimary;
}

bool plain_ident(const std::string &s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_'))
    return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
      return false;
  // `der` and `initial` are keywords that are also function names: they are
  // never variable names, so they print bare.
  static const char *const kKeywords[] = {
      "algorithm", "and", "annotation", "block", "break", "class", "connect", "connector",
      "constant", "constrainedby", "constraint", "discrete", "each", "else", "elseif",
      "elsewhen", "encapsulated", "end", "enumeration", "equation", "expandable", "extends",
      "external", "false", "final", "flow", "for", "function", "if", "import", "impure", "in",
      "inner", "input", "loop", "model", "not", "operator", "optimization", "or",
      "outer", "output", "package", "parameter", "partial", "protected", "public", "pure",
      "record", "redeclare", "replaceable", "return", "stream", "then", "true", "type", "when",
      "while", "within"};
  for (const char *k : kKeywords)
    if (s == k)
      return false;
  return true;
}

class Printer {
public:
  Printer(std::string &out, const VarNamer &namer) : out_(out), namer_(namer) {}

  void expr(const Expr &e, int min_prec) {
    bool paren = prec_of(e) < min_prec;
    if (paren) out_ += '(';
    body(e);
    if (paren) out_ += ')';
  }

  void ref_text(const ComponentRef &r) { ref(r); }

private:
  std::string &out_;
  const VarNamer &namer_;

  void ref(const ComponentRef &r) {
    if (r.global) out_ += '.';
    for (std::size_t i = 0; i < r.parts.size(); ++i) {
      if (i) out_ += '.';
      out_ += quote_name(r.parts[i].name);
      subscripts(r.parts[i].subscripts);
    }
  }

  void subscripts(const std::vector<ExprPtr> &subs) {
    if (subs.empty()) return;
    out_ += '[';
    for (std::size_t i = 0; i < subs.size(); ++i) {
      if (i) out_ += ", ";
      expr(*subs[i], kIf);
    }
    out_ += ']';
  }

  void list(const std::vector<ExprPtr> &xs) {
    for (std::size_t i = 0; i < xs.size(); ++i) {
      if (i) out_ += ", ";
      if (xs[i]) expr(*xs[i], kIf);
    }
  }

  void iterators(const std::vector<ForIndex> &its) {
    if (its.empty()) return;
    out_ += " for ";
    for (std::size_t i = 0; i < its.size(); ++i) {
      if (i) out_ += ", ";
      out_ += quote_name(its[i].name);
      if (its[i].range) {
        out_ += " in ";
        expr(*its[i].range, kIf);
      }
    }
  }

  void body(const Expr &e) {
    switch (e.kind) {
    case ExprKind::Real:
      out_ += format_real(e.number);
      return;
    case ExprKind::Integer:
      out_ += fmt::format("{}", static_cast<long long>(e.number));
      return;
    case ExprKind::String:
      out_ += '"' + escape_string(e.text) + '"';
      return;
    case ExprKind::Boolean:
      out_ += e.number != 0 ? "true" : "false";
      return;
    case ExprKind::Ref:
      if (e.var >= 0 && namer_) out_ += quote_name(namer_(e.var));
      else ref(e.ref);
      return;
    case ExprKind::Call:
      ref(e.ref);
      out_ += '(';
      list(e.args);
      for (std::size_t i = 0; i < e.named.size(); ++i) {
        if (i || !e.args.empty()) out_ += ", ";
        out_ += quote_name(e.named[i].name) + " = ";
        expr(*e.named[i].value, kIf);
      }
      iterators(e.iterators);
      out_ += ')';
      return;
    case ExprKind::Unary:
      out_ += e.op == Op::Not ? "not " : op_text(e.op);
      // `-a*b` would read back as -(a*b): the operand of unary +/- is a term.
      expr(*e.args[0], e.op == Op::Not ? kRel : kMul);
      return;
    case ExprKind::Binary: {
      int p = binary_prec(e.op);
      if (p == kPow) {
        expr(*e.args[0], kPrimary);
        out_ += op_text(e.op);
        expr(*e.args[1], kPrimary);
        return;
      }
      // Relations do not chain; + - * / are left-associative.
      expr(*e.args[0], p == kRel ? kAdd : p);
      out_ += ' ';
      out_ += op_text(e.op);
      out_ += ' ';
      expr(*e.args[1], p == kRel ? kAdd : p + 1);
      return;
    }
    case ExprKind::If:
      for (std::size_t i = 0; i + 1 < e.args.size(); i += 2) {
        out_ += i == 0 ? "if " : " elseif ";
        expr(*e.args[i], kIf);
        out_ += " then ";
        expr(*e.args[i + 1], kIf);
      }
      out_ += " else ";
      expr(*e.args.back(), kIf);
      return;
    case ExprKind::Array:
      out_ += '{';
      list(e.args);
      iterators(e.iterators);
      out_ += '}';
      return;
    case ExprKind::Matrix:
      out_ += '[';
      for (std::size_t r = 0; r < e.rows.size(); ++r) {
        if (r) out_ += "; ";
        list(e.rows[r]);
      }
      out_ += ']';
      return;
    case ExprKind::Range:
      for (std::size_t i = 0; i < e.args.size(); ++i) {
        if (i) out_ += ':';
        expr(*e.args[i], kOr);
      }
      return;
    case ExprKind::Tuple:
      out_ += '(';
      list(e.args);
      out_ += ')';
      return;
    case ExprKind::Colon:
      out_ += ':';
      return;
    case ExprKind::End:
      out_ += "end";
      return;
    }
  }
};

} // namespace

std::string quote_name(const std::string &name) {
  if (plain_ident(name))
    return name;
  if (name.size() >= 2 && name.front() == '\'' && name.back() == '\'')
    return name; // a Modelica quoted identifier, quotes included
  return "`" + name + "`";
}

std::string ast::ComponentRef::str() const {
  std::string out;
  Printer(out, nullptr).ref_text(*this);
  return out;
}

std::string format_real(double v) {
  if (std::isnan(v))
    return "(0.0/0.0)";
  if (std::isinf(v))
    return v > 0 ? "(1.0/0.0)" : "(-1.0/0.0)";
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".eE") == std::string::npos)
    s += '.';
  return s;
}

void print_expr(std::string &out, const Expr &e, const VarNamer &namer) {
  Printer(out, namer).expr(e, kIf);
}

std::string print_expr(const Expr &e, const VarNamer &namer) {
  std::string out;
  print_expr(out, e, namer);
  return out;
}

} // namespace mo::frontend
