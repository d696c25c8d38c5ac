// The class every generated model defines; see printer.hpp. It is the same
// text for all models: sizes, tables and section_<i>() functions printed
// before it differ. Kept as one piece so that it reads like hand-written code.
#include "printer.hpp"

namespace mo::codegen::detail {

const char* const model_class = R"(
const mo::runtime::ModelInfo& model_info() {
  static const mo::runtime::ModelInfo info = build_info();
  return info;
}

const std::array<mo::runtime::Sparsity, 7>& sparsities() {
  static const std::array<mo::runtime::Sparsity, 7> patterns = [] {
    std::array<mo::runtime::Sparsity, 7> s;
    for (std::size_t k = 0; k < 7; ++k) {
      const JacobianTables& j = jacobian_tables[k];
      s[k].rows = j.rows;
      s[k].cols = j.cols;
      s[k].col_start.assign(j.col_start, j.col_start + j.cols + 1);
      s[k].row_index.assign(j.row_index, j.row_index + j.col_start[j.cols]);
    }
    return s;
  }();
  return patterns;
}

const std::array<mo::runtime::Sparsity, 2>& hessian_sparsities() {
  static const std::array<mo::runtime::Sparsity, 2> patterns = [] {
    std::array<mo::runtime::Sparsity, 2> s;
    for (std::size_t k = 0; k < 2; ++k) {
      const HessianTables& h = hessian_tables[k];
      s[k].rows = s[k].cols = h.n;
      s[k].col_start.assign(h.col_start, h.col_start + h.n + 1);
      s[k].row_index.assign(h.row_index, h.row_index + h.col_start[h.n]);
    }
    return s;
  }();
  return patterns;
}

class GeneratedModel final : public mo::runtime::Model {
public:
  GeneratedModel() : w_(num_slots, 0.0), cross_(ng, 0), reversed_(ng, 0), relations_(ng, 0),
                     before_(nwhen, 0.0), now_(nwhen, 0.0), fired_(nwhen, 0), init_fired_(nwhen, 0), fired_count_(nwhen, 0),
                     sample_start_(nsample, 0.0), sample_interval_(nsample, 1.0),
                     tick_done_(nsample), tick_raised_(nsample) {
    reset();
  }

  const mo::runtime::ModelInfo& info() const override { return model_info(); }
  std::unique_ptr<mo::runtime::Model> clone() const override {
    return std::make_unique<GeneratedModel>(*this);
  }

  using mo::runtime::Model::initial_state;
  void initial_state(double t0, std::span<const double> u0, std::span<const double> p,
                     std::span<double> x0) override {
    reset();
    load_initial(t0, u0, p);
    section_starts();
    for (std::size_t i = 0; i < nx; ++i) x0[i] = w_[static_cast<std::size_t>(start_slots[i])];
    load_samples(x0);
    if (ndelay > 0) start_delays(t0, u0, p, x0);
    if (initial_flag >= 0 || any_every_event()) initial_event(t0, p, x0);
    if (nsample > 0) sample_event_at_start(t0, p, x0);
    if (ndelay > 0) record_delays(t0, x0, u0, p, {});
  }

  void rhs(double t, std::span<const double> x, std::span<const double> u,
           std::span<const double> p, std::span<double> xdot) override {
    load(t, x, u, p);
    section_steps();
    for (std::size_t i = 0; i < nx; ++i) xdot[i] = w_[static_cast<std::size_t>(derivative_slots[i])];
  }

  void outputs(double t, std::span<const double> x, std::span<const double> u,
               std::span<const double> p, std::span<double> y) override {
    load(t, x, u, p);
    section_steps();
    section_outputs();
    for (std::size_t i = 0; i < ny; ++i) y[i] = w_[static_cast<std::size_t>(output_slots[i])];
  }

  const mo::runtime::Sparsity& jacobian_sparsity(mo::runtime::Jacobian block) const override {
    return sparsities()[index(block)];
  }

  // Values by Jacobian-vector products: the seeds of one colour's columns
  // are 1, the product section runs, and each entry is read from its slot.
  void jacobian_values(mo::runtime::Jacobian block, double t, std::span<const double> x,
                       std::span<const double> u, std::span<const double> p,
                       std::span<double> values) override {
    const JacobianTables& j = jacobian_tables[index(block)];
    if (block == mo::runtime::Jacobian::x0_p)
      load_initial(t, u, p);  // start values depend on p at the initial point (t0, u0)
    else
      load(t, x, u, p);
    double* w = w_.data();
    for (std::size_t k = 0; k < j.num_base; ++k) j.base[k](w, nullptr, ws_);
    for (std::size_t c = 0; c < j.colours; ++c) {
      for (int k = j.colour_start[c]; k < j.colour_start[c + 1]; ++k) w[j.seeds[k]] = 1.0;
      for (std::size_t k = 0; k < j.num_product; ++k) j.product[k](w, nullptr, ws_);
      for (int e = j.entry_start[c]; e < j.entry_start[c + 1]; ++e)
        values[static_cast<std::size_t>(j.entry_index[e])] = w[j.entry_slot[e]];
      for (int k = j.colour_start[c]; k < j.colour_start[c + 1]; ++k) w[j.seeds[k]] = 0.0;
    }
  }

  bool provides_hessian(mo::runtime::Hessian) const override { return true; }
  const mo::runtime::Sparsity& hessian_sparsity(mo::runtime::Hessian which) const override {
    return hessian_sparsities()[static_cast<std::size_t>(which)];
  }

  // Values by second directional derivatives: σ seeds one colour, τ another
  // (or the same); each row's second derivative is then one entry of that
  // row's Hessian, added with its weight. Only the entries of wanted columns
  // are computed, by products over those columns coloured again (G::plan_hessian);
  // the others stay 0.
  void hessian_values(mo::runtime::Hessian which, double t, std::span<const double> x,
                      std::span<const double> u, std::span<const double> p,
                      std::span<const double> weights, std::span<double> values) override {
    hessian_values_for({}, which, t, x, u, p, weights, values);
  }
  void hessian_values_for(std::span<const std::uint8_t> columns, mo::runtime::Hessian which, double t,
                          std::span<const double> x, std::span<const double> u,
                          std::span<const double> p, std::span<const double> weights,
                          std::span<double> values) override {
    const std::size_t index = static_cast<std::size_t>(which);
    const HessianTables& h = hessian_tables[index];
    const G::HessianPlan& plan = hessian_plan(index, columns);
    load(t, x, u, p);
    double* w = w_.data();
    std::fill(values.begin(), values.begin() + h.col_start[h.n], 0.0);
    for (std::size_t k = 0; k < h.num_base; ++k) h.base[k](w, nullptr, ws_);
    auto seed = [&](std::size_t first, int colour, double value) {
      const auto k = static_cast<std::size_t>(colour);
      for (int c = plan.colour_start[k]; c < plan.colour_start[k + 1]; ++c)
        w[first + static_cast<std::size_t>(plan.colour_columns[static_cast<std::size_t>(c)])] = value;
    };
    int sigma = -1;  // products come by σ colour: the σ sections run once per colour
    for (std::size_t q = 0; q < plan.products(); ++q) {
      if (plan.sigma[q] != sigma) {
        if (sigma >= 0) seed(sigma_slot, sigma, 0.0);
        sigma = plan.sigma[q];
        seed(sigma_slot, sigma, 1.0);
        for (std::size_t k = 0; k < h.num_sigma; ++k) h.sigma_sections[k](w, nullptr, ws_);
      }
      seed(tau_slot, plan.tau[q], 1.0);
      for (std::size_t k = 0; k < h.num_product; ++k) h.product[k](w, nullptr, ws_);
      const auto first = static_cast<std::size_t>(plan.entry_start[q]);
      const auto last = static_cast<std::size_t>(plan.entry_start[q + 1]);
      for (std::size_t e = first; e < last; ++e)
        values[static_cast<std::size_t>(plan.entry_index[e])] +=
            weights[static_cast<std::size_t>(plan.entry_weight[e])] * w[plan.entry_slot[e]];
      seed(tau_slot, plan.tau[q], 0.0);
    }
    if (sigma >= 0) seed(sigma_slot, sigma, 0.0);
  }

  void event_indicators(double t, std::span<const double> x, std::span<const double> u,
                        std::span<const double> p, std::span<double> g) override {
    load(t, x, u, p);
    ws_.follow_time = false;
    section_steps();
    ws_.follow_time = true;
    run(section_index_crossings, nullptr);
    for (std::size_t i = 0; i < ng; ++i) g[i] = w_[static_cast<std::size_t>(crossing_slots[i])];
  }

  // The next tick start + k*interval of any sample() strictly after t (one
  // within rounding of t counts as reached), each computed from its k.
  double next_time_event(double t) const override {
    double next = std::numeric_limits<double>::infinity();
    const double tolerance = 8 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
    for (std::size_t i = 0; i < nsample; ++i) {
      const double s = sample_start_[i], h = sample_interval_[i];
      double k = std::max(0.0, std::floor((t - s) / h));
      while (k > 0.0 && s + (k - 1.0) * h > t + tolerance) k -= 1.0;  // floor rounded up
      while (s + k * h <= t + tolerance) k += 1.0;
      next = std::min(next, s + k * h);
    }
    if (ndelay > 0) next = std::min(next, ws_.delays.next_event(t));  // a delayed jump arrives
    return next;
  }

  // The delayed expressions at (t, x, u) into the history: the steps, then
  // the delay_arguments section. An empty u is all 0 (as at initial_state).
  bool record_delays(double t, std::span<const double> x, std::span<const double> u,
                     std::span<const double> p, std::span<const int> relations_from) override {
    if (ndelay == 0) return false;
    load(t, x, u, p);
    if (u.empty()) std::fill(w_.begin() + u_slot, w_.begin() + u_slot + nu, 0.0);
    if (!relations_from.empty() && event_rhs_section >= 0) {
      set_relations(relations_from);
      run(event_rhs_section, relations_.data());
    } else {
      section_steps();
    }
    run(delay_arguments_section, nullptr);
    bool jumped = false;  // a delayed value of the model itself (not a sensitivity) jumped
    for (std::size_t k = 0; k < ndelay; ++k)
      jumped = (ws_.delays.record(k, t, w_[static_cast<std::size_t>(delay_argument_slot[k])]) &&
                delay_of_sensitivities[k] == 0) || jumped;
    return jumped;
  }
  double shortest_delay() const override { return ws_.delays.shortest(); }

  // pre(d) := d; a when-clause fires if its condition is true now and was
  // false just before (an every-event clause at every call, so that each
  // event iteration solves the discrete equations again). Relations on
  // indicators take their value from the crossing direction (remembered
  // through the event iteration at one instant); the value before comes from
  // the opposite direction, or from the previous handler call at the same
  // instant.
  mo::runtime::EventResponse handle_event(const mo::runtime::EventCause& cause,
                                          std::span<double> x, std::span<const double> u,
                                          std::span<const double> p) override {
    ws_.delays.at_event(cause.t);
    load(cause.t, x, u, p);
    if (initialising_) set_initial(0.0);  // the conditions just before initialisation
    section_steps();
    for (std::size_t k = 0; k < npre; ++k)
      w_[static_cast<std::size_t>(pre_to[k])] = w_[static_cast<std::size_t>(pre_from[k])];
    bool fresh = false;
    for (std::size_t i = 0; i < ng && i < cause.crossings.size(); ++i) fresh = fresh || cause.crossings[i] != 0;
    if (fresh) {
      for (std::size_t i = 0; i < ng; ++i) cross_[i] = i < cause.crossings.size() ? cause.crossings[i] : 0;
    } else if (!(cause.t == event_time_)) {
      std::fill(cross_.begin(), cross_.end(), 0);
    }
    if (fresh || !(cause.t == event_time_) || initialising_) {
      for (std::size_t i = 0; i < ng; ++i) reversed_[i] = -cross_[i];
      // The values before the crossing come from the steps too: a condition
      // on a variable that a relation defines (the MSL's hard stop,
      // `stopped = if s <= smin then -1 else 0; when stopped <> 0 then`)
      // sees that relation as before the crossing (the state is past it).
      // An indicator that only left a held 0 keeps the steps' values (its
      // relations were at their value at 0 before, not at the other side).
      if (fresh) {
        for (std::size_t i = 0; i < ng; ++i) relations_[i] = std::abs(cross_[i]) == 1 ? -cross_[i] : 0;
        run(event_rhs_section, relations_.data());
      }
      if (!initialising_) conditions(reversed_.data(), before_);  // at initialisation: below
      if (fresh) section_steps();
    } else {
      before_ = now_;
    }
    event_time_ = cause.t;
    if (initialising_) {
      set_initial(1.0);
      section_steps();
    } else if (raise_samples(cause.t)) {
      section_steps();
    }
    // The discrete equations outside when-clauses belong to this iteration's
    // system, so a when-condition sees their new values: `when edge(off)`
    // with `off = not control` fires in the iteration where off changes
    // (the next one has pre(off) = off, and the edge would be lost).
    solve_mixed();
    // At initialisation the value before is always the condition with
    // initial() at 0 and the values of this iteration: only a clause that
    // initial() enables fires there (Modelica 3 §8.6), at most once.
    if (initialising_) {
      set_initial(0.0);
      section_steps();
      conditions(reversed_.data(), before_);
      set_initial(1.0);
      section_steps();
    }
    conditions(cross_.data(), now_);
    mo::runtime::EventResponse response;
    double* w = w_.data();
    std::fill(fired_.begin(), fired_.end(), 0);
    // A condition may read what another clause assigns at this instant (the
    // MSL's RadioButtonSource: `when change(table.y)` beside the table's own
    // clause): after each clause fires, the discrete equations and the
    // conditions again, and the clauses not fired yet once more, each at
    // most once. (In the next iteration pre(y) = y and change(y) is lost.)
    for (bool again = true; again;) {
      again = false;
      for (std::size_t k = 0; k < nwhen; ++k) {
        if (fired_[k] || when_every_event[k] || !activated(k)) continue;
        if (earlier_branch_activated(k)) continue;
        if (initialising_) {
          if (init_fired_[k] != 0) continue;
          init_fired_[k] = 1;
        }
        fired_[k] = 1;
        ++fired_count_[k];
        const bool changed = fire(k);
        if (when_terminate[k]) {  // terminate(): the run ends after this event
          response.terminate = true;
          response.message = when_terminate[k];
        }
        for (int r = when_reinit_start[k]; r < when_reinit_start[k + 1]; ++r) {
          x[static_cast<std::size_t>(when_reinit_state[r])] = w[when_reinit_value[r]];
          response.states_reinit = true;
        }
        if (!changed) continue;
        // The discrete equations outside when-clauses are solved with the
        // steps of what the clause assigned (a timer's entry time read by
        // `fire = time - entryTime > ...`). Without such equations the
        // conditions keep the steps this call started from (as Scilab does:
        // Coselica's friction modes in the Xcos corpus).
        if (any_every_event()) section_steps();
        solve_mixed();
        conditions(cross_.data(), now_);
        again = true;
      }
    }
    solve_mixed();
    for (std::size_t i = 0; i < nd; ++i)
      response.discrete_changed = response.discrete_changed || w[d_slot + i] != w[pre_d_slot + i];
    // Once the instant settles, sample() is false again: one more iteration
    // at the same instant lets what depends on it (b = sample(...)) settle too.
    if (!response.discrete_changed && samples_raised_) {
      for (std::size_t i = 0; i < nsample; ++i)
        if (!std::isnan(tick_raised_[i])) tick_done_[i] = tick_raised_[i];
      lower_samples();
      response.discrete_changed = true;
    }
    return response;
  }

  bool provides_event_tangents() const override { return event_rhs_section >= 0; }

  void rhs_at_event(double t, std::span<const double> x, std::span<const double> u,
                    std::span<const double> p, std::span<const int> relations_from,
                    std::span<double> xdot) override {
    if (event_rhs_section < 0) return rhs(t, x, u, p, xdot);
    load(t, x, u, p);
    set_relations(relations_from);
    run(event_rhs_section, relations_.data());
    for (std::size_t i = 0; i < nx; ++i) xdot[i] = w_[static_cast<std::size_t>(derivative_slots[i])];
  }

  void event_indicator_tangent(double t, std::span<const double> x, std::span<const double> u,
                               std::span<const double> p, std::span<const int> relations_from,
                               const mo::runtime::EventTangent& direction, std::span<double> dg) override {
    if (event_rhs_section < 0) return mo::runtime::Model::event_indicator_tangent(t, x, u, p, relations_from, direction, dg);
    load(t, x, u, p);
    set_relations(relations_from);
    run(event_rhs_section, relations_.data());
    seed_event(direction);
    run(event_tangent_section, relations_.data());
    for (std::size_t i = 0; i < ng; ++i) dg[i] = w_[static_cast<std::size_t>(indicator_tangent_slots[i])];
  }

  // The handler, then each direction through the clauses that fired, at the
  // states and discrete variables the handler found (relations as it saw them).
  mo::runtime::EventResponse handle_event_tangent(const mo::runtime::EventCause& cause,
                                                  std::span<double> x, std::span<const double> u,
                                                  std::span<const double> p,
                                                  std::span<mo::runtime::EventTangent> directions,
                                                  std::string& unsupported) override {
    if (event_rhs_section < 0) return mo::runtime::Model::handle_event_tangent(cause, x, u, p, directions, unsupported);
    const std::vector<double> x_before(x.begin(), x.end());
    const mo::runtime::EventResponse response = handle_event(cause, x, u, p);
    const std::vector<double> d_after(w_.begin() + d_slot, w_.begin() + d_slot + nd);
    std::copy(x_before.begin(), x_before.end(), w_.begin() + x_slot);
    for (std::size_t i = 0; i < nd; ++i) w_[d_slot + i] = w_[pre_d_slot + i];
    std::fill(relations_.begin(), relations_.end(), 0);
    run(event_rhs_section, relations_.data());
    for (mo::runtime::EventTangent& dir : directions) when_tangents(fired_, dir, unsupported);
    std::copy(d_after.begin(), d_after.end(), w_.begin() + d_slot);
    return response;
  }

  // δτ of the sample() ticks at t: δstart + k·δinterval, the same for every
  // sample that ticks there (else NaN); 0 without a tick.
  double time_event_tangent(double t, std::span<const double> x, std::span<const double> u,
                            std::span<const double> p, const mo::runtime::EventTangent& direction) override {
    if (event_rhs_section < 0) return 0.0;
    bool any = false;
    for (std::size_t i = 0; i < nsample; ++i) any = any || sample_tick(i, t);
    if (!any) return 0.0;
    load(t, x, u, p);
    std::fill(relations_.begin(), relations_.end(), 0);
    run(event_rhs_section, relations_.data());
    seed_event(direction);
    run(event_tangent_section, relations_.data());
    double tau = 0.0;
    bool first = true;
    for (std::size_t i = 0; i < nsample; ++i) {
      double k = 0.0;
      if (!sample_tick(i, t, &k)) continue;
      const double d = w_[static_cast<std::size_t>(sample_start_tangent_slots[i])] +
                       k * w_[static_cast<std::size_t>(sample_interval_tangent_slots[i])];
      if (!first && d != tau) return std::numeric_limits<double>::quiet_NaN();
      tau = d;
      first = false;
    }
    return tau;
  }

  // The clauses that fired at initialisation, at the state initial_state()
  // left (initial() false again, relations as they are).
  void initial_event_tangent(double t0, std::span<const double> x, std::span<const double> u,
                             std::span<const double> p, std::span<mo::runtime::EventTangent> directions,
                             std::string& unsupported) override {
    if (event_rhs_section < 0 || std::find(init_fired_.begin(), init_fired_.end(), 1) == init_fired_.end()) return;
    load(t0, x, u, p);
    std::fill(relations_.begin(), relations_.end(), 0);
    run(event_rhs_section, relations_.data());
    for (mo::runtime::EventTangent& dir : directions) when_tangents(init_fired_, dir, unsupported);
  }

  std::span<double> discrete() override { return {w_.data() + d_slot, nd}; }
  std::vector<int> take_fired_counts() override {
    std::vector<int> out(fired_count_.begin(), fired_count_.end());
    std::fill(fired_count_.begin(), fired_count_.end(), 0);
    return out;
  }
  std::string last_failure() const override { return ws_.failure; }
  std::vector<std::string> notes() const override { return mo::runtime::generated::singular_notes(ws_); }

private:
  static std::size_t index(mo::runtime::Jacobian block) { return static_cast<std::size_t>(block); }

  /// Discrete variables, pre() values and Newton guesses to their starts;
  /// no delay history.
  void reset() {
    ws_.delays.reset(ndelay);
    ws_.singular.clear();
    reset_discrete();
    for (std::size_t i = 0; i < nnewton; ++i) w_[static_cast<std::size_t>(newton_slots[i])] = newton_start[i];
    event_time_ = std::numeric_limits<double>::quiet_NaN();
    std::fill(tick_done_.begin(), tick_done_.end(), std::numeric_limits<double>::quiet_NaN());
    lower_samples();
    std::fill(fired_count_.begin(), fired_count_.end(), 0);
  }
  /// Whether clause k's condition became true at this call.
  bool activated(std::size_t k) const { return now_[k] != 0.0 && before_[k] == 0.0; }
  /// `when a then ... elsewhen b then ...`: clause k of branch b does not
  /// fire at an instant where a clause of an earlier branch of its
  /// when-equation is activated or has fired.
  bool earlier_branch_activated(std::size_t k) const {
    if (when_group[k] < 0 || when_branch[k] == 0) return false;
    for (std::size_t i = 0; i < nwhen; ++i)
      if (when_group[i] == when_group[k] && when_branch[i] < when_branch[k] && (fired_[i] || activated(i)))
        return true;
    return false;
  }

  // Discrete equations outside when-clauses hold at initialisation too (the
  // MSL's OnOffController: y = u < reference - bandwidth/2 or pre(y) and …
  // with pre(y) = false is true at t0 if u starts low).
  static bool any_every_event() {
    for (std::size_t k = 0; k < nwhen; ++k)
      if (when_every_event[k]) return true;
    return false;
  }
  // The event at initialisation (t0, the inputs initial_state loaded):
  // initial() is 1 and was 0 just before, so the clauses on it fire (in
  // order, each seeing what the earlier ones assigned), then event iteration
  // while discrete values change.
  void initial_event(double t0, std::span<const double> p, std::span<double> x0) {
    std::fill(init_fired_.begin(), init_fired_.end(), 0);
    initialising_ = true;
    event_time_ = std::numeric_limits<double>::quiet_NaN();
    const mo::runtime::EventCause cause{t0, {}, false};
    for (int iteration = 0; iteration < 100; ++iteration)
      if (!handle_event(cause, x0, {}, p).discrete_changed) break;
    initialising_ = false;
    set_initial(0.0);
    // Then, before the integration starts, the event iteration with initial()
    // false again, so that what initial() set outside when-clauses settles
    // (the MSL friction's `startForward = initial() and w_relfric > 0 or …`
    // is false at t = 0 in the MSL's reference results; left true, the
    // integration would start with the breakaway friction). A clause on
    // initial() does not fire again: its condition only falls.
    event_time_ = std::numeric_limits<double>::quiet_NaN();
    const mo::runtime::EventCause after{t0, {}, false};
    for (int iteration = 0; iteration < 100; ++iteration)
      if (!handle_event(after, x0, {}, p).discrete_changed) break;
    event_time_ = std::numeric_limits<double>::quiet_NaN();
  }
  // start and interval of every sample() at the parameters initial_state
  // loaded and the start x0 (a start may read a parameter that the initial
  // equations compute: a state whose derivative is 0).
  void load_samples(std::span<const double> x0) {
    if (nsample == 0) return;
    std::copy(x0.begin(), x0.end(), w_.begin() + x_slot);
    run(samples_section, nullptr);
    for (std::size_t i = 0; i < nsample; ++i) {
      sample_start_[i] = w_[static_cast<std::size_t>(sample_start_slot[i])];
      sample_interval_[i] = w_[static_cast<std::size_t>(sample_interval_slot[i])];
    }
  }
  // delay(e, T, Tmax) at the start: T and Tmax from the parameters (and x0),
  // and e(t0), which the delays read until the first record (MLS 3.7.2.4).
  // e may read a delay (a transmission line's two ends): a fixed-point
  // iteration from 0, a few passes.
  void start_delays(double t0, std::span<const double> u0, std::span<const double> p,
                    std::span<const double> x0) {
    std::copy(x0.begin(), x0.end(), w_.begin() + x_slot);
    run(delay_times_section, nullptr);
    for (std::size_t k = 0; k < ndelay; ++k) {
      const double max = w_[static_cast<std::size_t>(delay_max_slot[k])];
      if (delay_varying[k] != 0)  // its delay time at t0 comes from the steps below
        ws_.delays.set_varying(k, 0.0, max);
      else
        ws_.delays.set_times(k, w_[static_cast<std::size_t>(delay_time_slot[k])], max);
    }
    for (int pass = 0; pass < 20; ++pass) {
      load(t0, x0, u0, p);
      if (u0.empty()) std::fill(w_.begin() + u_slot, w_.begin() + u_slot + nu, 0.0);
      section_steps();
      run(delay_arguments_section, nullptr);
      bool moved = false;
      for (std::size_t k = 0; k < ndelay; ++k) {
        if (delay_varying[k] != 0)
          ws_.delays.set_varying(k, w_[static_cast<std::size_t>(delay_time_slot[k])],
                                 w_[static_cast<std::size_t>(delay_max_slot[k])]);
        const double e = w_[static_cast<std::size_t>(delay_argument_slot[k])];
        moved = moved || !(e == ws_.delays.value(k, t0));
        ws_.delays.set_start(k, e);
      }
      if (!moved) break;
    }
  }
  // True if t is start + k*interval (k >= 0) of sample i, within rounding;
  // k in `index`.
  bool sample_tick(std::size_t i, double t, double* index = nullptr) const {
    const double s = sample_start_[i], h = sample_interval_[i];
    if (!(h > 0.0)) return false;
    const double k = std::nearbyint((t - s) / h);
    const double tolerance = 8 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
    if (index) *index = k;
    return k >= 0.0 && std::abs(s + k * h - t) <= tolerance;
  }
  // Sets the flags of the samples that tick at t; true if any does. A tick
  // is handled once: a state event within rounding of it (a converter's
  // zero crossing at a Mean block's tick) is the same instant, not a new tick.
  bool raise_samples(double t) {
    bool& any = samples_raised_;
    for (std::size_t i = 0; i < nsample; ++i) {
      double k = 0.0;
      if (sample_tick(i, t, &k) && !(k == tick_done_[i])) {
        w_[d_slot + static_cast<std::size_t>(sample_flag[i])] = 1.0;
        tick_raised_[i] = k;
        any = true;
      }
    }
    return any;
  }
  void lower_samples() {
    samples_raised_ = false;
    std::fill(tick_raised_.begin(), tick_raised_.end(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t i = 0; i < nsample; ++i)
      w_[d_slot + static_cast<std::size_t>(sample_flag[i])] =
          w_[pre_d_slot + static_cast<std::size_t>(sample_flag[i])] = 0.0;
  }
  // A tick at t0 is an event right after the event at initialisation.
  void sample_event_at_start(double t0, std::span<const double> p, std::span<double> x0) {
    bool tick = false;
    for (std::size_t i = 0; i < nsample; ++i) tick = tick || sample_tick(i, t0);
    if (!tick) return;
    event_time_ = std::numeric_limits<double>::quiet_NaN();
    const mo::runtime::EventCause cause{t0, {}, true};
    for (int iteration = 0; iteration < 100; ++iteration)
      if (!handle_event(cause, x0, {}, p).discrete_changed) break;
    event_time_ = std::numeric_limits<double>::quiet_NaN();
  }
  void set_initial(double v) {
    if (initial_flag < 0) return;  // the model does not read initial()
    const auto i = static_cast<std::size_t>(initial_flag);
    w_[d_slot + i] = w_[pre_d_slot + i] = v;
  }

  void reset_discrete() {
    for (std::size_t i = 0; i < nd; ++i) w_[d_slot + i] = w_[pre_d_slot + i] = discrete_start[i];
  }

  /// load() at the initial point: the inputs u0, or all 0 if u0 is empty.
  void load_initial(double t0, std::span<const double> u0, std::span<const double> p) {
    load(t0, {}, u0, p);
    if (u0.empty()) std::fill(w_.begin() + u_slot, w_.begin() + u_slot + nu, 0.0);
  }

  /// Copies the arguments into their slots; outside events pre(d) = d.
  void load(double t, std::span<const double> x, std::span<const double> u, std::span<const double> p) {
    std::copy(x.begin(), x.end(), w_.begin() + x_slot);
    std::copy(u.begin(), u.end(), w_.begin() + u_slot);
    std::copy(p.begin(), p.end(), w_.begin() + p_slot);
    w_[t_slot] = t;
    for (std::size_t i = 0; i < nd; ++i) w_[pre_d_slot + i] = w_[d_slot + i];
    for (std::size_t k = 0; k < ndelay; ++k)  // a varying delay time: read where the steps compute it
      if (delay_varying[k] == 0) w_[static_cast<std::size_t>(delay_value_slot[k])] = ws_.delays.value(k, t);
    ws_.time = t;
    ws_.failure.clear();
  }

  // Runs when-clause k and makes its assignments; true if one changed a value.
  // Its relations on indicators follow the crossings of this instant.
  bool fire(std::size_t k) {
    double* w = w_.data();
    when_sections[k](w, cross_.data(), ws_);
    bool changed = false;
    for (int a = when_assign_start[k]; a < when_assign_start[k + 1]; ++a) {
      changed = changed || w[when_assign_target[a]] != w[when_assign_value[a]];
      w[when_assign_target[a]] = w[when_assign_value[a]];
    }
    return changed;
  }
  // The every-event clauses with when_before_steps[k] == first, in order.
  bool fire_every_event(bool first) {
    bool changed = false;
    for (std::size_t k = 0; k < nwhen; ++k) {
      if (!when_every_event[k] || (when_before_steps[k] != 0) != first) continue;
      fired_[k] = 1;
      ++fired_count_[k];
      changed = fire(k) || changed;
    }
    return changed;
  }

  // Modelica 3 §8.6: one event iteration solves the discrete equations
  // outside when-clauses (the every-event clauses) together with the
  // continuous ones, pre() held. By fixed-point iteration, each pass: the
  // clauses computed from discrete values alone (when_before_steps), the
  // continuous steps with the values just assigned, the clauses that read
  // the steps; until a pass changes nothing. (The MSL friction: `locked`
  // from pre(mode) and the start flags, `sa` from `locked`, `startForward`
  // from `sa`.) Without a fixed point after a bounded number of passes the
  // last values stand and the handler's event iteration goes on.
  // Expects the steps computed from the current discrete values.
  //
  // A cycle of passes is broken at a tie (the MSL's bearing and gear both
  // stuck: locked, the least-norm split asks more than the bearing's limit,
  // startForward; sliding at its limit with the gear holding, sa is exactly
  // tau0_max and `sa > tau0_max` false, locked again): an indicator at its
  // zero in one pass of the cycle and on one side in the others keeps that
  // side for the rest of the instant, as if it had crossed there (cross_), a
  // hysteresis at the relation's zero; then the passes go on.
  void solve_mixed() {
    mixed_passes_.clear();
    for (std::size_t pass = 0; pass < 2 * nd + 8; ++pass) {
      bool changed = fire_every_event(true);
      if (changed) section_steps();
      if (ng > 0 && pass > 0) {  // most calls settle in their first pass: nothing to record
        const std::size_t first = record_mixed_pass();
        if (first + 1 < mixed_passes_.size() && hold_ties(first)) mixed_passes_.clear();
      }
      changed = fire_every_event(false) || changed;
      if (!changed) return;
      section_steps();
    }
  }
  // Appends this pass's discrete values and indicators (the ones the clauses
  // computed from the steps will read); returns the last earlier pass with
  // the same discrete values (the start of a cycle), else the new one's index.
  std::size_t record_mixed_pass() {
    run(section_index_crossings, nullptr);
    MixedPass now;
    now.discrete.assign(w_.begin() + d_slot, w_.begin() + d_slot + nd);
    now.indicators.resize(ng);
    for (std::size_t i = 0; i < ng; ++i) now.indicators[i] = w_[static_cast<std::size_t>(crossing_slots[i])];
    std::size_t first = mixed_passes_.size();
    for (std::size_t k = 0; k < mixed_passes_.size(); ++k)
      if (mixed_passes_[k].discrete == now.discrete) first = k;
    mixed_passes_.push_back(std::move(now));
    return first;
  }
  // Holds the indicators at a tie in the cycle of passes first.. (at zero,
  // within 1e-9 of their largest value in it, in one pass; on one side in the
  // others). True if it held any.
  bool hold_ties(std::size_t first) {
    bool held = false;
    for (std::size_t i = 0; i < ng; ++i) {
      if (cross_[i] != 0) continue;
      double scale = 1.0;
      for (std::size_t k = first; k < mixed_passes_.size(); ++k)
        scale = std::max(scale, std::abs(mixed_passes_[k].indicators[i]));
      int side = 0;
      bool tie = false, both = false;
      for (std::size_t k = first; k < mixed_passes_.size(); ++k) {
        const double g = mixed_passes_[k].indicators[i];
        if (std::abs(g) <= 1e-9 * scale) {
          tie = true;
        } else {
          const int s = g > 0 ? 1 : -1;
          both = both || (side != 0 && s != side);
          side = s;
        }
      }
      if (!tie || both || side == 0) continue;
      cross_[i] = side;
      held = true;
    }
    return held;
  }

  void run(int section, const int* cross) {
    if (section >= 0) all_sections[section](w_.data(), cross, ws_);
  }
  void section_steps() { run(section_index_steps, nullptr); }
  void section_outputs() { run(section_index_outputs, nullptr); }
  void section_starts() { run(section_index_starts, nullptr); }
  void conditions(const int* cross, std::vector<double>& values) {
    run(section_index_conditions, cross);
    for (std::size_t k = 0; k < nwhen; ++k) values[k] = w_[static_cast<std::size_t>(condition_slots[k])];
  }

  void set_relations(std::span<const int> from) {
    for (std::size_t i = 0; i < ng; ++i) relations_[i] = i < from.size() ? from[i] : 0;
  }
  void seed_event(const mo::runtime::EventTangent& dir) {
    for (std::size_t i = 0; i < nx; ++i) w_[static_cast<std::size_t>(event_seed_x[i])] = dir.x[i];
    for (std::size_t i = 0; i < nu; ++i) w_[static_cast<std::size_t>(event_seed_u[i])] = dir.u.empty() ? 0.0 : dir.u[i];
    for (std::size_t i = 0; i < np; ++i) w_[static_cast<std::size_t>(event_seed_p[i])] = dir.p[i];
    for (std::size_t i = 0; i < nd; ++i)
      if (event_seed_d[i] >= 0) w_[static_cast<std::size_t>(event_seed_d[i])] = dir.d.empty() ? 0.0 : dir.d[i];
    w_[event_seed_t] = dir.t;
  }
  // One direction through the clauses with fired[k], in order, at the point
  // event_rhs_section computed: a reinit's δx and, for a discrete variable
  // with discrete sensitivities, an assignment's δd take the tangent; any
  // other assignment with a nonzero tangent is named in `unsupported`. Later
  // clauses see δd as it was when the call started (as the replay sees d).
  void when_tangents(const std::vector<char>& fired, mo::runtime::EventTangent& dir, std::string& unsupported) {
    double* w = w_.data();
    seed_event(dir);
    run(event_tangent_section, relations_.data());
    for (std::size_t k = 0; k < nwhen; ++k) {
      if (!fired[k]) continue;
      when_tangent_sections[k](w, relations_.data(), ws_);
      for (int a = when_assign_start[k]; a < when_assign_start[k + 1]; ++a) {
        const std::size_t i = static_cast<std::size_t>(when_assign_target[a]) - d_slot;
        const double value = w[assign_tangent_slots[a]];
        if (event_seed_d[i] >= 0 && !dir.d.empty())
          dir.d[i] = value;
        else if (value != 0.0 && unsupported.empty())
          unsupported = info().discrete[i].name;
      }
      for (int r = when_reinit_start[k]; r < when_reinit_start[k + 1]; ++r)
        dir.x[static_cast<std::size_t>(when_reinit_state[r])] = w[reinit_tangent_slots[r]];
    }
  }

  // The products of Hessian k for the wanted columns of its last call.
  const G::HessianPlan& hessian_plan(std::size_t k, std::span<const std::uint8_t> columns) {
    if (!plan_known_[k] || !std::equal(columns.begin(), columns.end(), plan_columns_[k].begin(),
                                       plan_columns_[k].end())) {
      const HessianTables& h = hessian_tables[k];
      const G::HessianTablesView view{h.n, h.col_start, h.row_index, h.colour_start, h.colour_columns,
                                      h.products, h.sigma, h.tau, h.entry_start, h.entry_weight,
                                      h.entry_slot, h.entry_index};
      plan_columns_[k].assign(columns.begin(), columns.end());
      G::plan_hessian(view, columns, plans_[k]);
      plan_known_[k] = true;
    }
    return plans_[k];
  }

  std::vector<double> w_;
  G::BlockWorkspace ws_;
  std::array<std::vector<std::uint8_t>, 2> plan_columns_;
  std::array<G::HessianPlan, 2> plans_;
  std::array<bool, 2> plan_known_{};
  std::vector<int> cross_, reversed_, relations_;
  struct MixedPass {
    std::vector<double> discrete, indicators;
  };
  std::vector<MixedPass> mixed_passes_;  ///< solve_mixed's passes since the last hold
  std::vector<double> before_, now_;
  std::vector<char> fired_;
  std::vector<char> init_fired_;  ///< clauses fired in the event at initialisation
  std::vector<int> fired_count_;  ///< per clause: firings since take_fired_counts() or reset()
  std::vector<double> sample_start_, sample_interval_;
  std::vector<double> tick_done_;    ///< per sample: the index k of its last handled tick (NaN: none)
  std::vector<double> tick_raised_;  ///< per sample: the tick raised at this instant (NaN: none)
  bool samples_raised_ = false;  ///< some sample() flag is 1 (an instant with ticks is being handled)
  double event_time_ = std::numeric_limits<double>::quiet_NaN();
  bool initialising_ = false;
};
)";

}  // namespace mo::codegen::detail
