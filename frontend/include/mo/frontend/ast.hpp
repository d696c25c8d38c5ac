#pragma once
/// The abstract syntax tree of a Modelica / Optimica source file, as written:
/// classes with their elements, modifications, equations and expressions.
/// Names are not resolved here; flatten.hpp does that. Every node carries the
/// SourceRange of the text it came from.
#include "mo/frontend/source.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace mo::frontend::ast {

struct Expr;
using ExprPtr = std::unique_ptr<Expr>;

enum class ExprKind : std::uint8_t {
  Real,      ///< numeric literal with a '.' or exponent: `number`
  Integer,   ///< numeric literal without one: `number` holds the value
  String,    ///< `text` (escapes resolved)
  Boolean,   ///< `number` is 0 or 1
  Ref,       ///< component reference: `ref`; in a flat model `var` is set
  Call,      ///< `ref` names the function; `args`, `named`, `iterators`
  Unary,     ///< `op` applied to args[0]
  Binary,    ///< args[0] `op` args[1]
  If,        ///< args = cond1, then1, cond2, then2, ..., else
  Array,     ///< `{a, b, ...}` or `{e for i in r}` (then `iterators` is set)
  Matrix,    ///< `[a, b; c, d]`: `rows`
  Range,     ///< start:stop (args size 2) or start:step:stop (size 3)
  Tuple,     ///< `(a, , b)` output list: null entries for omitted ones
  Colon,     ///< `:` as a subscript
  End,       ///< `end` inside a subscript
};

enum class Op : std::uint8_t {
  Add, Sub, Mul, Div, Pow,
  ElemAdd, ElemSub, ElemMul, ElemDiv, ElemPow,
  Lt, Le, Gt, Ge, Eq, Ne,
  And, Or,
  Neg, Plus, Not,
};

/// The Modelica spelling of an operator ("+", "<=", "and", ...).
const char *op_text(Op op);

/// One dotted part of a component reference: `name[subscripts]`.
struct RefPart {
  std::string name;
  std::vector<ExprPtr> subscripts;
};

/// `a.b[1].c`, or `.a.b` when `global` (lookup starts at the top level).
struct ComponentRef {
  bool global = false;
  std::vector<RefPart> parts;
  /// The reference as Modelica text, subscripts included.
  std::string str() const;
  /// True for a plain single name without subscripts, e.g. `sin`.
  bool is_simple() const { return !global && parts.size() == 1 && parts[0].subscripts.empty(); }
};

struct NamedArg {
  std::string name;
  ExprPtr value;
};

/// `i in range` of a for-equation, for-loop or array constructor.
struct ForIndex {
  std::string name;
  ExprPtr range; ///< null: the range is deduced from use (unsupported later)
  SourceRange loc;
};

struct Expr {
  ExprKind kind;
  Op op = Op::Add;
  SourceRange range;
  double number = 0;
  std::int32_t var = -1; ///< flat models: index of the flat variable
  /// A call the flattener made (a built-in, a variable at a time point):
  /// resolved already, so flattening it again does not look its name up.
  bool resolved = false;
  std::string text;
  ComponentRef ref;
  std::vector<ExprPtr> args;
  std::vector<NamedArg> named;
  std::vector<ForIndex> iterators;
  std::vector<std::vector<ExprPtr>> rows;

  explicit Expr(ExprKind k, SourceRange r = {}) : kind(k), range(r) {}
  ~Expr();
  Expr(const Expr &) = delete;
  Expr &operator=(const Expr &) = delete;
  /// A deep copy (iterative: safe on deep trees).
  ExprPtr clone() const;
};

/// True if `a` and `b` are the same expression: kinds, operators, numbers,
/// names and operands alike (source ranges aside). Iterative.
bool same_expr(const Expr &a, const Expr &b);

ExprPtr make_real(double v, SourceRange r = {});
ExprPtr make_integer(double v, SourceRange r = {});
ExprPtr make_bool(bool v, SourceRange r = {});
ExprPtr make_ref(std::string name, SourceRange r = {});
ExprPtr make_unary(Op op, ExprPtr a, SourceRange r = {});
ExprPtr make_binary(Op op, ExprPtr a, ExprPtr b, SourceRange r = {});
ExprPtr make_call(std::string fn, std::vector<ExprPtr> args, SourceRange r = {});
/// `fn(a)`.
ExprPtr make_call1(std::string fn, ExprPtr a, SourceRange r = {});

/// A modification: `(a = 1, b(start = 2)) = binding`.
struct ElementMod;
struct Component;
struct ClassDef;
struct Modification {
  std::vector<ElementMod> args;
  ExprPtr binding;
  SourceRange range;
  bool empty() const { return args.empty() && !binding; }
};

/// One argument of a class modification, `each final a.b(...) = e "doc"`.
struct ElementMod {
  bool each = false;
  bool final_ = false;
  bool redeclare = false; ///< `redeclare ...` or `replaceable ...` in a modifier
  std::vector<std::string> path; ///< a redeclaration: the redeclared element's name
  Modification mod;
  SourceRange range;
  /// A redeclaration: `redeclare T name(...)` (component) or
  /// `redeclare model name = T(...)` (short class); exactly one is set.
  std::unique_ptr<Component> component;
  std::unique_ptr<ClassDef> class_def;
};

enum class Variability : std::uint8_t { Continuous, Discrete, Parameter, Constant };
enum class Causality : std::uint8_t { None, Input, Output };
enum class Connection : std::uint8_t { Potential, Flow, Stream };

const char *variability_text(Variability v);

struct TypeName {
  bool global = false;
  std::vector<std::string> parts;
  SourceRange range;
  std::string str() const;
};

/// A component declaration `parameter Real a[2](start = 1) = 3 "doc"`.
struct Component {
  std::string name;
  SourceRange range;       ///< the declared name
  TypeName type;
  Variability variability = Variability::Continuous;
  Causality causality = Causality::None;
  Connection connection = Connection::Potential;
  bool final_ = false, inner = false, outer = false, replaceable = false, redeclare = false;
  bool is_protected = false;
  std::vector<ExprPtr> dims; ///< type subscripts followed by declaration subscripts
  Modification mod;
  ExprPtr condition;
  std::string description;
  /// `annotation(Evaluate = true)`: a parameter whose value is structural
  /// (the lowering uses it as a constant, so `CapVal*der(v)` with CapVal = 0
  /// drops der(v)).
  bool evaluate = false;
  /// `replaceable ... constrainedby T(mods)`: the constraining type's
  /// modifiers, which a redeclaration keeps instead of `mod` (MLS 7.3.2).
  bool has_constraint = false;
  Modification constraint_mod;
};

struct Extends {
  TypeName base;
  Modification mod;
  SourceRange range;
  bool is_protected = false;
  /// The implied base of a class extension `model extends M(...) ... end M;`
  /// (MLS 7.3.1): the class M that the enclosing class inherits.
  bool inherited_class = false;
};

struct Import {
  std::string alias;          ///< `import A = B.C;`
  std::vector<std::string> path;
  bool wildcard = false;      ///< `import B.*;`
  std::vector<std::string> names; ///< `import B.{x, y};`
  SourceRange range;
};

struct Equation;
struct EquationBranch {
  ExprPtr condition; ///< null for `else`
  std::vector<Equation> body;
  SourceRange range;
};

enum class EquationKind : std::uint8_t {
  Simple,     ///< lhs = rhs
  Connect,    ///< connect(lhs, rhs): both Ref expressions
  For,        ///< for indices loop body end for
  If,         ///< branches
  When,       ///< branches (when / elsewhen)
  Call,       ///< lhs is a Call: reinit, assert, terminate, ...
  Constraint, ///< Optimica: lhs rel rhs with `rel` Eq, Le or Ge
};

struct Equation {
  EquationKind kind = EquationKind::Simple;
  SourceRange range;
  ExprPtr lhs, rhs;
  Op rel = Op::Eq;
  std::vector<ForIndex> indices;
  std::vector<Equation> body;
  std::vector<EquationBranch> branches;
  std::string description;
};

/// Statements of algorithm sections (functions' bodies).
struct Statement;
struct StatementBranch {
  ExprPtr condition; ///< null for `else`
  std::vector<Statement> body;
  SourceRange range;
};

enum class StatementKind : std::uint8_t {
  Assign, ///< targets := value; several targets for `(a, , b) := f(...)`
  Call,   ///< value is a Call used as a statement: assert(...), f(...)
  Break,
  Return,
  If,     ///< branches
  For,    ///< for indices loop body end for
  While,  ///< while value loop body end while
  When,   ///< branches (when / elsewhen)
};

struct Statement {
  StatementKind kind = StatementKind::Assign;
  SourceRange range;
  std::vector<ExprPtr> targets; ///< Assign: Ref expressions; null for an omitted output
  ExprPtr value;                ///< Assign: the right side; Call: the call; While: the condition
  std::vector<ForIndex> indices;
  std::vector<Statement> body;
  std::vector<StatementBranch> branches;
};

/// An algorithm section of a model or block that is not plain equations
/// (algorithm_equations.cpp): flattened by executing its statements on
/// expressions (flatten_algorithms.cpp).
struct AlgorithmSection {
  bool initial = false; ///< `initial algorithm`
  SourceRange range;    ///< the `algorithm` keyword
  std::vector<Statement> body;
};

enum class Restriction : std::uint8_t {
  Class, Model, Record, OperatorRecord, Block, Connector, ExpandableConnector, Type,
  Package, Function, Operator, Optimization,
};
const char *restriction_text(Restriction r);

struct ClassDef;
using ClassPtr = std::unique_ptr<ClassDef>;

struct ClassDef {
  std::string name;
  SourceRange range;        ///< the class name after the prefixes
  SourceRange full_range;   ///< from the prefixes to `end Name`
  Restriction restriction = Restriction::Class;
  bool partial = false, encapsulated = false, final_ = false;
  bool is_protected = false;
  bool replaceable = false, redeclare = false; ///< element prefixes of a nested class
  std::string description;

  /// Short class `type Voltage = Real(unit = "V")` or `extends`-like alias.
  std::optional<TypeName> short_base;
  std::vector<ExprPtr> short_dims;
  Causality short_causality = Causality::None;
  std::vector<std::string> enumeration; ///< `type E = enumeration(a, b)`

  /// `optimization N(objective = ..., startTime = ...)` and long-class mods.
  Modification class_mod;
  /// The arguments of `annotation(__mocompile(...))` in the class's own
  /// annotations (study options); other annotations are ignored.
  Modification vendor_annotation;
  /// `annotation(GenerateEvents = true)` of a function: the relations of its
  /// body generate events when inlined; without it they do not (since MLS 3.2r2).
  bool generate_events = false;

  std::vector<ClassPtr> classes;
  std::vector<Component> components;
  std::vector<Extends> extends;
  std::vector<Import> imports;
  std::vector<Equation> equations;
  std::vector<Equation> initial_equations;
  std::vector<Equation> constraints;
  bool has_algorithm = false;   ///< algorithms are parsed but not flattened
  SourceRange algorithm_range;
  bool is_external = false;     ///< `external` function
  std::vector<Statement> algorithm; ///< functions: the statements of every algorithm section, in order
  std::vector<AlgorithmSection> model_algorithms; ///< other classes: sections that are not equations
  std::string external_language;    ///< `external "builtin"`: "builtin" (unescaped)
  std::string external_function;    ///< the called name in `external "C" y = f(u)`; may be empty
  std::string external_result;      ///< `y` in `external "C" y = f(u)`; empty without one
  std::vector<ExprPtr> external_args; ///< `u` in `external "C" y = f(u)`, as written
};

/// A parsed file: `within` prefix and its top-level classes.
struct StoredDefinition {
  FileId file = 0;
  std::vector<std::string> within;
  std::vector<ClassPtr> classes;
};

/// Resolves the escapes of a string literal's body (`\"`, `\n`, ...).
std::string unescape_string(std::string_view body);
/// The body of a Modelica string literal for `s`: quotes, backslashes and
/// control characters escaped. (C++ output has its own escaper in codegen.)
std::string escape_string(std::string_view s);

/// Prints the AST as an indented tree (mocompile --emit ast).
std::string dump(const StoredDefinition &sd);

} // namespace mo::frontend::ast
