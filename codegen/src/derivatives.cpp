// Jacobian-vector products and Jacobian structure; see derivatives.hpp.
#include "derivatives.hpp"

#include <algorithm>
#include <string>
#include <unordered_map>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::codegen::detail {

using symbolic::Expr;
using symbolic::ExprArena;
using symbolic::SymbolRole;

namespace {

/// A symbol name not yet used in the arena, built from `base`.
std::string unused_name(const ExprArena& a, const std::string& base) {
  std::string name = base;
  for (int k = 1; a.find_symbol(name); ++k) name = base + "#" + std::to_string(k);
  return name;
}

Expr seed(ExprArena& a, const std::string& kind, std::size_t index) {
  const std::string name = unused_name(a, "$seed." + kind + "[" + std::to_string(index) + "]");
  return a.symbol(name, SymbolRole::Algebraic, static_cast<std::int32_t>(index));
}

using Columns = std::vector<int>;

Columns merge(const Columns& x, const Columns& y) {
  Columns out;
  out.reserve(x.size() + y.size());
  std::set_union(x.begin(), x.end(), y.begin(), y.end(), std::back_inserter(out));
  return out;
}

}  // namespace

Derivatives build_derivatives(symbolic::OdeModel& m) {
  ExprArena& a = m.arena;
  Derivatives d;
  symbolic::ExprMap seeds, parameter_seeds;
  for (std::size_t i = 0; i < m.states.size(); ++i) {
    d.seeds.push_back(seed(a, "x", i));
    seeds[m.states[i].symbol] = d.seeds.back();
  }
  for (std::size_t i = 0; i < m.inputs.size(); ++i) {
    d.seeds.push_back(seed(a, "u", i));
    seeds[m.inputs[i].symbol] = d.seeds.back();
  }
  for (std::size_t i = 0; i < m.parameters.size(); ++i) {
    d.seeds.push_back(seed(a, "p", i));
    seeds[m.parameters[i].symbol] = d.seeds.back();
    parameter_seeds[m.parameters[i].symbol] = d.seeds.back();
  }
  d.directional = symbolic::differentiate_steps(m, seeds, [&](const std::string& v) {
    return unused_name(a, "$jvp(" + v + ")");
  });
  for (const auto& x : m.states) {
    auto it = d.directional.derivative.find(x.derivative);
    d.f_rows.push_back(it == d.directional.derivative.end() ? Expr() : it->second);
  }
  for (const auto& y : m.outputs)
    d.h_rows.push_back(symbolic::derivative_along(m, d.directional, y.value));
  std::vector<Expr> starts;  // one call: each call checks every seed
  for (const auto& x : m.states) starts.push_back(x.start);
  // Through the initial system's blocks: the implicit function theorem.
  d.initial_directional = symbolic::differentiate_steps(
      m, m.initial_steps, parameter_seeds,
      [&](const std::string& v) { return unused_name(a, "$jvp0(" + v + ")"); });
  d.x0_rows = symbolic::forward_derivative(a, starts, d.initial_directional.derivative, false);
  return d;
}

std::vector<std::vector<int>> seed_columns(const ExprArena& a, const std::vector<Expr>& seeds,
                                           const std::vector<const std::vector<symbolic::Step>*>& steps,
                                           const std::vector<Expr>& rows) {
  std::unordered_map<Expr, Columns> deps;
  for (std::size_t k = 0; k < seeds.size(); ++k) deps[seeds[k]] = {static_cast<int>(k)};
  auto columns_of = [&](std::span<const Expr> roots, const std::vector<Expr>& except) {
    Columns out;
    for (Expr leaf : symbolic::leaves(a, roots)) {
      if (std::find(except.begin(), except.end(), leaf) != except.end()) continue;
      if (auto it = deps.find(leaf); it != deps.end()) out = merge(out, it->second);
    }
    return out;
  };
  for (const auto* list : steps)
    for (const symbolic::Step& s : *list) {
      if (const auto* as = std::get_if<symbolic::Assignment>(&s)) {
        deps[as->target] = columns_of(std::span(&as->value, 1), {});
        continue;
      }
      const auto& b = std::get<symbolic::EquationBlock>(s);
      const Columns c = columns_of(b.residuals, b.unknowns);
      for (Expr z : b.unknowns) deps[z] = c;
    }
  std::vector<Columns> out;
  out.reserve(rows.size());
  for (Expr r : rows) out.push_back(r.valid() ? columns_of(std::span(&r, 1), {}) : Columns{});
  return out;
}

std::vector<std::vector<int>> row_columns(const ExprArena& a, const Derivatives& d,
                                          const std::vector<Expr>& rows) {
  return seed_columns(a, d.seeds, {&d.directional.steps}, rows);
}

SecondDerivatives build_second_derivatives(symbolic::OdeModel& m, const Derivatives& first) {
  ExprArena& a = m.arena;
  SecondDerivatives d;
  symbolic::ExprMap seeds;
  for (std::size_t i = 0; i < m.states.size(); ++i) {
    d.seeds.push_back(seed(a, "x2", i));
    seeds[m.states[i].symbol] = d.seeds.back();
  }
  for (std::size_t i = 0; i < m.inputs.size(); ++i) {
    d.seeds.push_back(seed(a, "u2", i));
    seeds[m.inputs[i].symbol] = d.seeds.back();
  }
  for (std::size_t i = 0; i < m.parameters.size(); ++i) {
    d.seeds.push_back(seed(a, "p2", i));
    seeds[m.parameters[i].symbol] = d.seeds.back();
  }
  // The model extended by the first-order steps and symbols, differentiated
  // along τ; the σ seeds are leaves with derivative 0. Restored afterwards.
  std::vector<symbolic::Step> base_steps = m.steps;
  const std::size_t base_algebraics = m.algebraics.size();
  m.steps.insert(m.steps.end(), first.directional.steps.begin(), first.directional.steps.end());
  m.algebraics.insert(m.algebraics.end(), first.directional.symbols.begin(),
                      first.directional.symbols.end());
  try {
    d.directional = symbolic::differentiate_steps(m, seeds, [&](const std::string& v) {
      return unused_name(a, "$hvp(" + v + ")");
    });
  } catch (...) {
    m.steps = std::move(base_steps);
    m.algebraics.resize(base_algebraics);
    throw;
  }
  m.steps = std::move(base_steps);
  m.algebraics.resize(base_algebraics);
  auto second = [&](const std::vector<Expr>& rows) {
    std::vector<Expr> present;
    for (Expr r : rows)
      if (r.valid()) present.push_back(r);
    const std::vector<Expr> derived =  // one call for all rows: linear in model size
        symbolic::forward_derivative(a, present, d.directional.derivative, false);
    std::vector<Expr> out;
    std::size_t k = 0;
    for (Expr r : rows) {
      Expr e;
      if (r.valid()) {
        e = derived[k++];
        if (a.is_constant(e, 0.0)) e = Expr();
      }
      out.push_back(e);
    }
    return out;
  };
  d.f_rows = second(first.f_rows);
  d.h_rows = second(first.h_rows);
  return d;
}

void pattern_and_colouring(const std::vector<std::vector<int>>& rows, int first, int count,
                           JacobianCode& code) {
  code.rows = static_cast<int>(rows.size());
  code.cols = count;
  std::vector<std::vector<int>> col_rows(static_cast<std::size_t>(count));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (int c : rows[r])
      if (c >= first && c < first + count) col_rows[static_cast<std::size_t>(c - first)].push_back(static_cast<int>(r));
  code.col_start.assign(1, 0);
  code.row_index.clear();
  for (const auto& rs : col_rows) {
    code.row_index.insert(code.row_index.end(), rs.begin(), rs.end());
    code.col_start.push_back(static_cast<int>(code.row_index.size()));
  }
  // Greedy colouring: a column takes the smallest colour no column sharing a row has.
  std::vector<std::vector<int>> row_cols(rows.size());
  for (int c = 0; c < count; ++c)
    for (int r : col_rows[static_cast<std::size_t>(c)]) row_cols[static_cast<std::size_t>(r)].push_back(c);
  std::vector<int> colour(static_cast<std::size_t>(count), -1);
  std::vector<int> forbidden;  // forbidden[k] == c: colour k is taken by a neighbour of c
  code.colours.clear();
  for (int c = 0; c < count; ++c) {
    const auto& rs = col_rows[static_cast<std::size_t>(c)];
    if (rs.empty()) continue;  // structurally zero column: never seeded
    for (int r : rs)
      for (int k : row_cols[static_cast<std::size_t>(r)])
        if (int ck = colour[static_cast<std::size_t>(k)]; ck >= 0) {
          if (forbidden.size() <= static_cast<std::size_t>(ck)) forbidden.resize(static_cast<std::size_t>(ck) + 1, -1);
          forbidden[static_cast<std::size_t>(ck)] = c;
        }
    int chosen = 0;
    while (static_cast<std::size_t>(chosen) < forbidden.size() && forbidden[static_cast<std::size_t>(chosen)] == c) ++chosen;
    colour[static_cast<std::size_t>(c)] = chosen;
    if (code.colours.size() <= static_cast<std::size_t>(chosen)) code.colours.resize(static_cast<std::size_t>(chosen) + 1);
    code.colours[static_cast<std::size_t>(chosen)].push_back(c);
  }
}

}  // namespace mo::codegen::detail
