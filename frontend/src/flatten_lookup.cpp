// Class lookup: the package tree of all files, lexical scopes, imports and
// classes inherited through `extends`.
#include "flattener.hpp"

#include <algorithm>

namespace mo::frontend {

std::string ClassNode::path() const {
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
  node_of[&def] = slot.get();
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
    if (auto it = cls->children.find(first); it != cls->children.end() && it->second->def)
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
    if (!cls->parent || !cls->parent->def)
      return nullptr;
    for (const auto &outer : cls->parent->def->extends) {
      ClassNode *b = extends_base(cls->parent, outer);
      if (b && b != cls->parent)
        if (ClassNode *found = find_member_class(b, ext.base.parts[0]); found && found != cls)
          return found;
    }
    return nullptr;
  }
  // Base names are looked up in the enclosing scope of the class: a class
  // cannot extend one of its own (inherited) members.
  return lookup_class(extends_scope(cls, ext, &lib_.root), ext.base.parts, ext.base.global, ext.base.range, false);
}

std::vector<std::pair<const ast::Extends *, ClassNode *>> Flattener::bases(ClassNode *cls, bool report) {
  std::vector<std::pair<const ast::Extends *, ClassNode *>> out;
  if (!cls || !cls->def)
    return out;
  for (const auto &ext : cls->def->extends) {
    if (ext.inherited_class && cls->parent && cls->parent->def &&
        cls->parent->def->restriction == ast::Restriction::Package) {
      // What the package inherits would still see the class it replaces
      // (a redeclared class is seen by the instance that replaced it only).
      if (report)
        diags_.report(DiagId::Unsupported, ext.range,
                      "class extension '" + cls->name + "' inside package '" + cls->parent->path() +
                          "' is not supported (the classes the package inherits would not see it)");
      continue;
    }
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
  auto it = cls->children.find(name);
  if (it != cls->children.end() && it->second->def)
    return it->second.get();
  if (ClassNode *loaded = lib_.load_member(*cls, name)) // Modelica's lookup in the file system
    return loaded;
  if (it != cls->children.end())
    return it->second.get(); // an implied package from `within`
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
    ClassNode *base = extends_base(cls, ext);
    if (base && base != cls)
      if (ClassNode *found = find_member_class(base, name, depth + 1))
        return found;
  }
  return nullptr;
}

ClassNode *Flattener::lookup_class(ClassNode *scope, const std::vector<std::string> &parts,
                                   bool global, SourceRange where, bool report) {
  ClassNode *found = nullptr;
  if (global) {
    found = find_member_class(&lib_.root, parts[0]);
  } else {
    for (ClassNode *s = scope; s && !found; s = s->parent) {
      found = find_member_class(s, parts[0]);
      if (found || !s->def)
        continue;
      for (const auto &imp : s->def->imports) {
        if (!imp.alias.empty() && imp.alias == parts[0]) {
          found = lookup_class(&lib_.root, imp.path, true, imp.range, false);
        } else if (imp.wildcard) {
          if (ClassNode *pkg = lookup_class(&lib_.root, imp.path, true, imp.range, false))
            found = find_member_class(pkg, parts[0]);
        } else if (!imp.names.empty()) {
          for (const auto &n : imp.names)
            if (n == parts[0])
              if (ClassNode *pkg = lookup_class(&lib_.root, imp.path, true, imp.range, false))
                found = find_member_class(pkg, n);
        } else if (imp.alias.empty() && !imp.path.empty() && imp.path.back() == parts[0]) {
          found = lookup_class(&lib_.root, imp.path, true, imp.range, false);
        }
        if (found)
          break;
      }
      if (s->def && s->def->encapsulated && !found) {
        found = find_member_class(&lib_.root, parts[0]);
        break;
      }
    }
  }
  for (std::size_t i = 1; found && i < parts.size(); ++i)
    found = find_member_class(found, parts[i]);
  if (!found && report) {
    std::string n;
    for (std::size_t i = 0; i < parts.size(); ++i)
      n += (i ? "." : "") + parts[i];
    fail(DiagId::UnknownClass, where, "unknown class '" + n + "'");
  }
  return found;
}

bool Flattener::resolve_type(ClassNode *scope, const ast::TypeName &type, ResolvedType &out,
                             const Instance *in) {
  flat::BaseType bt;
  ClassNode *cls = nullptr;
  if (in && !type.global && in->replaced.count(type.parts[0])) {
    cls = in->replaced.at(type.parts[0]);
    for (std::size_t i = 1; cls && i < type.parts.size(); ++i)
      cls = find_member_class(cls, type.parts[i]);
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
