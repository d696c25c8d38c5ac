// Nonlinear blocks as unknowns of an optimiser; see loop_inputs.hpp.
#include "mo/symbolic/loop_inputs.hpp"

#include <stdexcept>
#include <unordered_map>

namespace mo::symbolic {
namespace {

/// The declared attributes of every Algebraic and Derivative symbol, by node.
std::unordered_map<std::uint32_t, const VariableInfo*> unknown_infos(const OdeModel& model,
                                                                    std::vector<VariableInfo>& derivs) {
  std::unordered_map<std::uint32_t, const VariableInfo*> out;
  for (const OdeAlgebraic& a : model.algebraics) out[a.symbol.id()] = &a.info;
  derivs.reserve(model.states.size());
  for (const OdeState& s : model.states) {
    VariableInfo d;
    d.name = "der(" + s.info.name + ")";
    d.nominal = s.info.nominal;
    derivs.push_back(std::move(d));
    out[s.derivative.id()] = &derivs.back();
  }
  return out;
}

}  // namespace

LoopExposure expose_nonlinear_blocks(OdeModel& model) {
  LoopExposure out;
  std::vector<VariableInfo> derivs;
  const auto infos = unknown_infos(model, derivs);
  std::vector<Step> steps;
  steps.reserve(model.steps.size());
  for (Step& step : model.steps) {
    auto* block = std::get_if<EquationBlock>(&step);
    if (!block || block->linear) {
      steps.push_back(std::move(step));
      continue;
    }
    for (std::size_t i = 0; i < block->unknowns.size(); ++i) {
      const Expr z = block->unknowns[i];
      const auto it = infos.find(z.id());
      if (it == infos.end()) throw std::logic_error("a block unknown is neither algebraic nor a derivative");
      const VariableInfo& zi = *it->second;
      LoopInput li;
      li.input = model.inputs.size();
      li.variable = zi.name;
      li.start = i < block->start.size() ? block->start[i] : 0.0;
      li.min = zi.min, li.max = zi.max, li.nominal = zi.nominal;
      OdeInput w;
      w.info = zi;
      w.info.name = "$iteration(" + zi.name + ")";
      w.info.description = "iteration variable of a nonlinear block, chosen by the optimiser";
      w.symbol = model.arena.symbol(w.info.name, SymbolRole::Input, static_cast<std::int32_t>(li.input));
      steps.push_back(Assignment{z, w.symbol, i < block->origins.size() ? block->origins[i] : ""});
      model.inputs.push_back(std::move(w));
      out.inputs.push_back(std::move(li));
    }
    for (std::size_t k = 0; k < block->residuals.size(); ++k) {
      OdeOutput r;
      const std::size_t first = out.inputs.size() - block->unknowns.size();
      const std::string of = k < block->unknowns.size() ? out.inputs[first + k].variable : std::to_string(k);
      r.info.name = "$residual(" + of + ")";
      r.info.description = "residual of a nonlinear block, held at 0 by the optimiser";
      r.value = block->residuals[k];
      out.residuals.push_back(model.outputs.size());
      model.outputs.push_back(std::move(r));
    }
  }
  model.steps = std::move(steps);
  return out;
}

}  // namespace mo::symbolic
