// Class lookup: the package tree of all files, lexical scopes, imports and
// classes inherited through `extends`.
#include "flattener.hpp"

#include <algorithm>

namespace mo::frontend {

std::string ClassNode::path() const {
  if (context)
    return context->path();
  if (!parent || parent->name.empty())
    return name;
  return parent->path() + "." + name;
}

void Library::Impl::insert(ClassNode &parent, const ast::ClassDef &def) {
  auto &slot = parent.children[def.name];
  if (!slot) {
    slot = std::make_unique<ClassNode>();
    slot->name = def.name;
    slot->parent = &parent;
  }
  slot->def = &def; // a later file replaces an earlier definition of the same class
  for (const auto &nested : def.classes)
    insert(*slot, *nested);
}

Library::Library() : impl_(std::make_unique<Impl>()) {}
Library::~Library() = default;

void Library::add(std::unique_ptr<ast::StoredDefinition> file) {
  ClassNode *parent = &impl_->root;
  for (const auto &part : file->within) {
    auto &slot = parent->children[part];
    if (!slot) {
      slot = std::make_unique<ClassNode>();
      slot->name = part;
      slot->parent = parent;
    }
    parent = slot.get();
  }
  for (const auto &cls : file->classes) {
    if (parent == &impl_->root)
      impl_->order.push_back(cls->name);
    impl_->insert(*parent, *cls);
  }
  impl_->files.push_back(std::move(file));
}

std::vector<std::string> Library::top_level_names() const { return impl_->order; }

namespace detail {

static bool builtin_type(const std::string &n, flat::BaseType &t) {
  if (n == "Real") t = flat::BaseType::Real;
  else if (n == "Integer") t = flat::BaseType::Integer;
  else if (n == "Boolean") t = flat::BaseType::Boolean;
  else if (n == "String") t = flat::BaseType::String;
  else return false;
  return true;
}

/// Where the base of `ext` in `cls` is looked up: the enclosing scope, or
/// `cls` itself for a class declared in it (not one it inherits).
static ClassNode *extends_scope(ClassNode *cls, const ast::Extends &ext, ClassNode *root) {
  if (!ext.base.global && !ext.base.parts.empty()) {
    const std::string &first = ext.base.parts[0];
    const auto &own = cls->tree_class()->children;
    if (auto it = own.find(first); it != own.end() && it->second->def)
      return cls;
    for (const auto &imp : cls->def->imports) // `import A.B.C; extends C;`
      if ((imp.alias.empty() ? !imp.wildcard && imp.names.empty() && !imp.path.empty() && imp.path.back() == first
                             : imp.alias == first) ||
          std::find(imp.names.begin(), imp.names.end(), first) != imp.names.end())
        return cls;
  }
  return cls->parent ? cls->parent : root;
}

/// StateSelect and AssertionLevel: enumerations every Modelica tool predefines.
static bool predefined_enumeration(const std::string &n) {
  return n == "StateSelect" || n == "AssertionLevel";
}

ClassNode *Flattener::extends_base(ClassNode *cls, const ast::Extends &ext) {
  if (ext.inherited_class) { // the class of that name a base of the enclosing class has
    ClassNode *enclosing = cls->parent;
    if (!enclosing || !enclosing->def)
      return nullptr;
    // Seen from the class the enclosing one is part of: a package's
    // `redeclare record extends State` is the State its other inherited
    // classes see (MLS 7.3.1).
    ClassNode *derived = enclosing->context ? enclosing->context : enclosing;
    for (const auto &outer : enclosing->def->extends) {
      ClassNode *b = extends_base(enclosing, outer);
      if (b && b != enclosing)
        if (ClassNode *found = find_member_class(b, ext.base.parts[0]);
            found && found->tree_class() != cls->tree_class())
          return inherited_view(found, derived);
    }
    return nullptr;
  }
  // Base names are looked up in the enclosing scope of the class: a class
  // cannot extend one of its own (inherited) members.
  return lookup_class(extends_scope(cls, ext, &lib_.root), ext.base.parts, ext.base.global, ext.base.range, false);
}

ClassNode *Flattener::base_scope(ClassNode *base, ClassNode *derived) {
  auto &slot = base_scopes_[{derived, base}];
  if (!slot) {
    slot = std::make_unique<ClassNode>();
    slot->name = base->name;
    slot->def = base->def;
    slot->parent = base->parent;
    slot->origin = base;
    slot->context = derived;
  }
  return slot.get();
}

ClassNode *Flattener::inherited_view(ClassNode *found, ClassNode *derived) {
  ClassNode *declaring = found->parent;
  if (declaring && declaring->context)
    declaring = declaring->origin;
  if (!declaring || !declaring->def || declaring->tree_class() == derived->tree_class())
    return found;
  ClassNode *scope = base_scope(declaring, derived);
  const ClassNode *shown = found->tree_class();
  auto &slot = views_[{scope, shown}];
  if (!slot) {
    slot = std::make_unique<ClassNode>();
    slot->name = found->name;
    slot->def = found->def;
    slot->parent = scope;
    slot->origin = const_cast<ClassNode *>(shown);
  }
  return slot.get();
}

ClassNode *Flattener::own_class(ClassNode *cls, const std::string &name) {
  if (!cls->origin) {
    auto it = cls->children.find(name);
    if (it != cls->children.end() && it->second->def)
      return it->second.get();
    if (ClassNode *loaded = lib_.load_member(*cls, name)) // Modelica's lookup in the file system
      return loaded;
    return it != cls->children.end() ? it->second.get() : nullptr; // an implied package from `within`
  }
  if (cls->context)
    return nullptr; // a base scope's members are its derived class's
  if (auto it = cls->children.find(name); it != cls->children.end())
    return it->second.get();
  ClassNode *shown = own_class(cls->origin, name);
  if (!shown)
    return nullptr;
  auto view = std::make_unique<ClassNode>();
  view->name = shown->name;
  view->def = shown->def;
  view->parent = cls;
  view->origin = const_cast<ClassNode *>(shown->tree_class());
  return (cls->children[name] = std::move(view)).get();
}

std::vector<std::pair<const ast::Extends *, ClassNode *>> Flattener::bases(ClassNode *cls, bool report) {
  std::vector<std::pair<const ast::Extends *, ClassNode *>> out;
  if (!cls || !cls->def)
    return out;
  for (const auto &ext : cls->def->extends) {
    ClassNode *base = extends_base(cls, ext);
    if (!base && ext.inherited_class) {
      if (report)
        diags_.report(DiagId::UnknownClass, ext.range,
                      "class extension '" + cls->name + "': " +
                          (cls->parent ? "no base of '" + cls->parent->path() + "' has a class '" + cls->name + "'"
                                       : std::string("it is not inside a class")));
      continue;
    }
    if (!base) {
      flat::BaseType t;
      if (ext.base.parts.size() == 1 && builtin_type(ext.base.parts[0], t))
        continue; // `extends Real` in a type: handled as a short class would be
      if (ext.base.parts.size() == 1 && ext.base.parts[0] == "ExternalObject" && !ext.base.global)
        continue; // the predefined base of external objects (flatten_external_objects.cpp)
      if (report)
        diags_.report(DiagId::UnknownClass, ext.base.range,
                      "unknown class '" + ext.base.str() + "' in extends clause");
      continue;
    }
    out.emplace_back(&ext, base);
  }
  return out;
}

ClassNode *Flattener::find_member_class(ClassNode *cls, const std::string &name, unsigned depth) {
  if (!cls)
    return nullptr;
  if (depth > 0)
    return search_member_class(cls, name, depth);
  std::pair<ClassNode *, std::string> key{cls, name};
  if (auto hit = member_cache_.find(key); hit != member_cache_.end())
    return hit->second;
  const unsigned long cuts = member_search_cuts_;
  ClassNode *found = search_member_class(cls, name, 0);
  if (cuts == member_search_cuts_)
    member_cache_.emplace(std::move(key), found);
  return found;
}

ClassNode *Flattener::search_member_class(ClassNode *cls, const std::string &name, unsigned depth) {
  if (cls->context) // a base scope: its members are those of the class derived from it
    return find_member_class(cls->context, name, depth);
  if (ClassNode *own = own_class(cls, name))
    return own;
  if (!cls->def)
    return nullptr;
  // Looking up a base's name can come back to this very search (a base
  // named like the member sought, found through enclosing scopes): that
  // path finds nothing.
  if (depth > 32 || !member_searches_.insert({cls, name}).second) {
    ++member_search_cuts_;
    return nullptr;
  }
  struct Done {
    std::set<std::pair<ClassNode *, std::string>> &set;
    std::pair<ClassNode *, std::string> key;
    ~Done() { set.erase(key); }
  } done{member_searches_, {cls, name}};
  if (const auto &sb = cls->def->short_base) // `package P = Q`: the members of Q
    if (ClassNode *base = lookup_class(cls->parent, sb->parts, sb->global, sb->range, false); base && base != cls)
      return find_member_class(base, name, depth + 1);
  for (const auto &ext : cls->def->extends) {
    if (ClassNode *redeclared = redeclared_in_extends(cls, ext, name))
      return redeclared;
    ClassNode *base = extends_base(cls, ext);
    if (base && base != cls)
      if (ClassNode *found = find_member_class(base, name, depth + 1))
        return inherited_view(found, cls);
  }
  return nullptr;
}

ClassNode *Flattener::redeclared_in_extends(ClassNode *cls, const ast::Extends &ext, const std::string &name) {
  for (const ast::ElementMod &em : ext.mod.args)
    if (em.redeclare && em.class_def && em.class_def->name == name)
      return redeclared_class(*em.class_def, cls, nullptr); // read where the extends clause is written
  return nullptr;
}

/// `name` looked up from `scope` outwards through the enclosing classes and
/// their imports (MLS 5.3.1); `from` is set to the scope it was found in.
ClassNode *Flattener::lookup_first(ClassNode *scope, const std::string &name, ClassNode *&from) {
  for (ClassNode *s = scope; s; s = s->parent) {
    from = s;
    if (ClassNode *found = find_member_class(s, name))
      return found;
    if (!s->def)
      continue;
    for (const auto &imp : s->def->imports) {
      ClassNode *found = nullptr;
      if (!imp.alias.empty() && imp.alias == name) {
        found = lookup_class(&lib_.root, imp.path, true, imp.range, false);
      } else if (imp.wildcard) {
        if (ClassNode *pkg = lookup_class(&lib_.root, imp.path, true, imp.range, false))
          found = find_member_class(pkg, name);
      } else if (!imp.names.empty()) {
        for (const auto &n : imp.names)
          if (n == name)
            if (ClassNode *pkg = lookup_class(&lib_.root, imp.path, true, imp.range, false))
              found = find_member_class(pkg, n);
      } else if (imp.alias.empty() && !imp.path.empty() && imp.path.back() == name) {
        found = lookup_class(&lib_.root, imp.path, true, imp.range, false);
      }
      if (found)
        return found;
    }
    if (s->def->encapsulated) {
      from = &lib_.root;
      return find_member_class(&lib_.root, name);
    }
  }
  return nullptr;
}

static std::string joined(const std::vector<std::string> &parts) {
  std::string n;
  for (std::size_t i = 0; i < parts.size(); ++i)
    n += (i ? "." : "") + parts[i];
  return n;
}

ClassNode *Flattener::lookup_class(ClassNode *scope, const std::vector<std::string> &parts,
                                   bool global, SourceRange where, bool report) {
  auto rest = [&](ClassNode *found) {
    for (std::size_t i = 1; found && i < parts.size(); ++i)
      found = find_member_class(found, parts[i]);
    return found;
  };
  if (global) {
    ClassNode *found = rest(find_member_class(&lib_.root, parts[0]));
    if (!found && report)
      fail(DiagId::UnknownClass, where, "unknown class '" + joined(parts) + "'");
    return found;
  }
  ClassNode *from = nullptr;
  ClassNode *first = lookup_first(scope, parts[0], from);
  ClassNode *found = rest(first);
  // Modelica's lookup of A.B stops at the nearest A (MLS 5.3.2), and B must
  // be in it. JModelica goes on outwards to an A that has a B: its Optimica
  // examples name `DoublePendulum.DoublePendulum` inside package
  // DoublePendulum, whose model DoublePendulum is the nearest. Taken so,
  // with a warning.
  for (ClassNode *outer = first; !found && outer && from && from->parent;) {
    outer = lookup_first(from->parent, parts[0], from);
    found = rest(outer);
    if (found && outer_lookup_warned_.insert({where.file, where.begin}).second)
      diags_.report(DiagId::OuterLookup, where,
                    "'" + joined(parts) + "': the nearest '" + parts[0] + "' is '" + first->path() +
                        "', which has no element '" + parts[1] + "' (Modelica looks no further, §5.3.2); the '" +
                        parts[0] + "' further out, '" + outer->path() + "', is taken, as JModelica does");
  }
  if (!found && report)
    fail(DiagId::UnknownClass, where, "unknown class '" + joined(parts) + "'");
  return found;
}

ClassNode *Flattener::replaced_class(const Instance *in, const std::vector<std::string> &parts) {
  if (!in || parts.empty())
    return nullptr;
  auto it = in->replaced.find(parts[0]);
  if (it == in->replaced.end())
    return nullptr;
  ClassNode *cls = it->second;
  for (std::size_t i = 1; cls && i < parts.size(); ++i)
    cls = find_member_class(cls, parts[i]);
  return cls;
}

bool Flattener::resolve_type(ClassNode *scope, const ast::TypeName &type, ResolvedType &out,
                             const Instance *in) {
  flat::BaseType bt;
  ClassNode *cls = nullptr;
  if (in && !type.global && in->replaced.count(type.parts[0])) {
    cls = replaced_class(in, type.parts);
  } else {
    cls = lookup_class(scope, type.parts, type.global, type.range, false);
  }
  if (!cls && type.parts.size() == 1 && builtin_type(type.parts[0], bt)) {
    out.is_builtin = true;
    out.builtin = bt;
    return true;
  }
  if (!cls && type.parts.size() == 1 && predefined_enumeration(type.parts[0])) {
    out.is_builtin = true;
    out.builtin = flat::BaseType::Integer;
    out.is_enumeration = true;
    return true;
  }
  if (!cls) {
    diags_.report(DiagId::UnknownClass, type.range, "unknown class '" + type.str() + "'");
    return false;
  }
  // Follow short class definitions: `type Voltage = Real(unit = "V")`,
  // `connector RealInput = input Real`. Modifiers nearer the use win.
  for (unsigned hops = 0; cls && cls->def && cls->def->short_base; ++hops) {
    if (hops > 32) {
      diags_.report(DiagId::ExtendsCycle, type.range, "type '" + type.str() + "' is defined in terms of itself");
      return false;
    }
    const ast::ClassDef &d = *cls->def;
    if (d.restriction == ast::Restriction::Connector)
      out.is_connector = true;
    Modifier m = make_modifier(d.class_mod, nullptr, cls->parent);
    merge_into(m, out.mod);
    out.mod = std::move(m);
    if (out.causality == ast::Causality::None)
      out.causality = d.short_causality;
    for (const auto &dim : d.short_dims) {
      Scope s{nullptr, cls->parent, nullptr};
      out.dims.push_back(static_cast<int>(dimension_size(*dim, s)));
    }
    ClassNode *next = lookup_class(cls->parent, d.short_base->parts, d.short_base->global,
                                   d.short_base->range, false);
    if (!next && d.short_base->parts.size() == 1 && builtin_type(d.short_base->parts[0], bt)) {
      out.is_builtin = true;
      out.builtin = bt;
      return true;
    }
    if (!next) {
      diags_.report(DiagId::UnknownClass, d.short_base->range,
                    "unknown class '" + d.short_base->str() + "'");
      return false;
    }
    cls = next;
  }
  if (cls->def && !cls->def->enumeration.empty()) {
    out.is_builtin = true;
    out.builtin = flat::BaseType::Integer;
    out.is_enumeration = true;
    return true;
  }
  // `type T extends Real(...)`-style long types: a type class whose only
  // content is `extends <builtin>`; likewise `connector C extends Real; end C;`.
  // The base may itself be a type of a built-in (MultiBody's quaternion
  // `type Orientation extends Internal.QuaternionBase` with
  // `type QuaternionBase = Real[4]`, beside its equalityConstraint function).
  const bool long_type = cls->def && cls->def->components.empty() &&
                         (cls->def->restriction == ast::Restriction::Type ||
                          cls->def->restriction == ast::Restriction::Connector);
  if (long_type && cls->def->extends.size() == 1) {
    const auto &ext = cls->def->extends.front();
    ResolvedType base;
    if (ext.base.parts.size() == 1 && builtin_type(ext.base.parts[0], bt)) {
      base.is_builtin = true;
      base.builtin = bt;
    } else if (!resolve_type(cls->parent, ext.base, base, nullptr)) {
      return false;
    }
    if (base.is_builtin) {
      if (cls->def->restriction == ast::Restriction::Connector || base.is_connector)
        out.is_connector = true;
      Modifier m = make_modifier(ext.mod, nullptr, cls);
      merge_into(base.mod, m);
      merge_into(base.mod, out.mod);
      out.mod = std::move(base.mod);
      out.dims.insert(out.dims.end(), base.dims.begin(), base.dims.end());
      if (out.causality == ast::Causality::None)
        out.causality = base.causality;
      out.is_builtin = true;
      out.builtin = base.builtin;
      out.is_enumeration = base.is_enumeration;
      return true;
    }
  }
  out.cls = cls;
  return true;
}

} // namespace detail
} // namespace mo::frontend
