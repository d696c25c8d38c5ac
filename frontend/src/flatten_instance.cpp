// Phase 1 of flattening: the instance tree, flat variables and modifiers.
#include "flattener.hpp"
#include "mo/frontend/printer.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <optional>

namespace mo::frontend::detail {

using ast::Variability;

void Flattener::fail(DiagId id, SourceRange r, const std::string &msg) {
  diags_.report(id, r, msg);
  throw Reported{};
}

std::size_t Flattener::element_count(const std::vector<long long> &dims, SourceRange r, const std::string &what,
                                     const char *unit) {
  std::size_t total = 1;
  for (long long d : dims) {
    if (d <= 0)
      return 0;
    if (static_cast<std::size_t>(d) > opts_.max_elements / total)
      fail(DiagId::Unsupported, r,
           fmt::format("{} has more than {} {}, mocompile's limit", what, opts_.max_elements, unit));
    total *= static_cast<std::size_t>(d);
  }
  return total;
}

void Flattener::count_statement_loop_run(SourceRange r) {
  if (++statement_loop_runs_ > 10 * opts_.max_elements)
    fail(DiagId::Unsupported, r,
         fmt::format("the loops of algorithms and functions run more than {} times in all, mocompile's limit",
                     10 * opts_.max_elements));
}

Modifier Flattener::make_modifier(const ast::Modification &m, Instance *scope, ClassNode *lexical) {
  Modifier out;
  out.range = m.range;
  if (m.binding) {
    out.binding = m.binding.get();
    out.scope = scope;
    out.lexical = lexical;
  }
  for (const ast::ElementMod &em : m.args) {
    if (em.redeclare) {
      Modifier &node = out.sub[em.path.at(0)];
      redeclaration(em, scope, lexical, node);
      continue;
    }
    // `a.b(c = 1) = 2` is a(b(c = 1) = 2): build the nested path.
    Modifier *node = &out;
    for (std::size_t i = 0; i < em.path.size(); ++i) {
      node = &node->sub[em.path[i]];
      if (node->range.file == 0)
        node->range = em.range;
    }
    Modifier inner = make_modifier(em.mod, scope, lexical);
    inner.each = em.each;
    inner.final_ = em.final_;
    inner.range = em.range;
    merge_into(*node, inner);
  }
  return out;
}

void Flattener::merge_into(Modifier &inner, const Modifier &outer) {
  if (outer.binding) {
    inner.binding = outer.binding;
    inner.scope = outer.scope;
    inner.lexical = outer.lexical;
    inner.index = outer.index;
    inner.fields = outer.fields;
    inner.range = outer.range;
  }
  if (inner.range.file == 0)
    inner.range = outer.range;
  if (outer.redecl_component || outer.redecl_class) {
    inner.range = outer.range;
    inner.redecl_component = outer.redecl_component;
    inner.redecl_lexical = outer.redecl_lexical;
    inner.redecl_class = outer.redecl_class;
  }
  inner.each = inner.each || outer.each;
  inner.final_ = inner.final_ || outer.final_;
  for (const auto &[name, sub] : outer.sub)
    merge_into(inner.sub[name], sub);
}

/// Two declarations of one element that differ at most in attributes other
/// than the value: same type, prefixes, dimensions and binding (as text).
static bool same_declaration(const ast::Component &a, const ast::Component &b) {
  const auto text = [](const ast::ExprPtr &e) { return e ? print_expr(*e) : std::string(); };
  if (a.type.str() != b.type.str() || a.variability != b.variability || a.causality != b.causality ||
      a.connection != b.connection || a.inner != b.inner || a.outer != b.outer || a.dims.size() != b.dims.size() ||
      text(a.mod.binding) != text(b.mod.binding) || text(a.condition) != text(b.condition))
    return false;
  for (std::size_t k = 0; k < a.dims.size(); ++k)
    if (text(a.dims[k]) != text(b.dims[k]))
      return false;
  return true;
}

/// Whether modifier `again` of a base inherited a second time gives no
/// element anything `first` (the first path's) does not: the same bindings
/// (as written, read in the same instance) and redeclarations.
static bool modifies_as(const Modifier &again, const Modifier &first) {
  if (again.binding && (!first.binding || again.scope != first.scope || !ast::same_expr(*again.binding, *first.binding)))
    return false;
  if ((again.redecl_class && again.redecl_class != first.redecl_class) ||
      (again.redecl_component && again.redecl_component != first.redecl_component))
    return false;
  for (const auto &[name, sub] : again.sub) {
    const auto it = first.sub.find(name);
    if (it == first.sub.end() ? !sub.empty() : !modifies_as(sub, it->second))
      return false;
  }
  return true;
}

/// The modifier of array element `index`: bindings not marked `each` are
/// taken at that element.
static Modifier element_modifier(const Modifier &m, const std::vector<int> &index) {
  Modifier out = m;
  if (m.each)
    return out;
  auto &taken_at = out.fields.empty() ? out.index : out.fields.back().second;
  if (m.binding)
    taken_at.insert(taken_at.end(), index.begin(), index.end());
  for (auto &[name, sub] : out.sub)
    sub = element_modifier(m.sub.at(name), index);
  return out;
}

std::unique_ptr<flat::Model> Flattener::run(const std::string &class_name) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= class_name.size(); ++i)
    if (i == class_name.size() || class_name[i] == '.') {
      parts.push_back(class_name.substr(start, i - start));
      start = i + 1;
    }
  // A flat class may be named with dots (`Pkg.Model` printed backquoted).
  ClassNode *cls = nullptr;
  if (auto it = lib_.root.children.find(class_name); it != lib_.root.children.end())
    cls = it->second.get();
  if (!cls)
    cls = lookup_class(&lib_.root, parts, true, {}, false);
  if (!cls || !cls->def) {
    std::string known;
    for (const auto &n : lib_.order)
      known += (known.empty() ? "" : ", ") + n;
    diags_.report(DiagId::UnknownClass, {}, "class '" + class_name + "' not found" +
                                                (known.empty() ? "" : " (top-level classes: " + known + ")"));
    return nullptr;
  }
  model_ = std::make_unique<flat::Model>();
  model_->name = class_name;
  top_ = std::make_unique<Instance>();
  top_->cls = cls;
  all_instances_.push_back(top_.get());
  try {
    if (cls->def->partial)
      fail(DiagId::PartialInstantiated, cls->def->range,
           "partial class '" + class_name + "' cannot be simulated");
    instantiate_class(*top_, cls, Modifier{}, 0);
  } catch (Reported &) {
    return nullptr;
  }
  if (diags_.has_errors())
    return nullptr;
  expand_connectors();
  flatten_equations(*top_);
  finish_connections();
  return std::move(model_);
}

void Flattener::instantiate_class(Instance &inst, ClassNode *cls, const Modifier &mod, unsigned depth) {
  if (depth > opts_.max_depth)
    fail(DiagId::InstantiationTooDeep, inst.decl ? inst.decl->range : SourceRange{},
         "component nesting deeper than " + std::to_string(opts_.max_depth) +
             " levels (is a class instantiating itself?)");
  // A class seen through two derived classes (two views) is still one class.
  if (std::any_of(class_stack_.begin(), class_stack_.end(),
                  [&](const ClassNode *c) { return c->tree_class() == cls->tree_class(); })) {
    fail(DiagId::ExtendsCycle, cls->def->range,
         "class '" + cls->path() + "' extends itself (through its base classes)");
  }
  class_stack_.push_back(cls);
  const ast::ClassDef &def = *cls->def;
  if (def.has_algorithm)
    diags_.report(DiagId::Unsupported, def.algorithm_range,
                  "this algorithm section is not supported: only assignments (and when-statements of "
                  "them) that assign each variable once, before any statement reads it, are");
  const Modifier own = own_redeclarations(inst, cls);
  // This class's components, until its loop below has instantiated them,
  // can be looked up early (member()): by its bases' modifiers and
  // redeclarations, and by siblings' modifiers.
  std::vector<MemberKey> registered;
  for (const auto &c : def.components)
    if (!c.redeclare && later_members_.emplace(MemberKey{&inst, c.name}, LaterMember{&c, cls, &mod, depth}).second)
      registered.emplace_back(&inst, c.name);
  struct Unregister {
    std::map<MemberKey, LaterMember> &map;
    std::vector<MemberKey> &keys;
    ~Unregister() {
      for (const auto &k : keys)
        map.erase(k);
    }
  } unregister{later_members_, registered};
  replace_classes(inst, mod);
  for (auto &[ext, base] : bases(cls)) {
    // A class inherited along two paths is instantiated once: its elements
    // are identical duplicates, which Modelica merges (7.3). So are they
    // when the second path modifies them as the first did (the MSL's
    // DynamicPipe: PartialTwoPort's `final port_a_exposesState = ...` given
    // on both of its paths).
    const auto key = std::make_pair(&inst, static_cast<const ClassNode *>(base->tree_class()));
    if (const auto seen = inherited_.find(key); seen != inherited_.end()) {
      if (!ext->mod.empty() && !modifies_as(make_modifier(ext->mod, &inst, cls), seen->second))
        diags_.report(DiagId::DuplicateDeclaration, ext->range,
                      "'" + ext->base.str() + "' is inherited again with other modifiers; only identical "
                      "duplicates can be merged");
      continue;
    }
    if (!base->def) {
      diags_.report(DiagId::NotAClass, ext->base.range, "'" + ext->base.str() + "' is a package path, not a class");
      continue;
    }
    Modifier base_mod = make_modifier(ext->mod, &inst, cls);
    merge_into(base_mod, own);
    merge_into(base_mod, mod);
    inherited_.emplace(key, base_mod);
    instantiate_class(inst, base, base_mod, depth);
  }
  // Components: `inner` elements before the components whose `outer` ones
  // refer to them; then those without array dimensions, so that parameters
  // used as sizes exist before the arrays that need them; conditional
  // components last, so that the parameters of their conditions exist with
  // this instance's modifiers (the MSL's LimPID declares `with_D` after the
  // `D ... if with_D` it switches).
  std::vector<const ast::Component *> order;
  for (const auto &c : def.components)
    order.push_back(&c);
  const auto rank = [](const ast::Component *c) {
    if (c->inner && !c->outer)
      return 0;
    if (c->condition)
      return 3;
    return c->dims.empty() ? 1 : 2;
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](const ast::Component *a, const ast::Component *b) { return rank(a) < rank(b); });
  for (const ast::Component *c : order) {
    if (c->redeclare) { // passed to the bases, which declare the element
      if (!inst.member_index.count(c->name))
        diags_.report(DiagId::UnknownModifier, c->range,
                      "'" + c->name + "' is redeclared but no base class declares it");
      continue;
    }
    if (auto it = later_members_.find({&inst, c->name}); it != later_members_.end() && it->second.comp == c) {
      if (it->second.started)
        continue; // instantiated when an earlier element looked it up
      it->second.started = true;
    }
    if (inst.expandable && !inst.member_index.count(c->name)) {
      // Present only once a connection or a reference needs it (member()).
      potential_.emplace(MemberKey{&inst, c->name}, Potential{c, cls, mod, depth});
      continue;
    }
    if (auto it = inst.member_index.find(c->name); it != inst.member_index.end()) {
      const auto outer = outer_decls_.find({&inst, c->name});
      const ast::Component *prev = outer != outer_decls_.end() ? outer->second : it->second->decl;
      if (outer != outer_decls_.end() && c->outer && same_declaration(*prev, *c))
        continue; // `outer system` of two bases: one alias of the inner
      const bool inherited = prev && std::none_of(def.components.begin(), def.components.end(),
                                                  [&](const ast::Component &d) { return &d == prev; });
      if (inherited && same_declaration(*prev, *c)) {
        // The MSL redeclares a base's element with other attributes (MultiPhase's
        // MutualInductor: `parameter Integer m = 3` over TwoPlug's `m(min = 1) = 3`).
        diags_.report(DiagId::MergedDuplicate, c->range,
                      "'" + c->name + "' is also declared by a base class, with other attributes; merged "
                      "as the base's declaration (Modelica requires identical duplicates)");
        diags_.note(prev->range, "the base's declaration is here");
        continue;
      }
      diags_.report(DiagId::DuplicateDeclaration, c->range, "duplicate declaration of '" + c->name + "'");
      if (it->second->decl)
        diags_.note(it->second->decl->range, "previous declaration is here");
      continue;
    }
    try {
      instantiate_member(inst, *c, cls, mod, depth);
    } catch (Reported &) {
    }
  }
  for (const auto &eq : def.equations)
    inst.equations.emplace_back(&eq, cls);
  for (const auto &eq : def.initial_equations)
    inst.initial_equations.emplace_back(&eq, cls);
  for (const auto &eq : def.constraints)
    inst.constraints.emplace_back(&eq, cls);
  for (const auto &alg : def.model_algorithms)
    inst.algorithms.emplace_back(&alg, cls);
  class_stack_.pop_back();
}

void Flattener::instantiate_member(Instance &inst, const ast::Component &c, ClassNode *cls, const Modifier &mod,
                                   unsigned depth) {
  const auto modified = [&] {
    auto it = mod.sub.find(c.name);
    return it != mod.sub.end() && it->second.binding;
  };
  // The record's binding gives each field its value, over the field's own
  // default; a modifier of the field itself (`coreParameters(final m = 1)`
  // with `coreParameters = data.coreParameters` from outside) is more
  // specific and wins.
  const bool record_binding = mod.binding && is_record_instance(inst) && !modified();
  const auto bind_field = [&](Modifier &field) {
    field.binding = mod.binding;
    field.scope = mod.scope;
    field.lexical = mod.lexical;
    field.index = mod.index;
    field.fields = mod.fields;
    field.fields.emplace_back(c.name, std::vector<int>{});
    field.each = false;
  };
  if (auto it = mod.sub.find(c.name); it != mod.sub.end() && it->second.redecl_component) {
    // A field the record's type redeclares (SIunits.ComplexVoltage's `re`)
    // takes its part of the record's binding all the same.
    Modifier redeclared = it->second;
    if (record_binding)
      bind_field(redeclared);
    instantiate_redeclared(inst, c, cls, redeclared, depth);
    return;
  }
  Modifier cmod = make_modifier(c.mod, &inst, cls);
  if (auto it = mod.sub.find(c.name); it != mod.sub.end()) {
    if (c.final_ && !it->second.empty())
      diags_.report(DiagId::UnknownModifier, it->second.range, "'" + c.name + "' is final and cannot be modified");
    merge_into(cmod, it->second);
  }
  // `each` belongs to the arrays of the component whose modifier holds it
  // (MLS 7.2.5: `C c[5](each a = {1, 2, 3})`), consumed by element_modifier()
  // there, or meaningless if that component is scalar (the MSL's
  // `SineVoltage s(each V = fill(v, m))`); the member splits its own binding
  // over its own dimensions.
  cmod.each = false;
  if (record_binding)
    bind_field(cmod);
  instantiate_component(inst, c, cls, std::move(cmod), depth);
}

Instance *Flattener::member(Instance &inst, const std::string &name) {
  if (auto it = inst.member_index.find(name); it != inst.member_index.end())
    return it->second;
  auto later = later_members_.find({&inst, name});
  if (later == later_members_.end() || later->second.started)
    return inst.expandable ? present_member(inst, name) : nullptr;
  LaterMember m = later->second;
  later->second.started = true; // a cycle (a binding that needs its own element) finds nothing
  instantiate_member(inst, *m.comp, m.cls, *m.mod, m.depth);
  auto it = inst.member_index.find(name);
  return it == inst.member_index.end() ? nullptr : it->second;
}

Instance *Flattener::present_member(Instance &inst, const std::string &name) {
  auto it = potential_.find({&inst, name});
  if (it == potential_.end() || it->second.started)
    return nullptr;
  it->second.started = true;
  const Potential &p = it->second;
  instantiate_member(inst, *p.comp, p.cls, p.mod, p.depth);
  auto m = inst.member_index.find(name);
  if (m == inst.member_index.end())
    return nullptr;
  m->second->is_connector = true; // every element of an expandable connector is one (MLS 9.1.3)
  return m->second;
}

Instance *Flattener::find_inner(const Instance &from, const std::string &name) {
  for (const Instance *p = from.parent; p; p = p->parent)
    if (auto it = p->member_index.find(name); it != p->member_index.end())
      if ((it->second->decl && it->second->decl->inner) || default_inners_.count(it->second))
        return it->second;
  return nullptr;
}

Instance *Flattener::default_inner(const ast::Component &outer, ClassNode *cls, unsigned depth) {
  const auto later = later_members_.find({top_.get(), outer.name});
  if (top_->member_index.count(outer.name) || (later != later_members_.end() && later->second.comp != &outer) ||
      making_default_inner_)
    return nullptr; // the model's own element of that name (made or still to come) is not an inner one
  diags_.report(DiagId::DefaultInner, outer.range,
                "no enclosing instance declares an 'inner' element '" + outer.name + "' for this 'outer' one; "
                "the model gets one of type '" + outer.type.str() + "' with its default values (MLS 5.4)");
  making_default_inner_ = &outer;
  try {
    instantiate_component(*top_, outer, cls, Modifier{}, depth);
  } catch (...) {
    making_default_inner_ = nullptr;
    throw;
  }
  making_default_inner_ = nullptr;
  Instance *inner = top_->member_index.at(outer.name);
  default_inners_.insert(inner);
  return inner;
}

void Flattener::check_modifier_names(const Instance &inst, const Modifier &mod) {
  for (const auto &[name, sub] : mod.sub) {
    if (inst.member_index.count(name) || inst.replaced.count(name) || potential_.count({&inst, name}))
      continue;
    std::string where = inst.decl ? "component '" + inst.decl->name + "' of type '" + inst.decl->type.str() + "'"
                                  : "class '" + (inst.cls ? inst.cls->path() : std::string("?")) + "'";
    diags_.report(DiagId::UnknownModifier, sub.range, "modifier '" + name + "' does not name an element of " + where);
  }
}

void Flattener::instantiate_component(Instance &parent, const ast::Component &comp, ClassNode *cls,
                                      Modifier mod, unsigned depth) {
  Scope here{&parent, cls, nullptr};
  if (comp.outer && making_default_inner_ != &comp) {
    // The nearest enclosing instance's `inner` element of that name (MLS 5.4):
    // the outer name becomes an alias of it in this instance.
    Instance *inner = find_inner(parent, comp.name);
    if (!inner)
      inner = default_inner(comp, cls, depth);
    if (!inner)
      fail(DiagId::UnknownComponent, comp.range,
           "no enclosing instance declares an 'inner' element '" + comp.name + "' for this 'outer' one");
    parent.member_index[comp.name] = inner;
    outer_decls_[{&parent, comp.name}] = &comp;
    return;
  }
  if (comp.condition) {
    ast::ExprPtr c = scalar_expr(*comp.condition, here);
    if (eval(*c, comp.condition->range) == 0) {
      disabled_.insert({&parent, comp.name}); // its connections are removed too
      return; // conditional component switched off
    }
  }
  ResolvedType rt;
  if (!resolve_type(cls, comp.type, rt, &parent))
    throw Reported{};
  Modifier full = rt.mod;
  merge_into(full, mod);
  if (!rt.is_builtin && is_external_object_class(rt.cls)) {
    declare_external_object(parent, comp, rt.cls, full);
    return;
  }

  auto child = std::make_unique<Instance>();
  Instance &inst = *child;
  inst.name = comp.name;
  inst.flat = parent.flat.empty() ? comp.name : parent.flat + "." + comp.name;
  inst.parent = &parent;
  inst.decl = &comp;
  inst.cls = rt.cls;
  inst.variability = std::max(comp.variability, parent.variability);
  inst.causality = comp.causality != ast::Causality::None ? comp.causality
                   : rt.causality != ast::Causality::None ? rt.causality
                                                          : parent.causality;
  inst.is_flow = comp.connection == ast::Connection::Flow || parent.is_flow;
  inst.is_enumeration = rt.is_enumeration;
  inst.is_connector = rt.is_connector;
  inst.is_stream = comp.connection == ast::Connection::Stream || parent.is_stream;
  if (comp.connection == ast::Connection::Stream && !parent.is_connector)
    fail(DiagId::Unsupported, comp.range, "'stream' is allowed only on a component of a connector (MLS 15.1)");
  std::optional<Tensor> bound; // the binding, when ':' sizes come from it
  for (std::size_t i = 0; i < comp.dims.size(); ++i) {
    const auto &d = comp.dims[i];
    if (d->kind == ast::ExprKind::Colon) {
      if (!full.binding)
        fail(DiagId::Unsupported, d->range, "an array of unknown size ':' needs a binding to take its size from");
      if (!bound)  // a record's field: its part of the record's binding
        bound = binding_tensor(full);
      if (i >= bound->dims.size())
        fail(DiagId::TypeMismatch, full.binding->range,
             "the binding has fewer dimensions than '" + comp.name + "' is declared with");
      inst.dims.push_back(bound->dims[i]);
      continue;
    }
    long long n = dimension_size(*d, here);
    if (n < 0 || n > 10'000'000)
      fail(DiagId::BadSubscript, d->range, "array size " + std::to_string(n) + " is out of range");
    inst.dims.push_back(static_cast<int>(n));
  }
  for (int d : rt.dims)
    inst.dims.push_back(d);
  if (!rt.is_builtin) {
    const ast::ClassDef &def = *rt.cls->def;
    if (def.partial)
      fail(DiagId::PartialInstantiated, comp.type.range,
           "component '" + comp.name + "' has partial type '" + comp.type.str() + "'");
    if (def.restriction == ast::Restriction::Package || def.restriction == ast::Restriction::Function)
      fail(DiagId::NotAClass, comp.type.range,
           "'" + comp.type.str() + "' is a " + ast::restriction_text(def.restriction) +
               " and cannot be the type of a component");
    // `connector ComplexOutput = output Complex`: a connector of a record type.
    inst.is_connector = rt.is_connector || def.restriction == ast::Restriction::Connector ||
                        def.restriction == ast::Restriction::ExpandableConnector;
    inst.expandable = def.restriction == ast::Restriction::ExpandableConnector;
  }
  parent.member_index[comp.name] = &inst;
  parent.members.push_back(std::move(child));
  if (!inst.dims.empty()) {
    make_elements(inst, comp, rt, full, depth);
  } else if (rt.is_builtin) {
    make_scalar(inst, rt, full);
  } else {
    instantiate_structured(inst, rt.cls, full, depth);
  }
}

void Flattener::instantiate_structured(Instance &inst, ClassNode *cls, const Modifier &mod, unsigned depth) {
  all_instances_.push_back(&inst);
  std::vector<ClassNode *> saved;
  saved.swap(class_stack_); // extends cycles are per class, not per component
  try {
    instantiate_class(inst, cls, mod, depth + 1);
  } catch (...) {
    class_stack_.swap(saved);
    throw;
  }
  class_stack_.swap(saved);
  check_modifier_names(inst, mod);
}

void Flattener::make_elements(Instance &inst, const ast::Component &comp, const ResolvedType &rt,
                              const Modifier &mod, unsigned depth) {
  const std::size_t total = element_count(std::vector<long long>(inst.dims.begin(), inst.dims.end()), comp.range,
                                          "'" + inst.flat + "'");
  std::vector<int> idx(inst.dims.size(), 1);
  for (std::size_t k = 0; k < total; ++k) {
    auto el = std::make_unique<Instance>();
    std::string sub;
    for (std::size_t i = 0; i < idx.size(); ++i)
      sub += (i ? "," : "") + std::to_string(idx[i]);
    el->name = "[" + sub + "]";
    el->flat = inst.flat + el->name;
    el->parent = inst.parent;
    el->decl = &comp;
    el->cls = inst.cls;
    el->variability = inst.variability;
    el->causality = inst.causality;
    el->is_flow = inst.is_flow;
    el->is_stream = inst.is_stream;
    el->is_connector = inst.is_connector;
    el->expandable = inst.expandable;
    el->is_enumeration = inst.is_enumeration;
    Modifier emod = element_modifier(mod, idx);
    if (rt.is_builtin) {
      make_scalar(*el, rt, emod);
    } else {
      instantiate_structured(*el, rt.cls, emod, depth);
    }
    inst.elements.push_back(std::move(el));
    for (std::size_t i = idx.size(); i-- > 0;) { // row-major increment
      if (++idx[i] <= inst.dims[i]) break;
      idx[i] = 1;
    }
  }
}

/// Whether modification `mod` of scalar `inst` was written outside the class
/// that declares it (by a user of that class), or `inst` is the model's own.
bool Flattener::written_by_user(const Instance &inst, const Modifier &mod) const {
  const Instance *owner = inst.parent;  // the declaring class's instance (an array element's too)
  return owner == top_.get() || (mod.scope != nullptr && mod.scope != owner);
}

/// Whether `Evaluate = true` covers parameter `inst`: on its own declaration or on that
/// of a record parameter it is a field of (`parameter Card card annotation(Evaluate =
/// true)`, the MSL's Spice3 model cards), as the annotation of a record is that of its
/// elements. A model component is not a parameter, so the search ends there.
static bool annotated_evaluate(const Instance &inst) {
  for (const Instance *p = &inst; p != nullptr && p->variability == Variability::Parameter; p = p->parent)
    if (p->decl && p->decl->evaluate)
      return true;
  return false;
}

void Flattener::make_scalar(Instance &inst, const ResolvedType &rt, const Modifier &mod) {
  if (++scalars_made_ > opts_.max_elements)
    fail(DiagId::Unsupported, inst.decl ? inst.decl->range : SourceRange{},
         fmt::format("the model has more than {} scalar variables, mocompile's limit", opts_.max_elements));
  flat::Variable v;
  v.name = inst.flat;
  v.type = rt.builtin;
  v.variability = inst.variability;
  if (v.variability == Variability::Continuous && rt.builtin != flat::BaseType::Real)
    v.variability = Variability::Discrete; // Integer/Boolean variables change only at events
  v.causality = inst.causality;
  v.is_flow = inst.is_flow;
  v.is_stream = inst.is_stream;
  // Inputs of the model itself are known signals. In Xcos' flat files the
  // `input` prefix of a connector is copied onto nested names (`f.signal`):
  // those are connected inside the model and stay unknowns.
  v.top_level_input = inst.causality == ast::Causality::Input && inst.parent == top_.get() &&
                      inst.flat.find('.') == std::string::npos;
  v.description = inst.decl ? inst.decl->description : "";
  v.evaluate = v.variability == Variability::Parameter && annotated_evaluate(inst);
  v.range = inst.decl ? inst.decl->range : SourceRange{};
  if (model_->find(v.name) >= 0)
    fail(DiagId::DuplicateDeclaration, v.range, "two components flatten to the same name '" + v.name + "'");
  inst.var = model_->add(std::move(v));
  if (inst.is_stream)
    stream_vars_[inst.var] = &inst;
  static const char *const kAttributes[] = {"start", "fixed", "min", "max", "nominal", "unit",
                                            "displayUnit", "quantity", "stateSelect", "free",
                                            "initialGuess"};
  for (const auto &entry : mod.sub) {
    const std::string &name = entry.first;
    const Modifier &sub = entry.second;
    bool known = std::find_if(std::begin(kAttributes), std::end(kAttributes),
                              [&](const char *a) { return name == a; }) != std::end(kAttributes);
    if (!known) {
      diags_.report(DiagId::UnknownModifier, sub.range,
                    "'" + name + "' is not an attribute of " + flat::base_type_text(rt.builtin) +
                        " (in the declaration of '" + inst.flat + "')");
      continue;
    }
    if (sub.binding) {
      pending_by_var_[inst.var].push_back(pending_.size());
      pending_.push_back(PendingBinding{inst.var, name, sub});
      // The author's start: one they write, or the class's that they make an
      // initial value (`phi(fixed = true)` on a joint whose class declares
      // phi(start = 0)).
      const bool fixed_false =
          name == "fixed" && sub.binding->kind == ast::ExprKind::Boolean && sub.binding->number == 0.0;
      if ((name == "start" || (name == "fixed" && !fixed_false)) && written_by_user(inst, sub))
        model_->variables[static_cast<std::size_t>(inst.var)].start_by_user = true;
    }
  }
  if (mod.binding) {
    pending_by_var_[inst.var].push_back(pending_.size());
    pending_.push_back(PendingBinding{inst.var, "", mod});
  }
}

} // namespace mo::frontend::detail
