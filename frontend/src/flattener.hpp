#pragma once
// Internals of flattening, shared by the flatten_*.cpp files.
//
// Phase 1 (flatten_instance.cpp) builds the instance tree: one Instance per
// component (array elements included), flat variables for the scalars, and
// merged modifiers. Phase 2 flattens bindings, equations and connections
// (flatten_expr.cpp, flatten_equations.cpp, flatten_connect.cpp) into the
// flat::Model. Class lookup lives in flatten_lookup.cpp.
#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"
#include "mo/frontend/flatten.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <tuple>
#include <optional>
#include <memory>
#include <set>
#include <unordered_map>
#include <unordered_set>

namespace mo::frontend {

/// A class in the package tree, with its lexical parent.
///
/// A class found through inheritance is a *view* (MLS 5.6.1, 7.1): the
/// elements of a base B are elements of the derived class D, so a class
/// inherited from B, looked up in D, sees D's redeclared classes and
/// constants. A view `V` shows `origin` (same `def`); its parent is the
/// *base scope* of B in D, a node with `origin` B and `context` D whose
/// member lookups go to D and whose parent is B's (lexical) parent. Views
/// are made by the Flattener (flatten_lookup.cpp) and live as long as it.
struct ClassNode {
  std::string name;
  const ast::ClassDef *def = nullptr; ///< null for the root and implied packages
  ClassNode *parent = nullptr;
  std::map<std::string, std::unique_ptr<ClassNode>> children; ///< of a view: views, made when looked up
  ClassNode *origin = nullptr;  ///< a view or base scope: the class of the package tree it shows
  ClassNode *context = nullptr; ///< a base scope: the derived class its members are looked up in
  std::string path() const;     ///< a view's: its name in the class it was found in
  /// The class of the package tree this node is or shows.
  const ClassNode *tree_class() const { return origin ? origin->tree_class() : this; }
};

struct Library::Impl {
  ClassNode root;
  std::vector<std::unique_ptr<ast::StoredDefinition>> files;
  std::vector<std::string> order;
  void insert(ClassNode &parent, const ast::ClassDef &def);

  // Lazy loading by Modelica's lookup rules (library_loader.cpp).
  SourceManager *sources = nullptr;
  DiagnosticEngine *diags = nullptr;
  std::vector<std::string> roots;                        ///< MODELICAPATH-like roots
  std::unordered_map<const ClassNode *, std::string> directory_of; ///< directory packages
  std::set<std::pair<const ClassNode *, std::string>> tried; ///< loads attempted
  /// Loads class `name` of `parent` from the file system when `parent` is the
  /// root (search roots) or a directory package; null when there is none.
  ClassNode *load_member(ClassNode &parent, const std::string &name);
  /// Parses `file` and inserts its classes into `parent`; false on errors.
  bool load_file(ClassNode &parent, const std::string &file);
};

namespace detail {

struct Instance;
struct Signature; // a function's elements (flatten_functions.cpp)

/// Appends the index of every variable referenced in `eq`, its branches'
/// conditions and bodies included (repeats possible; iterative, no recursion).
void equation_uses(const ast::Equation &eq, std::vector<std::int32_t> &out);

/// A merged modification tree: outer modifications override inner ones.
/// A binding is flattened in the scope of the instance that wrote it.
struct Modifier {
  std::map<std::string, Modifier> sub;
  const ast::Expr *binding = nullptr;
  Instance *scope = nullptr;   ///< instance whose members the binding sees
  ClassNode *lexical = nullptr; ///< class the modification was written in
  std::vector<int> index;       ///< array element the binding is taken at
  /// Then the record fields it is taken at, each with the element of the
  /// field (a record's binding binds its fields: `Pt c = Pt(3, 4)`).
  std::vector<std::pair<std::string, std::vector<int>>> fields;
  bool each = false;
  bool final_ = false;
  SourceRange range;
  /// A redeclaration of this element (flatten_redeclare.cpp): the component
  /// that replaces it, with the class it was written in, or the class.
  const ast::Component *redecl_component = nullptr;
  ClassNode *redecl_lexical = nullptr;
  ClassNode *redecl_class = nullptr;
  bool empty() const { return sub.empty() && !binding && !redecl_component && !redecl_class; }
};

/// The type a component declaration resolves to, through short classes.
struct ResolvedType {
  ClassNode *cls = nullptr;            ///< null for a built-in type
  flat::BaseType builtin = flat::BaseType::Real;
  bool is_builtin = false;
  ast::Causality causality = ast::Causality::None;
  std::vector<int> dims;               ///< from short class definitions
  Modifier mod;                        ///< from short class definitions
  bool is_enumeration = false;
  bool is_connector = false;           ///< `connector RealInput = input Real`
};

/// One component instance. Arrays hold their elements (row-major);
/// structured instances hold members; scalars of a built-in type a variable.
struct Instance {
  std::string name;   ///< local name (element: "[2]")
  std::string flat;   ///< full flat name
  Instance *parent = nullptr;
  ClassNode *cls = nullptr; ///< class whose scope names in it resolve in
  const ast::Component *decl = nullptr;
  std::vector<int> dims;   ///< non-empty: an array; elements in `elements`
  std::vector<std::unique_ptr<Instance>> elements;
  std::vector<std::unique_ptr<Instance>> members;
  std::unordered_map<std::string, Instance *> member_index;
  std::int32_t var = -1;   ///< scalar of a built-in type
  bool is_connector = false;
  bool is_flow = false;
  bool is_stream = false; ///< `stream` (MLS 15.1): carried by its connector's flow
  /// An `expandable connector`: its declared elements are only potentially
  /// present (Flattener::potential_) until a connection or a reference
  /// needs them (flatten_expandable.cpp).
  bool expandable = false;
  bool is_structured() const { return dims.empty() && var < 0; }
  /// Equations of the classes (and bases) of this instance, with the class
  /// each was written in (for lexical lookup).
  std::vector<std::pair<const ast::Equation *, ClassNode *>> equations, initial_equations;
  std::vector<std::pair<const ast::Equation *, ClassNode *>> constraints;
  /// Algorithm sections that are not plain equations (flatten_algorithms.cpp).
  std::vector<std::pair<const ast::AlgorithmSection *, ClassNode *>> algorithms;
  ast::Variability variability = ast::Variability::Continuous;
  ast::Causality causality = ast::Causality::None;
  bool is_enumeration = false;
  /// Classes of this instance replaced by a redeclaration, by name: a type
  /// name of a component of the instance starting with one resolves there.
  std::map<std::string, ClassNode *> replaced;
};

/// The fields of a record class in declaration order (bases first), each
/// with its array dimensions, its own layout if it is a record, and where its
/// scalars start in one record's scalars (flatten_records.cpp).
struct RecordLayout {
  struct Field {
    std::string name;
    std::vector<int> dims;
    std::shared_ptr<const RecordLayout> record; ///< null: a Real/Integer/Boolean field
    std::size_t offset = 0;                     ///< first scalar of the field
    std::size_t size = 0;                       ///< scalars of the field
    const ast::Component *decl = nullptr;       ///< its declaration
    ClassNode *owner = nullptr;                 ///< the class that declares it
    /// The default: the record class's extends modifier of the field (the most
    /// derived), else the declaration's binding; null without one.
    const ast::Expr *binding = nullptr;
    ClassNode *binding_scope = nullptr;         ///< the class the binding is read in
  };
  ClassNode *cls = nullptr;
  std::vector<Field> fields;
  std::size_t size = 0; ///< scalars of one record
  const Field *find(const std::string &name) const {
    for (const Field &f : fields)
      if (f.name == name)
        return &f;
    return nullptr;
  }
  /// True if both have the same field names, sizes and nesting.
  bool same_shape(const RecordLayout &o) const;
};

/// True if values of layouts `a` and `b` are of one kind: both numbers
/// (null) or records of the same shape.
bool same_record_type(const std::shared_ptr<const RecordLayout> &a, const std::shared_ptr<const RecordLayout> &b);

/// A value of an array expression during flattening: dims and elements in
/// row-major order; a scalar has no dims and one element. A record value
/// (`record` set) holds the scalars of each record in layout order: an
/// array of n records has n * record->size elements.
struct Tensor {
  std::vector<int> dims;
  std::vector<ast::ExprPtr> elems;
  std::shared_ptr<const RecordLayout> record;
  bool is_scalar() const { return dims.empty() && !record; }
  static Tensor scalar(ast::ExprPtr e) {
    Tensor t;
    t.elems.push_back(std::move(e));
    return t;
  }
};

/// A deep copy of `t` (its expressions cloned, its record layout shared).
Tensor clone_tensor(const Tensor &t);

/// True for a `record` or `operator record` class.
bool is_record_class(const ClassNode *cls);

/// The binding that modification `m` gives its element `name` (`name = e`),
/// or null (a redeclaration, a nested modifier, none).
const ast::Expr *element_binding(const ast::Modification &m, const std::string &name);

/// A constant (or parameter) declared in a class or inherited by it: its
/// declaration, the binding that applies — an extends modifier on the way
/// from the class looked in to the declaration (the most derived first),
/// else its own — and the class that binding is read in (for an inherited
/// declaration, its class as part of the one looked in: `{mediumName}` in a
/// base reads the derived package's mediumName).
struct FoundConstant {
  const ast::Component *decl = nullptr;
  const ast::Expr *binding = nullptr;
  ClassNode *scope = nullptr;
};

/// `e` without the noEvent() calls around it (flatten_functions.cpp): the
/// inliner wraps a function's relations in them (Flattener::no_event_depth_).
const ast::Expr &without_no_event(const ast::Expr &e);
/// True for a (scalar) instance of a record class.
bool is_record_instance(const Instance &inst);

/// For-loop and iterator bindings in scope while flattening an expression.
struct LoopEnv {
  std::vector<std::pair<std::string, double>> values;
  const double *find(const std::string &n) const {
    for (auto it = values.rbegin(); it != values.rend(); ++it)
      if (it->first == n) return &it->second;
    return nullptr;
  }
};

/// The inputs, outputs and locals of a function being inlined, by name;
/// an element not assigned yet is null (flatten_functions.cpp).
using FunctionLocals = std::map<std::string, Tensor>;

/// Where an expression is flattened: the instance whose members are in
/// scope, the class for lexical lookup, and loop variables.
struct Scope {
  Instance *inst = nullptr;
  ClassNode *cls = nullptr;
  const LoopEnv *env = nullptr;
  bool in_optimization = false;
  bool in_when = false;
  const FunctionLocals *locals = nullptr; ///< inside a function body being inlined
};

/// A reference to flat variable `v` of `m` (its name, resolved).
ast::ExprPtr var_ref(const flat::Model &m, std::int32_t v, SourceRange r);

/// `terms` joined by `join` (a + b, a * b, min(a, b)): left to right as
/// written up to 256 terms, beyond as a balanced tree of such runs, so that a
/// long sum (`a * b` of 40000-element vectors, a large connection set) nests
/// log-deep instead of overflowing the stack of every recursive pass after
/// it. `terms` must not be empty.
ast::ExprPtr join_terms(std::vector<ast::ExprPtr> terms,
                        const std::function<ast::ExprPtr(ast::ExprPtr, ast::ExprPtr)> &join);

class Flattener;
/// sum/product/min/max (`name`) of the elements of `a`, joined by
/// join_terms; an empty sum is 0, an empty product 1, min/max of nothing an
/// error (flatten_arrays.cpp).
Tensor reduce_elements(Flattener &f, const std::string &name, Tensor a, SourceRange r);

/// Bounds on one value that an algorithm computes symbolically (a function's
/// local or output, a model algorithm's variable). No value nests deeper
/// than the parser lets source text nest: a loop that accumulates an
/// expression (`y := y + t` a million times) stops after a thousand runs
/// instead of costing the square of its length. And none has more nodes
/// than Flattener::max_value_nodes(): a value that doubles on each run (a
/// varying `if` in a loop) stops there. Sizes, not depth, are large in real
/// models: the MSL's NoiseExamples.Distributions inlines values of 3.5
/// million nodes, 77 levels deep.
constexpr std::size_t kMaxValueDepth = 1'000;
/// The bound on a value while a call of parameters only is inlined: the
/// MSL's Matrices.exp of a parameter matrix branches on the parameters' values
/// at every step of its series, grows past it within a second, and is then
/// evaluated (it took a minute to reach the general bound first).
constexpr std::size_t kEvaluableValueNodes = 20'000;
/// Whether `e` nests deeper than kMaxValueDepth or has more than
/// `max_nodes` nodes; counts no further than either bound.
bool too_large_value(const ast::Expr &e, std::size_t max_nodes);

/// Thrown (and caught at the statement level) once a diagnostic has been
/// reported for the current equation or binding.
struct Reported {};

/// Sets a flag for its lifetime, then gives it back the value it had.
struct Flag {
  bool &flag;
  bool saved;
  Flag(bool &f, bool value) : flag(f), saved(f) { flag = value; }
  ~Flag() { flag = saved; }
  Flag(const Flag &) = delete;
  Flag &operator=(const Flag &) = delete;
};

/// The scalar equations of the balance count, each as the unknowns it uses:
/// equation_count(eq) rows per equation, except that a variable assigned in
/// when-clauses is one row however many clauses assign it.
std::vector<std::vector<std::int32_t>> balance_rows(const flat::Model &m);

/// The virtual connection graph of overdetermined connectors (MLS 9.4,
/// flatten_overconstrained.cpp): nodes are record instances with an
/// equalityConstraint function.
struct OverconstrainedGraph {
  struct Edge {
    Instance *a, *b;
    SourceRange range;
  };
  std::vector<Instance *> roots;                        ///< Connections.root
  std::unordered_map<Instance *, SourceRange> root_range; ///< where each is declared a root
  std::vector<std::pair<Instance *, int>> potential;    ///< Connections.potentialRoot, priority
  std::vector<Edge> branches;                           ///< Connections.branch
  std::vector<Edge> connections;                        ///< connect() between overdetermined records
  /// The connections broken once the graph is closed (they close a loop, or
  /// would join two parts with a definite root each): their
  /// equalityConstraint residues replace their equations (MLS 9.4.1).
  std::vector<Edge> broken;
  std::unordered_set<Instance *> selected;              ///< the roots chosen, once closed
  std::unordered_map<Instance *, int> depth;            ///< distance from its root in the spanning tree
};

/// Connections.root, potentialRoot or branch as an equation.
bool is_connections_statement(const ast::Equation &eq);
/// True if `e` calls Connections.isRoot or rooted (its value waits for the graph).
bool reads_connection_graph(const ast::Expr &e);

class Flattener {
public:
  Flattener(Library::Impl &lib, DiagnosticEngine &diags, const FlattenOptions &opts)
      : lib_(lib), diags_(diags), opts_(opts) {}

  std::unique_ptr<flat::Model> run(const std::string &class_name);

  // -- lookup (flatten_lookup.cpp)
  ClassNode *lookup_class(ClassNode *scope, const std::vector<std::string> &parts, bool global,
                          SourceRange where, bool report = true);
  ClassNode *lookup_first(ClassNode *scope, const std::string &name, ClassNode *&from);
  std::set<std::pair<FileId, std::uint32_t>> outer_lookup_warned_; ///< (file, offset) of names warned about
  ClassNode *find_member_class(ClassNode *cls, const std::string &name, unsigned depth = 0);
  ClassNode *search_member_class(ClassNode *cls, const std::string &name, unsigned depth);
  std::set<std::pair<ClassNode *, std::string>> member_searches_; ///< in progress in find_member_class
  /// Searches cut short (a search met again, or too deep): a result found
  /// while one was cut may differ from a fresh search's, and is not cached.
  unsigned long member_search_cuts_ = 0;
  struct MemberKeyHash {
    std::size_t operator()(const std::pair<ClassNode *, std::string> &k) const {
      return std::hash<const void *>()(k.first) ^ (std::hash<std::string>()(k.second) * 31u);
    }
  };
  /// find_member_class's answers (null: no such member), by class and name:
  /// the class tree only grows by the loads those searches make themselves.
  std::unordered_map<std::pair<ClassNode *, std::string>, ClassNode *, MemberKeyHash> member_cache_;
  /// The class `parts` names where its first name is a class that `in` (an
  /// instance) has replaced by a redeclaration (`redeclare package Medium =
  /// ...`: `Medium.f`, `Medium.nX`'s package); null otherwise.
  ClassNode *replaced_class(const Instance *in, const std::vector<std::string> &parts);
  /// The type `type` names in class `scope`; a first name that `in` (the
  /// instance being built) has replaced by a redeclaration resolves there.
  bool resolve_type(ClassNode *scope, const ast::TypeName &type, ResolvedType &out,
                    const Instance *in = nullptr);
  /// The bases of `cls` (its `extends`), resolved; reports unknown bases
  /// unless `report` is false (a search that only probes enclosing classes).
  std::vector<std::pair<const ast::Extends *, ClassNode *>> bases(ClassNode *cls, bool report = true);
  /// The class `ext` of `cls` names, or null: looked up in the enclosing
  /// scope, or for a class extension (`model extends M`) the M that a base
  /// of the enclosing class has.
  ClassNode *extends_base(ClassNode *cls, const ast::Extends &ext);
  /// `found`, a member class of a base of `derived`, as a member of
  /// `derived`: a view whose lookups go through `derived` (ClassNode).
  ClassNode *inherited_view(ClassNode *found, ClassNode *derived);
  /// The base scope of class `base` within `derived` (ClassNode).
  ClassNode *base_scope(ClassNode *base, ClassNode *derived);
  /// The class `name` declared in `cls` itself (not inherited), or null; a
  /// view's are views of its origin's.
  ClassNode *own_class(ClassNode *cls, const std::string &name);
  std::map<std::pair<ClassNode *, const ClassNode *>, std::unique_ptr<ClassNode>> views_; ///< by parent and class shown
  std::map<std::pair<ClassNode *, ClassNode *>, std::unique_ptr<ClassNode>> base_scopes_; ///< by derived and base class
  /// The class `name` that extends clause `ext` of `cls` redeclares (`extends
  /// PartialMedium(redeclare record ThermodynamicState = BaseProps)`), or null.
  ClassNode *redeclared_in_extends(ClassNode *cls, const ast::Extends &ext, const std::string &name);
  /// The default record class `cls` gives its field `c` (declared in
  /// `owner`), and the class it is read in: an extends modifier on the way
  /// from cls to owner (the most derived first), else c's own binding.
  std::pair<const ast::Expr *, ClassNode *> field_binding(ClassNode *cls, ClassNode *owner, const ast::Component &c);

  // -- instances (flatten_instance.cpp)
  void instantiate_class(Instance &inst, ClassNode *cls, const Modifier &mod, unsigned depth);
  Modifier make_modifier(const ast::Modification &m, Instance *scope, ClassNode *lexical);
  static void merge_into(Modifier &inner, const Modifier &outer);
  void instantiate_component(Instance &parent, const ast::Component &comp, ClassNode *cls,
                             Modifier mod, unsigned depth);
  void make_scalar(Instance &inst, const ResolvedType &rt, const Modifier &mod);
  /// The number of elements of an array of size `dims`; reports `what` at
  /// `r` beyond opts_.max_elements (counted without overflow), naming the
  /// things counted `unit`.
  std::size_t element_count(const std::vector<long long> &dims, SourceRange r, const std::string &what,
                            const char *unit = "elements");
  std::size_t scalars_made_ = 0; ///< scalar variables so far (make_scalar), at most opts_.max_elements
  std::size_t loop_iterations_ = 0; ///< for-equation bodies run so far, at most opts_.max_elements
  std::size_t statement_loop_runs_ = 0; ///< loop bodies of algorithms and inlined functions run so far
  /// The most nodes one value of an algorithm may have (too_large_value).
  std::size_t max_value_nodes() const { return std::min(5 * opts_.max_elements, value_nodes_cap_); }
  /// Lowered while a call whose arguments are all parameters is inlined
  /// (inline_or_evaluate): such a call can be evaluated instead, which a
  /// value past kEvaluableValueNodes makes the better choice.
  std::size_t value_nodes_cap_ = static_cast<std::size_t>(-1);
  /// Counts one run of a for- or while-loop's body in an algorithm or an
  /// inlined function; reports at `r` past 10 x opts_.max_elements in all
  /// (nested loops of a million runs each took hours).
  void count_statement_loop_run(SourceRange r);
  bool written_by_user(const Instance &inst, const Modifier &mod) const;
  /// Instantiates a structured component (or array element) of class `cls`
  /// and checks that its modifiers name elements of it.
  void instantiate_structured(Instance &inst, ClassNode *cls, const Modifier &mod, unsigned depth);
  void make_elements(Instance &inst, const ast::Component &comp, const ResolvedType &rt,
                     const Modifier &mod, unsigned depth);
  void check_modifier_names(const Instance &inst, const Modifier &mod);
  /// Instantiates `c`, declared in `cls`, as a member of `inst` under the
  /// instance's modifiers `mod` (a redeclaration in `mod` replaces it).
  void instantiate_member(Instance &inst, const ast::Component &c, ClassNode *cls, const Modifier &mod,
                          unsigned depth);
  /// The member `name` of `inst`, or null. A component that `inst`'s class
  /// declares but has not reached yet is instantiated now: Modelica lets a
  /// base class's redeclaration use an element the derived class declares
  /// (`redeclare ThermalPort p(final useDamperCage = useDamperCage)`), and
  /// two siblings' modifiers use each other's members (`start(reset =
  /// {stop.on})`, `stop(reset = {start.on})`).
  Instance *member(Instance &inst, const std::string &name);
  struct LaterMember {
    const ast::Component *comp;
    ClassNode *cls;
    const Modifier *mod; ///< the instance's modifiers, alive while its class is instantiated
    unsigned depth;
    bool started = false;
  };
  using MemberKey = std::pair<const Instance *, std::string>; ///< instance and element name
  /// Components of instances under construction, by instance and name.
  std::map<MemberKey, LaterMember> later_members_;
  /// The declared elements of expandable connectors, not present yet: by
  /// instance and name, with the modifiers they would be instantiated with.
  struct Potential {
    const ast::Component *comp;
    ClassNode *cls;
    Modifier mod;
    unsigned depth;
    bool started = false;
  };
  std::map<MemberKey, Potential> potential_;
  /// `outer` elements: their declarations (the member is the inner instance).
  std::map<MemberKey, const ast::Component *> outer_decls_;
  /// The potential element `name` of expandable `inst` made present, or null.
  Instance *present_member(Instance &inst, const std::string &name);
  /// The `inner` element `name` of the nearest instance enclosing `from`, or null.
  Instance *find_inner(const Instance &from, const std::string &name);
  /// The `inner` element an `outer` one without any gets (MLS 5.4: tools may
  /// add one): an element of the model itself, of the outer's type with its
  /// defaults, added once per name with a warning.
  Instance *default_inner(const ast::Component &outer, ClassNode *cls, unsigned depth);
  std::set<const Instance *> default_inners_;
  const ast::Component *making_default_inner_ = nullptr;

  // -- redeclarations (flatten_redeclare.cpp)
  /// Fills `node` with the redeclaration `em` (a component or a class),
  /// written in class `lexical` at instance `scope`.
  void redeclaration(const ast::ElementMod &em, Instance *scope, ClassNode *lexical, Modifier &node);
  /// The modifier that class `cls`'s own `redeclare` elements put on its
  /// bases, and records its redeclared classes in `inst.replaced`.
  Modifier own_redeclarations(Instance &inst, ClassNode *cls);
  /// Records the class redeclarations of `mod` in `inst.replaced`.
  void replace_classes(Instance &inst, const Modifier &mod);
  /// Instantiates `comp` of class `cls` as redeclared by `mod`: the new
  /// declaration's type with the original declaration's modifiers (or its
  /// constraining clause's) under the redeclaration's and outer ones.
  void instantiate_redeclared(Instance &inst, const ast::Component &comp, ClassNode *cls, const Modifier &mod,
                              unsigned depth);
  /// The class a redeclaration `def` written in `lexical` puts in place (in
  /// a modifier of instance `scope`, or of an extends clause: null).
  ClassNode *redeclared_class(const ast::ClassDef &def, ClassNode *lexical, const Instance *scope);
  /// Class nodes of redeclarations that are not an existing class, by where
  /// they are written and their definition.
  std::map<std::pair<ClassNode *, const ast::ClassDef *>, std::unique_ptr<ClassNode>> redeclared_classes_;
  /// A binding, flattened and taken at the modifier's element index.
  ast::ExprPtr binding_expr(const Modifier &m);
  /// The value `m` binds: its binding flattened in its scope, then the
  /// element (m.index) and record fields (m.fields) it selects.
  Tensor binding_tensor(const Modifier &m);
  /// Array bindings flattened once for all their elements, by binding and
  /// scope: `parameter Real table[n, 2] = [...]` took each of its 2n
  /// elements from a new flattening of the whole table (quadratic).
  std::map<std::tuple<const ast::Expr *, Instance *, ClassNode *>, Tensor> array_bindings_;
  /// Bindings taken element by element whose flattening failed (reported once).
  std::set<std::tuple<const ast::Expr *, Instance *, ClassNode *>> failed_bindings_;

  struct PendingBinding {
    std::int32_t var;
    std::string attribute; ///< "" for the value binding
    Modifier mod;
  };
  std::vector<PendingBinding> pending_;
  /// Indices into pending_ per variable: parameters are evaluated on demand
  /// (array sizes) long before phase 2 walks the whole list.
  std::unordered_map<std::int32_t, std::vector<std::size_t>> pending_by_var_;
  /// Flattens the still-pending `attribute` binding of `var` ("" = value),
  /// or returns null when there is none.
  ast::ExprPtr take_pending(std::int32_t var, const std::string &attribute);
  std::vector<ClassNode *> class_stack_;

  // -- expressions (flatten_expr.cpp)
  Tensor expr(const ast::Expr &e, const Scope &s);
  /// expr() of every kind but the operators: kept out of expr()'s own frame,
  /// which a long sum (nested as deep as it has terms) repeats per operand.
  Tensor expr_node(const ast::Expr &e, const Scope &s);
  ast::ExprPtr scalar_expr(const ast::Expr &e, const Scope &s);
  /// Evaluates a flat expression; throws Reported when it is not constant.
  double eval(const ast::Expr &flat_expr, SourceRange where);
  /// The value of a String expression of parameters (a literal, a String
  /// parameter's binding, an if-expression of them), or nullopt: `=` and
  /// `<>` of two such evaluate (`Star star if terminalConnection <> "D"`).
  std::optional<std::string> eval_string(const ast::Expr &flat_expr, SourceRange where, unsigned depth = 0);
  double eval_param(std::int32_t var, SourceRange where);
  /// Flattens and evaluates `e` as an integer (dims, subscripts, ranges).
  long long eval_int(const ast::Expr &e, const Scope &s);
  std::vector<double> eval_range(const ast::Expr &e, const Scope &s);

  // -- arrays (flatten_arrays.cpp)
  /// Number of literals when `ref` names an enumeration type, else -1.
  int enumeration_size(const ast::ComponentRef &ref, const Scope &s, SourceRange where);
  /// Size of one declared dimension: an Integer expression or an enumeration type.
  long long dimension_size(const ast::Expr &d, const Scope &s);
  /// `{body for i in r1, j in r2, ...}`: the last iterator runs along the first dimension.
  Tensor comprehension(const ast::Expr &body, const std::vector<ast::ForIndex> &iterators, const Scope &s,
                       SourceRange where);
  /// `[a, b; c, d]` with scalar, vector or matrix elements (Modelica's cat/promote rules).
  Tensor array_constructor(const ast::Expr &e, const Scope &s);
  Tensor matrix_constructor(const ast::Expr &e, const Scope &s);
  /// The array built-ins and reductions with iterators: true and `out` set
  /// when `call` is one of them; reports bad arguments.
  bool array_function(const ast::Expr &call, const Scope &s, Tensor &out);

  // -- functions (flatten_functions.cpp)
  /// The function class a call names, or null when it names none.
  ClassNode *lookup_function(const ast::Expr &call, const Scope &s);
  /// MLS 5.3.1: a simple name is looked up in the enclosing scopes before the
  /// built-ins of the global scope, so a function declared there named like a
  /// built-in (`Modelica.Math.Matrices.exp` inside Matrices, ComplexMath's
  /// `exp`, a model's own `sum`) is the one called. The function, or null when
  /// the call is qualified, names a reserved type (Real, Integer, Boolean,
  /// String) or a component in scope (Optimica's `x(t)`), or lookup finds no
  /// function or an `external "builtin"` one of the name (Modelica.Math.exp
  /// inside Modelica.Math: the built-in). Cached per scope class and name.
  ClassNode *enclosing_function(const ast::Expr &call, const Scope &s);
  std::map<std::pair<ClassNode *, std::string>, ClassNode *> enclosing_functions_;
  /// `fn` applied to flattened `values`, its first inputs in order (the rest
  /// take their defaults): its first output inlined, or nullopt when the
  /// values do not fit those inputs (a record of the input's class for a
  /// record input, a number otherwise, as many dimensions as declared). For
  /// operator records (flatten_operators.cpp); `site` gives the ranges.
  std::optional<Tensor> apply_function(ClassNode *fn, std::vector<Tensor> values, const ast::Expr &site);
  /// A call of user function `fn` inlined: its outputs (at most `wanted`) as
  /// expressions of the arguments; `external "builtin"` maps to the built-in.
  /// Reports what cannot be inlined and throws Reported.
  /// `preset`: input values bound by the short definitions that led to `fn`
  /// (short_function_base), used where the call gives none.
  std::vector<Tensor> call_function(ClassNode *fn, const ast::Expr &call, const Scope &s,
                                    std::size_t wanted = 1,
                                    std::vector<std::pair<std::string, Tensor>> preset = {});
  /// Elements of `t` made of numbers only become one finite number (Boolean
  /// by the top operation, Integer for Integer literals under + - *, else
  /// Real): an algorithm's counter (`i := i + 1`) stays a literal.
  void fold_numbers(Tensor &t);
  /// call_function on flattened arguments: inlined, or evaluated now where
  /// the algorithm cannot be inlined and the arguments are parameters.
  std::vector<Tensor> inline_or_evaluate(ClassNode *fn, const Signature &sig, const std::vector<bool> &given,
                                         std::vector<Tensor> arguments, const ast::Expr &call,
                                         std::size_t wanted);
  /// A vectorized call (MLS 12.4.6): `fn` once per index of `over`, the
  /// `sliced` arguments (those with those leading dimensions beyond their
  /// declaration) sliced; the first outputs as one array of dimensions
  /// `over` then the output's own.
  Tensor call_elementwise(ClassNode *fn, const Signature &sig, const std::vector<bool> &given,
                          const std::vector<Tensor> &arguments, const std::vector<bool> &sliced,
                          const ast::Expr &call, const std::vector<int> &over);
  /// A call statement of function `fn` without outputs that has an effect
  /// the tool provides (the impure random generator's state); false if none.
  bool call_statement(ClassNode *fn, const ast::Expr &call, const Scope &s);
  /// The indices into `slot` (a local's value) that `ref` designates
  /// (subscripts and record fields); `shape` gets their dims and record.
  std::vector<std::size_t> designate(const Tensor &slot, const ast::ComponentRef &ref, const Scope &s,
                                     SourceRange where, Tensor &shape);
  // -- operator records (flatten_operators.cpp, MLS 14)
  /// `op` on `operands` (one for unary minus and `not`, else two), a record
  /// among them: the function of operator 'op' of the first operator record
  /// among them that takes them (MLS 14.3), or else the number operand
  /// converted by that record's 'constructor' (MLS 14.4). Reports when no
  /// operand is an operator record or no function takes the operands.
  Tensor overloaded_operator(ast::Op op, std::vector<Tensor> operands, const ast::Expr &site);
  /// overloaded_operator per element of array operands (MLS 10.6), or
  /// nullopt where the operator or the sizes do not allow it.
  std::optional<Tensor> overloaded_elementwise(ast::Op op, const std::vector<Tensor> &operands, const ast::Expr &site);
  /// overloaded_operator for unary `e` and binary `e` (flatten_expr.cpp).
  Tensor unary_on_record(const ast::Expr &e, Tensor a);
  Tensor binary_on_records(const ast::Expr &e, Tensor a, Tensor b);
  /// The functions of operator `name` ("'+'", "'constructor'") of `record`:
  /// an `operator function` itself, or the functions of an `operator`.
  std::vector<ClassNode *> operator_functions(ClassNode *record, const std::string &name);
  /// `R(args)` for an operator record R that has a 'constructor' (MLS 14.2):
  /// its function that takes the flattened positional `call` arguments, or
  /// nullopt (no 'constructor', named arguments, or none takes them: the
  /// record constructor applies).
  std::optional<Tensor> overloaded_constructor(ClassNode *record, const ast::Expr &call, const Scope &s);
  /// The class a call names (a function, a record constructor), or null.
  ClassNode *lookup_called_class(const ast::Expr &call, const Scope &s);
  /// A call that names a function through components (`world.gravityAcceleration(r)`,
  /// MLS 5.3.2): the instance its leading parts name (an outer one's inner
  /// element) and the function class declared in it, replaceable ones as
  /// the instance redeclares them; {null, null} otherwise.
  std::pair<Instance *, ClassNode *> function_of_instance(const ast::Expr &call, const Scope &s);
  /// Follows `function F = G(k = e)` to the long function it names; the
  /// modifiers' bindings (nearer ones first) as input values, evaluated
  /// where F is declared: in `owner` for a function of an instance, else in
  /// F's enclosing class.
  ClassNode *short_function_base(ClassNode *fn, Instance *owner, const ast::Expr &call,
                                 std::vector<std::pair<std::string, Tensor>> &preset);
  /// A reference to a local of an inlined function, or false.
  bool local_value(const ast::ComponentRef &ref, const Scope &s, SourceRange where, Tensor &out);
  /// `String(x, ...)`: kept as a call (assert messages).
  Tensor string_call(const ast::Expr &call, const Scope &s);

  // -- records (flatten_records.cpp)
  /// Reports a record value used as an operand of `operation`.
  void no_record(const Tensor &t, SourceRange where, const std::string &operation);
  void no_record(const Tensor &t, SourceRange where, ast::Op op);
  /// A variable in an expression: a reference, or a constant's value.
  ast::ExprPtr variable_expr(std::int32_t var, SourceRange where);
  /// The layout of record class `cls` (cached); reports array fields of
  /// unknown size and fields of other classes.
  std::shared_ptr<const RecordLayout> record_layout(ClassNode *cls, SourceRange where);
  std::map<ClassNode *, std::shared_ptr<const RecordLayout>> record_layouts_;
  /// The value of record instances `insts` (an array of them when `dims`):
  /// their variables in layout order.
  Tensor record_value(const std::vector<Instance *> &insts, const std::vector<int> &dims, SourceRange where);
  /// `R(a, b, name = c)` for record class `cls`: fields from the arguments,
  /// positional then named, the others from their declared bindings.
  Tensor record_constructor(ClassNode *cls, const ast::Expr &call, const Scope &s);
  /// The field `name` of record value `t` (of every record of an array).
  Tensor record_field(const Tensor &t, const std::string &name, SourceRange where);
  /// A record value of layout `layout` (times `dims`) with each field's
  /// declared binding where it has one and null elements elsewhere.
  Tensor record_defaults(const std::shared_ptr<const RecordLayout> &layout, const std::vector<int> &dims,
                         SourceRange where);
  // -- named intermediates of inlined functions (flatten_intermediates.cpp)
  /// The most nodes a value an inlined function computes keeps as an
  /// expression where it may become a variable (intermediate()).
  static constexpr std::size_t kIntermediateNodes = 200;
  /// What `value`, a number that is a function of present values only (no
  /// der, pre, ...), can be: a continuous variable (it varies in time), a
  /// parameter (of parameters only); None for anything else.
  enum class IntermediateKind { None, Varying, Parameter };
  IntermediateKind intermediate_kind(const ast::Expr &value) const;
  /// While a continuous equation is flattened (intermediates_on_): `value`,
  /// computed by inlined function `fn` for its local `local`, as a new
  /// variable defined by it (an equation, or a parameter's binding) if it
  /// has more than kIntermediateNodes nodes and is of a kind; defined under
  /// inline_guards_ (else 0); one variable per distinct value. Otherwise
  /// `value` itself.
  ast::ExprPtr intermediate(ast::ExprPtr value, ClassNode *fn, const std::string &local, SourceRange where);
  /// Moves the intermediates' equations into the model.
  void flush_intermediates();
  /// Set while a continuous equation (not initial, not in a when-clause or
  /// an if-equation on varying conditions) or a continuous variable's
  /// binding is flattened.
  bool intermediates_on_ = false;
  /// Set while the equations of the models' equation sections are flattened
  /// (flatten_equations), cleared inside if-equations on varying conditions.
  bool continuous_section_ = false;
  /// The varying conditions that hold where the statement being inlined
  /// runs: the branches of the `if`s around it.
  std::vector<ast::ExprPtr> inline_guards_;
  /// Runs of inlined functions under way that have taken a decision (a
  /// varying condition around a return, break or while: inline_call runs
  /// the algorithm once per way). Their values make no intermediates: a
  /// root finder's while-loop takes thousands of ways, each guarded by all
  /// its decisions.
  unsigned decided_paths_ = 0;
  std::unordered_map<std::string, std::int32_t> intermediate_by_text_;
  std::vector<ast::Equation> intermediate_equations_;
  unsigned intermediate_count_ = 0;
  unsigned function_depth_ = 0;
  /// Functions being inlined whose relations generate no events (those
  /// without `GenerateEvents = true` whose outputs are all Real): while it is
  /// non-zero, expr() wraps each relation it builds in noEvent().
  unsigned no_event_depth_ = 0;
  /// Bases instantiated per instance, with the modifier they were instantiated with.
  std::map<std::pair<Instance *, const ClassNode *>, Modifier> inherited_;
  std::set<std::pair<const Instance *, std::string>> disabled_; ///< conditional components switched off

  // -- external objects and the tables of ModelicaStandardTables
  //    (flatten_external_objects.cpp, flatten_tables.cpp)
  /// True if `cls` extends the predefined `ExternalObject`.
  bool is_external_object_class(ClassNode *cls);
  /// Records component `comp` of external-object class `cls` with its
  /// binding (the constructor call) as a member of `parent`; no variable.
  void declare_external_object(Instance &parent, const ast::Component &comp, ClassNode *cls, const Modifier &mod);
  /// A call of an external "C" function that the tool provides itself
  /// (ModelicaStandardTables' tables): its output as an expression of the
  /// external object's table, in `out`; false if `c_name` is none of them.
  /// `args` are the call's arguments matched to the function's inputs.
  bool provided_external(const std::string &c_name, const std::vector<const ast::Expr *> &args,
                         const ast::Expr &call, const Scope &s, Tensor &out);
  /// The same for ModelicaStrings_substring and ModelicaStrings_length on
  /// constant strings (flatten_strings.cpp): the result in `out`.
  bool provided_string_function(const std::string &c_name, const std::vector<const ast::Expr *> &args,
                                const ast::Expr &call, const Scope &s, Tensor &out);
  /// The random functions of ModelicaExternalC (flatten_random.cpp): a call
  /// of external "C" function `def` (the function `fn_name`, its inputs and
  /// outputs named in order, `args` matched to the inputs): its outputs in
  /// `out`; false if def names none of them.
  bool provided_random(const ast::ClassDef &def, const std::string &fn_name, const std::vector<std::string> &inputs,
                       const std::vector<std::string> &outputs, const std::vector<const ast::Expr *> &args,
                       const ast::Expr &call, const Scope &s, std::vector<Tensor> &out);
  /// The same for a call statement without outputs (the impure generator's
  /// setInternalState); false if def names none.
  bool provided_random_statement(const ast::ClassDef &def, const std::vector<std::string> &inputs,
                                 const std::vector<const ast::Expr *> &args, const ast::Expr &call, const Scope &s);
  /// The elements of `t` as 32-bit Integers, evaluated now (reported otherwise).
  std::vector<std::int32_t> random_integers(const Tensor &t, SourceRange where);
  /// Warns once per function that it is evaluated at translation.
  void evaluated_random(const std::string &fn_name, SourceRange where, const std::string &why);
  std::set<std::string> random_warned_;
  std::optional<std::int32_t> automatic_seed_;  ///< automaticGlobalSeed(), drawn once
  std::vector<std::int32_t> impure_state_;       ///< the impure xorshift1024* state
  std::int32_t impure_id_ = 0;                   ///< the id initializeImpureRandom gave
  unsigned calls_in_when_ = 0;                   ///< functions being inlined for a when-clause
  /// impureRandom() in a when-clause: the next number from the hidden state
  /// (made discrete variables on first use), the clause's state stepped.
  ast::ExprPtr impure_event_draw(SourceRange where);
  /// Appends `state = stepped state` to the body of the when-branch just
  /// flattened if it drew impure numbers.
  void impure_draws_of_branch(std::vector<ast::Equation> &body);
  /// The hidden state's variables start where the translation's draws left it.
  void impure_starts();
  std::vector<std::int32_t> impure_vars_;         ///< ModelicaRandom.impureState[1..33]
  std::vector<ast::ExprPtr> impure_branch_state_;  ///< the state after this branch's draws
  int impure_branch_ = -1;                         ///< the when-branch that draws, or -1
  int impure_branch_draws_ = 0;                    ///< its draws so far
  int when_branch_serial_ = 0;                     ///< counts the when-branches flattened
  struct ExternalObject;
  std::map<const Instance *, std::shared_ptr<ExternalObject>> external_objects_;
  /// The table behind the external-object reference `ref` (flattened once).
  std::shared_ptr<ExternalObject> external_object(const ast::Expr &ref, const Scope &s);
  /// Fills `t` from its constructor call (inline or from a file).
  void build_table(ExternalObject &t);
  /// Checks `t`'s sizes, keys, columns and options; takes its keys.
  void check_table(ExternalObject &t);

  // -- equations and connections (flatten_equations.cpp, flatten_connect.cpp)
  void flatten_equations(Instance &inst);
  void equation(const ast::Equation &eq, const Scope &s, std::vector<ast::Equation> &out);
  void tuple_equation(const ast::Equation &eq, const Scope &s, std::vector<ast::Equation> &out);
  void equal_elements(const ast::Equation &eq, Tensor &l, Tensor &r, std::vector<ast::Equation> &out);
  /// `graph_only`: only the edges of the connection graph (a connect inside
  /// an if-equation, seen before the graph is closed; its equations come later).
  void connect(const ast::Equation &eq, const Scope &s, bool graph_only = false);
  /// True if `eq` is a connect(), or a for-loop of nothing but connect()s
  /// (flattened before the other equations, so that cardinality() sees them).
  static bool only_connections(const ast::Equation &eq);
  /// cardinality(c): how often connector c occurs in connect() (MLS 3.7.2.3).
  Tensor cardinality(const ast::Expr &call, const Scope &s);
  /// Expandable connectors (MLS 9.1.3), before any equation is flattened:
  /// an element that a connect() names is made present (a declared one
  /// instantiated, an undeclared one created with the type of the other
  /// side), and connected expandable connectors get each other's elements,
  /// to a fixed point (flatten_expandable.cpp).
  void expand_connectors();
  /// A new element `name` of expandable connector `bus`, of the type of
  /// `like` (the other side of a connect), neither input nor output.
  Instance *add_bus_member(Instance &bus, const std::string &name, const Instance &like);
  void instantiate_like(Instance &inst, const Instance &like);
  /// An algorithm section executed on expressions (flatten_algorithms.cpp):
  /// appends `v = value` per assigned variable (when-clauses for those of
  /// `when` statements) to `out`; reports what it cannot express.
  void algorithm_section(const ast::AlgorithmSection &alg, const Scope &s, std::vector<ast::Equation> &out);
  void finish_connections();
  // -- overdetermined connectors (flatten_overconstrained.cpp)
  /// A record instance that declares an equalityConstraint function.
  bool is_overdetermined(const Instance &x);
  /// The graph node argument k of a Connections call names.
  Instance *graph_node(const ast::Expr &call, std::size_t k, const Scope &s);
  /// Records Connections.root / potentialRoot / branch.
  void connections_statement(const ast::Equation &eq, const Scope &s);
  /// Runs `body` once per iteration of the for-equation `eq` (nested
  /// indices, the last innermost), with a scope that binds the indices.
  void for_each_iteration(const ast::Equation &eq, const Scope &s, const std::function<void(const Scope &)> &body);
  /// Records the Connections statements of `eq`, and the graph edges of its
  /// connect()s, through if-equations on parameters (the branch taken) and
  /// for-loops.
  void collect_graph_statements(const ast::Equation &eq, const Scope &s);
  /// Chooses the roots and the spanning trees, and the connections to break
  /// (graph_.broken); reports branches that close a loop or join two definite
  /// roots, and parts without a root.
  void close_connection_graph();
  /// The pairs of scalar variables (both orders) that the broken connections
  /// join: finish_connections gives them no equations.
  std::set<std::pair<std::int32_t, std::int32_t>> broken_connection_pairs();
  /// 0 = equalityConstraint(A, B) for each broken connection (MLS 9.4.1).
  void equality_constraints();
  /// Connections.isRoot(A) or rooted(A), from the closed graph.
  bool connections_query(const ast::Expr &call, const Scope &s);
  OverconstrainedGraph graph_;
  bool graph_closed_ = false;
  bool graph_probe_ = false;  ///< collecting the edges of connect()s in if-equations, diagnostics rolled back

  // -- shared state
  Library::Impl &lib_;
  DiagnosticEngine &diags_;
  const FlattenOptions &opts_;
  std::unique_ptr<flat::Model> model_;
  std::unique_ptr<Instance> top_;
  std::vector<std::int8_t> param_state_; ///< 0 unevaluated, 1 evaluating, 2 done, 3 failed
  std::vector<Instance *> all_instances_;
  std::unordered_map<const Instance *, int> connect_count_;  ///< per connector: its connect() occurrences
  bool connections_counted_ = false;  ///< every connect() outside if-equations is flattened

  [[noreturn]] void fail(DiagId id, SourceRange r, const std::string &msg);
  /// Resolves a component reference to instances (a tensor of them when
  /// subscripts select several); null when the first name is no member.
  bool resolve_instances(const ast::ComponentRef &ref, const Scope &s, SourceRange where,
                         std::vector<int> &dims, std::vector<Instance *> &out);
  /// The constant `name` that an import clause of `cls` brings in (decl null: none).
  FoundConstant imported_constant(ClassNode *cls, const std::string &name);
  /// `a[i]` with a subscript that varies in time: `if i == 1 then a[1] ...
  /// else a[n]` in `out` (flatten_varying_subscripts.cpp); false when every
  /// subscript of `ref_expr` is known now.
  bool varying_subscript(const ast::Expr &ref_expr, const Scope &s, Tensor &out);
  /// Told of every varying subscript `index` into a dimension of size `n`
  /// while a function is inlined: an index outside 1..n is an error in
  /// Modelica, so the ways through it bound it (flatten_functions.cpp).
  std::function<void(const ast::Expr &index, int n)> on_varying_index;
  /// A constant reached lexically (package constants, enumeration literals).
  bool lookup_constant(const ast::ComponentRef &ref, const Scope &s, SourceRange where, Tensor &out);
  /// lookup_constant's named constant: `k`, `P.k`, `P.k[i]`.
  bool named_constant(const ast::ComponentRef &ref, const Scope &s, SourceRange where, Tensor &out);
  /// A field of a record constant: `data.R`, `P.data.alow[2]`,
  /// `fluidConstants[1].molarMass`; false if no prefix of `ref` is one.
  bool record_constant_field(const ast::ComponentRef &ref, const Scope &s, SourceRange where, Tensor &out);
  /// The value of record constant `decl` (declared or inherited in `scope`)
  /// without a binding, from its modifiers (`constant DataRecord H2O(name =
  /// "H2O", MM = 0.018)`, `each` ones for an array of records) and the
  /// record's defaults; nullopt if `decl` is not of a record type.
  std::optional<Tensor> record_from_modifiers(ClassNode *scope, const ast::Component &decl, SourceRange where);

  // connections: set elements are 2*var + (1 if seen from outside);
  // see flatten_connect.cpp.
  std::vector<std::pair<std::int32_t, std::int32_t>> connections_;
  std::vector<SourceRange> connection_ranges_;
  /// `graph_only`: the pair's graph edges, no connection equations.
  void connect_pair(Instance *a, bool a_outside, Instance *b, bool b_outside, SourceRange where,
                    bool graph_only = false);
  /// True if `ref` passes through a conditional component that is switched
  /// off (in every element, where it passes through an array of components).
  bool through_disabled(const ast::ComponentRef &ref, const Scope &s) const;
  void flatten_bindings();
  void flatten_optimization();
  /// The class attributes of the optimization (objective, startTime, ...):
  /// the top class's own modification, then those of the optimization
  /// classes it extends (depth first) for the attributes not set before.
  std::vector<const ast::ElementMod *> optimization_attributes();
  /// Optimica `finalTime(free = true, min, max, initialGuess)` (with or without
  /// a value) among `attributes`: declares the parameter `finalTime` that holds it (see
  /// flatten_optimica_time.cpp) and sets free_final_time_. Reports a free
  /// startTime, unknown attributes and a model variable already named finalTime.
  void declare_free_final_time(const std::vector<const ast::ElementMod *> &attributes);
  /// The variable of a free final time, or -1 (finalTime fixed).
  std::int32_t free_final_time_ = -1;
  void check_balance();
  /// A simple equation identical to an earlier one (either side order) is
  /// dropped with a warning (flatten_repeated.cpp).
  void drop_repeated_equations();
  /// semiLinear() at zero flow on a connection of two components (MLS
  /// 3.7.2.5, rule 1): the first one's flow equation becomes the one for the
  /// shared potential (flatten_semilinear.cpp). `sets`: the connection sets.
  void semilinear_connections(const std::vector<std::vector<std::int32_t>> &sets);
  // -- stream connectors (flatten_stream.cpp, MLS 15)
  /// inStream(v) and actualStream(v), element by element: inStream stays a
  /// call of the stream variable until the connection sets are known.
  Tensor stream_operator(const ast::Expr &call, const Scope &s);
  /// The flow variable of the connector that stream variable `v` belongs to.
  std::int32_t stream_flow(std::int32_t v, SourceRange where);
  /// The equations of the outside connectors' stream variables, and every
  /// inStream() replaced by its value from the sets (`sets`: set elements
  /// 2*var + 1 if seen from outside).
  void stream_connections(const std::vector<std::vector<std::int32_t>> &sets);
  /// Stream variables: their scalar instances, by variable.
  std::unordered_map<std::int32_t, const Instance *> stream_vars_;
  /// Inputs no equation defines become inputs of the model (flatten_free_inputs.cpp).
  void mark_free_inputs();
  /// `v = e` in a when-clause with der(v) elsewhere becomes reinit(v, e) (flatten_free_inputs.cpp).
  void when_assignments_to_reinits();
  bool is_constant(const ast::Expr &flat_expr) const;
  /// Moves each `p = e` of `produced` (initial equations) where p is a
  /// parameter declared fixed = false without a value and e reads parameters
  /// and constants only (not p) into p's binding (flatten_parameter_equations.cpp).
  void bind_computed_parameters(std::vector<ast::Equation> &produced);
  /// True if `flat_expr` reads only literals and parameters whose values the
  /// flattening has already fixed (they sized an array, chose an if-equation's
  /// branch, bounded a loop): deciding on it now changes nothing that a later
  /// parameter value could still change, and cannot fail.
  bool already_evaluated(const ast::Expr &flat_expr) const;
  /// True if `flat_expr` (of parameters, is_constant) reads only constants,
  /// parameters marked `Evaluate = true` and parameters already fixed
  /// (already_evaluated): its value is part of the model's structure, known now.
  bool structural(const ast::Expr &flat_expr) const;
};

} // namespace detail
} // namespace mo::frontend
