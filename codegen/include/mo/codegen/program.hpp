// The instruction list that generated C++ is printed from.
//
// Every value of a model evaluation lives in one work array w: a slot per
// variable symbol (states first, then inputs, parameters, time, discrete
// variables, pre(discrete), Jacobian seeds) and a slot per expression node
// that some section computes. A section is straight-line code in the order
// of the model's steps, each distinct node computed once (common
// subexpressions for free), with equation-block solves in between:
//
//   Node    w[slot(e)] = kind(w[operand slots] or constants)
//   Copy    w[slot]    = w[slot(e)] or the constant e
//   Solve   linear block J z = -c, or Newton on 0 = r(z) (inner section)
//
// Jacobian blocks are values of one Jacobian-vector product section run once
// per colour of a column colouring (CPR), all chosen at generation time.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "mo/symbolic/ode.hpp"

namespace mo::codegen {

using Slot = std::uint32_t;
/// Program::node_slots entry of a node without a slot.
inline constexpr Slot no_slot = 0xFFFFFFFFu;

/// One instruction of a section.
struct Instruction {
  enum class Op : std::uint8_t {
    Node,            ///< w[slot] = node's operation on its operands
    Copy,            ///< w[slot] = value of `node` (a constant, leaf or computed node)
    LinearSolve,     ///< solve Program::blocks[block]
    NonlinearSolve,  ///< Newton on Program::blocks[block]
    /// w[slot] = delay line `block` read at its delay time `node`'s operand 1
    /// (a delay() whose delay time varies: DelayCode::varying)
    Delay,
  };
  Op op = Op::Node;
  symbolic::Expr node;    ///< Node: what to compute; Copy: the value
  Slot slot = 0;          ///< Node, Copy: the slot written
  std::int32_t block = -1;  ///< Solve: block index
  /// Node of a relation on an event indicator: its index; the value then comes
  /// from the crossing direction cross[crossing] when that is nonzero.
  std::int32_t crossing = -1;
  double value_if_down = 0.0;  ///< the relation's value when g crossed downwards
};

/// Straight-line code with block solves.
struct Section {
  std::string name;                 ///< identifier part, e.g. "steps"
  std::vector<Instruction> code;    ///< in order
  bool uses_crossings = false;      ///< reads cross[] (event condition sections)
};

/// An equation block as slots.
struct BlockCode {
  bool linear = true;
  std::vector<Slot> unknowns;   ///< z
  std::vector<Slot> values;     ///< linear: offsets c; nonlinear: residuals r
  struct Entry {
    int row;
    int col;
    Slot slot;
  };
  std::vector<Entry> entries;   ///< Jacobian entries
  int inner_section = -1;       ///< nonlinear: computes values and entries from z
  std::vector<double> start;    ///< nonlinear: first guess of z
  std::vector<double> nominal;  ///< nonlinear: scale of each z (the variable's nominal)
  std::vector<double> lower;    ///< nonlinear: min of each z (-inf if none)
  std::vector<double> upper;    ///< nonlinear: max of each z (+inf if none)
  std::string description;      ///< for failure messages (model text, escape when printing)
};

/// One Jacobian block: pattern, colouring and where its values appear.
struct JacobianCode {
  int rows = 0;
  int cols = 0;
  std::vector<int> col_start;  ///< CSC, size cols + 1
  std::vector<int> row_index;  ///< CSC rows, ascending per column
  std::vector<Slot> entry_slot;  ///< per entry: slot holding it after its colour's product
  std::vector<Slot> seed_slot;   ///< per column: the seed slot set to 1 for it
  std::vector<std::vector<int>> colours;  ///< columns seeded together
  std::vector<int> base_sections;    ///< run once before the products
  std::vector<int> product_sections;  ///< run once per colour
};

/// One Hessian ∇²_z(λᵀf) or ∇²_z(μᵀh), lower triangle, z = (x, u, p).
/// Values come from second directional derivatives D²f_i[σ, τ] with σ and τ
/// the sums of the unit vectors of two colours A ≤ B of a column colouring in
/// which no row's second-order columns share a colour: each row's value is
/// then one tensor entry T_i(a, b), accumulated with weight λ_i.
struct HessianCode {
  int n = 0;                   ///< nx + nu + np
  std::vector<int> col_start;  ///< CSC of the lower triangle, size n + 1
  std::vector<int> row_index;  ///< ascending per column
  std::vector<std::vector<int>> colours;  ///< columns of z seeded together
  struct Entry {
    int weight;  ///< row i: multiplier λ_i (μ_i)
    Slot slot;   ///< slot of D² row i after the product sections
    int index;   ///< Hessian entry the value is added to
  };
  struct Product {
    int sigma_colour, tau_colour;  ///< colours seeded in σ and in τ
    std::vector<Entry> entries;
  };
  std::vector<Product> products;     ///< one product run each, by σ colour
  std::vector<int> base_sections;    ///< run once
  std::vector<int> sigma_sections;   ///< run when σ's colour changes (they read σ only)
  std::vector<int> product_sections;  ///< run per product
};

/// A when-clause as slots.
struct WhenCode {
  int section = -1;  ///< computes the values of assignments and reinits
  bool every_event = false;  ///< fires at every handler call (WhenClause::every_event)
  /// every_event only: evaluated before the continuous steps in each pass of
  /// the event iteration (symbolic::every_event_before_steps)
  bool before_steps = false;
  std::vector<std::pair<Slot, Slot>> assignments;  ///< (discrete slot, value slot)
  std::vector<std::pair<std::size_t, Slot>> reinits;  ///< (state index, value slot)
  bool terminates = false;        ///< terminate(): the run ends when the clause fires
  std::string terminate_message;  ///< its text
  int group = -1;  ///< symbolic::WhenClause::group where prioritised, else -1: the branches a clause yields to
  int branch = 0;  ///< symbolic::WhenClause::branch
};

/// A sample(start, interval) as slots (symbolic::OdeSample): the `samples`
/// section computes start and interval from the parameters.
struct SampleCode {
  int flag = -1;           ///< index of its flag in the discrete variables
  Slot start = 0, interval = 0;
};

/// A delay(e, T, Tmax) (symbolic ExprKind::Delay): load() puts its value,
/// read from the model's history, into `value`; the `delay_times` section
/// computes T and Tmax from the parameters, `delay_arguments` (after the
/// steps) computes e for the history.
struct DelayCode {
  Slot value = 0, argument = 0, time = 0, max = 0;
  /// The delay time varies: `value` is computed where the steps need it
  /// (Instruction::Op::Delay), `time` is the slot of T after the steps, and
  /// delay_times computes only Tmax.
  bool varying = false;
  /// The delayed expression reads forward sensitivities (a delay the
  /// sensitivity equations added): its jumps are the sensitivities'.
  bool of_sensitivities = false;
};

/// Derivatives of the event map (symbolic/event_tangents.hpp) as sections.
/// `rhs` recomputes the steps with every relation on an indicator valued from
/// cross[] (f just before or just after an event); `tangent` then gives the
/// indicators' tangents along the seeds, and whens[k] the tangents of
/// when-clause k's values. Empty (sections -1) for a model without events.
struct EventTangentCode {
  int rhs = -1, tangent = -1;
  std::vector<int> whens;              ///< per when-clause, a section index
  std::vector<Slot> seed_x, seed_u, seed_p;  ///< δx, δu, δp
  Slot seed_t = 0;                     ///< δt
  std::vector<int> seed_d;             ///< δd per discrete variable: its slot, or -1 (held fixed)
  std::vector<Slot> indicator_slots;   ///< δg_k after `tangent`
  std::vector<Slot> assign_slots;      ///< δ(value) per assignment, in WhenCode order
  std::vector<Slot> reinit_slots;      ///< δ(value) per reinit, in WhenCode order
  std::vector<Slot> sample_start_slots, sample_interval_slots;  ///< δstart, δinterval per sample()
};

/// Where the fixed variables live.
struct SlotLayout {
  Slot states = 0, inputs = 0, parameters = 0, time = 0, discrete = 0, pre_discrete = 0;
  Slot seeds_x = 0, seeds_u = 0, seeds_p = 0;
  Slot seeds2 = 0;  ///< second seeds τ (x, u, p), nx + nu + np slots
};

/// The whole model as sections over one work array.
struct Program {
  SlotLayout layout;
  Slot num_slots = 0;
  std::deque<Section> sections;  ///< a deque: references stay valid while sections are added
  std::vector<Slot> node_slots;   ///< slot of each arena node, or no_slot
  std::vector<BlockCode> blocks;

  // Section indices; the printed methods run them in this order:
  //   rhs: steps · outputs: steps, outputs · initial_state: starts ·
  //   event_indicators: steps, crossings · handle_event: steps, conditions, whens.
  int steps = -1, outputs = -1, starts = -1, crossings = -1, conditions = -1;
  std::vector<Slot> derivative_slots;  ///< der(x_i) after steps
  std::vector<Slot> output_slots;      ///< y_j after outputs
  std::vector<Slot> start_slots;       ///< x0_i after starts
  std::vector<Slot> crossing_slots;    ///< g_k after crossings
  std::vector<Slot> condition_slots;   ///< when-condition k after conditions
  std::vector<std::pair<Slot, Slot>> pre_copies;  ///< (pre(v) slot, v slot) of non-discrete v
  std::vector<WhenCode> whens;
  int samples_section = -1;            ///< computes every SampleCode's start and interval (-1: none)
  std::vector<SampleCode> samples;
  int delay_times = -1, delay_arguments = -1;  ///< sections of DelayCode (-1: no delay())
  std::vector<DelayCode> delays;
  std::unordered_map<std::uint32_t, int> delay_lines;  ///< Delay node id → index in `delays`
  EventTangentCode event_tangents;        ///< sensitivities through events
  std::array<JacobianCode, 7> jacobians;  ///< in mo::runtime::Jacobian order
  std::array<HessianCode, 2> hessians;    ///< in mo::runtime::Hessian order (f, h)
  std::vector<double> start_values;       ///< x0 at the default parameters
  std::vector<std::size_t> newton_blocks; ///< indices of nonlinear blocks (their unknowns reset at start)
};

/// Lowers `model` to a Program. Adds derivative nodes and seed symbols to
/// model.arena (the model's meaning is unchanged). Throws std::invalid_argument
/// for a model code generation cannot handle (a der() node outside the
/// Derivative symbols, a step target that is not an Algebraic/Derivative symbol).
Program lower_to_program(symbolic::OdeModel& model);

}  // namespace mo::codegen
