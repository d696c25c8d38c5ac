// External objects (Modelica 3, section 12.9.7) and the tables of the MSL's
// ModelicaStandardTables library, which the tool provides itself.
//
// A component whose class extends the predefined `ExternalObject` is no
// variable: its binding, a call of the class's constructor, is kept and
// flattened at its first use. A call of one of the C functions below with
// such an object becomes an expression of the object's table, so that the
// symbolic stages differentiate it like any other (sensitivities to table
// entries included) and nothing external is linked:
//
// - CombiTimeTable: the value (`_getValue`) is a balanced tree of
//   noEvent(x < key) over the rows, in the row's segment constant or linear,
//   outside the table held, continued through the last two points, or
//   periodic; `_nextTimeEvent` is the next row time that is a time event
//   (each row for constant segments, a repeated time for linear ones, the
//   table's end). As in the C library, between the instant the integrator
//   reaches that time and the table block's when-clause updating it (that
//   is, while t >= nextTimeEvent = pre(nextTimeEvent)), the value is the one
//   from the left, so that the step up to a jump is smooth.
// - CombiTable1D: the same tree in the input u, continued linearly outside.
// - CombiTable2D: bilinear, continued linearly outside.
//
// Akima splines (smoothness = ContinuousDerivative) are not provided.
#include "flattener.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;
using ast::Op;

struct Flattener::ExternalObject {
  enum class Kind { TimeTable, Table1D, Table2D };
  // The declaration, flattened at first use.
  ClassNode *cls = nullptr;
  Modifier mod;
  std::string name;
  SourceRange range;
  bool built = false;
  // The table.
  Kind kind = Kind::TimeTable;
  int rows = 0, cols = 0;
  std::vector<ExprPtr> table; ///< row-major, flat expressions
  std::vector<double> key;    ///< first column (2-D: of rows 2..), evaluated
  std::vector<double> key2;   ///< 2-D: first row (columns 2..), evaluated
  std::vector<int> columns;   ///< 1-based table columns of the outputs
  int smoothness = 1;         ///< Modelica.Blocks.Types.Smoothness: 1 linear, 2 Akima, 3 constant
  int extrapolation = 2;      ///< Extrapolation: 1 hold, 2 last two points, 3 periodic, 4 none
  double start_time = 0;
  ExprPtr at(int r, int c) const { return table[static_cast<std::size_t>(r * cols + c)]->clone(); }
};

namespace {

constexpr double kNoEvent = std::numeric_limits<double>::max(); // DBL_MAX: no further time event

ExprPtr num(double v) { return ast::make_real(v); }
ExprPtr bin(Op op, ExprPtr a, ExprPtr b) { return ast::make_binary(op, std::move(a), std::move(b)); }
ExprPtr no_event(ExprPtr e) {
  std::vector<ExprPtr> a;
  a.push_back(std::move(e));
  return ast::make_call("noEvent", std::move(a));
}
ExprPtr call1(const char *fn, ExprPtr e) {
  std::vector<ExprPtr> a;
  a.push_back(std::move(e));
  return ast::make_call(fn, std::move(a));
}
ExprPtr if_then(ExprPtr c, ExprPtr a, ExprPtr b) {
  auto e = std::make_unique<Expr>(ExprKind::If);
  e->args.push_back(std::move(c));
  e->args.push_back(std::move(a));
  e->args.push_back(std::move(b));
  return e;
}
/// noEvent(x < k), or noEvent(x <= k) for the limit from the left.
ExprPtr below(const Expr &x, double k, bool left) { return no_event(bin(left ? Op::Le : Op::Lt, x.clone(), num(k))); }

/// The line through rows (r0, key0) and (r1, key1) of column `c` at x.
ExprPtr line(const Flattener::ExternalObject &t, const std::vector<double> &key, int r0, int r1, int c,
             const Expr &x) {
  if (key[r1] == key[r0])
    return t.at(r1, c);
  ExprPtr slope = bin(Op::Div, bin(Op::Sub, t.at(r1, c), t.at(r0, c)), num(key[r1] - key[r0]));
  return bin(Op::Add, t.at(r0, c), bin(Op::Mul, std::move(slope), bin(Op::Sub, x.clone(), num(key[r0]))));
}

/// Rows' values along `key` (1-D and time tables): segments lo..hi-1 as a
/// balanced tree; segment i is [key_i, key_i+1) (left: (key_i, key_i+1]).
ExprPtr segments(const Flattener::ExternalObject &t, int c, const Expr &x, bool left, int lo, int hi,
                 bool constant) {
  if (hi - lo == 1)
    return constant ? t.at(lo, c) : line(t, t.key, lo, lo + 1, c, x);
  const int mid = (lo + hi) / 2;
  return if_then(below(x, t.key[mid], left), segments(t, c, x, left, lo, mid, constant),
                 segments(t, c, x, left, mid, hi, constant));
}

/// Column c of a 1-D or time table at x, with its extrapolation (periodic
/// tables: x already mapped into the period).
ExprPtr column_at(const Flattener::ExternalObject &t, int c, const Expr &x, bool left, int extrapolation) {
  const int n = t.rows;
  if (n == 1)
    return t.at(0, c);
  const bool constant = t.smoothness == 3;
  ExprPtr inside = segments(t, c, x, left, 0, n - 1, constant);
  ExprPtr before, after;
  if (extrapolation == 2) { // through the last two points
    before = line(t, t.key, 0, 1, c, x);
    after = line(t, t.key, n - 2, n - 1, c, x);
  } else {
    before = t.at(0, c);
    after = t.at(n - 1, c);
  }
  // At the last key itself the table's own value (from the left: the
  // segment before it).
  ExprPtr beyond = left ? no_event(bin(Op::Gt, x.clone(), num(t.key[n - 1])))
                        : no_event(bin(Op::Ge, x.clone(), num(t.key[n - 1])));
  return if_then(below(x, t.key[0], left), std::move(before),
                 if_then(std::move(beyond), std::move(after), std::move(inside)));
}

/// x mapped into one period [k0, kn) (left: (k0, kn]).
ExprPtr periodic(const Flattener::ExternalObject &t, const Expr &x, bool left) {
  const double k0 = t.key.front(), period = t.key.back() - k0;
  ExprPtr cycles = call1(left ? "ceil" : "floor", bin(Op::Div, bin(Op::Sub, x.clone(), num(k0)), num(period)));
  ExprPtr shifted = bin(Op::Sub, x.clone(), bin(Op::Mul, num(period), no_event(std::move(cycles))));
  return left ? bin(Op::Add, std::move(shifted), num(period)) : std::move(shifted);
}

/// A time table's column c at shifted time s (0 before the start time).
ExprPtr time_value(const Flattener::ExternalObject &t, int c, const Expr &s, bool left) {
  ExprPtr value;
  if (t.extrapolation == 3 && t.rows > 1) {
    ExprPtr p = periodic(t, s, left);
    value = column_at(t, c, *p, left, 1);
  } else {
    value = column_at(t, c, s, left, t.extrapolation);
  }
  return if_then(below(s, 0.0, left), num(0.0), std::move(value));
}

/// The time events of one pass through the table after its first key:
/// each new row time (constant segments) or each repeated one (a jump of
/// linear segments), then the last key.
std::vector<double> event_keys(const Flattener::ExternalObject &t) {
  std::vector<double> out;
  const int n = t.rows;
  for (int i = 1; i < n - 1; ++i) {
    const bool event = t.smoothness == 3 ? t.key[i] > t.key[i - 1] : t.key[i] == t.key[i + 1];
    if (event && (out.empty() || t.key[i] > out.back()) && t.key[i] < t.key[n - 1])
      out.push_back(t.key[i]);
  }
  out.push_back(t.key[n - 1]);
  return out;
}

/// The first of `keys` after x (a chain: the events are few).
ExprPtr next_key(const std::vector<double> &keys, const Expr &x, ExprPtr otherwise) {
  ExprPtr e = std::move(otherwise);
  for (std::size_t i = keys.size(); i-- > 0;)
    e = if_then(below(x, keys[i], false), num(keys[i]), std::move(e));
  return e;
}

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
        if (used != word.size())
          throw std::invalid_argument(word);
      } catch (...) {
        why = "'" + word + "' in table '" + name + "' of '" + path + "' is not a number";
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
  if (t->built)
    return t;
  const Expr *call = t->mod.binding;
  ClassNode *ctor = find_member_class(t->cls, "constructor");
  if (call->kind != ExprKind::Call || !ctor || !ctor->def || !ctor->def->is_external)
    fail(DiagId::Unsupported, call->range,
         "the binding of external object '" + t->name + "' must call its class's external constructor");
  const std::string &c_name = ctor->def->external_function;
  if (c_name == "ModelicaStandardTables_CombiTimeTable_init")
    t->kind = ExternalObject::Kind::TimeTable;
  else if (c_name == "ModelicaStandardTables_CombiTable1D_init")
    t->kind = ExternalObject::Kind::Table1D;
  else if (c_name == "ModelicaStandardTables_CombiTable2D_init")
    t->kind = ExternalObject::Kind::Table2D;
  else
    fail(DiagId::Unsupported, call->range,
         "external object '" + t->name + "': its constructor's C function '" + c_name +
             "' is not provided (only ModelicaStandardTables' CombiTimeTable, CombiTable1D and CombiTable2D are)");
  // The constructor's inputs, matched by position and by name.
  std::vector<std::string> inputs;
  for (const auto &c : ctor->def->components)
    if (c.causality == ast::Causality::Input)
      inputs.push_back(c.name);
  std::map<std::string, const Expr *> arg;
  for (std::size_t i = 0; i < call->args.size() && i < inputs.size(); ++i)
    arg[inputs[i]] = call->args[i].get();
  for (const auto &na : call->named)
    arg[na.name] = na.value.get();
  const Scope bs{t->mod.scope, t->mod.lexical, nullptr};
  auto need = [&](const std::string &name) -> const Expr & {
    auto it = arg.find(name);
    if (it == arg.end() || !it->second)
      fail(DiagId::WrongArgumentCount, call->range, "the constructor of '" + t->name + "' has no argument '" + name + "'");
    return *it->second;
  };
  // The file name is `if tableOnFile and fileName <> "NoName" and not
  // Strings.isEmpty(fileName) then fileName else "NoName"`: conditions are
  // decided left to right, so that a table given inline never calls
  // isEmpty's external C function.
  std::function<bool(const Expr &)> holds = [&](const Expr &c) -> bool {
    if (c.kind == ExprKind::Binary && (c.op == Op::And || c.op == Op::Or)) {
      const bool first = holds(*c.args[0]);
      return c.op == Op::And ? first && holds(*c.args[1]) : first || holds(*c.args[1]);
    }
    if (c.kind == ExprKind::Unary && c.op == Op::Not)
      return !holds(*c.args[0]);
    return eval(*scalar_expr(c, bs), c.range) != 0;
  };
  std::function<std::string(const Expr &)> text_of = [&](const Expr &e) -> std::string {
    if (e.kind == ExprKind::If) {
      for (std::size_t i = 0; i + 1 < e.args.size(); i += 2)
        if (holds(*e.args[i]))
          return text_of(*e.args[i + 1]);
      return text_of(*e.args.back());
    }
    std::optional<std::string> v = eval_string(*scalar_expr(e, bs), e.range);
    if (!v)
      fail(DiagId::NotConstant, e.range, "this name of table '" + t->name + "' must be a constant string");
    return *v;
  };
  auto text = [&](const std::string &name) { return text_of(need(name)); };
  const std::string table_name = text("tableName"), file_name = text("fileName");
  if (file_name != "NoName" && !file_name.empty()) {
    if (file_name.rfind("modelica://", 0) == 0)
      fail(DiagId::Unsupported, need("fileName").range,
           "table file '" + file_name + "': modelica:// URIs are not resolved; give a file path");
    std::vector<double> values;
    std::string why;
    if (!read_text_table(file_name, table_name, t->rows, t->cols, values, why))
      fail(DiagId::CannotReadFile, need("fileName").range, "table of '" + t->name + "': " + why);
    for (double v : values)
      t->table.push_back(num(v));
  } else {
    Tensor table = expr(need("table"), bs);
    if (table.dims.size() != 2 || table.dims[0] < 1 || table.dims[1] < 1)
      fail(DiagId::TypeMismatch, need("table").range, "table of '" + t->name + "' must be a non-empty matrix");
    t->rows = table.dims[0];
    t->cols = table.dims[1];
    t->table = std::move(table.elems);
  }
  if (arg.count("smoothness"))
    t->smoothness = static_cast<int>(eval(*scalar_expr(need("smoothness"), bs), need("smoothness").range));
  if (arg.count("extrapolation"))
    t->extrapolation = static_cast<int>(eval(*scalar_expr(need("extrapolation"), bs), need("extrapolation").range));
  if (arg.count("startTime"))
    t->start_time = eval(*scalar_expr(need("startTime"), bs), need("startTime").range);
  if (arg.count("columns")) {
    Tensor columns = expr(need("columns"), bs);
    for (const auto &c : columns.elems)
      t->columns.push_back(static_cast<int>(eval(*c, need("columns").range)));
  }
  const SourceRange where = call->range;
  const bool two_d = t->kind == ExternalObject::Kind::Table2D;
  // Keys: the first column (and, 2-D, the first row), strictly or (for jumps
  // of 1-D and time tables) weakly increasing.
  for (int r = two_d ? 1 : 0; r < t->rows; ++r)
    t->key.push_back(eval(*t->table[static_cast<std::size_t>(r * t->cols)], where));
  for (int c = 1; two_d && c < t->cols; ++c)
    t->key2.push_back(eval(*t->table[static_cast<std::size_t>(c)], where));
  auto check_keys = [&](const std::vector<double> &k, bool strict, const char *what) {
    for (std::size_t i = 1; i < k.size(); ++i)
      if (k[i] < k[i - 1] || (strict && k[i] == k[i - 1]))
        fail(DiagId::EvaluationError, where,
             fmt::format("table of '{}': its {} must increase{} ({} after {})", t->name, what,
                         strict ? " strictly" : "", k[i], k[i - 1]));
  };
  check_keys(t->key, two_d, two_d ? "first column (from row 2)" : "first column");
  check_keys(t->key2, true, "first row (from column 2)");
  if ((two_d && (t->rows < 2 || t->cols < 2)) || (!two_d && t->cols < 2))
    fail(DiagId::TypeMismatch, where, "table of '" + t->name + "' has too few columns or rows");
  for (int c : t->columns)
    if (c < 2 || c > t->cols)
      fail(DiagId::BadSubscript, where, fmt::format("table of '{}': column {} is not among its columns 2..{}", t->name, c, t->cols));
  // The C library treats a spline through two points as linear segments.
  const int points = two_d ? std::min(t->rows, t->cols) - 1 : t->rows;
  if (t->smoothness == 2 && points <= 2)
    t->smoothness = 1;
  if (t->smoothness == 2)
    fail(DiagId::Unsupported, need("smoothness").range,
         "table of '" + t->name + "': smoothness = ContinuousDerivative (Akima splines) is not supported; "
         "LinearSegments and ConstantSegments are");
  if (two_d && t->smoothness != 1)
    fail(DiagId::Unsupported, need("smoothness").range,
         "table of '" + t->name + "': a 2-D table is provided with LinearSegments only");
  if (t->kind == ExternalObject::Kind::TimeTable && t->extrapolation == 3 && t->rows > 1 &&
      t->key.back() == t->key.front())
    fail(DiagId::EvaluationError, where, "table of '" + t->name + "': a periodic table needs a period > 0");
  if (t->kind == ExternalObject::Kind::TimeTable && t->extrapolation == 4)
    diags_.report(DiagId::IgnoredModifier, need("extrapolation").range,
                  "table of '" + t->name + "': extrapolation = NoExtrapolation is not checked during a "
                  "simulation; outside the table its end values are held");
  t->built = true;
  return t;
}

bool Flattener::provided_external(const std::string &c_name, const std::vector<const Expr *> &args,
                                  const Expr &call, const Scope &s, Tensor &out) {
  static const std::string kPrefix = "ModelicaStandardTables_";
  if (c_name.rfind(kPrefix, 0) != 0)
    return false;
  const std::string fn = c_name.substr(kPrefix.size());
  auto arg = [&](std::size_t i) -> const Expr & {
    if (i >= args.size() || !args[i])
      fail(DiagId::WrongArgumentCount, call.range, fmt::format("'{}' needs argument {}", c_name, i + 1));
    return *args[i];
  };
  auto value = [&](std::size_t i) { return scalar_expr(arg(i), s); };
  auto column = [&](const ExternalObject &t) {
    const double i = eval(*value(1), arg(1).range);
    if (i < 1 || i > static_cast<double>(t.columns.size()) || i != std::floor(i))
      fail(DiagId::BadSubscript, arg(1).range,
           fmt::format("output {} of table '{}' is not among its {} columns", i, t.name, t.columns.size()));
    return t.columns[static_cast<std::size_t>(i) - 1] - 1;
  };
  using Kind = ExternalObject::Kind;
  auto object = [&](Kind kind) {
    std::shared_ptr<ExternalObject> t = external_object(arg(0), s);
    if (t->kind != kind)
      fail(DiagId::TypeMismatch, arg(0).range, "'" + t->name + "' is another kind of table than '" + c_name + "' reads");
    return t;
  };
  if (fn == "CombiTimeTable_read" || fn == "CombiTable1D_read" || fn == "CombiTable2D_read") {
    out = Tensor::scalar(num(1.0)); // read when flattened
    return true;
  }
  if (fn == "CombiTimeTable_minimumTime" || fn == "CombiTimeTable_maximumTime") {
    auto t = object(Kind::TimeTable);
    out = Tensor::scalar(num(fn == "CombiTimeTable_minimumTime" ? t->key.front() : t->key.back()));
    return true;
  }
  if (fn == "CombiTimeTable_getValue") {
    auto t = object(Kind::TimeTable);
    const int c = column(*t);
    ExprPtr time = value(2);
    ExprPtr s_now = bin(Op::Sub, time->clone(), num(t->start_time));
    ExprPtr now = time_value(*t, c, *s_now, false);
    if (args.size() < 5 || !args[3] || !args[4]) {
      out = Tensor::scalar(std::move(now));
      return true;
    }
    // Reached the next time event, which the block's when-clause has not
    // moved yet: the value from the left of it.
    ExprPtr next = value(3), pre_next = value(4);
    ExprPtr s_next = bin(Op::Sub, next->clone(), num(t->start_time));
    ExprPtr reached =
        no_event(bin(Op::And, bin(Op::Ge, time->clone(), next->clone()),
                     bin(Op::And, bin(Op::Le, next->clone(), pre_next->clone()), bin(Op::Lt, next->clone(), num(kNoEvent)))));
    out = Tensor::scalar(if_then(std::move(reached), time_value(*t, c, *s_next, true), std::move(now)));
    return true;
  }
  if (fn == "CombiTimeTable_nextTimeEvent") {
    auto t = object(Kind::TimeTable);
    ExprPtr s_now = bin(Op::Sub, value(1), num(t->start_time));
    ExprPtr next;
    if (t->rows == 1) {
      next = num(kNoEvent);
    } else if (t->extrapolation == 3) {
      const double k0 = t->key.front(), period = t->key.back() - k0;
      ExprPtr offset = bin(Op::Mul, num(period),
                           no_event(call1("floor", bin(Op::Div, bin(Op::Sub, s_now->clone(), num(k0)), num(period)))));
      ExprPtr within = bin(Op::Sub, s_now->clone(), offset->clone());
      next = bin(Op::Add, std::move(offset), next_key(event_keys(*t), *within, num(t->key.back())));
      next = bin(Op::Add, std::move(next), num(t->start_time));
    } else {
      std::vector<double> keys{t->key.front()};
      for (double k : event_keys(*t))
        keys.push_back(k);
      for (double &k : keys)
        k += t->start_time;
      ExprPtr shifted = bin(Op::Add, s_now->clone(), num(t->start_time));
      next = next_key(keys, *shifted, num(kNoEvent));
    }
    out = Tensor::scalar(if_then(below(*s_now, 0.0, false), num(t->start_time), std::move(next)));
    return true;
  }
  if (fn == "CombiTable1D_getValue") {
    auto t = object(Kind::Table1D);
    const int c = column(*t);
    ExprPtr u = value(2);
    out = Tensor::scalar(column_at(*t, c, *u, false, 2));
    return true;
  }
  if (fn == "CombiTable2D_getValue") {
    auto t = object(Kind::Table2D);
    ExprPtr u1 = value(1), u2 = value(2);
    const int n1 = static_cast<int>(t->key.size()), n2 = static_cast<int>(t->key2.size());
    // Bilinear in the cell of (u1, u2); outside, the border cells continued.
    auto cell = [&](int i, int j) {
      auto y = [&](int a, int b) { return t->at(a + 1, b + 1); };
      auto w = [](const Expr &u, double lo, double hi) {
        return bin(Op::Div, bin(Op::Sub, u.clone(), num(lo)), num(hi - lo));
      };
      ExprPtr a = w(*u1, t->key[i], t->key[i + 1]), b = w(*u2, t->key2[j], t->key2[j + 1]);
      // y00 + a (y10 - y00) + b (y01 - y00) + a b (y11 - y10 - y01 + y00)
      ExprPtr e = y(i, j);
      e = bin(Op::Add, std::move(e), bin(Op::Mul, a->clone(), bin(Op::Sub, y(i + 1, j), y(i, j))));
      e = bin(Op::Add, std::move(e), bin(Op::Mul, b->clone(), bin(Op::Sub, y(i, j + 1), y(i, j))));
      ExprPtr twist = bin(Op::Add, bin(Op::Sub, bin(Op::Sub, y(i + 1, j + 1), y(i + 1, j)), y(i, j + 1)), y(i, j));
      return bin(Op::Add, std::move(e), bin(Op::Mul, bin(Op::Mul, std::move(a), std::move(b)), std::move(twist)));
    };
    if (n1 == 1 || n2 == 1)
      fail(DiagId::Unsupported, call.range, "2-D table '" + t->name + "' needs at least two rows and two columns of values");
    std::function<ExprPtr(int, int, int)> over_u2 = [&](int i, int lo, int hi) -> ExprPtr {
      if (hi - lo == 1)
        return cell(i, lo);
      const int mid = (lo + hi) / 2;
      return if_then(below(*u2, t->key2[mid], false), over_u2(i, lo, mid), over_u2(i, mid, hi));
    };
    std::function<ExprPtr(int, int)> over_u1 = [&](int lo, int hi) -> ExprPtr {
      if (hi - lo == 1)
        return over_u2(lo, 0, n2 - 1);
      const int mid = (lo + hi) / 2;
      return if_then(below(*u1, t->key[mid], false), over_u1(lo, mid), over_u1(mid, hi));
    };
    out = Tensor::scalar(over_u1(0, n1 - 1));
    return true;
  }
  return false; // another function of the library: reported by the caller
}

} // namespace mo::frontend::detail
