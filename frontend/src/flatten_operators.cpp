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
//   - else, `+` and `-` of arrays of one size, `*` and `/` of an array by a
//     scalar and `-a` apply to each element (MLS 10.6).
// The '0' operator (sum of records) is not supported: it is reported.
#include "flattener.hpp"

#include <fmt/format.h>

#include <algorithm>

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

std::vector<Tensor> copies(const std::vector<Tensor> &ts) {
  std::vector<Tensor> out;
  for (const Tensor &t : ts)
    out.push_back(clone_tensor(t));
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
        one.push_back(clone_tensor(operands[k]));
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
  if (std::optional<Tensor> r = overloaded_elementwise(op, operands, site))
    return std::move(*r);
  std::string kinds;
  for (const Tensor &t : operands) {
    const std::string kind = t.record ? t.record->cls->path() : t.dims.empty() ? "a number" : "an array";
    kinds += (kinds.empty() ? "" : " and ") + kind + (t.record && !t.dims.empty() ? " array" : "");
  }
  fail(DiagId::TypeMismatch, site.range,
       fmt::format("no function of operator {} of '{}' takes {}{}", name, record->path(), kinds,
                   functions.empty() ? " (the record defines no such operator)" : ""));
}

std::optional<Tensor> Flattener::overloaded_elementwise(Op op, const std::vector<Tensor> &operands, const Expr &site) {
  // MLS 10.6 for operator records: `+`, `-` of arrays of one size and
  // `*`, `/` of an array by a scalar apply to each element; `-a` too.
  const Tensor *array = nullptr;
  for (const Tensor &t : operands)
    if (!t.dims.empty()) {
      if (array && t.dims != array->dims)
        return std::nullopt;
      array = &t;
    }
  const bool all_arrays = std::all_of(operands.begin(), operands.end(), [](const Tensor &t) { return !t.dims.empty(); });
  const bool any_size = (op == Op::Add || op == Op::Sub || op == Op::Neg) && all_arrays;
  const bool by_scalar = (op == Op::Mul || op == Op::Div) && operands.size() == 2 &&
                         (operands[0].dims.empty() || operands[1].dims.empty());
  if (!array || !(any_size || by_scalar))
    return std::nullopt;
  std::size_t count = 1;
  for (int d : array->dims)
    count *= static_cast<std::size_t>(d);
  Tensor out;
  out.dims = array->dims;
  for (std::size_t k = 0; k < count; ++k) {
    std::vector<Tensor> element;
    for (const Tensor &t : operands) {
      Tensor x;
      x.record = t.record;
      const std::size_t stride = t.dims.empty() ? t.elems.size() : t.elems.size() / count;
      const std::size_t first = t.dims.empty() ? 0 : k * stride;
      for (std::size_t j = 0; j < stride; ++j)
        x.elems.push_back(t.elems[first + j]->clone());
      element.push_back(std::move(x));
    }
    Tensor r = element[0].record || (element.size() == 2 && element[1].record)
                   ? overloaded_operator(op, std::move(element), site)
                   : Tensor{};
    if (!r.dims.empty() || (k > 0 && !same_record_type(r.record, out.record)))
      return std::nullopt;
    out.record = r.record;
    for (auto &e : r.elems)
      out.elems.push_back(std::move(e));
  }
  return out;
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
