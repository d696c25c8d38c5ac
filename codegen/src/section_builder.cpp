// Sections with each node once; see section_builder.hpp.
#include "section_builder.hpp"

#include <stdexcept>

#include "mo/symbolic/traversal.hpp"

namespace mo::codegen::detail {

using symbolic::Expr;
using symbolic::ExprKind;

Slot SlotMap::of(Expr e) {
  Slot& s = slot_.at(e.id());
  if (s == none) s = next_++;
  return s;
}

SectionBuilder::SectionBuilder(const symbolic::ExprArena& arena, SlotMap& slots, Program& program,
                               Validity valid)
    : a_(arena), slots_(slots), program_(program), valid_(std::move(valid)) {
  valid_.resize(a_.size(), 0);
}

void SectionBuilder::override_relation(Expr e, int indicator, double value_if_down) {
  overrides_[e.id()] = {indicator, value_if_down};
  if (tainted_.empty()) tainted_.assign(a_.size(), 0);
  tainted_[e.id()] = 1;
  // Every node above e: ids are topological, so one ascending sweep suffices.
  for (std::uint32_t id = e.id() + 1; id < a_.size(); ++id) {
    const Expr n(id);
    if (a_.is_leaf(n) || a_.is_constant(n)) continue;
    const std::size_t k = symbolic::arity(a_.kind(n));
    for (std::size_t i = 0; i < k && !tainted_[id]; ++i)
      tainted_[id] = tainted_[a_.operand(n, i).id()];
  }
}

bool SectionBuilder::varying_delay(Expr e) const {
  const auto it = program_.delay_lines.find(e.id());
  return it != program_.delay_lines.end() && program_.delays[static_cast<std::size_t>(it->second)].varying;
}

bool SectionBuilder::is_valid(Expr e) const {
  if (!tainted_.empty() && tainted_[e.id()]) return false;
  return valid_[e.id()] != 0;
}

void SectionBuilder::emit_node(Expr e, Section& s) {
  Instruction ins;
  ins.op = Instruction::Op::Node;
  ins.node = e;
  ins.slot = slots_.of(e);
  if (auto it = overrides_.find(e.id()); it != overrides_.end()) {
    ins.crossing = it->second.first;
    ins.value_if_down = it->second.second;
    s.uses_crossings = true;
  }
  s.code.push_back(ins);
  valid_[e.id()] = 1;
  if (!tainted_.empty()) tainted_[e.id()] = 0;
}

void SectionBuilder::require(Expr root, Section& s) {
  // Iterative post-order: a node is emitted after its operands.
  std::vector<std::pair<Expr, bool>> stack{{root, false}};
  while (!stack.empty()) {
    auto [e, expanded] = stack.back();
    if (a_.is_constant(e) || is_valid(e)) {
      stack.pop_back();
      continue;
    }
    const ExprKind kind = a_.kind(e);
    if (kind == ExprKind::Der)
      throw std::invalid_argument(
          "code generation: der() of a variable appears outside the Derivative symbols");
    if (kind == ExprKind::Delay && varying_delay(e)) {  // read at T, computed first
      if (!expanded) {
        stack.back().second = true;
        const Expr t = a_.operand(e, 1);
        if (!a_.is_constant(t) && !is_valid(t)) stack.emplace_back(t, false);
        continue;
      }
      stack.pop_back();
      Instruction ins;
      ins.op = Instruction::Op::Delay;
      ins.node = e;
      ins.slot = slots_.of(e);
      ins.block = program_.delay_lines.at(e.id());
      s.code.push_back(ins);
      valid_[e.id()] = 1;
      continue;
    }
    if (a_.is_leaf(e)) {  // symbols, pre() and fixed delays: loaded, never computed
      slots_.of(e);
      valid_[e.id()] = 1;
      stack.pop_back();
      continue;
    }
    if (expanded) {
      stack.pop_back();
      emit_node(e, s);
      continue;
    }
    stack.back().second = true;
    const std::size_t n = symbolic::arity(kind);
    for (std::size_t i = n; i-- > 0;) {
      const Expr op = a_.operand(e, i);
      if (!a_.is_constant(op) && !is_valid(op)) stack.emplace_back(op, false);
    }
  }
}

Slot SectionBuilder::root(Expr e, Section& s) {
  if (a_.is_constant(e)) {
    Instruction ins;
    ins.op = Instruction::Op::Copy;
    ins.node = e;
    ins.slot = slots_.fresh();
    s.code.push_back(ins);
    return ins.slot;
  }
  require(e, s);
  return slots_.of(e);
}

void SectionBuilder::assign(Slot target, Expr value, Section& s) {
  if (!a_.is_constant(value)) require(value, s);
  Instruction ins;
  ins.op = Instruction::Op::Copy;
  ins.node = value;
  ins.slot = target;
  s.code.push_back(ins);
}

void SectionBuilder::block(const symbolic::EquationBlock& b, const std::string& description,
                           Section& s) {
  const std::size_t n = b.unknowns.size();
  if (b.residuals.size() != n || (b.linear && b.offset.size() != n))
    throw std::invalid_argument("code generation: " + description +
                                " has unequal numbers of unknowns and equations");
  BlockCode code;
  code.linear = b.linear;
  code.description = description;
  for (Expr z : b.unknowns) {
    code.unknowns.push_back(slots_.of(z));
    valid_[z.id()] = 1;
  }
  if (b.linear) {
    for (Expr c : b.offset) code.values.push_back(root(c, s));
    for (const auto& e : b.jacobian)
      code.entries.push_back({static_cast<int>(e.row), static_cast<int>(e.col), root(e.value, s)});
  } else {
    nonlinear(b, code, s);
  }
  Instruction ins;
  ins.op = b.linear ? Instruction::Op::LinearSolve : Instruction::Op::NonlinearSolve;
  ins.block = static_cast<std::int32_t>(program_.blocks.size());
  if (!b.linear) program_.newton_blocks.push_back(program_.blocks.size());
  program_.blocks.push_back(std::move(code));
  s.code.push_back(ins);
}

// Nodes that depend on the unknowns go to an inner section (Newton evaluates
// it per iterate); the rest is computed once before the solve. Inner nodes
// are not marked valid afterwards: after a failed solve the unknowns are NaN
// and everything computed from them must be recomputed to show it.
void SectionBuilder::nonlinear(const symbolic::EquationBlock& b, BlockCode& code, Section& s) {
  std::vector<Expr> roots(b.residuals);
  for (const auto& e : b.jacobian) roots.push_back(e.value);
  const std::vector<Expr> order = symbolic::topological_order(a_, roots);
  std::vector<std::uint8_t> dependent(a_.size(), 0);
  for (Expr z : b.unknowns) dependent[z.id()] = 1;
  for (Expr e : order) {
    if (a_.kind(e) == ExprKind::Delay && varying_delay(e) && dependent[a_.operand(e, 1).id()])
      throw std::invalid_argument("code generation: a delay time that depends on the unknowns of an "
                                  "algebraic loop is not supported");
    if (a_.is_leaf(e) || a_.is_constant(e) || is_valid(e)) continue;
    for (std::size_t i = 0; i < symbolic::arity(a_.kind(e)); ++i)
      dependent[e.id()] |= dependent[a_.operand(e, i).id()];
  }
  // Outer: the independent operands of dependent nodes, and independent roots.
  for (Expr e : order) {
    if (!dependent[e.id()] || a_.is_leaf(e)) continue;
    for (std::size_t i = 0; i < symbolic::arity(a_.kind(e)); ++i) {
      const Expr op = a_.operand(e, i);
      if (!dependent[op.id()]) require(op, s);
    }
  }
  for (Expr r : roots)
    if (!dependent[r.id()] && !a_.is_constant(r)) require(r, s);
  Section inner;
  inner.name = "newton" + std::to_string(program_.blocks.size());
  const Validity outer = valid_;
  for (Expr e : order)
    if (dependent[e.id()] && !a_.is_leaf(e)) emit_node(e, inner);
  auto slot_in_inner = [&](Expr e) { return root(e, a_.is_constant(e) ? inner : s); };
  for (Expr r : b.residuals) code.values.push_back(slot_in_inner(r));
  for (const auto& e : b.jacobian)
    code.entries.push_back({static_cast<int>(e.row), static_cast<int>(e.col), slot_in_inner(e.value)});
  valid_ = outer;
  code.start = b.start;
  code.start.resize(b.unknowns.size(), 0.0);
  code.inner_section = static_cast<int>(program_.sections.size());
  program_.sections.push_back(std::move(inner));
}

}  // namespace mo::codegen::detail
