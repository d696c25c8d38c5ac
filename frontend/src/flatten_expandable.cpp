// Expandable connectors (Modelica 3, section 9.1.3): a signal bus whose
// elements are those its connections name. A declared element is only
// potentially present (Flattener::potential_) and enters the flat model
// when a connect() or a reference names it; a connect() to an undeclared
// element adds it with the type of the other side; expandable connectors
// connected to each other get the union of their elements. Unused declared
// elements never become variables.
#include "flattener.hpp"

#include <set>

namespace mo::frontend::detail {

namespace {

/// One side of a connect(): a present instance, or an element `name` that
/// expandable connector `bus` does not have yet.
struct BusSide {
  Instance *inst = nullptr;
  Instance *bus = nullptr;
  std::string name;
};

} // namespace

/// Resolves `ref` (no subscripts) in `scope`, making declared elements of
/// expandable connectors present; false when it is not such a reference
/// (connect() itself reports what is wrong with it).
static bool bus_side(Flattener &f, const ast::ComponentRef &ref, Instance &scope, BusSide &out) {
  if (ref.global || ref.parts.empty())
    return false;
  for (const auto &p : ref.parts)
    if (!p.subscripts.empty())
      return false;
  if (f.disabled_.count({&scope, ref.parts[0].name}))
    return false;
  Instance *cur = f.member(scope, ref.parts[0].name);
  for (std::size_t p = 1; cur && p < ref.parts.size(); ++p) {
    if (!cur->dims.empty())
      return false;
    Instance *next = f.member(*cur, ref.parts[p].name);
    if (!next && cur->expandable && p + 1 == ref.parts.size()) {
      out.bus = cur;
      out.name = ref.parts[p].name;
      return true;
    }
    cur = next;
  }
  out.inst = cur;
  return cur != nullptr;
}

/// Makes `inst` (named, placed and registered by the caller) an instance of
/// `like`'s type: a variable of its base type, an array of such elements,
/// or a structured instance of its class, without modifiers.
void Flattener::instantiate_like(Instance &inst, const Instance &like) {
  inst.decl = like.decl;
  inst.cls = like.cls;
  inst.is_flow = like.is_flow;
  inst.is_connector = true;
  inst.is_enumeration = like.is_enumeration;
  inst.expandable = like.expandable;
  inst.dims = like.dims;
  if (!like.dims.empty()) {
    for (const auto &el : like.elements) {
      auto child = std::make_unique<Instance>();
      child->name = el->name;
      child->flat = inst.flat + el->name;
      child->parent = inst.parent;
      child->variability = inst.variability;
      instantiate_like(*child, *el);
      inst.elements.push_back(std::move(child));
    }
  } else if (like.var >= 0) {
    ResolvedType rt;
    rt.is_builtin = true;
    rt.builtin = model_->variables[like.var].type;
    rt.is_enumeration = like.is_enumeration;
    make_scalar(inst, rt, Modifier{});
  } else {
    instantiate_structured(inst, like.cls, Modifier{}, 1);
  }
}

Instance *Flattener::add_bus_member(Instance &bus, const std::string &name, const Instance &like) {
  auto child = std::make_unique<Instance>();
  Instance &inst = *child;
  inst.name = name;
  inst.flat = bus.flat + "." + name;
  inst.parent = &bus;
  inst.variability = std::max(like.variability, bus.variability);
  bus.member_index[name] = &inst;
  bus.members.push_back(std::move(child));
  instantiate_like(inst, like);
  return &inst;
}

void Flattener::expand_connectors() {
  if (std::none_of(all_instances_.begin(), all_instances_.end(), [](const Instance *i) { return i->expandable; }))
    return;
  // Connected expandable connectors, in the order found (pairs may grow).
  std::vector<std::pair<Instance *, Instance *>> pairs;
  std::set<std::pair<Instance *, Instance *>> paired;
  auto add_pair = [&](Instance *a, Instance *b) {
    if (a == b || !paired.insert({std::min(a, b), std::max(a, b)}).second)
      return false;
    pairs.emplace_back(a, b);
    return true;
  };
  // Connections written at the top of an equation section (those in loops
  // and if-equations must name declared elements).
  for (std::size_t k = 0; k < all_instances_.size(); ++k) {
    Instance *owner = all_instances_[k];
    for (const auto &[eq, cls] : owner->equations) {
      if (eq->kind != ast::EquationKind::Connect)
        continue;
      try {
        BusSide side[2];
        if (!bus_side(*this, eq->lhs->ref, *owner, side[0]) || !bus_side(*this, eq->rhs->ref, *owner, side[1]))
          continue;
        if (!side[0].inst && !side[1].inst)
          fail(DiagId::ConnectIncompatible, eq->range,
               "connect() of two undeclared elements '" + side[0].bus->flat + "." + side[0].name + "' and '" +
                   side[1].bus->flat + "." + side[1].name + "' of expandable connectors: one side must exist");
        for (int j = 0; j < 2; ++j)
          if (!side[j].inst)
            side[j].inst = add_bus_member(*side[j].bus, side[j].name, *side[1 - j].inst);
        if (side[0].inst->expandable && side[1].inst->expandable)
          add_pair(side[0].inst, side[1].inst);
      } catch (Reported &) {
      }
    }
  }
  // Each connected pair gets the elements of the other, to a fixed point:
  // a new element that is itself expandable pairs with its counterpart.
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      for (int dir = 0; dir < 2; ++dir) {
        Instance *from = dir == 0 ? pairs[k].first : pairs[k].second;
        Instance *to = dir == 0 ? pairs[k].second : pairs[k].first;
        for (std::size_t m = 0; m < from->members.size(); ++m) {
          Instance *element = from->members[m].get();
          try {
            const std::size_t before = to->members.size();
            Instance *other = member(*to, element->name);
            if (!other)
              other = add_bus_member(*to, element->name, *element);
            changed = changed || to->members.size() != before;
            if (element->expandable && other->expandable)
              changed = add_pair(element, other) || changed;
          } catch (Reported &) {
          }
        }
      }
    }
  }
}

} // namespace mo::frontend::detail
