// Redeclarations (MLS 7.3): `redeclare T x(...)` and `redeclare model M = T`
// in modifiers and extends clauses, `replaceable` elements, `constrainedby`,
// and `redeclare` elements of a class that extends the one declaring them.
//
// A redeclaration is carried by the Modifier of the element it replaces, so
// that the usual merge (outer modifications win) also picks the outermost
// redeclaration. Redeclared classes are recorded per instance
// (Instance::replaced) and consulted when a component type of that instance
// is resolved.
#include "flattener.hpp"

namespace mo::frontend::detail {

void Flattener::redeclaration(const ast::ElementMod &em, Instance *scope, ClassNode *lexical, Modifier &node) {
  Modifier r;
  if (em.component) {
    r = make_modifier(em.component->mod, scope, lexical);
    r.redecl_component = em.component.get();
    r.redecl_lexical = lexical;
  } else if (em.class_def) {
    r.redecl_class = redeclared_class(*em.class_def, lexical, scope);
  }
  r.each = em.each;
  r.final_ = em.final_;
  r.range = em.range;
  if (node.range.file == 0)
    node.range = em.range;
  merge_into(node, r);
}

ClassNode *Flattener::redeclared_class(const ast::ClassDef &def, ClassNode *lexical, const Instance *scope) {
  // `redeclare package P = Q`: Q itself, looked up where the redeclaration
  // was written (a class that instance replaced first); otherwise a class
  // node of its own, whose short base is looked up in that scope.
  ClassNode *target = nullptr;
  if (def.short_base && def.class_mod.empty() && def.short_dims.empty()) {
    const ast::TypeName &b = *def.short_base;
    if (scope && !b.global && scope->replaced.count(b.parts[0]))
      target = replaced_class(scope, b.parts);
    else
      target = lookup_class(lexical, b.parts, b.global, b.range, false);
  }
  if (target)
    return target;
  auto &slot = redeclared_classes_[{lexical, &def}];
  if (!slot) {
    slot = std::make_unique<ClassNode>();
    slot->name = def.name;
    slot->def = &def;
    slot->parent = lexical;
  }
  return slot.get();
}

Modifier Flattener::own_redeclarations(Instance &inst, ClassNode *cls) {
  Modifier out;
  const ast::ClassDef &def = *cls->def;
  for (const auto &c : def.components) {
    if (!c.redeclare)
      continue;
    Modifier &node = out.sub[c.name];
    node = make_modifier(c.mod, &inst, cls);
    node.redecl_component = &c;
    node.redecl_lexical = cls;
    node.range = c.range;
  }
  for (const auto &nested : def.classes) {
    if (!nested->redeclare)
      continue;
    ClassNode *node_class = own_class(cls, nested->name); // a view's: a view too
    if (!node_class)
      continue;
    Modifier &node = out.sub[nested->name];
    node.redecl_class = node_class;
    node.range = nested->range;
  }
  return out;
}

void Flattener::replace_classes(Instance &inst, const Modifier &mod) {
  for (const auto &[name, sub] : mod.sub)
    if (sub.redecl_class)
      inst.replaced[name] = sub.redecl_class;
}

void Flattener::instantiate_redeclared(Instance &inst, const ast::Component &comp, ClassNode *cls,
                                       const Modifier &mod, unsigned depth) {
  // Reported, then instantiated as redeclared all the same (one diagnostic).
  if (comp.final_)
    diags_.report(DiagId::NotReplaceable, mod.range, "'" + comp.name + "' is final and cannot be redeclared");
  else if (!comp.replaceable)
    diags_.report(DiagId::NotReplaceable, mod.range,
                  "'" + comp.name + "' is redeclared but its declaration is not 'replaceable'");
  // The original declaration's condition stays (a redeclaration has none of
  // its own): the MSL machines redeclare `thermalAmbient ... if not
  // useThermalPort` with their own ambient model.
  if (comp.condition) {
    Scope here{&inst, cls, nullptr};
    ast::ExprPtr c = scalar_expr(*comp.condition, here);
    if (eval(*c, comp.condition->range) == 0) {
      disabled_.insert({&inst, comp.name}); // its connections are removed too
      return;
    }
  }
  // The original declaration's modifiers stay, or those of its constraining
  // clause when it has one (MLS 7.3.2); the redeclaration's and outer ones win.
  Modifier cmod = make_modifier(comp.has_constraint ? comp.constraint_mod : comp.mod, &inst, cls);
  Modifier outer = mod;
  outer.redecl_component = nullptr; // the new declaration's own type resolves below
  merge_into(cmod, outer);
  instantiate_component(inst, *mod.redecl_component, mod.redecl_lexical, std::move(cmod), depth);
}

} // namespace mo::frontend::detail
