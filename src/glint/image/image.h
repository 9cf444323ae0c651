// glint::Image: the float RGB frame the renderer fills, and the pixel math on
// it (the sRGB transfer functions, tone maps). Plain data: reading and writing
// image files is io/image_file.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace glint {

// An RGB float image, row 0 at the top, 3 floats per pixel, linear values.
struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // size 3*width*height, row-major from the top row

  Image() = default;
  // Zero-filled. Throws glint::Error for negative or absurdly large sizes.
  Image(int w, int h);

  float* pixel(int x, int y);
  const float* pixel(int x, int y) const;
};

// Keeps 3*width*height within int (stb and tinyexr take int sizes) and stops a
// corrupt header from asking for an absurd allocation.
inline constexpr std::size_t kMaxImagePixels = std::size_t{1} << 28;
inline constexpr long kMaxImageDimension = 1L << 20;
// Both sides > 0 and within the limits above: a size an image file may have.
bool valid_image_size(long width, long height);

// Clamp to [0,1] (NaN -> 0) then the standard sRGB OETF.
float srgb_encode(float linear);
// The inverse of srgb_encode; input clamped to [0,1] (NaN -> 0).
float srgb_decode(float encoded);
// round(srgb_encode(linear) * 255); NaN -> 0.
std::uint8_t to_srgb8(float linear);

// How an 8-bit output maps linear values above 1 into [0, 1] (per channel,
// after exposure, before the sRGB curve). clamp is the contract's behaviour.
enum class ToneMap { clamp, reinhard, aces };

// Reinhard x/(1+x); ACES: Krzysztof Narkowicz's fit of the ACES filmic curve,
// x(2.51x+0.03) / (x(2.43x+0.59)+0.14), clamped to [0, 1]. Negative and NaN -> 0.
float tone_map(float linear, ToneMap map);

}  // namespace glint
