// The float image and the pixel math on it (sRGB, tone maps). Reading and
// writing image files is io/image_file.cpp.
#include "glint/image/image.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <string>

#include "glint/error.h"
#include "glint/image/srgb8.h"

namespace glint {

const Srgb8Table& srgb8_table() {
  static const Srgb8Table table;
  return table;
}

bool valid_image_size(long w, long h) {
  return w > 0 && h > 0 && w <= kMaxImageDimension && h <= kMaxImageDimension &&
         static_cast<std::size_t>(w) * static_cast<std::size_t>(h) <= kMaxImagePixels;
}

Image::Image(int w, int h) {
  if (w < 0 || h < 0 || (w > 0 && h > 0 && !valid_image_size(w, h))) {
    throw Error("invalid image size " + std::to_string(w) + "x" + std::to_string(h));
  }
  width = w;
  height = h;
  rgb.assign(3 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0f);
}

float* Image::pixel(int x, int y) {
  assert(x >= 0 && x < width && y >= 0 && y < height);
  return rgb.data() + 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x));
}

const float* Image::pixel(int x, int y) const { return const_cast<Image*>(this)->pixel(x, y); }

float tone_map(float linear, ToneMap map) {
  if (!(linear > 0.0f)) return 0.0f;  // also NaN
  const double x = linear;
  switch (map) {
    case ToneMap::clamp: return std::min(linear, 1.0f);
    case ToneMap::reinhard: return std::isinf(x) ? 1.0f : static_cast<float>(x / (1.0 + x));
    case ToneMap::aces:
      if (std::isinf(x)) return 1.0f;
      return static_cast<float>(std::clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0));
  }
  return 0.0f;
}

float srgb_encode(float linear) {
  if (!(linear > 0.0f)) return 0.0f;  // also NaN
  if (linear >= 1.0f) return 1.0f;
  const double x = linear;  // double: the float result is then correctly rounded in practice
  return static_cast<float>(x < 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055);
}

float srgb_decode(float encoded) {
  if (!(encoded > 0.0f)) return 0.0f;  // also NaN
  if (encoded >= 1.0f) return 1.0f;
  const double x = encoded;
  return static_cast<float>(x < 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
}

std::uint8_t to_srgb8(float linear) { return srgb8_with(srgb8_table(), linear); }

}  // namespace glint
