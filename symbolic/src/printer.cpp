#include "mo/symbolic/printer.hpp"

#include <algorithm>

#include <cmath>
#include <deque>
#include <string>
#include <fmt/format.h>
#include <vector>

#include "mo/runtime/modelica_random.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic {

namespace {

// Modelica precedence levels, loosest first. An operand whose level is below
// the level its position requires gets parentheses.
enum Level : int {
  kIf = 0,         // if-then-else
  kOr = 1,         // or
  kAnd = 2,        // and
  kNot = 3,        // not
  kRelation = 4,   // < <= > >= == <>
  kAdditive = 5,   // binary + -, and unary minus (only at the start of a sum)
  kTerm = 6,       // * /
  kFactor = 7,     // ^ (not associative)
  kPrimary = 8,    // literals, names, function calls
};

constexpr std::string_view keywords[] = {
    "algorithm", "and", "annotation", "block", "break", "class", "connect",
    "connector", "constant", "constrainedby", "der", "discrete", "each", "else",
    "elseif", "elsewhen", "encapsulated", "end", "enumeration", "equation",
    "expandable", "extends", "external", "false", "final", "flow", "for",
    "function", "if", "import", "impure", "in", "initial", "inner", "input",
    "loop", "model", "not", "operator", "or", "outer", "output", "package",
    "parameter", "partial", "protected", "public", "pure", "record", "redeclare",
    "replaceable", "return", "stream", "then", "true", "type", "when", "while",
    "within"};

bool is_ident_start(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
bool is_digit(char c) { return c >= '0' && c <= '9'; }

// IDENT [ '[' integer {',' integer} ']' ] { '.' the same }.
bool is_component_reference(std::string_view name) {
  std::size_t i = 0;
  while (true) {
    const std::size_t start = i;
    if (i >= name.size() || !is_ident_start(name[i])) return false;
    while (i < name.size() && (is_ident_start(name[i]) || is_digit(name[i]))) ++i;
    const std::string_view ident = name.substr(start, i - start);
    for (std::string_view keyword : keywords)
      if (ident == keyword) return false;
    if (i < name.size() && name[i] == '[') {
      ++i;
      while (true) {
        if (i >= name.size() || !is_digit(name[i])) return false;
        while (i < name.size() && is_digit(name[i])) ++i;
        if (i < name.size() && name[i] == ',') { ++i; continue; }
        if (i < name.size() && name[i] == ']') { ++i; break; }
        return false;
      }
    }
    if (i == name.size()) return true;
    if (name[i] != '.') return false;
    ++i;
  }
}

std::string constant_text(double value) {
  if (std::isnan(value)) return "(0.0/0.0)";
  if (std::isinf(value)) return value > 0 ? "Modelica.Constants.inf" : "-Modelica.Constants.inf";
  return fmt::format("{}", value);
}

int level(const ExprArena& arena, Expr e) {
  const ExprKind k = arena.kind(e);
  switch (k) {
  case ExprKind::Constant: return std::signbit(arena.constant_value(e)) ? kAdditive : kPrimary;
  case ExprKind::Select: return kIf;
  case ExprKind::Or: return kOr;
  case ExprKind::And: return kAnd;
  case ExprKind::Not: return kNot;
  case ExprKind::Lt:
  case ExprKind::Le:
  case ExprKind::Gt:
  case ExprKind::Ge:
  case ExprKind::Eq:
  case ExprKind::Ne: return kRelation;
  case ExprKind::Add:
  case ExprKind::Sub:
  case ExprKind::Neg: return kAdditive;
  case ExprKind::Mul:
  case ExprKind::Div: return kTerm;
  case ExprKind::Pow: return kFactor;
  case ExprKind::Symbol:
  case ExprKind::Der:
  case ExprKind::Pre:
  case ExprKind::Sin:
  case ExprKind::Cos:
  case ExprKind::Tan:
  case ExprKind::Asin:
  case ExprKind::Acos:
  case ExprKind::Atan:
  case ExprKind::Atan2:
  case ExprKind::Sinh:
  case ExprKind::Cosh:
  case ExprKind::Tanh:
  case ExprKind::Exp:
  case ExprKind::Log:
  case ExprKind::Log10:
  case ExprKind::Sqrt:
  case ExprKind::Abs:
  case ExprKind::Sign:
  case ExprKind::Min:
  case ExprKind::Max:
  case ExprKind::Floor:
  case ExprKind::Ceil:
  case ExprKind::NoEvent:
  case ExprKind::Smooth:
  case ExprKind::ArgList:
  case ExprKind::External:
  case ExprKind::Delay: return kPrimary;
  }
  return kPrimary;
}

// A unit of pending output: literal text, or a node printed at a minimum level.
struct Item {
  std::string_view text;
  Expr node;
  int min_level = 0;
};

class ModelicaPrinter {
public:
  ModelicaPrinter(const ExprArena& arena, std::string& out, const ExprNames* names = nullptr)
      : arena_(arena), out_(out), names_(names) {}

  void print(Expr root) {
    root_ = root;
    stack_.push_back(Item{{}, root, kIf});
    while (!stack_.empty()) {
      const Item item = stack_.back();
      stack_.pop_back();
      if (!item.node.valid()) out_ += item.text;
      else expand(item.node, item.min_level);
    }
  }

private:
  // Items are pushed in reverse: the last pushed is printed first.
  void text(std::string_view s) { pending_.push_back(Item{s, Expr(), 0}); }
  void operand(Expr e, int min_level) { pending_.push_back(Item{{}, e, min_level}); }
  void flush() {
    stack_.insert(stack_.end(), pending_.rbegin(), pending_.rend());
    pending_.clear();
  }

  void infix(Expr e, std::string_view op, int left, int right) {
    operand(arena_.operand(e, 0), left);
    text(op);
    operand(arena_.operand(e, 1), right);
  }

  void call(Expr e) {
    text(kind_spelling(arena_.kind(e)));
    text("(");
    std::size_t n = arity(arena_.kind(e));
    // delay(e, T): delayMax is T unless the call gave another.
    if (arena_.kind(e) == ExprKind::Delay && arena_.operand(e, 1) == arena_.operand(e, 2)) n = 2;
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0) text(", ");
      operand(arena_.operand(e, i), kIf);
    }
    text(")");
  }

  // A Derivative symbol named "der(v)" (as lowering names them) prints as
  // der(v) with v quoted if needed; any other symbol prints as its name.
  void symbol(const SymbolInfo& info) {
    const std::string& n = info.name;
    if (info.role == SymbolRole::Derivative && n.size() > 5 && n.starts_with("der(") &&
        n.back() == ')') {
      out_ += "der(";
      out_ += modelica_name(std::string_view(n).substr(4, n.size() - 5));
      out_ += ')';
      return;
    }
    if (info.role == SymbolRole::Discrete &&
        (n == "initial()" || n.starts_with("sample("))) {  // the flags initial() and sample() read
      out_ += n;
      return;
    }
    out_ += modelica_name(n);
  }

  void expand(Expr e, int min_level) {
    if (names_ && e != root_) {
      if (const auto it = names_->find(e); it != names_->end()) {
        out_ += it->second;
        return;
      }
    }
    if (level(arena_, e) < min_level) {
      text("(");
      operand(e, kIf);
      text(")");
      flush();
      return;
    }
    const ExprKind k = arena_.kind(e);
    switch (k) {
    case ExprKind::Constant: out_ += constant_text(arena_.constant_value(e)); return;
    case ExprKind::Symbol: symbol(arena_.symbol_info(e)); return;
    case ExprKind::Der:
    case ExprKind::Pre:
      out_ += kind_spelling(k);
      out_ += '(';
      out_ += modelica_name(arena_.symbol_info(arena_.operand(e, 0)).name);
      out_ += ')';
      return;
    case ExprKind::Add: infix(e, " + ", kAdditive, kTerm); break;
    case ExprKind::Sub: infix(e, " - ", kAdditive, kTerm); break;
    case ExprKind::Mul: infix(e, "*", kTerm, kFactor); break;
    case ExprKind::Div: infix(e, "/", kTerm, kFactor); break;
    case ExprKind::Pow: infix(e, "^", kPrimary, kPrimary); break;
    case ExprKind::Neg:
      text("-");
      operand(arena_.operand(e, 0), kTerm);
      break;
    case ExprKind::Lt: infix(e, " < ", kAdditive, kAdditive); break;
    case ExprKind::Le: infix(e, " <= ", kAdditive, kAdditive); break;
    case ExprKind::Gt: infix(e, " > ", kAdditive, kAdditive); break;
    case ExprKind::Ge: infix(e, " >= ", kAdditive, kAdditive); break;
    case ExprKind::Eq: infix(e, " == ", kAdditive, kAdditive); break;
    case ExprKind::Ne: infix(e, " <> ", kAdditive, kAdditive); break;
    case ExprKind::And: infix(e, " and ", kAnd, kNot); break;
    case ExprKind::Or: infix(e, " or ", kOr, kAnd); break;
    case ExprKind::Not:
      text("not ");
      operand(arena_.operand(e, 0), kRelation);
      break;
    case ExprKind::Select:
      // Nested ifs in the condition or then-branch get parentheses for clarity.
      text("if ");
      operand(arena_.operand(e, 0), kOr);
      text(" then ");
      operand(arena_.operand(e, 1), kOr);
      text(" else ");
      operand(arena_.operand(e, 2), kIf);
      break;
    case ExprKind::Sin:
    case ExprKind::Cos:
    case ExprKind::Tan:
    case ExprKind::Asin:
    case ExprKind::Acos:
    case ExprKind::Atan:
    case ExprKind::Atan2:
    case ExprKind::Sinh:
    case ExprKind::Cosh:
    case ExprKind::Tanh:
    case ExprKind::Exp:
    case ExprKind::Log:
    case ExprKind::Log10:
    case ExprKind::Sqrt:
    case ExprKind::Abs:
    case ExprKind::Sign:
    case ExprKind::Min:
    case ExprKind::Max:
    case ExprKind::Floor:
    case ExprKind::Ceil:
    case ExprKind::NoEvent:
    case ExprKind::Smooth:
    case ExprKind::ArgList:
    case ExprKind::Delay: call(e); break;
    case ExprKind::External: external(e); break;
    }
    flush();
  }

  // The flat call: ModelicaRandom_xorshift64star(k, state...) for output k.
  void external(Expr e) {
    const int code = static_cast<int>(arena_.constant_value(arena_.operand(e, 0)));
    namespace random = runtime::modelica_random;
    text(random::c_name(static_cast<random::Generator>(random::generator_of(code))));
    owned_.push_back("(" + std::to_string(code % random::kCodeBase));
    text(owned_.back());
    for (const Expr a : arena_.external_args(e)) {
      text(", ");
      operand(a, kIf);
    }
    text(")");
  }

  const ExprArena& arena_;
  std::string& out_;
  const ExprNames* names_;  ///< nodes printed as a name, or null
  Expr root_;
  std::vector<Item> stack_;
  std::vector<Item> pending_;
  std::deque<std::string> owned_;  ///< texts made while printing (stable addresses)
};

} // namespace

void append_modelica(const ExprArena& arena, Expr e, std::string& out) {
  ModelicaPrinter(arena, out).print(e);
}

void append_modelica(const ExprArena& arena, Expr e, std::string& out, const ExprNames& names) {
  ModelicaPrinter(arena, out, &names).print(e);
}

std::string to_modelica(const ExprArena& arena, Expr e) {
  std::string out;
  append_modelica(arena, e, out);
  return out;
}

std::string modelica_name(std::string_view name) {
  const bool simple = name.find_first_of(".[") == std::string_view::npos;
  if (simple && is_component_reference(name)) return std::string(name);
  const bool backquotable = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return c != '`' && static_cast<unsigned char>(c) >= 0x20 && c != 0x7f;
  });
  if (backquotable) return "`" + std::string(name) + "`";
  std::string quoted = "'";
  for (char c : name) {
    switch (c) {
    case '\'': quoted += "\\'"; break;
    case '\\': quoted += "\\\\"; break;
    case '\n': quoted += "\\n"; break;
    case '\r': quoted += "\\r"; break;
    case '\t': quoted += "\\t"; break;
    default: quoted += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
    }
  }
  quoted += '\'';
  return quoted;
}

namespace {
std::string_view role_name(SymbolRole role) {
  switch (role) {
  case SymbolRole::State: return "State";
  case SymbolRole::Derivative: return "Derivative";
  case SymbolRole::Algebraic: return "Algebraic";
  case SymbolRole::Input: return "Input";
  case SymbolRole::Parameter: return "Parameter";
  case SymbolRole::Time: return "Time";
  case SymbolRole::Discrete: return "Discrete";
  }
  return "?";
}
} // namespace

std::string dump_graph(const ExprArena& arena, std::span<const Expr> outputs) {
  std::string out;
  for (const Expr e : topological_order(arena, outputs, LeafOperands::Visit)) {
    const ExprKind k = arena.kind(e);
    out += fmt::format("%{} = ", e.id());
    if (k == ExprKind::Constant) {
      out += constant_text(arena.constant_value(e));
    } else if (k == ExprKind::Symbol) {
      const SymbolInfo& s = arena.symbol_info(e);
      out += fmt::format("{} ({} {})", modelica_name(s.name), role_name(s.role), s.index);
    } else {
      out += kind_name(k);
      out += '(';
      for (std::size_t i = 0; i < arity(k); ++i)
        out += fmt::format("{}%{}", i > 0 ? ", " : "", arena.operand(e, i).id());
      out += ')';
    }
    out += '\n';
  }
  for (std::size_t i = 0; i < outputs.size(); ++i)
    out += fmt::format("out[{}] = %{}\n", i, outputs[i].id());
  return out;
}

} // namespace mo::symbolic
