// Record values in expressions (MLS 12.6): a record is carried as the
// scalars of its fields in declaration order (RecordLayout), so that a
// record passes through functions, if-expressions and equations element by
// element like an array. A reference to a record component gives its
// variables, `R(...)` builds one from its arguments and declared bindings,
// and `r.x` picks the field's scalars.
#include "flattener.hpp"

#include <fmt/format.h>
#include <functional>
#include <tuple>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;

bool RecordLayout::same_shape(const RecordLayout &o) const {
  if (fields.size() != o.fields.size() || size != o.size)
    return false;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const Field &a = fields[i], &b = o.fields[i];
    if (a.name != b.name || a.dims != b.dims || !same_record_type(a.record, b.record))
      return false;
  }
  return true;
}

bool same_record_type(const std::shared_ptr<const RecordLayout> &a, const std::shared_ptr<const RecordLayout> &b) {
  return !a == !b && (!a || a->same_shape(*b));
}

namespace {

std::size_t product(const std::vector<int> &dims) {
  std::size_t n = 1;
  for (int d : dims)
    n *= static_cast<std::size_t>(d);
  return n;
}

} // namespace

bool is_record_class(const ClassNode *cls) {
  return cls && cls->def &&
         (cls->def->restriction == ast::Restriction::Record ||
          cls->def->restriction == ast::Restriction::OperatorRecord);
}

bool is_record_instance(const Instance &inst) { return inst.var < 0 && inst.dims.empty() && is_record_class(inst.cls); }

/// The MSL's `record M330_50A extends BaseData(tabris = [...])`: the
/// extends modifier is M330_50A's default for tabris (and sizes its `[:, :]`).
const ast::Expr *element_binding(const ast::Modification &m, const std::string &name) {
  for (const ast::ElementMod &em : m.args)
    if (!em.redeclare && em.path.size() == 1 && em.path[0] == name && em.mod.binding)
      return em.mod.binding.get();
  return nullptr;
}

std::pair<const ast::Expr *, ClassNode *> Flattener::field_binding(ClassNode *cls, ClassNode *owner,
                                                                   const ast::Component &c) {
  using Found = std::pair<const ast::Expr *, ClassNode *>;
  std::function<Found(ClassNode *, unsigned)> search = [&](ClassNode *k, unsigned depth) -> Found {
    if (!k || k == owner || depth > 32)
      return {nullptr, nullptr};
    for (auto &[ext, base] : bases(k)) {
      if (const ast::Expr *b = element_binding(ext->mod, c.name))
        return {b, k};
      if (Found found = search(base, depth + 1); found.first)
        return found;
    }
    return {nullptr, nullptr};
  };
  if (Found found = search(cls, 0); found.first)
    return found;
  return {c.mod.binding.get(), c.mod.binding ? owner : nullptr};
}

std::shared_ptr<const RecordLayout> Flattener::record_layout(ClassNode *cls, SourceRange where) {
  if (auto it = record_layouts_.find(cls); it != record_layouts_.end()) {
    if (!it->second)
      fail(DiagId::Unsupported, where, "record '" + cls->path() + "' contains itself");
    return it->second;
  }
  record_layouts_[cls] = nullptr; // in progress: a record that contains itself
  auto layout = std::make_shared<RecordLayout>();
  layout->cls = cls;
  // Bases first, then the class's own components (MLS 7.1: inherited elements come first).
  std::vector<ClassNode *> order;
  std::function<void(ClassNode *, unsigned)> visit = [&](ClassNode *c, unsigned depth) {
    if (!c || !c->def || depth > 32)
      return;
    for (auto &[ext, base] : bases(c))
      visit(base, depth + 1);
    order.push_back(c);
  };
  visit(cls, 0);
  for (ClassNode *owner : order)
    for (const ast::Component &c : owner->def->components) {
      if (layout->find(c.name))
        continue; // an identical element inherited twice
      ResolvedType rt;
      if (!resolve_type(owner, c.type, rt))
        throw Reported{};
      RecordLayout::Field f;
      f.name = c.name;
      f.decl = &c;
      f.owner = owner;
      Scope in_class{nullptr, owner, nullptr};
      std::tie(f.binding, f.binding_scope) = field_binding(cls, owner, c);
      std::optional<Tensor> bound;  // the default's value, which sizes `[:]` dimensions
      for (std::size_t k = 0; k < c.dims.size(); ++k) {
        const auto &d = c.dims[k];
        if (d->kind == ExprKind::Colon) {
          if (!bound && f.binding)
            bound = expr(*f.binding, Scope{nullptr, f.binding_scope, nullptr});
          if (!bound || bound->dims.size() != c.dims.size())
            fail(DiagId::Unsupported, c.range,
                 "record field '" + c.name + "' of '" + cls->path() + "' is an array of unknown size");
          f.dims.push_back(bound->dims[k]);
          continue;
        }
        f.dims.push_back(static_cast<int>(eval_int(*d, in_class)));
      }
      f.dims.insert(f.dims.end(), rt.dims.begin(), rt.dims.end());
      if (!rt.is_builtin && !rt.is_enumeration) {
        if (!is_record_class(rt.cls))
          fail(DiagId::Unsupported, c.range,
               "record field '" + c.name + "' of '" + cls->path() + "' is neither a number nor a record");
        f.record = record_layout(rt.cls, c.range);
      }
      f.offset = layout->size;
      f.size = product(f.dims) * (f.record ? f.record->size : 1);
      layout->size += f.size;
      layout->fields.push_back(std::move(f));
    }
  record_layouts_[cls] = layout;
  return layout;
}

ExprPtr Flattener::variable_expr(std::int32_t var, SourceRange where) {
  // No reference into model_->variables is held across eval_param: it can
  // instantiate a later element (member()), which adds variables.
  if (model_->variables[var].variability != ast::Variability::Continuous &&
      model_->variables[var].type == flat::BaseType::String) {
    // A String constant or parameter is its text: lowering has no strings
    // (the MSL's transformers take substrings of `VectorGroup` when
    // flattening and test them, `C1 == "D"`).
    auto r = ast::make_ref(model_->variables[var].name, where);
    r->var = var;
    if (const std::optional<std::string> text = eval_string(*r, where)) {
      auto e = std::make_unique<ast::Expr>(ast::ExprKind::String, where);
      e->text = *text;
      return e;
    }
    return r;
  }
  if (model_->variables[var].variability == ast::Variability::Constant) {
    const flat::BaseType type = model_->variables[var].type;
    const double v = eval_param(var, where);
    if (type == flat::BaseType::Boolean) // a Boolean stays one (Machines' `constant Boolean quasiStationary`)
      return ast::make_bool(v != 0.0, where);
    return type != flat::BaseType::Real ? ast::make_integer(v, where) : ast::make_real(v, where);
  }
  auto r = ast::make_ref(model_->variables[var].name, where);
  r->var = var;
  return r;
}

Tensor Flattener::record_value(const std::vector<Instance *> &insts, const std::vector<int> &dims,
                               SourceRange where) {
  Tensor t;
  t.dims = dims;
  std::function<void(Instance &, const RecordLayout &)> leaves = [&](Instance &inst, const RecordLayout &layout) {
    for (const RecordLayout::Field &f : layout.fields) {
      Instance *m = member(inst, f.name);
      if (!m)
        fail(DiagId::UnknownComponent, where, "'" + inst.flat + "' has no field '" + f.name + "'");
      std::vector<Instance *> elements;
      if (m->dims.empty())
        elements.push_back(m);
      for (auto &el : m->elements)
        elements.push_back(el.get());
      if (elements.size() != product(f.dims))
        fail(DiagId::TypeMismatch, where, "'" + m->flat + "' does not have the size of its record field");
      for (Instance *el : elements) {
        if (f.record)
          leaves(*el, *f.record);
        else if (el->var >= 0)
          t.elems.push_back(variable_expr(el->var, where));
        else
          fail(DiagId::TypeMismatch, where, "'" + el->flat + "' is not a number");
      }
    }
  };
  for (Instance *inst : insts) {
    auto layout = record_layout(inst->cls, where);
    if (t.record && !t.record->same_shape(*layout))
      fail(DiagId::TypeMismatch, where, "the elements of this record array have different fields");
    t.record = layout;
    leaves(*inst, *layout);
  }
  return t;
}

Tensor Flattener::record_field(const Tensor &t, const std::string &name, SourceRange where) {
  const RecordLayout::Field *f = t.record ? t.record->find(name) : nullptr;
  if (!f)
    fail(DiagId::UnknownComponent, where,
         t.record ? "record '" + t.record->cls->path() + "' has no field '" + name + "'"
                  : "a value that is not a record is used as one (no field '" + name + "')");
  Tensor out;
  out.dims = t.dims;
  out.dims.insert(out.dims.end(), f->dims.begin(), f->dims.end());
  out.record = f->record;
  for (std::size_t start = 0; start < t.elems.size(); start += t.record->size)
    for (std::size_t k = 0; k < f->size; ++k) {
      const ExprPtr &e = t.elems[start + f->offset + k];
      out.elems.push_back(e ? e->clone() : nullptr);
    }
  return out;
}

namespace {

/// True if `e` reads a field of `fields` that is not (wholly) set.
bool reads_unset(const Expr &root, const FunctionLocals &fields) {
  std::vector<const Expr *> work{&root};
  while (!work.empty()) {
    const Expr *e = work.back();
    work.pop_back();
    if (e->kind == ExprKind::Ref && !e->ref.global)
      if (auto it = fields.find(e->ref.parts[0].name); it != fields.end())
        for (const auto &x : it->second.elems)
          if (!x)
            return true;
    for (const auto &a : e->args)
      if (a)
        work.push_back(a.get());
  }
  return false;
}

/// The record built from `given` (per field, the caller's expression or
/// null) in the caller's scope `caller`; a field without one takes its
/// declared binding, flattened in its class with the fields before it in
/// scope, or stays null (`missing_ok`: also where the binding reads a field
/// still null, as in a function's local record) or is reported.
Tensor build_record(Flattener &f, const std::shared_ptr<const RecordLayout> &layout,
                    const std::vector<const Expr *> &given, const Scope &caller, bool missing_ok,
                    SourceRange where) {
  Tensor out;
  out.record = layout;
  FunctionLocals fields;
  for (std::size_t i = 0; i < layout->fields.size(); ++i) {
    const RecordLayout::Field &fd = layout->fields[i];
    Tensor v;
    if (given[i]) {
      v = f.expr(*given[i], caller);
    } else if (fd.binding && !(missing_ok && reads_unset(*fd.binding, fields))) {
      Scope own{nullptr, fd.binding_scope, nullptr};
      own.locals = &fields;
      v = f.expr(*fd.binding, own);
    } else if (fd.record) {
      v = f.record_defaults(fd.record, fd.dims, where);
    } else if (missing_ok) {
      v.dims = fd.dims;
      v.elems.resize(fd.size);
    } else {
      f.fail(DiagId::WrongArgumentCount, where,
             "field '" + fd.name + "' of record '" + layout->cls->path() + "' has no value and no default");
    }
    const bool fits = v.elems.size() == fd.size && (v.is_scalar() ? fd.dims.empty() : v.dims == fd.dims) &&
                      same_record_type(v.record, fd.record);
    if (!fits)
      f.fail(DiagId::TypeMismatch, given[i] ? given[i]->range : where,
             "the value of field '" + fd.name + "' of record '" + layout->cls->path() + "' has the wrong size or type");
    Tensor copy;
    copy.dims = v.dims;
    copy.record = v.record;
    for (auto &e : v.elems) {
      copy.elems.push_back(e ? e->clone() : nullptr);
      out.elems.push_back(std::move(e));
    }
    fields[fd.name] = std::move(copy);
  }
  return out;
}

} // namespace

Tensor Flattener::record_defaults(const std::shared_ptr<const RecordLayout> &layout, const std::vector<int> &dims,
                                  SourceRange where) {
  Tensor one = build_record(*this, layout, std::vector<const Expr *>(layout->fields.size(), nullptr), Scope{},
                            true, where);
  Tensor out;
  out.dims = dims;
  out.record = layout;
  for (std::size_t k = 0; k < product(dims); ++k)
    for (const auto &e : one.elems)
      out.elems.push_back(e ? e->clone() : nullptr);
  return out;
}

std::optional<Tensor> Flattener::record_from_modifiers(ClassNode *scope, const ast::Component &decl,
                                                      SourceRange where) {
  ResolvedType rt;
  if (!resolve_type(scope, decl.type, rt))
    throw Reported{};
  if (rt.is_builtin || !rt.cls || !is_record_class(rt.cls))
    return std::nullopt;
  auto layout = record_layout(rt.cls, where);
  const Scope in_scope{nullptr, scope, nullptr};
  std::vector<int> dims;
  for (const auto &d : decl.dims)
    dims.push_back(static_cast<int>(eval_int(*d, in_scope)));
  dims.insert(dims.end(), rt.dims.begin(), rt.dims.end());
  std::vector<const Expr *> given(layout->fields.size(), nullptr);
  for (const ast::ElementMod &em : decl.mod.args) {
    const RecordLayout::Field *f = em.path.size() == 1 ? layout->find(em.path[0]) : nullptr;
    if (em.redeclare || !f || !em.mod.binding || !em.mod.args.empty())
      fail(DiagId::Unsupported, em.range,
           "record constant '" + decl.name + "': only modifiers that bind a field ('f = e') are supported");
    if (!dims.empty() && !em.each)
      fail(DiagId::Unsupported, em.range,
           "array of record constants '" + decl.name + "': only 'each' modifiers of its fields are supported");
    given[static_cast<std::size_t>(f - layout->fields.data())] = em.mod.binding.get();
  }
  const Tensor one = build_record(*this, layout, given, in_scope, false, where);
  Tensor out;
  out.dims = dims;
  out.record = layout;
  for (std::size_t k = 0; k < product(dims); ++k)
    for (const auto &e : one.elems)
      out.elems.push_back(e->clone());
  return out;
}

Tensor Flattener::record_constructor(ClassNode *cls, const Expr &call, const Scope &s) {
  auto layout = record_layout(cls, call.range);
  // MLS 12.6: the constructor's inputs are the fields but constants and
  // fields with a final binding, in declaration order.
  std::vector<std::size_t> inputs;
  for (std::size_t i = 0; i < layout->fields.size(); ++i) {
    const ast::Component &c = *layout->fields[i].decl;
    if (c.variability != ast::Variability::Constant && !(c.final_ && c.mod.binding))
      inputs.push_back(i);
  }
  std::vector<const Expr *> given(layout->fields.size(), nullptr);
  if (call.args.size() > inputs.size())
    fail(DiagId::WrongArgumentCount, call.range,
         fmt::format("record constructor {}() takes {} argument(s), {} given", cls->path(), inputs.size(),
                     call.args.size()));
  for (std::size_t i = 0; i < call.args.size(); ++i)
    given[inputs[i]] = call.args[i].get();
  for (const auto &na : call.named) {
    std::size_t k = 0;
    while (k < inputs.size() && layout->fields[inputs[k]].name != na.name)
      ++k;
    if (k == inputs.size())
      fail(DiagId::WrongArgumentCount, na.value->range,
           "record constructor " + cls->path() + "() has no input named '" + na.name + "'");
    if (given[inputs[k]])
      fail(DiagId::WrongArgumentCount, na.value->range,
           "input '" + na.name + "' of record constructor " + cls->path() + "() is given twice");
    given[inputs[k]] = na.value.get();
  }
  return build_record(*this, layout, given, s, false, call.range);
}

} // namespace mo::frontend::detail
