// Chain rule through assignments and blocks; see directional.hpp.
#include "mo/symbolic/directional.hpp"

#include <stdexcept>

#include "mo/symbolic/differentiate.hpp"

namespace mo::symbolic {

namespace {

class Differentiator {
public:
  Differentiator(OdeModel& m, const std::vector<Step>& steps, const ExprMap& seeds,
                 const DerivativeNamer& namer)
      : m_(m), steps_(steps), a_(m.arena), namer_(namer) {
    out_.derivative = seeds;
  }

  Directional run() {
    for (const Step& s : steps_) {
      if (const auto* as = std::get_if<Assignment>(&s))
        assignment(*as);
      else
        block(std::get<EquationBlock>(s));
    }
    return std::move(out_);
  }

private:
  /// A new Algebraic symbol for the derivative of `target`.
  Expr new_symbol(Expr target) {
    const std::string name = namer_(a_.symbol_info(target).name);
    const Expr s = a_.symbol(name, SymbolRole::Algebraic,
                             static_cast<std::int32_t>(m_.algebraics.size() + out_.symbols.size()));
    VariableInfo info;
    info.name = name;
    out_.symbols.push_back({info, s});
    return s;
  }

  void assignment(const Assignment& as) {
    const Expr d = forward_derivative(a_, std::span(&as.value, 1), out_.derivative, false)[0];
    if (a_.is_constant(d, 0.0)) return;
    if (a_.is_constant(d) || a_.is_leaf(d)) {
      out_.derivative[as.target] = d;
      return;
    }
    const Expr s = new_symbol(as.target);
    out_.steps.emplace_back(Assignment{s, d});
    out_.derivative[as.target] = s;
  }

  void block(const EquationBlock& b) {
    // c = Σ ∂r/∂w · dw with the block's own unknowns held fixed (dz = 0).
    const std::vector<Expr> c = forward_derivative(a_, b.residuals, out_.derivative, false);
    bool all_zero = true;
    for (Expr e : c) all_zero = all_zero && a_.is_constant(e, 0.0);
    if (all_zero) return;  // dz = 0: J is nonsingular at a solution
    EquationBlock d;
    d.linear = true;
    d.jacobian = b.jacobian;
    d.offset = c;
    for (Expr z : b.unknowns) d.unknowns.push_back(new_symbol(z));
    ExprMap dz;
    for (std::size_t j = 0; j < b.unknowns.size(); ++j) dz[d.unknowns[j]] = d.unknowns[j];
    std::vector<Expr> r(c);
    for (const BlockEntry& e : b.jacobian)
      r[e.row] = a_.add(r[e.row], a_.mul(e.value, d.unknowns[e.col]));
    d.residuals = std::move(r);
    for (std::size_t j = 0; j < b.unknowns.size(); ++j)
      out_.derivative[b.unknowns[j]] = d.unknowns[j];
    out_.steps.emplace_back(std::move(d));
  }

  OdeModel& m_;
  const std::vector<Step>& steps_;
  ExprArena& a_;
  const DerivativeNamer& namer_;
  Directional out_;
};

}  // namespace

Directional differentiate_steps(OdeModel& model, const ExprMap& seeds,
                                const DerivativeNamer& namer) {
  return differentiate_steps(model, model.steps, seeds, namer);
}

Directional differentiate_steps(OdeModel& model, const std::vector<Step>& steps,
                                const ExprMap& seeds, const DerivativeNamer& namer) {
  for (const auto& [leaf, value] : seeds) {
    (void)value;
    if (!model.arena.is_leaf(leaf))
      throw std::invalid_argument("differentiate_steps: a seed key is not a leaf");
  }
  return Differentiator(model, steps, seeds, namer).run();
}

Expr derivative_along(OdeModel& model, const Directional& d, Expr e) {
  return forward_derivative(model.arena, std::span(&e, 1), d.derivative, false)[0];
}

}  // namespace mo::symbolic
