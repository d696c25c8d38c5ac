// Preferred states the model never differentiates; see preferred_states.hpp.
#include "preferred_states.hpp"

#include <exception>
#include <utility>

#include "index_reduction.hpp"

namespace mo::symbolic::detail {

namespace {

std::size_t at(int i) { return static_cast<std::size_t>(i); }

bool preferred(const DaeVar& v) { return v.state_select == "prefer" || v.state_select == "always"; }

/// Live variables with stateSelect prefer or always, no derivative, and an
/// equation they appear in.
std::vector<int> undifferentiated_preferred(const Dae& dae) {
  std::vector<char> used(dae.vars.size(), 0);
  for (const auto& row : incidence(dae))
    for (int v : row) used[at(v)] = 1;
  std::vector<int> out;
  for (std::size_t v = 0; v < dae.vars.size(); ++v) {
    const DaeVar& d = dae.vars[v];
    if (used[v] && !d.eliminated && d.derivative == none && preferred(d))
      out.push_back(static_cast<int>(v));
  }
  return out;
}

/// What index reduction changes in a Dae (the arena only grows).
struct Snapshot {
  std::vector<DaeVar> vars;
  std::vector<DaeEq> eqs;
  std::vector<int> var_of_symbol;
};

Snapshot take(const Dae& dae) { return {dae.vars, dae.eqs, dae.var_of_symbol}; }

void restore(Dae& dae, Snapshot s) {
  dae.vars = std::move(s.vars);
  dae.eqs = std::move(s.eqs);
  dae.var_of_symbol = std::move(s.var_of_symbol);
  dae.symbol_prefix += '\x1e';  // the trial's symbols stay in the arena
}

/// Reduces the index with derivatives added for `forced`; nullopt (and the
/// Dae possibly half-changed) if that fails. Reports nothing.
std::optional<std::vector<bool>> trial(Dae& dae, const std::vector<int>& forced) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine quiet(sources);
  try {
    for (int v : forced) dae.derivative_of(v);
    if (!pantelides(dae, quiet)) return std::nullopt;
    return select_states(dae);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace

std::optional<std::vector<bool>> reduce_index(Dae& dae, frontend::DiagnosticEngine& diags) {
  std::vector<int> forced = undifferentiated_preferred(dae);
  // At most twice: all candidates, then those of them the first trial made
  // states (a forced variable that ends as a dummy only adds equations).
  for (int attempt = 0; attempt < 2 && !forced.empty(); ++attempt) {
    Snapshot before = take(dae);
    const auto state = trial(dae, forced);
    std::vector<int> made;
    if (state)
      for (int v : forced)
        if ((*state)[at(v)]) made.push_back(v);
    if (state && made.size() == forced.size()) return state;
    restore(dae, std::move(before));
    forced = std::move(made);
  }
  if (!pantelides(dae, diags)) return std::nullopt;
  return select_states(dae);
}

}  // namespace mo::symbolic::detail
