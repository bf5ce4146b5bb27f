// Random: xoshiro256** step, SplitMix64 seeding, uniform and polar-method normal variates.
#include "insert/random.h"

#include <cmath>
#include <stdexcept>

#include "insert/portable_math.h"

namespace quarry {

namespace {
constexpr std::uint64_t rotate_left(std::uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}
}  // namespace

std::uint64_t splitmix64_next(std::uint64_t& state) {
  state += 0x9E3779B97F4A7C15ull;
  std::uint64_t z = state;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

Random::Random(std::uint64_t seed) {
  // SplitMix64 is a bijection of its counter, so four successive outputs are never all zero.
  for (auto& word : state_) word = splitmix64_next(seed);
}

std::uint64_t Random::next_u64() {
  const std::uint64_t result = rotate_left(state_[1] * 5, 7) * 9;
  const std::uint64_t shifted = state_[1] << 17;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= shifted;
  state_[3] = rotate_left(state_[3], 45);
  return result;
}

double Random::uniform() {
  return static_cast<double>(next_u64() >> 11) * 0x1.0p-53;
}

double Random::normal() {
  // Marsaglia & Bray (1964): (u, v) uniform in the unit disc, s = u² + v²; then
  // u·√(−2 ln s / s) is N(0, 1). Acceptance π/4, so on average 1.27 pairs per variate.
  for (;;) {
    const double u = 2.0 * uniform() - 1.0;
    const double v = 2.0 * uniform() - 1.0;
    const double s = u * u + v * v;
    if (s > 0.0 && s < 1.0) return u * std::sqrt(-2.0 * portable_log(s) / s);
  }
}

void Random::set_state(const State& state) {
  if (state[0] == 0 && state[1] == 0 && state[2] == 0 && state[3] == 0)
    throw std::invalid_argument(
        "Random::set_state: the all-zero state is not a valid xoshiro256** state");
  state_ = state;
}

}  // namespace quarry
