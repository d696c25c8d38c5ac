// generate_cpp(): the files of generate.hpp, around the printed sections.
#include "mo/codegen/generate.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

#include "mo/codegen/cpp_text.hpp"
#include "mo/codegen/program.hpp"
#include "mo/symbolic/printer.hpp"
#include "printer.hpp"

namespace mo::codegen {

namespace {

using symbolic::OdeModel;
using symbolic::VariableInfo;

template <class T, class F>
std::string array(const std::string& type, const std::string& name, const std::vector<T>& items,
                  F&& print) {
  if (items.empty()) return fmt::format("constexpr const {}* {} = nullptr;\n", type, name);
  std::string out = fmt::format("const {} {}[] = {{\n", type, name);
  for (const auto& item : items) out += "  " + print(item) + ",\n";
  return out + "};\n";
}

std::string sv(const std::string& s) { return cpp_string_literal(s) + "sv"; }

template <class Vars>
std::string name_tables(const std::string& prefix, const Vars& vars) {
  auto field = [&](const std::string& suffix, auto get) {
    return array("std::string_view", prefix + "_" + suffix, vars,
                 [&](const auto& v) { return sv(get(v.info)); });
  };
  return field("names", [](const VariableInfo& i) { return i.name; }) +
         field("descriptions", [](const VariableInfo& i) { return i.description; }) +
         field("units", [](const VariableInfo& i) { return i.unit; });
}

std::string info_tables(const OdeModel& m, const Program& p) {
  std::string out;
  out += fmt::format("constexpr std::string_view model_name = {};\n", sv(m.name));
  out += name_tables("state", m.states) + name_tables("input", m.inputs) +
         name_tables("output", m.outputs) + name_tables("parameter", m.parameters) +
         name_tables("discrete", m.discrete);
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < m.states.size(); ++i) idx.push_back(i);
  out += array("double", "state_start", p.start_values, [](double v) { return cpp_double(v); });
  out += array("double", "state_attributes", idx, [&](std::size_t i) {  // nominal, min, max
    const auto& s = m.states[i].info;
    return fmt::format("{}, {}, {}", cpp_double(s.nominal), cpp_double(s.min), cpp_double(s.max));
  });
  out += array("long", "state_sensitivity", idx, [&](std::size_t i) {  // state, parameter or -1
    const auto& s = m.states[i].sensitivity;
    return s ? fmt::format("{}, {}", s->state, s->parameter) : std::string("-1, -1");
  });
  std::vector<std::size_t> pidx;
  for (std::size_t i = 0; i < m.parameters.size(); ++i) pidx.push_back(i);
  out += array("double", "parameter_attributes", pidx, [&](std::size_t i) {  // value, min, max
    const auto& q = m.parameters[i];
    return fmt::format("{}, {}, {}", cpp_double(q.value), cpp_double(q.info.min), cpp_double(q.info.max));
  });
  std::vector<double> dstart;
  std::vector<std::string> dsens;  // this index, discrete, parameter
  for (std::size_t i = 0; i < m.discrete.size(); ++i) {
    dstart.push_back(m.discrete[i].start);
    if (const auto& s = m.discrete[i].sensitivity)
      dsens.push_back(fmt::format("{}, {}, {}", i, s->discrete, s->parameter));
  }
  out += array("double", "discrete_start", dstart, [](double v) { return cpp_double(v); });
  out += fmt::format("constexpr std::size_t ndsens = {};\n", dsens.size());
  out += array("long", "discrete_sensitivity", dsens, [](const std::string& s) { return s; });
  return out;
}

constexpr const char* info_builder = R"(mo::runtime::ModelInfo build_info() {
  mo::runtime::ModelInfo info;
  info.name = std::string(model_name);
  auto variable = [](std::string_view n, std::string_view d, std::string_view u) {
    return mo::runtime::Variable{std::string(n), std::string(d), std::string(u)};
  };
  for (std::size_t i = 0; i < nx; ++i) {
    mo::runtime::StateVariable s;
    static_cast<mo::runtime::Variable&>(s) = variable(state_names[i], state_descriptions[i], state_units[i]);
    s.start = state_start[i];
    s.nominal = state_attributes[3 * i];
    s.min = state_attributes[3 * i + 1];
    s.max = state_attributes[3 * i + 2];
    if (state_sensitivity[2 * i] >= 0)
      s.sensitivity = mo::runtime::SensitivityOf{static_cast<std::size_t>(state_sensitivity[2 * i]),
                                                 static_cast<std::size_t>(state_sensitivity[2 * i + 1])};
    info.states.push_back(std::move(s));
  }
  for (std::size_t i = 0; i < nu; ++i)
    info.inputs.push_back(variable(input_names[i], input_descriptions[i], input_units[i]));
  for (std::size_t i = 0; i < ny; ++i)
    info.outputs.push_back(variable(output_names[i], output_descriptions[i], output_units[i]));
  for (std::size_t i = 0; i < np; ++i) {
    mo::runtime::Parameter q;
    static_cast<mo::runtime::Variable&>(q) =
        variable(parameter_names[i], parameter_descriptions[i], parameter_units[i]);
    q.value = parameter_attributes[3 * i];
    q.min = parameter_attributes[3 * i + 1];
    q.max = parameter_attributes[3 * i + 2];
    info.parameters.push_back(std::move(q));
  }
  for (std::size_t i = 0; i < nd; ++i)
    info.discrete.push_back(variable(discrete_names[i], discrete_descriptions[i], discrete_units[i]));
  for (std::size_t i = 0; i < ndsens; ++i)
    info.discrete_sensitivities.push_back({static_cast<std::size_t>(discrete_sensitivity[3 * i]),
                                           static_cast<std::size_t>(discrete_sensitivity[3 * i + 1]),
                                           static_cast<std::size_t>(discrete_sensitivity[3 * i + 2])});
  info.num_event_indicators = ng;
  for (std::size_t i = 0; i < ng; ++i) info.indicator_in_rhs.push_back(indicator_in_rhs[i] != 0);
  for (std::size_t i = 0; i < ng; ++i) info.indicator_text.emplace_back(indicator_text[i]);
  for (std::size_t i = 0; i < nu; ++i) info.input_in_initial.push_back(input_in_initial[i] != 0);
  info.num_delays = ndelay;
  return info;
}

)";

std::string slot_array(const std::string& name, const std::vector<Slot>& slots) {
  return array("int", name, slots, [](Slot s) { return std::to_string(s); });
}

std::string section_table(const Program& p) {
  std::vector<bool> inner(p.sections.size(), false);
  for (const auto& b : p.blocks)
    if (b.inner_section >= 0) inner[static_cast<std::size_t>(b.inner_section)] = true;
  std::string out = "const SectionFunction all_sections[] = {";
  for (std::size_t i = 0; i < p.sections.size(); ++i)
    out += inner[i] ? std::string("nullptr, ") : fmt::format("section_{}, ", i);
  return out + fmt::format(
                   "}};\nconstexpr int section_index_steps = {}, section_index_outputs = {}, "
                   "section_index_starts = {}, section_index_crossings = {}, "
                   "section_index_conditions = {};\n\n",
                   p.steps, p.outputs, p.starts, p.crossings, p.conditions);
}

std::string jacobian_tables(const Program& p) {
  std::string out = section_table(p);
  std::string list = "const JacobianTables jacobian_tables[7] = {\n";
  for (std::size_t k = 0; k < 7; ++k) {
    const JacobianCode& j = p.jacobians[k];
    const std::string n = fmt::format("jac{}", k);
    std::vector<int> colour_start{0}, seeds, entry_start{0}, entry_index;
    std::vector<Slot> entry_slot;
    for (const auto& colour : j.colours) {
      for (int c : colour) {
        seeds.push_back(static_cast<int>(j.seed_slot[static_cast<std::size_t>(c)]));
        for (int e = j.col_start[static_cast<std::size_t>(c)]; e < j.col_start[static_cast<std::size_t>(c) + 1]; ++e) {
          entry_index.push_back(e);
          entry_slot.push_back(j.entry_slot[static_cast<std::size_t>(e)]);
        }
      }
      colour_start.push_back(static_cast<int>(seeds.size()));
      entry_start.push_back(static_cast<int>(entry_index.size()));
    }
    auto ints = [&](const std::string& suffix, const std::vector<int>& v) {
      out += array("int", n + "_" + suffix, v, [](int x) { return std::to_string(x); });
    };
    ints("col_start", j.col_start);
    ints("row_index", j.row_index);
    ints("colour_start", colour_start);
    ints("seeds", seeds);
    ints("entry_start", entry_start);
    ints("entry_index", entry_index);
    out += slot_array(n + "_entry_slot", entry_slot);
    std::vector<std::string> base, product;
    for (int s : j.base_sections) base.push_back(fmt::format("section_{}", s));
    for (int s : j.product_sections) product.push_back(fmt::format("section_{}", s));
    out += array("SectionFunction", n + "_base", base, [](const std::string& s) { return s; });
    out += array("SectionFunction", n + "_product", product, [](const std::string& s) { return s; });
    list += fmt::format(
        "  {{{1}, {2}, {0}_col_start, {0}_row_index, {3}, {0}_colour_start, {0}_seeds, {0}_entry_start, "
        "{0}_entry_index, {0}_entry_slot, {0}_base, {4}, {0}_product, {5}}},\n",
        n, j.rows, j.cols, j.colours.size(), base.size(), product.size());
  }
  return out + list + "};\n\n";
}

std::string hessian_tables(const Program& p) {
  std::string out = fmt::format("constexpr std::size_t sigma_slot = {}, tau_slot = {};\n", p.layout.seeds_x,
                                p.layout.seeds2);
  std::string list = "const HessianTables hessian_tables[2] = {\n";
  for (std::size_t k = 0; k < 2; ++k) {
    const HessianCode& h = p.hessians[k];
    const std::string n = fmt::format("hess{}", k);
    std::vector<int> colour_start{0}, colour_columns, sigma, tau, entry_start{0}, weight, index;
    std::vector<Slot> slot;
    for (const auto& colour : h.colours) {
      colour_columns.insert(colour_columns.end(), colour.begin(), colour.end());
      colour_start.push_back(static_cast<int>(colour_columns.size()));
    }
    for (const auto& pr : h.products) {
      sigma.push_back(pr.sigma_colour);
      tau.push_back(pr.tau_colour);
      for (const auto& e : pr.entries) {
        weight.push_back(e.weight);
        slot.push_back(e.slot);
        index.push_back(e.index);
      }
      entry_start.push_back(static_cast<int>(weight.size()));
    }
    auto ints = [&](const std::string& suffix, const std::vector<int>& v) {
      out += array("int", n + "_" + suffix, v, [](int x) { return std::to_string(x); });
    };
    ints("col_start", h.col_start);
    ints("row_index", h.row_index);
    ints("colour_start", colour_start);
    ints("colour_columns", colour_columns);
    ints("sigma", sigma);
    ints("tau", tau);
    ints("entry_start", entry_start);
    ints("entry_weight", weight);
    out += slot_array(n + "_entry_slot", slot);
    ints("entry_index", index);
    std::vector<std::string> base, sigma_sections, product;
    for (int s : h.base_sections) base.push_back(fmt::format("section_{}", s));
    for (int s : h.sigma_sections) sigma_sections.push_back(fmt::format("section_{}", s));
    for (int s : h.product_sections) product.push_back(fmt::format("section_{}", s));
    out += array("SectionFunction", n + "_base", base, [](const std::string& s) { return s; });
    out += array("SectionFunction", n + "_sigma_sections", sigma_sections, [](const std::string& s) { return s; });
    out += array("SectionFunction", n + "_product", product, [](const std::string& s) { return s; });
    list += fmt::format(
        "  {{{1}, {0}_col_start, {0}_row_index, {0}_colour_start, {0}_colour_columns, {2}, {0}_sigma, "
        "{0}_tau, {0}_entry_start, {0}_entry_weight, {0}_entry_slot, {0}_entry_index, {0}_base, {3}, "
        "{0}_sigma_sections, {5}, {0}_product, {4}}},\n",
        n, h.n, h.products.size(), base.size(), product.size(), sigma_sections.size());
  }
  return out + list + "};\n\n";
}

std::string when_tables(const Program& p) {
  std::string out;
  std::vector<int> assign_start{0}, assign_target, assign_value, reinit_start{0}, reinit_state,
      reinit_value, every_event, before_steps, group, branch;
  std::vector<std::string> sections, terminate_messages;  // messages escaped: model text
  for (const auto& w : p.whens) {
    sections.push_back(fmt::format("section_{}", w.section));
    terminate_messages.push_back(w.terminates ? cpp_string_literal(w.terminate_message) : "nullptr");
    every_event.push_back(w.every_event ? 1 : 0);
    before_steps.push_back(w.before_steps ? 1 : 0);
    group.push_back(w.group);
    branch.push_back(w.branch);
    for (auto [t, v] : w.assignments) assign_target.push_back(static_cast<int>(t)), assign_value.push_back(static_cast<int>(v));
    for (auto [x, v] : w.reinits) reinit_state.push_back(static_cast<int>(x)), reinit_value.push_back(static_cast<int>(v));
    assign_start.push_back(static_cast<int>(assign_target.size()));
    reinit_start.push_back(static_cast<int>(reinit_state.size()));
  }
  auto ints = [&](const std::string& n, const std::vector<int>& v) {
    out += array("int", n, v, [](int x) { return std::to_string(x); });
  };
  out += array("SectionFunction", "when_sections", sections, [](const std::string& s) { return s; });
  ints("when_every_event", every_event);
  ints("when_before_steps", before_steps);
  ints("when_group", group);
  ints("when_branch", branch);
  ints("when_assign_start", assign_start);
  ints("when_assign_target", assign_target);
  ints("when_assign_value", assign_value);
  ints("when_reinit_start", reinit_start);
  ints("when_reinit_state", reinit_state);
  ints("when_reinit_value", reinit_value);
  out += array("char*", "when_terminate", terminate_messages, [](const std::string& s) { return s; });
  std::vector<int> pre_to, pre_from, newton_slots;
  std::vector<double> newton_start;
  for (auto [to, from] : p.pre_copies) pre_to.push_back(static_cast<int>(to)), pre_from.push_back(static_cast<int>(from));
  for (std::size_t b : p.newton_blocks)
    for (std::size_t i = 0; i < p.blocks[b].unknowns.size(); ++i) {
      newton_slots.push_back(static_cast<int>(p.blocks[b].unknowns[i]));
      newton_start.push_back(p.blocks[b].start[i]);
    }
  ints("pre_to", pre_to);
  ints("pre_from", pre_from);
  ints("newton_slots", newton_slots);
  out += array("double", "newton_start", newton_start, [](double v) { return cpp_double(v); });
  out += slot_array("derivative_slots", p.derivative_slots);
  out += slot_array("output_slots", p.output_slots);
  out += slot_array("start_slots", p.start_slots);
  out += slot_array("crossing_slots", p.crossing_slots);
  out += slot_array("condition_slots", p.condition_slots);
  return out;
}

/// Tables of Program::samples (null arrays without sample()).
std::string sample_tables(const Program& p) {
  std::vector<int> flag, start, interval;
  for (const auto& smp : p.samples) {
    flag.push_back(smp.flag);
    start.push_back(static_cast<int>(smp.start));
    interval.push_back(static_cast<int>(smp.interval));
  }
  auto ints = [](const std::string& n, const std::vector<int>& v) {
    return array("int", n, v, [](int x) { return std::to_string(x); });
  };
  return fmt::format("constexpr std::size_t nsample = {};\nconstexpr int samples_section = {};\n",
                     p.samples.size(), p.samples_section) +
         ints("sample_flag", flag) + ints("sample_start_slot", start) +
         ints("sample_interval_slot", interval);
}

/// Tables of Program::delays (DelayCode).
std::string delay_tables(const Program& p) {
  std::vector<Slot> value, argument, time, max, varying, sensitivity;
  for (const DelayCode& d : p.delays) {
    value.push_back(d.value);
    argument.push_back(d.argument);
    time.push_back(d.time);
    max.push_back(d.max);
    varying.push_back(d.varying ? 1 : 0);
    sensitivity.push_back(d.of_sensitivities ? 1 : 0);
  }
  return fmt::format("constexpr std::size_t ndelay = {};\nconstexpr int delay_times_section = {}, "
                     "delay_arguments_section = {};\n",
                     p.delays.size(), p.delay_times, p.delay_arguments) +
         slot_array("delay_value_slot", value) + slot_array("delay_argument_slot", argument) +
         slot_array("delay_time_slot", time) + slot_array("delay_max_slot", max) +
         slot_array("delay_varying", varying) + slot_array("delay_of_sensitivities", sensitivity);
}

/// Tables of Program::event_tangents (sections -1 and null arrays without events).
std::string event_tangent_tables(const Program& p) {
  const EventTangentCode& e = p.event_tangents;
  std::string out = fmt::format(
      "constexpr int event_rhs_section = {}, event_tangent_section = {};\n"
      "constexpr std::size_t event_seed_t = {};\n",
      e.rhs, e.tangent, e.seed_t);
  std::vector<std::string> sections;
  for (int k : e.whens) sections.push_back(fmt::format("section_{}", k));
  out += array("SectionFunction", "when_tangent_sections", sections, [](const std::string& s) { return s; });
  out += slot_array("event_seed_x", e.seed_x);
  out += slot_array("event_seed_u", e.seed_u);
  out += slot_array("event_seed_p", e.seed_p);
  out += array("int", "event_seed_d", e.seed_d, [](int x) { return std::to_string(x); });
  out += slot_array("indicator_tangent_slots", e.indicator_slots);
  out += slot_array("assign_tangent_slots", e.assign_slots);
  out += slot_array("reinit_tangent_slots", e.reinit_slots);
  out += slot_array("sample_start_tangent_slots", e.sample_start_slots);
  out += slot_array("sample_interval_tangent_slots", e.sample_interval_slots);
  return out;
}

std::string sizes(const OdeModel& m, const Program& p) {
  return fmt::format(
      "constexpr std::size_t nx = {}, nu = {}, ny = {}, np = {}, nd = {}, ng = {}, nwhen = {}, "
      "nnewton = {};\n"
      "constexpr std::size_t num_slots = {}, x_slot = {}, u_slot = {}, p_slot = {}, t_slot = {}, "
      "d_slot = {}, pre_d_slot = {};\n"
      "constexpr std::size_t npre = {};\n"
      "constexpr int initial_flag = {};  // index in the discrete variables of initial(), or -1\n\n",
      m.states.size(), m.inputs.size(), m.outputs.size(), m.parameters.size(), m.discrete.size(),
      m.zero_crossings.size(), m.whens.size(),
      [&] {
        std::size_t n = 0;
        for (std::size_t b : p.newton_blocks) n += p.blocks[b].unknowns.size();
        return n;
      }(),
      p.num_slots, p.layout.states, p.layout.inputs, p.layout.parameters, p.layout.time,
      p.layout.discrete, p.layout.pre_discrete, p.pre_copies.size(), m.initial_flag);
}

/// Indicator g as Modelica text for the runtime's diagnostics (a chattering
/// relation); empty if its tree is larger than a message can show (a DAG's
/// text writes out every use of a subexpression, see to_modelica()).
std::string indicator_text(const symbolic::ExprArena& arena, symbolic::Expr g) {
  constexpr std::size_t kMaxNodes = 200;
  std::size_t visited = 0;
  std::vector<symbolic::Expr> stack{g};
  while (!stack.empty()) {
    if (++visited > kMaxNodes) return {};
    const symbolic::Expr e = stack.back();
    stack.pop_back();
    if (arena.kind(e) == symbolic::ExprKind::External) return {};
    for (std::size_t i = 0; i < symbolic::arity(arena.kind(e)); ++i) stack.push_back(arena.operand(e, i));
  }
  return symbolic::to_modelica(arena, g);
}

/// Per event indicator, 1 if a relation on it enters the right-hand side,
/// and its text; per input, 1 if the initial system reads it.
std::string flag_tables(const OdeModel& m) {
  std::vector<int> in_rhs;
  for (std::size_t i = 0; i < m.zero_crossings.size(); ++i)
    in_rhs.push_back(i < m.zero_crossing_in_steps.size() && !m.zero_crossing_in_steps[i] ? 0 : 1);
  std::vector<int> in_initial;
  for (bool read : m.inputs_in_initial_system()) in_initial.push_back(read ? 1 : 0);
  return array("int", "indicator_in_rhs", in_rhs, [](int x) { return std::to_string(x); }) +
         array("std::string_view", "indicator_text", m.zero_crossings,
               [&](symbolic::Expr g) { return sv(indicator_text(m.arena, g)); }) +
         array("int", "input_in_initial", in_initial, [](int x) { return std::to_string(x); });
}

std::string typed_header(const OdeModel& m, const CodegenOptions& o) {
  std::string out = fmt::format(
      "// Generated by mocompile: typed access to model {0}. Do not edit.\n#pragma once\n\n"
      "#include <cstddef>\n#include <memory>\n\n#include \"mo/runtime/model.hpp\"\n\n"
      "namespace {0} {{\n\n"
      "inline constexpr std::size_t num_states = {1};\ninline constexpr std::size_t num_inputs = {2};\n"
      "inline constexpr std::size_t num_outputs = {3};\ninline constexpr std::size_t num_parameters = {4};\n"
      "inline constexpr std::size_t num_discrete = {5};\ninline constexpr std::size_t num_event_indicators = {6};\n\n",
      o.name, m.states.size(), m.inputs.size(), m.outputs.size(), m.parameters.size(),
      m.discrete.size(), m.zero_crossings.size());
  auto indices = [&](const std::string& ns, const auto& vars) {
    out += "/// Indices by (mapped) name; info() has the exact names.\nnamespace " + ns + " {\n";
    std::set<std::string> used;
    for (std::size_t i = 0; i < vars.size(); ++i)
      out += fmt::format("inline constexpr std::size_t {} = {};\n",
                         cpp_identifier(vars[i].info.name, used), i);
    out += "}  // namespace " + ns + "\n\n";
  };
  indices("state", m.states);
  indices("input", m.inputs);
  indices("output", m.outputs);
  indices("parameter", m.parameters);
  indices("discrete_variable", m.discrete);
  out += fmt::format(
      "/// A new instance of the model in its initial discrete state.\n"
      "std::unique_ptr<mo::runtime::Model> create();\n\n}}  // namespace {0}\n\n"
      "/// The same for dlopen: a new instance the caller owns (delete it).\n"
      "extern \"C\" mo::runtime::Model* {0}_create();\n",
      o.name);
  return out;
}

}  // namespace

std::vector<std::string> GeneratedSources::sources() const {
  std::vector<std::string> out;
  for (const auto& f : files)
    if (f.path.ends_with(".cpp")) out.push_back(f.path);
  return out;
}

GeneratedSources generate_cpp(OdeModel& model, const CodegenOptions& options) {
  if (!is_cpp_identifier(options.name))
    throw std::invalid_argument("code generation: the name '" + options.name +
                                "' is not a usable C++ identifier");
  if (options.instructions_per_function == 0 || options.instructions_per_file == 0)
    throw std::invalid_argument("code generation: instruction limits must be positive");
  const Program program = lower_to_program(model);
  const detail::PrintedSections printed = detail::print_sections(model.arena, program, options);
  const std::string& n = options.name;
  GeneratedSources out;
  out.factory_symbol = n + "_create";
  out.instructions = printed.instructions;
  out.work_slots = program.num_slots;
  out.files.push_back({n + ".hpp", typed_header(model, options)});
  out.files.push_back(
      {n + "_internal.hpp",
       fmt::format("// Generated by mocompile. Do not edit.\n#pragma once\n\n#include <cmath>\n#include <limits>\n\n"
                   "#include \"mo/runtime/generated_support.hpp\"\n\nnamespace {0}::detail {{\n"
                   "namespace G = mo::runtime::generated;\n{1}}}  // namespace {0}::detail\n",
                   n, printed.declarations)});
  for (std::size_t k = 0; k < printed.parts.size(); ++k)
    out.files.push_back({fmt::format("{}_part{}.cpp", n, k),
                         fmt::format("// Generated by mocompile. Do not edit.\n#include \"{0}_internal.hpp\"\n\n"
                                     "namespace {0}::detail {{\n\n{1}\n}}  // namespace {0}::detail\n",
                                     n, printed.parts[k])});
  std::string text = fmt::format(
      "// Generated by mocompile. Do not edit.\n#include \"{0}.hpp\"\n#include \"{0}_internal.hpp\"\n\n"
      "#include <algorithm>\n#include <array>\n#include <string>\n#include <string_view>\n#include <vector>\n\n"
      "namespace {0} {{\nnamespace {{\n\nusing namespace std::string_view_literals;\n"
      "namespace G = mo::runtime::generated;\n"
      "using SectionFunction = bool (*)(double*, const int*, G::BlockWorkspace&);\n\n",
      n);
  text += sizes(model, program) + delay_tables(program) + flag_tables(model) + info_tables(model, program) + info_builder + printed.runners +
          R"(struct JacobianTables {
  int rows, cols;
  const int* col_start;
  const int* row_index;
  std::size_t colours;
  const int* colour_start;
  const int* seeds;
  const int* entry_start;
  const int* entry_index;
  const int* entry_slot;
  const SectionFunction* base;
  std::size_t num_base;
  const SectionFunction* product;
  std::size_t num_product;
};

struct HessianTables {
  int n;
  const int* col_start;
  const int* row_index;
  const int* colour_start;
  const int* colour_columns;
  std::size_t products;
  const int* sigma;
  const int* tau;
  const int* entry_start;
  const int* entry_weight;
  const int* entry_slot;
  const int* entry_index;
  const SectionFunction* base;
  std::size_t num_base;
  const SectionFunction* sigma_sections;
  std::size_t num_sigma;
  const SectionFunction* product;
  std::size_t num_product;
};

)" + jacobian_tables(program) + hessian_tables(program) +
          when_tables(program) + sample_tables(program) + event_tangent_tables(program) + detail::model_class + fmt::format(R"(
}}  // namespace

std::unique_ptr<mo::runtime::Model> create() {{ return std::make_unique<GeneratedModel>(); }}

}}  // namespace {0}

extern "C" __attribute__((visibility("default"))) mo::runtime::Model* {0}_create() {{
  return new {0}::GeneratedModel();
}}
)",
                                                             n);
  out.files.push_back({n + "_model.cpp", std::move(text)});
  return out;
}

void write_sources(const GeneratedSources& sources, const std::string& directory) {
  namespace fs = std::filesystem;
  fs::create_directories(directory);
  for (const auto& f : sources.files) {
    const fs::path target = fs::path(directory) / f.path;
    const fs::path temp = target.string() + ".tmp" + std::to_string(::getpid());
    {
      std::ofstream os(temp, std::ios::binary);
      os << f.text;
      os.flush();
      if (!os) {
        std::error_code ignored;
        fs::remove(temp, ignored);
        throw std::system_error(errno, std::generic_category(), "cannot write " + temp.string());
      }
    }
    fs::rename(temp, target);
  }
}

}  // namespace mo::codegen
