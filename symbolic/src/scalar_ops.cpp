#include "scalar_ops.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace mo::symbolic::detail {

namespace {
double boolean(bool value) { return value ? 1.0 : 0.0; }
} // namespace

double apply_scalar(ExprKind kind, double a, double b, double c) {
  switch (kind) {
  case ExprKind::Constant:
  case ExprKind::Symbol:
  case ExprKind::Der:
  case ExprKind::Pre:
  case ExprKind::Delay:
    throw std::logic_error("internal error: apply_scalar on leaf kind " +
                           std::string(kind_name(kind)));
  case ExprKind::ArgList:
  case ExprKind::External:  // the evaluator and ExprArena::external() read the argument list
    throw std::logic_error("internal error: apply_scalar on " + std::string(kind_name(kind)));
  case ExprKind::Add: return a + b;
  case ExprKind::Sub: return a - b;
  case ExprKind::Mul: return a * b;
  case ExprKind::Div: return a / b;
  case ExprKind::Neg: return -a;
  case ExprKind::Pow: return std::pow(a, b);
  case ExprKind::Sin: return std::sin(a);
  case ExprKind::Cos: return std::cos(a);
  case ExprKind::Tan: return std::tan(a);
  case ExprKind::Asin: return std::asin(a);
  case ExprKind::Acos: return std::acos(a);
  case ExprKind::Atan: return std::atan(a);
  case ExprKind::Atan2: return std::atan2(a, b);
  case ExprKind::Sinh: return std::sinh(a);
  case ExprKind::Cosh: return std::cosh(a);
  case ExprKind::Tanh: return std::tanh(a);
  case ExprKind::Exp: return std::exp(a);
  case ExprKind::Log: return std::log(a);
  case ExprKind::Log10: return std::log10(a);
  case ExprKind::Sqrt: return std::sqrt(a);
  case ExprKind::Abs: return std::fabs(a);
  case ExprKind::Sign:
    if (std::isnan(a)) return a;
    return a > 0 ? 1.0 : (a < 0 ? -1.0 : 0.0);
  // NaN in either operand gives NaN, so that min/max are commutative.
  case ExprKind::Min:
    if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::quiet_NaN();
    return a < b ? a : b;
  case ExprKind::Max:
    if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::quiet_NaN();
    return a > b ? a : b;
  case ExprKind::Floor: return std::floor(a);
  case ExprKind::Ceil: return std::ceil(a);
  case ExprKind::Select: return a != 0 ? b : c;
  case ExprKind::Lt: return boolean(a < b);
  case ExprKind::Le: return boolean(a <= b);
  case ExprKind::Gt: return boolean(a > b);
  case ExprKind::Ge: return boolean(a >= b);
  case ExprKind::Eq: return boolean(a == b);
  case ExprKind::Ne: return boolean(a != b);
  case ExprKind::And: return boolean(a != 0 && b != 0);
  case ExprKind::Or: return boolean(a != 0 || b != 0);
  case ExprKind::Not: return boolean(a == 0);
  case ExprKind::NoEvent: return a;
  case ExprKind::Smooth: return b;
  }
  throw std::logic_error("internal error: apply_scalar on unknown kind");
}

} // namespace mo::symbolic::detail
