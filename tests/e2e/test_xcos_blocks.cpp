// A diagram's non-Modelica blocks translated to Modelica (tools/xcos_blocks.hpp),
// from block lists written by hand in the format of the Scilab script: which
// inputs close, the diagnostics for a block that is not translated, and
// malformed or hostile lists. The closed loop is simulated against Scilab in
// test_diagrams.cpp (BlockLoop) and in the corpus test (ControlledTemperature).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli.hpp"
#include "xcos_blocks.hpp"

namespace fs = std::filesystem;
using namespace mo::tools;

namespace {

const std::string kFlat =
    "class Loop_imf\n"
    "\tReal `x`(start=0.);\n"
    "\toutput Real `OutPutPort1.vo` \"\";\n"
    "\tinput Real `InPutPort1.vi` \"\";\n"
    "\tinput Real `InPutPort2.vi` \"\";\n"
    "equation\n"
    "\tder(`x`) = (`InPutPort1.vi` + `InPutPort2.vi`);\n"
    "\t`OutPutPort1.vo` = `x`;\n"
    "end Loop_imf;\n";

XcosBlocks parse(const std::string& text) {
  const fs::path file = mo::e2e::scratch("xcos-blocks") / "blocks.txt";
  std::ofstream(file) << text;
  return read_xcos_blocks(file);
}

/// A block line with its fields (sizes scalar, nothing else unless given).
std::string block(int k, const std::string& gui, const std::string& sim, const std::string& fields) {
  return "block " + std::to_string(k) + " " + gui + " " + sim + "\nin 1 1\nout 1 1\nevtin 1 0\n" + fields;
}

}  // namespace

TEST_CASE("diagram blocks: a relay on the model's output closes input 1 - a RELAY_f leaves input 2 open",
          "[xcos][diagram]") {
  // 1 CONST_m 0.5, 2 SUMMATION (+1, -1): e = 0.5 - y, 3 HYSTHERESIS, 4 RELAY_f (not translated).
  const auto blocks = parse("mo-xcos-blocks 1\nmodelica 5 2 1\n" + block(1, "CONST_m", "cstblk4_m", "opar 1 0.5\n") +
                            block(2, "SUMMATION", "summation", "ipar 2 1 -1\n") +
                            block(3, "HYSTHERESIS", "hystheresis", "rpar 4 0.1 -0.1 1 -1\nnzcross 1 2\n") +
                            block(4, "RELAY_f", "relay", "ipar 1 1\n") +
                            "link 1 1 2 1\nlink 5 1 2 2\nlink 2 1 3 1\nlink 3 1 5 1\nlink 1 1 4 1\nlink 4 1 5 2\nend\n");
  const ClosedLoop loop = close_xcos_loop(blocks, kFlat);
  CHECK(loop.closed == std::vector<int>{1});
  CHECK(loop.translated == std::vector<std::string>{"CONST_m (block 1)", "SUMMATION (block 2)", "HYSTHERESIS (block 3)"});
  REQUIRE(loop.warnings.size() == 1);
  CHECK(loop.warnings[0] == "input `InPutPort2.vi` stays open: block RELAY_f (block 4) is not translated: its "
                            "computational function 'relay' is not among the blocks translated to Modelica");
  CHECK(loop.equations.find("xcos_b2_y1 = xcos_b1_y1 - `OutPutPort1.vo`;") != std::string::npos);
  CHECK(loop.equations.find("elsewhen xcos_b2_y1 <= (-0.10000000000000001) then") != std::string::npos);
  CHECK(loop.equations.find("`InPutPort1.vi` = xcos_b3_y1;") != std::string::npos);
  const std::string closed = with_closed_loop(kFlat, loop);
  CHECK(closed.find("  discrete Real xcos_b3_y1;\nequation\n") != std::string::npos);
  CHECK(closed.find("  `InPutPort1.vi` = xcos_b3_y1;\nend Loop_imf;\n") != std::string::npos);
}

TEST_CASE("diagram blocks: sources, curve, gains and products in Modelica", "[xcos][diagram]") {
  const auto blocks = parse(
      "mo-xcos-blocks 1\nmodelica 8 1 0\n" + block(1, "CURV_f", "intplt", "rpar 10 0 1 1 3 0 2 2 0 0 0\nipar 5 4 2 10 2 10\n") +
      block(2, "GENSIN_f", "gensin", "rpar 3 2 3 0.5\n") + block(3, "BIGSOM_f", "sum", "rpar 2 1 -2\n") +
      block(4, "GAINBLK", "gainblk", "rpar 1 4\n") + block(5, "RAMP", "ramp", "rpar 3 0.5 1 2\n") +
      block(6, "PRODUCT", "product", "ipar 2 1 -1\n") + block(7, "SATURATION", "satur", "rpar 2 1 -1\n") +
      "link 1 1 3 1\nlink 2 1 3 2\nlink 3 1 4 1\nlink 4 1 6 1\nlink 5 1 6 2\nlink 6 1 7 1\nlink 7 1 8 1\nend\n");
  const ClosedLoop loop = close_xcos_loop(blocks, kFlat);
  INFO(loop.equations);
  CHECK(loop.closed == std::vector<int>{1});
  CHECK(loop.warnings.size() == 0);
  // CURV_f: clamped outside 0..3, the repeated abscissa 1 skipped (intplt never picks it).
  CHECK(loop.equations.find("xcos_b1_y1 = if time <= 0 then 0 elseif time < 1 then 0 + 2*(time - 0) elseif time < 3 "
                            "then 2 + (-1)*(time - 1) else 0;") != std::string::npos);
  CHECK(loop.equations.find("xcos_b2_y1 = 2*sin(3*time + 0.5);") != std::string::npos);
  CHECK(loop.equations.find("xcos_b3_y1 = xcos_b1_y1 + (-2)*xcos_b2_y1;") != std::string::npos);
  CHECK(loop.equations.find("xcos_b5_y1 = if time >= 1 then 2 + 0.5*(time - 1) else 2;") != std::string::npos);
  CHECK(loop.equations.find("xcos_b6_y1 = 1*xcos_b4_y1/xcos_b5_y1;") != std::string::npos);
  CHECK(loop.equations.find("xcos_b7_y1 = if xcos_b6_y1 >= 1 then 1 elseif xcos_b6_y1 <= (-1) then (-1) else "
                            "xcos_b6_y1;") != std::string::npos);
}

TEST_CASE("diagram blocks: what is not translated is said, and names never reach the model", "[xcos][diagram]") {
  SECTION("a vector signal") {
    const auto blocks = parse("mo-xcos-blocks 1\nmodelica 2 1 0\nblock 1 CONST_m cstblk4_m\nin 0\nout 1 2\nopar 2 1 2\n"
                              "link 1 1 2 1\nend\n");
    const ClosedLoop loop = close_xcos_loop(blocks, kFlat);
    CHECK(loop.closed.empty());
    REQUIRE(loop.warnings.size() == 1);
    CHECK(loop.warnings[0].find("block CONST_m (block 1) is not translated: it has a port of size 2") !=
          std::string::npos);
  }
  SECTION("a block activated by a clock") {
    const auto blocks = parse("mo-xcos-blocks 1\nmodelica 3 1 0\n" + block(1, "GAINBLK", "gainblk", "rpar 1 2\n") +
                              block(2, "CONST_m", "cstblk4_m", "opar 1 1\n") +
                              "link 2 1 1 1\nlink 1 1 3 1\nevent 2 1 1 1\nend\n");
    const ClosedLoop loop = close_xcos_loop(blocks, kFlat);
    CHECK(loop.closed.empty());
    REQUIRE(loop.warnings.size() == 1);
    CHECK(loop.warnings[0].find("GAINBLK (block 1) is not translated: it is activated by events") != std::string::npos);
  }
  SECTION("an interface or function name that is not a plain name is '?'") {
    const auto blocks = parse("mo-xcos-blocks 1\nmodelica 2 1 0\nblock 1 a\"b;system() x`y\nin 0\nout 1 1\n"
                              "link 1 1 2 1\nend\n");
    REQUIRE(blocks.blocks.size() == 1);
    CHECK(blocks.blocks[0].gui == "?");
    CHECK(blocks.blocks[0].sim == "?");
    const ClosedLoop loop = close_xcos_loop(blocks, kFlat);
    CHECK(loop.closed.empty());
    REQUIRE(loop.warnings.size() == 1);
    CHECK(loop.warnings[0].find("block ? (block 1) is not translated") != std::string::npos);
  }
  SECTION("a flat model that uses the prefix gets another one") {
    const auto blocks =
        parse("mo-xcos-blocks 1\nmodelica 2 1 0\n" + block(1, "CONST", "cstblk4", "rpar 1 3\n") + "link 1 1 2 1\nend\n");
    std::string flat = kFlat;
    flat.insert(flat.find("equation"), "\tReal `xcos_b1_y1`;\n");
    const ClosedLoop loop = close_xcos_loop(blocks, flat);
    CHECK(loop.equations.find("  _xcos_b1_y1 = 3;\n") != std::string::npos);
  }
}

TEST_CASE("diagram blocks: a malformed block list is an error with its line", "[xcos][diagram]") {
  auto error_of = [](const std::string& text) {
    try {
      parse(text);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error_of("something else\n").find("blocks.txt:1: error: not a block list of version 1") != std::string::npos);
  CHECK(error_of("mo-xcos-blocks 1\nmodelica 2 1 0\nblock 1 CONST cstblk4\nrpar 2 1\nend\n")
            .find("blocks.txt:4: error: 'rpar' should list 2 numbers") != std::string::npos);
  CHECK(error_of("mo-xcos-blocks 1\nmodelica 2 1 0\nblock 1 CONST cstblk4\nrpar 1 1e999x\nend\n")
            .find("blocks.txt:4: error: '1e999x' is not a number") != std::string::npos);
  CHECK(error_of("mo-xcos-blocks 1\nmodelica 2 1 0\nblock 1 CONST cstblk4\nlink 1 1 7 1\nend\n")
            .find("a link names a block or port that does not exist") != std::string::npos);
  CHECK(error_of("mo-xcos-blocks 1\nmodelica 2 1 0\nblock 1 CONST cstblk4\n").find("no 'end'") != std::string::npos);
}
