// Operator records (MLS 14): `a + b` of records calls the function of the
// record's operator '+' that takes them; `R(x)` calls R's 'constructor'. The
// MSL's Complex (Complex.mo) is the operator record the library builds on:
// ComplexMath, ComplexBlocks and the QuasiStationary libraries.
//
// Resolution, as MLS 14.3 and 14.4 give it for the cases the MSL uses:
//   - the functions of 'op' of the first operator record among the operands
//     are tried in turn; the first that takes the operands as they are
//     (records of its inputs' classes, numbers, dimensions) is called;
//   - else a number operand beside the record is converted by the record's
//     'constructor' (Complex(2)) and the functions are tried again.
// Element-wise operators on arrays of records and the '0' operator (sum of
// records) are not supported: they are reported.
#include "flattener.hpp"

#include <fmt/format.h>

namespace mo::frontend::detail {

using ast::Expr;
using ast::Op;

namespace {

/// The operator's name as an operator record declares it, or "" for one
/// that cannot be overloaded.
std::string operator_name(Op op, bool unary) {
  switch (op) {
  case Op::Add: return "'+'";
  case Op::Sub: return "'-'";
  case Op::Neg: return unary ? "'-'" : "";
  case Op::Mul: return "'*'";
  case Op::Div: return "'/'";
  case Op::Pow: return "'^'";
  case Op::Eq: return "'=='";
  case Op::Ne: return "'<>'";
  case Op::Lt: return "'<'";
  case Op::Le: return "'<='";
  case Op::Gt: return "'>'";
  case Op::Ge: return "'>='";
  case Op::And: return "'and'";
  case Op::Or: return "'or'";
  case Op::Not: return "'not'";
  default: return "";
  }
}

Tensor copy(const Tensor &t) {
  Tensor out;
  out.dims = t.dims;
  out.record = t.record;
  for (const auto &e : t.elems)
    out.elems.push_back(e ? e->clone() : nullptr);
  return out;
}

std::vector<Tensor> copies(const std::vector<Tensor> &ts) {
  std::vector<Tensor> out;
  for (const Tensor &t : ts)
    out.push_back(copy(t));
  return out;
}

bool is_operator_record(const Tensor &t) {
  return t.record && t.record->cls && t.record->cls->def &&
         t.record->cls->def->restriction == ast::Restriction::OperatorRecord;
}

} // namespace

std::vector<ClassNode *> Flattener::operator_functions(ClassNode *record, const std::string &name) {
  ClassNode *op = find_member_class(record, name);
  if (!op || !op->def)
    return {};
  if (op->def->restriction == ast::Restriction::Function)
    return {op};
  std::vector<ClassNode *> out;
  if (op->def->restriction != ast::Restriction::Operator)
    return out;
  for (const auto &nested : op->def->classes) // declaration order
    if (ClassNode *fn = find_member_class(op, nested->name); fn && fn->def &&
                                                               fn->def->restriction == ast::Restriction::Function)
      out.push_back(fn);
  return out;
}

Tensor Flattener::overloaded_operator(Op op, std::vector<Tensor> operands, const Expr &site) {
  const std::string name = operator_name(op, operands.size() == 1);
  const Tensor *holder = nullptr;
  for (const Tensor &t : operands)
    if (!holder && is_operator_record(t))
      holder = &t;
  if (!holder || name.empty()) {
    for (const Tensor &t : operands)
      no_record(t, site.range, op);
    fail(DiagId::TypeMismatch, site.range, "operator '" + std::string(ast::op_text(op)) + "' on records");
  }
  ClassNode *record = holder->record->cls;
  const std::vector<ClassNode *> functions = operator_functions(record, name);
  const auto first_taking = [&](const std::vector<Tensor> &values) -> std::optional<Tensor> {
    for (ClassNode *fn : functions)
      if (auto r = apply_function(fn, copies(values), site))
        return r;
    return std::nullopt;
  };
  if (auto r = first_taking(operands))
    return std::move(*r);
  if (operands.size() == 2) { // a number beside the record: converted by its constructor
    for (std::size_t k = 0; k < 2; ++k) {
      if (operands[k].record || !operands[1 - k].record || operands[1 - k].record->cls != record)
        continue;
      for (ClassNode *ctor : operator_functions(record, "'constructor'")) {
        std::vector<Tensor> one;
        one.push_back(copy(operands[k]));
        if (auto converted = apply_function(ctor, std::move(one), site)) {
          std::vector<Tensor> values = copies(operands);
          values[k] = std::move(*converted);
          if (auto r = first_taking(values))
            return std::move(*r);
          break;
        }
      }
    }
  }
  std::string kinds;
  for (const Tensor &t : operands) {
    const std::string kind = t.record ? t.record->cls->path() : t.dims.empty() ? "a number" : "an array";
    kinds += (kinds.empty() ? "" : " and ") + kind + (t.record && !t.dims.empty() ? " array" : "");
  }
  fail(DiagId::TypeMismatch, site.range,
       fmt::format("no function of operator {} of '{}' takes {}{}", name, record->path(), kinds,
                   functions.empty() ? " (the record defines no such operator)" : ""));
}

std::optional<Tensor> Flattener::overloaded_constructor(ClassNode *record, const Expr &call, const Scope &s) {
  if (!record->def || record->def->restriction != ast::Restriction::OperatorRecord || !call.named.empty())
    return std::nullopt;
  const std::vector<ClassNode *> ctors = operator_functions(record, "'constructor'");
  if (ctors.empty())
    return std::nullopt;
  std::vector<Tensor> args;
  for (const auto &a : call.args)
    args.push_back(expr(*a, s));
  for (ClassNode *ctor : ctors)
    if (auto r = apply_function(ctor, copies(args), call))
      return r;
  return std::nullopt;
}

} // namespace mo::frontend::detail
