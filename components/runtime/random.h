#pragma once
// Reproducible randomness: every random draw in dmpl comes from a stream keyed by
// (seed, seq, stream id), so a lockstep run with the same seed is the same run, whatever the
// order in which messages arrive.
#include <cstdint>
#include <limits>

namespace dmpl {

// xoshiro256** seeded through SplitMix64; satisfies UniformRandomBitGenerator.
class Rng {
 public:
  using result_type = uint64_t;
  Rng(uint64_t seed, uint64_t seq, uint64_t stream);
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return std::numeric_limits<result_type>::max(); }
  result_type operator()();
  // Standard normal and uniform [0, 1) draws (implemented here, so they do not depend on the
  // standard library's distributions).
  double Normal();
  double Uniform();

 private:
  uint64_t s_[4];
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace dmpl
