// Rng: a small, fast, seedable generator (PCG32). Each pixel seeds its own from
// its coordinates, so images are bit-identical whatever the thread count.
#pragma once

#include <cstdint>

namespace glint {

class Rng {
 public:
  explicit Rng(uint64_t seed, uint64_t stream = 0) {
    inc_ = (stream << 1u) | 1u;
    next_u32();
    state_ += seed;
    next_u32();
  }
  uint32_t next_u32() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }
  // Uniform in [0, 1).
  double next_double() { return next_u32() * 0x1p-32; }

 private:
  uint64_t state_ = 0;
  uint64_t inc_ = 1;
};

// Mixes several integers into one well-distributed seed (splitmix64 finalizer).
inline uint64_t mix_seed(uint64_t a, uint64_t b = 0, uint64_t c = 0) {
  uint64_t z = a * 0x9E3779B97F4A7C15ULL ^ (b + 0x632BE59BD9B4E019ULL) * 0xBF58476D1CE4E5B9ULL ^
               (c + 0x1F83D9ABFB41BD6BULL) * 0x94D049BB133111EBULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace glint
