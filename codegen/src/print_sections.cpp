// Sections → part functions, block tables and section runners; see printer.hpp.
#include <fmt/format.h>

#include <stdexcept>

#include "mo/codegen/cpp_text.hpp"
#include "printer.hpp"

namespace mo::codegen::detail {

namespace {

template <class T>
std::string int_array(const std::string& name, const std::vector<T>& values) {
  if (values.empty()) return fmt::format("constexpr const int* {} = nullptr;\n", name);
  return fmt::format("const int {}[] = {{{}}};\n", name, fmt::join(values, ", "));
}

std::string double_array(const std::string& name, const std::vector<double>& values) {
  std::vector<std::string> text;
  for (double v : values) text.push_back(cpp_double(v));
  return fmt::format("const double {}[] = {{{}}};\n", name, fmt::join(text, ", "));
}

class SectionPrinter {
public:
  SectionPrinter(const symbolic::ExprArena& a, const Program& p, const CodegenOptions& o)
      : a_(a), p_(p), o_(o) {}

  PrintedSections run() {
    std::vector<bool> inner(p_.sections.size(), false);
    for (const auto& b : p_.blocks)
      if (b.inner_section >= 0) inner[static_cast<std::size_t>(b.inner_section)] = true;
    // Inner (Newton) sections first: blocks refer to their runners.
    for (std::size_t i = 0; i < p_.sections.size(); ++i)
      if (inner[i]) inner_runner(i);
    for (std::size_t b = 0; b < p_.blocks.size(); ++b) block_table(b);
    for (std::size_t i = 0; i < p_.sections.size(); ++i)
      if (!inner[i]) runner(i);
    flush_part();
    return std::move(out_);
  }

private:
  /// Prints the straight-line run code[first, last) as part functions;
  /// returns the calls to them.
  std::string straight_line(const Section& s, std::size_t first, std::size_t last) {
    std::string calls;
    for (std::size_t begin = first; begin < last; begin += o_.instructions_per_function) {
      const std::size_t end = std::min(last, begin + o_.instructions_per_function);
      const std::string name = fmt::format("c{}", functions_++);
      if (part_instructions_ > 0 && part_instructions_ + (end - begin) > o_.instructions_per_file)
        flush_part();
      std::string& part = part_;
      part += fmt::format("void {}(double* w, const int*{}) {{\n", name, s.uses_crossings ? " cross" : "");
      for (std::size_t i = begin; i < end; ++i) {
        const Instruction& ins = s.code[i];
        if (ins.op == Instruction::Op::Delay)
          throw std::invalid_argument("code generation: a delay() with a varying delay time inside an "
                                      "algebraic loop's Newton iteration is not supported");
        if (ins.op == Instruction::Op::Node)
          part += fmt::format("  w[{}] = {};\n", ins.slot, node_code(a_, p_, ins));
        else
          part += fmt::format("  w[{}] = {};\n", ins.slot, operand_code(a_, p_, ins.node));
      }
      part += "}\n";
      part_instructions_ += end - begin;
      out_.instructions += end - begin;
      out_.declarations += fmt::format("void {}(double* w, const int* cross);\n", name);
      calls += fmt::format("  detail::{}(w, cross);\n", name);
    }
    return calls;
  }

  void flush_part() {
    if (part_.empty()) return;
    out_.parts.push_back(std::move(part_));
    part_.clear();
    part_instructions_ = 0;
  }

  void inner_runner(std::size_t i) {
    const Section& s = p_.sections[i];
    const std::string calls = straight_line(s, 0, s.code.size());
    out_.runners += fmt::format("void section_{}(double* w, const int* cross) {{\n  (void)cross;\n{}}}\n\n",
                                i, calls);
  }

  void block_table(std::size_t index) {
    const BlockCode& b = p_.blocks[index];
    const std::string n = fmt::format("block{}", index);
    std::string& r = out_.runners;
    r += int_array(n + "_unknowns", b.unknowns);
    r += int_array(n + "_values", b.values);
    if (b.entries.empty()) {
      r += fmt::format("constexpr const G::BlockEntry* {}_entries = nullptr;\n", n);
    } else {
      r += fmt::format("const G::BlockEntry {}_entries[] = {{", n);
      for (std::size_t k = 0; k < b.entries.size(); ++k)
        r += fmt::format("{}{{{}, {}, {}}}", k ? ", " : "", b.entries[k].row, b.entries[k].col,
                         b.entries[k].slot);
      r += "};\n";
    }
    if (b.linear)
      r += fmt::format("const G::LinearBlock {0} = {{{1}, {0}_unknowns, {0}_values, {0}_entries, {2}, {3}}};\n\n",
                       n, b.unknowns.size(), b.entries.size(), cpp_string_literal(b.description));
    else if (b.nominal.size() != b.unknowns.size() || b.lower.size() != b.unknowns.size() ||
             b.upper.size() != b.unknowns.size())
      throw std::logic_error("code generation: " + n + " has no nominal values or bounds for its unknowns");
    else
      r += double_array(n + "_nominal", b.nominal) + double_array(n + "_lower", b.lower) +
           double_array(n + "_upper", b.upper) +
           fmt::format("const G::NonlinearBlock {0} = {{{1}, {0}_unknowns, {0}_values, {0}_entries, {2}, "
                       "section_{3}, {4}, {0}_nominal, {0}_lower, {0}_upper}};\n\n",
                       n, b.unknowns.size(), b.entries.size(), b.inner_section,
                       cpp_string_literal(b.description));
  }

  void runner(std::size_t i) {
    const Section& s = p_.sections[i];
    std::string body;
    std::size_t run_start = 0;
    for (std::size_t k = 0; k <= s.code.size(); ++k) {
      const bool end = k == s.code.size();
      const bool solve = !end && (s.code[k].op == Instruction::Op::LinearSolve ||
                                  s.code[k].op == Instruction::Op::NonlinearSolve ||
                                  s.code[k].op == Instruction::Op::Delay);
      if (!end && !solve) continue;
      body += straight_line(s, run_start, k);
      run_start = k + 1;
      if (solve && s.code[k].op == Instruction::Op::Delay)  // the line read at T now
        body += fmt::format("  w[{}] = G::delay_value(ws, {}, {});\n", s.code[k].slot, s.code[k].block,
                            operand_code(a_, p_, a_.operand(s.code[k].node, 1)));
      else if (solve && s.code[k].op == Instruction::Op::LinearSolve)
        body += fmt::format("  ok = G::solve_linear(block{}, w, ws) && ok;\n", s.code[k].block);
      else if (solve)
        body += fmt::format("  ws.cross = cross;\n  ok = G::solve_nonlinear(block{}, w, ws) && ok;\n",
                            s.code[k].block);
    }
    out_.runners += fmt::format(
        "/// Section {} ({}).\nbool section_{}(double* w, const int* cross, G::BlockWorkspace& ws) {{\n"
        "  (void)cross, (void)ws;\n  bool ok = true;\n{}  return ok;\n}}\n\n",
        i, s.name, i, body);
  }

  const symbolic::ExprArena& a_;
  const Program& p_;
  const CodegenOptions& o_;
  PrintedSections out_;
  std::string part_;
  std::size_t part_instructions_ = 0;
  std::size_t functions_ = 0;
};

}  // namespace

PrintedSections print_sections(const symbolic::ExprArena& arena, const Program& program,
                               const CodegenOptions& options) {
  if (options.part_files == 0) return SectionPrinter(arena, program, options).run();
  std::size_t total = 0;
  for (const auto& s : program.sections)
    for (const auto& ins : s.code)
      total += ins.op == Instruction::Op::Node || ins.op == Instruction::Op::Copy ? 1 : 0;
  // A file may overshoot its share by one function: leave that much room.
  CodegenOptions even = options;
  even.instructions_per_file =
      (total + options.part_files - 1) / options.part_files + options.instructions_per_function;
  PrintedSections out = SectionPrinter(arena, program, even).run();
  if (out.parts.size() > options.part_files)
    throw std::logic_error("internal error: code generation: more part files than requested");
  out.parts.resize(options.part_files);
  return out;
}

}  // namespace mo::codegen::detail
