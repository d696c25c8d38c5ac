// The value of a flat expression; see flat_constant.hpp.
#include "flat_constant.hpp"

#include <cmath>

namespace mo::tools {

namespace ast = frontend::ast;
namespace flat = frontend::flat;

std::optional<double> constant_value(const flat::Model& m, const ast::Expr& e) {
  switch (e.kind) {
    case ast::ExprKind::Real:
    case ast::ExprKind::Integer:
    case ast::ExprKind::Boolean:
      return e.number;
    case ast::ExprKind::Ref: {
      if (e.var < 0 || static_cast<std::size_t>(e.var) >= m.variables.size()) return std::nullopt;
      const flat::Variable& v = m.variables[static_cast<std::size_t>(e.var)];
      if (v.attr.free && constant_value(m, *v.attr.free).value_or(0.0) != 0.0) return std::nullopt;
      return v.value;
    }
    case ast::ExprKind::Unary: {
      const auto x = constant_value(m, *e.args[0]);
      if (!x) return std::nullopt;
      return e.op == ast::Op::Neg ? -*x : e.op == ast::Op::Not ? double(*x == 0.0) : *x;
    }
    case ast::ExprKind::Binary: {
      const auto a = constant_value(m, *e.args[0]), b = constant_value(m, *e.args[1]);
      if (!a || !b) return std::nullopt;
      switch (e.op) {
        case ast::Op::Add: case ast::Op::ElemAdd: return *a + *b;
        case ast::Op::Sub: case ast::Op::ElemSub: return *a - *b;
        case ast::Op::Mul: case ast::Op::ElemMul: return *a * *b;
        case ast::Op::Div: case ast::Op::ElemDiv: return *a / *b;
        case ast::Op::Pow: case ast::Op::ElemPow: return std::pow(*a, *b);
        case ast::Op::Lt: return double(*a < *b);
        case ast::Op::Le: return double(*a <= *b);
        case ast::Op::Gt: return double(*a > *b);
        case ast::Op::Ge: return double(*a >= *b);
        case ast::Op::Eq: return double(*a == *b);
        case ast::Op::Ne: return double(*a != *b);
        case ast::Op::And: return double(*a != 0.0 && *b != 0.0);
        case ast::Op::Or: return double(*a != 0.0 || *b != 0.0);
        default: return std::nullopt;
      }
    }
    case ast::ExprKind::If: {  // cond1, then1, cond2, then2, ..., else
      for (std::size_t i = 0; i + 1 < e.args.size(); i += 2) {
        const auto c = constant_value(m, *e.args[i]);
        if (!c) return std::nullopt;
        if (*c != 0.0) return constant_value(m, *e.args[i + 1]);
      }
      return e.args.empty() ? std::nullopt : constant_value(m, *e.args.back());
    }
    default:
      return std::nullopt;
  }
}

}  // namespace mo::tools
