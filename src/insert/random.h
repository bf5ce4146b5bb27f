// Random: the portable, serialisable random-number generator of the particle factories.
// xoshiro256** (Blackman & Vigna, ACM TOMS 47(4), 2021) seeded by SplitMix64 (Steele, Lea &
// Flood, OOPSLA 2014). Own code throughout, so a seed gives the same sequence on every platform.
#pragma once

#include <array>
#include <cstdint>

namespace quarry {

// One SplitMix64 step: advances `state` and returns the next 64-bit output.
std::uint64_t splitmix64_next(std::uint64_t& state);

class Random {
 public:
  using State = std::array<std::uint64_t, 4>;

  // Seeds the four state words with successive SplitMix64 outputs of `seed` (never all zero).
  explicit Random(std::uint64_t seed);

  // Next raw 64-bit output. Cost: a handful of integer operations.
  std::uint64_t next_u64();
  // Uniform in [0, 1) with 53 random bits: (next >> 11) · 2⁻⁵³.
  double uniform();
  // Standard normal N(0, 1) by Marsaglia's polar method, with portable_log so the value is
  // identical everywhere. The second variate of each pair is discarded, so the whole generator
  // state is the four words of state() and a checkpoint restarts bit-exactly.
  double normal();

  // The complete generator state; set_state(state()) continues the sequence exactly.
  // Precondition of set_state: not all four words zero (xoshiro's one fixed point).
  State state() const { return state_; }
  void set_state(const State& state);

 private:
  State state_{};
};

}  // namespace quarry
