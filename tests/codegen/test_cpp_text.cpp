// Escaping of untrusted text and identifier mapping (no compiler needed).
#include <catch2/catch.hpp>

#include "mo/codegen/cpp_text.hpp"

using namespace mo::codegen;

TEST_CASE("cpp_string_literal escapes quotes, backslashes, controls, trigraphs, comment ends") {
  CHECK(cpp_string_literal("plain") == "\"plain\"");
  CHECK(cpp_string_literal("a\"b\\c") == "\"a\\\"b\\\\c\"");
  CHECK(cpp_string_literal("line\nnext\t") == "\"line\\nnext\\t\"");
  CHECK(cpp_string_literal("?\?=") == "\"\\?\\?=\"");
  CHECK(cpp_string_literal("*/ x") == "\"*\\057 x\"");
  CHECK(cpp_string_literal(std::string("a\0" "1", 3)) == "\"a\\0001\"");
  CHECK(cpp_string_literal("\xc3\xa9") == "\"\\303\\251\"");
  CHECK(cpp_string_literal("\r\x7f") == "\"\\015\\177\"");
}

TEST_CASE("cpp_double round-trips and parenthesises negatives") {
  CHECK(cpp_double(2.0) == "2.0");
  CHECK(cpp_double(-0.5) == "(-0.5)");
  CHECK(cpp_double(0.1) == "0.1");
  CHECK(cpp_double(1e300) == "1e+300");
  CHECK(cpp_double(-0.0) == "(-0.0)");
  CHECK(cpp_double(std::numeric_limits<double>::infinity()) == "std::numeric_limits<double>::infinity()");
}

TEST_CASE("cpp_identifier maps any name to a fresh identifier") {
  std::set<std::string> used;
  CHECK(cpp_identifier("pendulum.phi", used) == "pendulum_phi");
  CHECK(cpp_identifier("pendulum_phi", used) == "pendulum_phi_2");
  CHECK(cpp_identifier("d(phi)/d(m2)", used) == "d_phi_d_m2");
  CHECK(cpp_identifier("'\"); system(\"rm -rf /\"); //'", used) == "system_rm_rf");
  CHECK(cpp_identifier("class", used) == "class_");
  CHECK(cpp_identifier("1x", used) == "v_1x");
  CHECK(cpp_identifier("__x", used) == "x");
  CHECK(cpp_identifier("", used) == "v_");
  for (const auto& id : used) CHECK(is_cpp_identifier(id));
  CHECK_FALSE(is_cpp_identifier("a__b"));
  CHECK_FALSE(is_cpp_identifier("_a"));
  CHECK_FALSE(is_cpp_identifier("int"));
  CHECK(is_cpp_identifier("mo_model"));
}
