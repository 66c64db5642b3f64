// Deterministic random numbers for stages.
//
// Every random choice in sylva comes from an Rng obtained through StageContext::rng(stream),
// seeded from the node's explicit `seed` parameter and a stream name. xoshiro256** (Blackman &
// Vigna 2018) is written here instead of using <random>'s distributions because those are
// implementation-defined: std::uniform_real_distribution may give different numbers with another
// standard library, and outputs must be byte-identical everywhere. The generator is 20 lines.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace sylva {

class Rng {
 public:
  // Seeds the four state words from SHA-256(seed, stream) so distinct streams are independent.
  Rng(std::uint64_t seed, std::string_view stream);

  std::uint64_t next_u64();
  // Uniform in [0, 1) with 53 random bits.
  double uniform();
  // Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform in [-1, 1): the Weber–Penn "±V" variation factor.
  double signed_unit() { return uniform(-1.0, 1.0); }
  // Uniform integer in [0, n), n > 0, without modulo bias (Lemire's method).
  std::uint64_t below(std::uint64_t n);
  // Standard normal (Box–Muller, no cached second value, so the sequence is stateless per call).
  double normal();

 private:
  std::array<std::uint64_t, 4> s_{};
};

}  // namespace sylva
