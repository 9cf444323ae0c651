// The table behind to_srgb8 (image.h), for encoders that turn whole images
// into 8-bit codes: look the table up once, then srgb8_with per value
// (inline, in the encoder's loop). Internal (not installed).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace glint {

// Code k is round(encode(x) * 255): the number of code boundaries
// decode((k + 0.5) / 255) at or below x.
struct Srgb8Table {
  // boundary[255] = infinity: no code past 255.
  std::array<float, 256> boundary{};
  // The code at the start of each bucket of floats sharing their top 16 bits
  // (sign, exponent, 7 mantissa bits): a bucket spans at most one boundary.
  std::vector<std::uint8_t> bucket_code;

  Srgb8Table() {
    for (int k = 0; k < 255; ++k) {
      const double e = (k + 0.5) / 255.0;
      boundary[k] = static_cast<float>(e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4));
    }
    boundary[255] = std::numeric_limits<float>::infinity();
    const std::uint32_t buckets = std::bit_cast<std::uint32_t>(1.0f) >> 16;
    bucket_code.resize(buckets);
    for (std::uint32_t i = 0; i < buckets; ++i) {
      const float start = std::bit_cast<float>(i << 16);
      bucket_code[i] = static_cast<std::uint8_t>(std::upper_bound(boundary.begin(), boundary.begin() + 255, start) -
                                                 boundary.begin());
    }
  }
};

// One table for the program, built on first use.
const Srgb8Table& srgb8_table();

inline std::uint8_t srgb8_with(const Srgb8Table& t, float linear) {
  if (!(linear > 0.0f)) return 0;  // also NaN
  if (linear >= 1.0f) return 255;
  unsigned code = t.bucket_code[std::bit_cast<std::uint32_t>(linear) >> 16];
  // The one boundary a bucket may span, without a branch (taken half the
  // time, it was mispredicted as often); the loop is for form's sake.
  code += linear >= t.boundary[code];
  while (linear >= t.boundary[code]) ++code;
  return static_cast<std::uint8_t>(code);
}

}  // namespace glint
