// External objects (Modelica 3, section 12.9.7): a component whose class
// extends the predefined `ExternalObject` is no variable. Its binding, a call
// of the class's constructor, is kept and flattened at the first call of one
// of its functions: for the constructors of ModelicaStandardTables (the MSL's
// CombiTimeTable, CombiTable1D(s), CombiTable2D) into the table, its keys
// and options (external_object.hpp); any other constructor is refused there.
#include "external_object.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::Op;

namespace {

/// ModelicaStandardTables' text format: `#1`, then `double name(rows, cols)`
/// and the rows; `#` starts a comment.
bool read_text_table(const std::string &path, const std::string &name, int &rows, int &cols,
                     std::vector<double> &values, std::string &why) {
  std::ifstream in(path);
  if (!in) {
    why = "cannot open '" + path + "'";
    return false;
  }
  std::string line;
  bool found = false;
  while (std::getline(in, line)) {
    const std::string code = line.substr(0, line.find('#'));
    std::istringstream ls(code);
    std::string type, rest;
    if (!(ls >> type) || (type != "double" && type != "float"))
      continue;
    std::getline(ls, rest);
    const auto open = rest.find('('), comma = rest.find(',', open), close = rest.find(')', comma);
    if (open == std::string::npos || comma == std::string::npos || close == std::string::npos)
      continue;
    std::string declared = rest.substr(0, open);
    declared.erase(0, declared.find_first_not_of(" \t"));
    declared.erase(declared.find_last_not_of(" \t") + 1);
    if (declared != name)
      continue;
    try {
      rows = std::stoi(rest.substr(open + 1, comma - open - 1));
      cols = std::stoi(rest.substr(comma + 1, close - comma - 1));
    } catch (...) {
      break;
    }
    found = rows > 0 && cols > 0;
    break;
  }
  if (!found) {
    why = "no table 'double " + name + "(rows, columns)' in '" + path + "'";
    return false;
  }
  const std::size_t wanted = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  while (values.size() < wanted && std::getline(in, line)) {
    std::string code = line.substr(0, line.find('#'));
    for (char &ch : code)
      if (ch == ',' || ch == ';' || ch == '\t')
        ch = ' ';
    std::istringstream ls(code);
    std::string word;
    while (ls >> word) {
      try {
        std::size_t used = 0;
        values.push_back(std::stod(word, &used));
        if (used != word.size() || !std::isfinite(values.back()))
          throw std::invalid_argument(word);
      } catch (...) {
        why = "'" + word + "' in table '" + name + "' of '" + path + "' is not a finite number";
        return false;
      }
    }
  }
  if (values.size() != wanted) {
    why = fmt::format("table '{}' of '{}' has {} numbers, not {} x {}", name, path, values.size(), rows, cols);
    return false;
  }
  return true;
}

} // namespace

bool Flattener::is_external_object_class(ClassNode *cls) {
  if (!cls || !cls->def)
    return false;
  for (const auto &ext : cls->def->extends)
    if (!ext.base.global && ext.base.parts.size() == 1 && ext.base.parts[0] == "ExternalObject")
      return true;
  return false;
}

void Flattener::declare_external_object(Instance &parent, const ast::Component &comp, ClassNode *cls,
                                        const Modifier &mod) {
  auto child = std::make_unique<Instance>();
  child->name = comp.name;
  child->flat = parent.flat.empty() ? comp.name : parent.flat + "." + comp.name;
  child->parent = &parent;
  child->decl = &comp;
  child->cls = cls;
  child->variability = ast::Variability::Parameter;
  if (!comp.dims.empty())
    fail(DiagId::Unsupported, comp.range, "arrays of external objects are not supported");
  if (!mod.binding)
    fail(DiagId::Unsupported, comp.range,
         "external object '" + child->flat + "' needs a binding: a call of its class's constructor");
  auto object = std::make_shared<ExternalObject>();
  object->cls = cls;
  object->mod = mod;
  object->name = child->flat;
  object->range = comp.range;
  external_objects_[child.get()] = std::move(object);
  parent.member_index[comp.name] = child.get();
  parent.members.push_back(std::move(child));
}

std::shared_ptr<Flattener::ExternalObject> Flattener::external_object(const Expr &ref, const Scope &s) {
  std::vector<int> dims;
  std::vector<Instance *> found;
  if (ref.kind != ExprKind::Ref || s.locals || !resolve_instances(ref.ref, s, ref.range, dims, found) ||
      found.size() != 1 || !external_objects_.count(found[0]))
    fail(DiagId::Unsupported, ref.range,
         "this argument must name an external object component (a table's tableID) directly");
  std::shared_ptr<ExternalObject> t = external_objects_.at(found[0]);
  if (t->failed)
    throw Reported{}; // reported at its first use
  if (!t->built) {
    try {
      build_table(*t);
      check_table(*t);
    } catch (Reported &) {
      t->failed = true;
      throw;
    }
    t->built = true;
  }
  return t;
}

namespace {

/// The constructor call of an external object, its arguments by the
/// constructor's input names, flattened in the binding's scope.
struct ConstructorCall {
  Flattener &f;
  const Flattener::ExternalObject &t;
  const Expr &call;
  Scope scope;
  std::map<std::string, const Expr *> args;

  ConstructorCall(Flattener &fl, const Flattener::ExternalObject &obj, ClassNode *ctor)
      : f(fl), t(obj), call(*obj.mod.binding), scope{obj.mod.scope, obj.mod.lexical, nullptr} {
    std::vector<std::string> inputs;
    for (const auto &c : ctor->def->components)
      if (c.causality == ast::Causality::Input)
        inputs.push_back(c.name);
    for (std::size_t i = 0; i < call.args.size() && i < inputs.size(); ++i)
      args[inputs[i]] = call.args[i].get();
    for (const auto &na : call.named)
      args[na.name] = na.value.get();
  }
  bool has(const std::string &name) const { return args.count(name) && args.at(name); }
  const Expr &need(const std::string &name) {
    if (!has(name))
      f.fail(DiagId::WrongArgumentCount, call.range,
             "the constructor of '" + t.name + "' has no argument '" + name + "'");
    return *args.at(name);
  }
  double number(const std::string &name) { return f.eval(*f.scalar_expr(need(name), scope), need(name).range); }
  /// The file name is `if tableOnFile and fileName <> "NoName" and not
  /// Strings.isEmpty(fileName) then fileName else "NoName"`: conditions are
  /// decided left to right, so that a table given inline never calls
  /// isEmpty's external C function.
  bool holds(const Expr &c) {
    if (c.kind == ExprKind::Binary && (c.op == Op::And || c.op == Op::Or)) {
      const bool first = holds(*c.args[0]);
      return c.op == Op::And ? first && holds(*c.args[1]) : first || holds(*c.args[1]);
    }
    if (c.kind == ExprKind::Unary && c.op == Op::Not)
      return !holds(*c.args[0]);
    return f.eval(*f.scalar_expr(c, scope), c.range) != 0;
  }
  std::string text(const Expr &e) {
    if (e.kind == ExprKind::If) {
      for (std::size_t i = 0; i + 1 < e.args.size(); i += 2)
        if (holds(*e.args[i]))
          return text(*e.args[i + 1]);
      return text(*e.args.back());
    }
    std::optional<std::string> v = f.eval_string(*f.scalar_expr(e, scope), e.range);
    if (!v)
      f.fail(DiagId::NotConstant, e.range, "this name of table '" + t.name + "' must be a constant string");
    return *v;
  }
};

} // namespace

void Flattener::build_table(ExternalObject &t) {
  const Expr *call = t.mod.binding;
  ClassNode *ctor = find_member_class(t.cls, "constructor");
  if (call->kind != ExprKind::Call || !ctor || !ctor->def || !ctor->def->is_external)
    fail(DiagId::Unsupported, call->range,
         "the binding of external object '" + t.name + "' must call its class's external constructor");
  const std::string &c_name = ctor->def->external_function;
  if (c_name == "ModelicaStandardTables_CombiTimeTable_init")
    t.kind = ExternalObject::Kind::TimeTable;
  else if (c_name == "ModelicaStandardTables_CombiTable1D_init")
    t.kind = ExternalObject::Kind::Table1D;
  else if (c_name == "ModelicaStandardTables_CombiTable2D_init")
    t.kind = ExternalObject::Kind::Table2D;
  else
    fail(DiagId::Unsupported, call->range,
         "external object '" + t.name + "': its constructor's C function '" + c_name +
             "' is not provided (only ModelicaStandardTables' CombiTimeTable, CombiTable1D and CombiTable2D are)");
  ConstructorCall cc(*this, t, ctor);
  const std::string table_name = cc.text(cc.need("tableName")), file_name = cc.text(cc.need("fileName"));
  if (file_name != "NoName" && !file_name.empty()) {
    if (file_name.rfind("modelica://", 0) == 0)
      fail(DiagId::Unsupported, cc.need("fileName").range,
           "table file '" + file_name + "': modelica:// URIs are not resolved; give a file path");
    std::vector<double> values;
    std::string why;
    if (!read_text_table(file_name, table_name, t.rows, t.cols, values, why))
      fail(DiagId::CannotReadFile, cc.need("fileName").range, "table of '" + t.name + "': " + why);
    for (double v : values)
      t.table.push_back(ast::make_real(v));
  } else {
    Tensor table = expr(cc.need("table"), cc.scope);
    if (table.dims.size() != 2 || table.dims[0] < 1 || table.dims[1] < 1)
      fail(DiagId::TypeMismatch, cc.need("table").range, "table of '" + t.name + "' must be a non-empty matrix");
    t.rows = table.dims[0];
    t.cols = table.dims[1];
    t.table = std::move(table.elems);
  }
  t.range = call->range;
  if (cc.has("smoothness"))
    t.smoothness = static_cast<int>(cc.number("smoothness"));
  if (cc.has("extrapolation"))
    t.extrapolation = static_cast<int>(cc.number("extrapolation"));
  if (cc.has("startTime"))
    t.start_time = cc.number("startTime");
  if (cc.has("columns")) {
    Tensor columns = expr(cc.need("columns"), cc.scope);
    for (const auto &c : columns.elems)
      t.columns.push_back(static_cast<int>(eval(*c, cc.need("columns").range)));
  }
}

void Flattener::check_table(ExternalObject &t) {
  const SourceRange where = t.range;
  const bool two_d = t.kind == ExternalObject::Kind::Table2D;
  if ((two_d && (t.rows < 2 || t.cols < 2)) || (!two_d && t.cols < 2))
    fail(DiagId::TypeMismatch, where, "table of '" + t.name + "' has too few columns or rows");
  // Keys: the first column (and, 2-D, the first row), strictly or (for jumps
  // of 1-D and time tables) weakly increasing.
  for (int r = two_d ? 1 : 0; r < t.rows; ++r)
    t.key.push_back(eval(*t.table[static_cast<std::size_t>(r * t.cols)], where));
  for (int c = 1; two_d && c < t.cols; ++c)
    t.key2.push_back(eval(*t.table[static_cast<std::size_t>(c)], where));
  auto check_keys = [&](const std::vector<double> &k, bool strict, const char *what) {
    for (std::size_t i = 1; i < k.size(); ++i)
      if (k[i] < k[i - 1] || (strict && k[i] == k[i - 1]))
        fail(DiagId::EvaluationError, where,
             fmt::format("table of '{}': its {} must increase{} ({} after {})", t.name, what,
                         strict ? " strictly" : "", k[i], k[i - 1]));
  };
  check_keys(t.key, two_d, two_d ? "first column (from row 2)" : "first column");
  check_keys(t.key2, true, "first row (from column 2)");
  for (int c : t.columns)
    if (c < 2 || c > t.cols)
      fail(DiagId::BadSubscript, where,
           fmt::format("table of '{}': column {} is not among its columns 2..{}", t.name, c, t.cols));
  // The C library treats a spline through two points as linear segments.
  const int points = two_d ? std::min(t.rows, t.cols) - 1 : t.rows;
  if (t.smoothness == 2 && points <= 2)
    t.smoothness = 1;
  if (two_d && t.smoothness != 1)
    fail(DiagId::Unsupported, where,
         "table of '" + t.name + "': a 2-D table is provided with smoothness = LinearSegments only "
         "(not ContinuousDerivative's Akima splines, not ConstantSegments)");
  if (t.smoothness == 2)
    for (std::size_t i = 1; i < t.key.size(); ++i)
      if (t.key[i] == t.key[i - 1])
        fail(DiagId::EvaluationError, where,
             fmt::format("table of '{}': a spline (ContinuousDerivative) needs strictly increasing keys ({} twice)",
                         t.name, t.key[i]));
  const bool time_table = t.kind == ExternalObject::Kind::TimeTable;
  if (time_table && t.extrapolation == 3 && t.rows > 1 && t.key.back() == t.key.front())
    fail(DiagId::EvaluationError, where, "table of '" + t.name + "': a periodic table needs a period > 0");
  if (time_table && t.extrapolation == 4)
    diags_.report(DiagId::IgnoredModifier, where,
                  "table of '" + t.name + "': extrapolation = NoExtrapolation is not checked during a "
                  "simulation; outside the table its end values are held");
}

} // namespace mo::frontend::detail
