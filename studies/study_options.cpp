// Study options from the __mocompile annotation and the command line.
#include "study_options.hpp"

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <optional>

namespace mo::tools {

namespace {

namespace ast = frontend::ast;

/// An option value as written: a number, a string (or bare name), or a list.
struct Value {
  enum Kind { Number, String, List } kind = Number;
  double number = 0.0;
  std::string text;
  std::vector<Value> items;
};

std::optional<Value> from_expr(const ast::Expr& e) {
  Value v;
  switch (e.kind) {
  case ast::ExprKind::Real:
  case ast::ExprKind::Integer:
  case ast::ExprKind::Boolean: v.number = e.number; return v;
  case ast::ExprKind::String: v.kind = Value::String; v.text = e.text; return v;
  case ast::ExprKind::Ref: v.kind = Value::String; v.text = e.ref.str(); return v;
  case ast::ExprKind::Unary:
    if (e.op == ast::Op::Neg || e.op == ast::Op::Plus)
      if (auto inner = from_expr(*e.args[0]); inner && inner->kind == Value::Number) {
        if (e.op == ast::Op::Neg) inner->number = -inner->number;
        return inner;
      }
    return std::nullopt;
  case ast::ExprKind::Array:
    if (!e.iterators.empty()) return std::nullopt;
    v.kind = Value::List;
    for (const auto& item : e.args) {
      auto x = from_expr(*item);
      if (!x) return std::nullopt;
      v.items.push_back(std::move(*x));
    }
    return v;
  default: return std::nullopt;
  }
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\n");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\n") - a + 1);
}

Value from_text(const std::string& raw) {
  const std::string s = trim(raw);
  Value v;
  if (s.size() >= 2 && s.front() == '{' && s.back() == '}') {
    v.kind = Value::List;
    const std::string body = s.substr(1, s.size() - 2);
    std::size_t start = 0;
    int depth = 0;
    bool quoted = false;
    for (std::size_t i = 0; i <= body.size(); ++i) {
      if (i < body.size() && body[i] == '"') quoted = !quoted;
      if (!quoted && i < body.size() && body[i] == '{') ++depth;
      if (!quoted && i < body.size() && body[i] == '}') --depth;
      if (i == body.size() || (body[i] == ',' && depth == 0 && !quoted)) {
        if (!trim(body.substr(start, i - start)).empty())
          v.items.push_back(from_text(body.substr(start, i - start)));
        start = i + 1;
      }
    }
    return v;
  }
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') {
    v.kind = Value::String;
    v.text = s.substr(1, s.size() - 2);
    return v;
  }
  if (s == "true" || s == "false") {
    v.number = s == "true";
    return v;
  }
  try {
    std::size_t used = 0;
    v.number = std::stod(s, &used);
    if (used == s.size()) return v;
  } catch (const std::exception&) {
  }
  v.kind = Value::String;
  v.text = s;
  return v;
}

using Setter = std::function<std::string(const Value&, StudyOptions&)>;  // error or ""

Setter number_of(double StudyOptions::*field) {
  return [field](const Value& v, StudyOptions& o) -> std::string {
    if (v.kind != Value::Number) return "expects a number";
    o.*field = v.number;
    return {};
  };
}

Setter integer_of(int StudyOptions::*field, int min) {
  return [field, min](const Value& v, StudyOptions& o) -> std::string {
    if (v.kind != Value::Number || v.number != std::floor(v.number) || v.number < min)
      return fmt::format("expects an integer >= {}", min);
    o.*field = static_cast<int>(v.number);
    return {};
  };
}

Setter flag_of(bool StudyOptions::*field) {
  return [field](const Value& v, StudyOptions& o) -> std::string {
    if (v.kind != Value::Number) return "expects true or false";
    o.*field = v.number != 0.0;
    return {};
  };
}

Setter text_of(std::string StudyOptions::*field) {
  return [field](const Value& v, StudyOptions& o) -> std::string {
    if (v.kind != Value::String) return "expects a string";
    o.*field = v.text;
    return {};
  };
}

Setter choice_of(std::string StudyOptions::*field, std::vector<std::string> allowed) {
  return [field, allowed](const Value& v, StudyOptions& o) -> std::string {
    for (const auto& a : allowed)
      if (v.kind == Value::String && v.text == a) {
        o.*field = a;
        return {};
      }
    return "expects one of " + fmt::format("{}", fmt::join(allowed, ", "));
  };
}

Setter strings_of(std::vector<std::string> StudyOptions::*field) {
  return [field](const Value& v, StudyOptions& o) -> std::string {
    std::vector<std::string> out;
    const std::vector<Value> one{v};
    for (const Value& item : v.kind == Value::List ? v.items : one) {
      if (item.kind != Value::String) return "expects a list of names or strings";
      out.push_back(item.text);
    }
    o.*field = std::move(out);
    return {};
  };
}

template <class T>
Setter numbers_of(std::vector<T> StudyOptions::*field) {
  return [field](const Value& v, StudyOptions& o) -> std::string {
    std::vector<T> out;
    const std::vector<Value> one{v};
    for (const Value& item : v.kind == Value::List ? v.items : one) {
      if (item.kind != Value::Number) return "expects a list of numbers";
      out.push_back(static_cast<T>(item.number));
    }
    o.*field = std::move(out);
    return {};
  };
}

/// `starts`: a count of random starts, a list of signals, or a list of
/// signals with one count among them (`{"const:0", 20}`).
Setter starts_of() {
  return [](const Value& v, StudyOptions& o) -> std::string {
    const std::string expects = "expects a number of random starts, a list of signals, or both in one list";
    std::vector<std::string> listed;
    int random = 0, counts = 0;
    const std::vector<Value> one{v};
    for (const Value& item : v.kind == Value::List ? v.items : one) {
      if (item.kind == Value::String) {
        listed.push_back(item.text);
        continue;
      }
      if (item.kind != Value::Number || item.number != std::floor(item.number) || item.number < 0 ||
          item.number > 1e6 || ++counts > 1)
        return expects;
      random = static_cast<int>(item.number);
    }
    o.starts = std::move(listed);
    o.random_starts = random;
    return {};
  };
}

/// `blocking_factors`: numbers (every control) or strings "input=f1,f2,..." (per input).
Setter blocking_of() {
  return [](const Value& v, StudyOptions& o) -> std::string {
    const std::vector<Value> one{v};
    const auto& items = v.kind == Value::List ? v.items : one;
    const bool named = !items.empty() && items.front().kind == Value::String;
    for (const Value& item : items)
      if ((item.kind == Value::String) != named)
        return "expects a list of numbers, or of strings \"input=f1,f2,...\"";
    if (!named) return numbers_of(&StudyOptions::blocking_factors)(v, o);
    return strings_of(&StudyOptions::input_blocking_factors)(v, o);
  };
}

const std::map<std::string, Setter>& setters() {
  using S = StudyOptions;
  static const std::map<std::string, Setter> table = {
      {"task", choice_of(&S::task, {"optimal_control", "design", "estimation", "monte_carlo"})},
      {"n_e", integer_of(&S::n_e, 1)},
      {"n_cp", integer_of(&S::n_cp, 1)},
      {"scheme", choice_of(&S::scheme, {"radau", "gauss"})},
      {"element_lengths", numbers_of(&S::element_lengths)},
      {"blocking_factors", blocking_of()},
      {"du_bounds", strings_of(&S::du_bounds)},
      {"piecewise_constant_controls", flag_of(&S::piecewise_constant_controls)},
      {"init_result", text_of(&S::init_result)},
      {"init_traj", flag_of(&S::init_traj)},
      {"nominal_traj", flag_of(&S::nominal_traj)},
      {"nonlinear_blocks", choice_of(&S::nonlinear_blocks, {"nlp", "newton"})},
      {"hessian", choice_of(&S::hessian, {"automatic", "exact", "limited_memory"})},
      {"tol", number_of(&S::tol)},
      {"max_iter", integer_of(&S::max_iter, 0)},
      {"max_cpu_time", number_of(&S::max_cpu_time)},
      {"acceptable_tol", number_of(&S::acceptable_tol)},
      {"acceptable_iter", integer_of(&S::acceptable_iter, 0)},
      {"acceptable_obj_change_tol", number_of(&S::acceptable_obj_change_tol)},
      {"ipopt_options", strings_of(&S::ipopt_options)},
      {"criterion", choice_of(&S::criterion, {"A", "T", "D", "E"})},
      {"parameters", strings_of(&S::parameters)},
      {"outputs", strings_of(&S::outputs)},
      {"sigma", numbers_of(&S::sigma)},
      {"measurements", integer_of(&S::measurements, 1)},
      {"measurement_times", numbers_of(&S::measurement_times)},
      {"starts", starts_of()},
      {"seed", integer_of(&S::seed, 0)},
      {"cluster_tol", number_of(&S::cluster_tol)},
      {"hessian_fallback", flag_of(&S::hessian_fallback)},
      {"data", strings_of(&S::data)},
      {"inputs", strings_of(&S::inputs)},
      {"confidence", number_of(&S::confidence)},
      {"seeds", integer_of(&S::seeds, 1)},
      {"plot", flag_of(&S::plot)},
  };
  return table;
}

/// Applies one option; "" on success, else the message.
std::string apply(const std::string& name, const std::optional<Value>& value, StudyOptions& o) {
  const auto it = setters().find(name);
  if (it == setters().end())
    return fmt::format("unknown study option '{}' (known: {})", name,
                       fmt::join(study_option_names(), ", "));
  if (!value) return fmt::format("study option '{}' needs a literal value", name);
  if (auto error = it->second(*value, o); !error.empty())
    return fmt::format("study option '{}' {}", name, error);
  return {};
}

}  // namespace

std::vector<std::string> study_option_names() {
  std::vector<std::string> out;
  for (const auto& [name, setter] : setters()) out.push_back(name);
  return out;
}

ParsedOptions parse_study_options(const frontend::flat::Optimization& opt,
                                  const std::vector<OptionOverride>& overrides,
                                  frontend::DiagnosticEngine& diags) {
  ParsedOptions out;
  for (const auto& o : opt.options) {
    const auto value = o.value ? from_expr(*o.value) : std::nullopt;
    if (auto error = apply(o.name, value, out.options); !error.empty()) {
      diags.report(frontend::DiagId::BadOptimization, o.range, error);
      out.ok = false;
    }
  }
  for (const auto& o : overrides)
    if (auto error = apply(o.name, from_text(o.value), out.options); !error.empty()) {
      out.errors.push_back("--option " + o.name + ": " + error);
      out.ok = false;
    }
  return out;
}

}  // namespace mo::tools
