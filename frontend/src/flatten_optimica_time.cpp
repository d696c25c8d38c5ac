// Optimica's free final time: `finalTime(free = true, min = .., max = ..,
// initialGuess = ..)`, with or without a value, becomes a free parameter
// named `finalTime` of the flat model. The objective and the constraints
// refer to it (flatten_expr.cpp resolves `finalTime` there); the study tools
// rescale time so that the horizon [startTime, finalTime] is τ ∈ [0, 1]
// (studies/study_time_scaling.cpp).
#include "flattener.hpp"

#include <fmt/format.h>

#include <set>

namespace mo::frontend::detail {

using ast::ExprKind;
using ast::ExprPtr;

namespace {

/// The attributes written on `startTime(...)`/`finalTime(...)`.
struct TimeAttributes {
  ExprPtr free, min, max, initial_guess;
};

}  // namespace

std::vector<const ast::ElementMod *> Flattener::optimization_attributes() {
  std::vector<const ast::ElementMod *> out;
  std::set<std::string> set;
  std::set<const ClassNode *> visited;
  auto visit = [&](auto &self, ClassNode *c) -> void {
    if (!c || !c->def || !visited.insert(c).second) return;
    std::vector<std::string> own;
    for (const ast::ElementMod &em : c->def->class_mod.args) {
      const std::string n = em.path.empty() ? "" : em.path[0];
      if (set.count(n)) continue;  // the derived class sets it
      own.push_back(n);
      out.push_back(&em);
    }
    set.insert(own.begin(), own.end());
    for (auto &[ext, base] : bases(c, false))
      if (base && base->def && base->def->restriction == ast::Restriction::Optimization) self(self, base);
  };
  visit(visit, top_->cls);
  return out;
}

void Flattener::declare_free_final_time(const std::vector<const ast::ElementMod *> &attributes) {
  Scope top{top_.get(), top_->cls, nullptr};
  for (const ast::ElementMod *attribute : attributes) {
    const ast::ElementMod &em = *attribute;
    if (em.path.size() != 1 || (em.path[0] != "startTime" && em.path[0] != "finalTime") ||
        em.mod.args.empty())
      continue;
    const std::string &which = em.path[0];
    TimeAttributes attrs;
    bool ok = true;
    for (const ast::ElementMod &a : em.mod.args) {
      const std::string name = a.path.size() == 1 ? a.path[0] : "";
      ExprPtr *slot = name == "free" ? &attrs.free : name == "min" ? &attrs.min
                    : name == "max" ? &attrs.max : name == "initialGuess" ? &attrs.initial_guess
                    : nullptr;
      if (!slot || !a.mod.binding) {
        diags_.report(DiagId::BadOptimization, a.range,
                      fmt::format("'{}' is not an attribute of {} (expected free, min, max or "
                                  "initialGuess with a value)", name, which));
        ok = false;
        continue;
      }
      try {
        *slot = scalar_expr(*a.mod.binding, top);
      } catch (Reported &) {
        ok = false;
      }
    }
    if (!ok || !attrs.free) continue;
    try {
      if (eval(*attrs.free, em.range) == 0.0) continue;
    } catch (Reported &) {
      continue;
    }
    if (which == "startTime") {
      diags_.report(DiagId::BadOptimization, em.range,
                    "a free startTime is not supported (only finalTime may be free)");
      continue;
    }
    if (model_->find("finalTime") >= 0) {
      diags_.report(DiagId::BadOptimization, em.range,
                    "a free finalTime needs the name 'finalTime', which a variable of the model "
                    "already has");
      continue;
    }
    flat::Variable v;
    v.name = "finalTime";
    v.variability = ast::Variability::Parameter;
    v.range = em.range;
    v.description = "the free final time of the optimization";
    // The first guess: initialGuess, else the value written, else the default 1.
    try {
      if (attrs.initial_guess)
        v.binding = attrs.initial_guess->clone();
      else if (em.mod.binding)
        v.binding = scalar_expr(*em.mod.binding, top);
      else
        v.binding = ast::make_real(1.0, em.range);
      v.value = eval(*v.binding, em.range);
    } catch (Reported &) {
      continue;
    }
    v.attr.free = ast::make_bool(true, em.range);
    v.attr.min = std::move(attrs.min);
    v.attr.max = std::move(attrs.max);
    v.attr.initial_guess = std::move(attrs.initial_guess);
    free_final_time_ = model_->add(std::move(v));
  }
}

}  // namespace mo::frontend::detail
