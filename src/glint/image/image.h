// glint::Image and its file formats: the float RGB frame the renderer fills,
// the sRGB transfer functions, and reading/writing .png .jpg .ppm .pfm .exr.
// Writes are atomic (temp file + rename), so a failed write never damages an existing file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>
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

enum class ImageFormat { png, jpg, ppm, pfm, exr };

// By extension, case-insensitive; nullopt for anything else (including no extension).
std::optional<ImageFormat> image_format_for_path(const std::filesystem::path& path);
// ".png, .jpg, .ppm, .pfm, .exr", for error messages.
std::string_view supported_image_extensions();

// Clamp to [0,1] (NaN -> 0) then the standard sRGB OETF.
float srgb_encode(float linear);
// The inverse of srgb_encode; input clamped to [0,1] (NaN -> 0).
float srgb_decode(float encoded);
// round(srgb_encode(linear) * 255); NaN -> 0.
std::uint8_t to_srgb8(float linear);

// Writes `image` in the format named by the extension of `path`:
// .pfm/.exr exact linear float32, .png/.jpg(quality 95)/.ppm(P6) clamped 8-bit sRGB.
// Atomic: an existing file at `path` is replaced only by a complete new file.
// Throws glint::Error("<path>: cannot write: <reason>").
void write_image(const Image& image, const std::filesystem::path& path);

// Reads any of the five formats back into linear floats (8-bit formats are
// sRGB-decoded). For tests and tools. Throws glint::Error("<path>: cannot read: <reason>").
Image read_image(const std::filesystem::path& path);

}  // namespace glint
