// The pseudo-random generators that the Modelica Standard Library's
// Modelica.Math.Random calls as external "C" functions of ModelicaExternalC
// (ModelicaRandom.c): xorshift64*, xorshift128+ and xorshift1024* by
// Sebastiano Vigna, on states of 32-bit Integers (two per 64-bit word, low
// half first, as on the little-endian machines the library's reference
// results come from), each returning a Real in (0, 1]. mocompile provides
// them instead of linking ModelicaExternalC: the compiler folds calls with
// known arguments (symbolic), generated models evaluate the others at events.
// Header-only, dependency-free: the symbolic library includes it too, so that
// both always compute the same numbers.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string_view>

namespace mo::runtime::modelica_random {

/// A generator, by the number the flat model's call carries.
enum class Generator : int { Xorshift64star = 1, Xorshift128plus = 2, Xorshift1024star = 3 };

/// Flat models call generator g's output k (0: the Real in (0, 1]; 1..n: the
/// new state's elements) as code g * kCodeBase + k.
inline constexpr int kCodeBase = 100;

/// The ModelicaExternalC name of `g`.
constexpr std::string_view c_name(Generator g) {
  switch (g) {
  case Generator::Xorshift64star: return "ModelicaRandom_xorshift64star";
  case Generator::Xorshift128plus: return "ModelicaRandom_xorshift128plus";
  case Generator::Xorshift1024star: return "ModelicaRandom_xorshift1024star";
  }
  return "";
}

/// The generator whose ModelicaExternalC name is `name`, as an int; 0 for none.
constexpr int generator_named(std::string_view name) {
  for (const auto g : {Generator::Xorshift64star, Generator::Xorshift128plus, Generator::Xorshift1024star})
    if (name == c_name(g)) return static_cast<int>(g);
  return 0;
}

/// The number of Integers in `g`'s state (2, 4, 33: sixteen words and an index).
constexpr std::size_t state_size(Generator g) {
  switch (g) {
  case Generator::Xorshift64star: return 2;
  case Generator::Xorshift128plus: return 4;
  case Generator::Xorshift1024star: return 33;
  }
  return 0;
}

namespace detail {

inline std::uint64_t word(std::int32_t low, std::int32_t high) {
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(low)) |
         static_cast<std::uint64_t>(static_cast<std::uint32_t>(high)) << 32;
}
inline std::int32_t low(std::uint64_t w) { return static_cast<std::int32_t>(static_cast<std::uint32_t>(w)); }
inline std::int32_t high(std::uint64_t w) { return static_cast<std::int32_t>(static_cast<std::uint32_t>(w >> 32)); }

/// The 64 bits as a signed integer times 2^-64, plus 1/2: in (0, 1] (zero
/// cannot appear; doornik.com/research/randomdouble.pdf).
inline double unit(std::uint64_t w) { return static_cast<double>(static_cast<std::int64_t>(w)) * 0x1p-64 + 0.5; }

}  // namespace detail

/// One step of `g` from `in` (state_size(g) Integers): the new state into
/// `out` (same size) and the Real drawn, returned.
inline double step(Generator g, std::span<const std::int32_t> in, std::span<std::int32_t> out) {
  using namespace detail;
  switch (g) {
  case Generator::Xorshift64star: {
    std::uint64_t x = word(in[0], in[1]);
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    x *= 2685821657736338717ULL;
    out[0] = low(x);
    out[1] = high(x);
    return unit(x);
  }
  case Generator::Xorshift128plus: {
    std::uint64_t s1 = word(in[0], in[1]);
    const std::uint64_t s0 = word(in[2], in[3]);
    s1 ^= s1 << 23;
    const std::uint64_t next = (s1 ^ s0 ^ (s1 >> 17) ^ (s0 >> 26)) + s0;
    out[0] = low(s0);
    out[1] = high(s0);
    out[2] = low(next);
    out[3] = high(next);
    return unit(next);
  }
  case Generator::Xorshift1024star: {
    std::uint64_t s[16];
    for (int i = 0; i < 16; ++i) s[i] = word(in[2 * i], in[2 * i + 1]);
    int p = in[32] & 15;
    const std::uint64_t s0 = s[p];
    p = (p + 1) & 15;
    std::uint64_t s1 = s[p];
    s1 ^= s1 << 31;
    s1 ^= s1 >> 11;
    s[p] = (s0 ^ (s0 >> 30)) ^ s1;
    for (int i = 0; i < 16; ++i) {
      out[2 * i] = low(s[i]);
      out[2 * i + 1] = high(s[i]);
    }
    out[32] = p;
    return unit(s[p] * 1181783497276652981ULL);
  }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

/// The generator a flat call's code names, or nullptr-like 0 for none.
inline int generator_of(int code) {
  const int g = code / kCodeBase;
  return g >= 1 && g <= 3 ? g : 0;
}

/// Output `code % kCodeBase` of generator `code / kCodeBase` at the state
/// `args` (Integers as doubles): the Real drawn (0) or the new state's
/// element k (1-based). NaN for an unknown code, a state of the wrong size or
/// an element that is not a 32-bit Integer.
inline double value(int code, std::span<const double> args) {
  const int gi = generator_of(code);
  const int k = code % kCodeBase;
  if (gi == 0) return std::numeric_limits<double>::quiet_NaN();
  const auto g = static_cast<Generator>(gi);
  const std::size_t n = state_size(g);
  if (args.size() != n || k < 0 || static_cast<std::size_t>(k) > n) return std::numeric_limits<double>::quiet_NaN();
  std::int32_t in[33], out[33];
  for (std::size_t i = 0; i < n; ++i) {
    const double v = args[i];
    if (!(v >= -2147483648.0 && v <= 2147483647.0) || v != std::floor(v))
      return std::numeric_limits<double>::quiet_NaN();
    in[i] = static_cast<std::int32_t>(v);
  }
  const double y = step(g, std::span(in, n), std::span(out, n));
  return k == 0 ? y : static_cast<double>(out[k - 1]);
}

}  // namespace mo::runtime::modelica_random
