// Image files: .png .jpg .ppm .pfm .exr .hdr written from and read into a
// glint::Image (image/image.h), and layered EXRs.
// Writes are atomic (temp file + rename), so a failed write never damages an existing file.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "glint/image/image.h"

namespace glint {

enum class ImageFormat { png, jpg, ppm, pfm, exr, hdr };

// By extension, case-insensitive; nullopt for anything else (including no extension).
std::optional<ImageFormat> image_format_for_path(const std::filesystem::path& path);
// ".png, .jpg, .ppm, .pfm, .exr, .hdr", for error messages.
std::string_view supported_image_extensions();

// How 8-bit outputs encode linear values. Float outputs ignore all of it.
struct WriteOptions {
  double exposure = 0;  // EV: linear values are multiplied by 2^exposure first
  ToneMap tonemap = ToneMap::clamp;
  // The values are data (normals, depths already scaled to [0,1]), not light:
  // 8-bit code = round(clamp(v, 0, 1) * 255), no sRGB curve, no exposure, no tone map.
  bool data = false;
};

// Why `format` cannot hold an image of width x height, or nullopt: a JPEG
// is at most 65535 pixels a side (its header has 16 bits for each). Any
// valid_image_size fits the other formats.
std::optional<std::string> image_size_limit_reason(ImageFormat format, int width, int height);

// True for the formats that store 8-bit codes (.png .jpg .ppm); the others
// (.pfm .exr .hdr) store linear values and are never exposed or tone-mapped.
bool is_8bit_format(ImageFormat format);

// Writes `image` in the format named by the extension of `path`:
// .pfm/.exr exact linear float32, .hdr Radiance RGBE (8-bit mantissas, shared
// exponent: about 1% relative precision), .png/.jpg(quality 95)/.ppm(P6) 8-bit
// sRGB (clamped, or exposed and tone-mapped per `options`).
// Atomic: an existing file at `path` is replaced only by a complete new file.
// Throws glint::Error("<path>: cannot write: <reason>").
void write_image(const Image& image, const std::filesystem::path& path, const WriteOptions& options = {});

// A PNG compressed while its image is still being rendered, so that the
// compression overlaps the render instead of following it: threads of its
// own (8-bit codes, libpng) take each band of rows once rows_final() says
// the renderer has finished them (RenderOptions::rows_final). write(), once
// every row is final, waits for the compression and writes what
// write_image(image, path, options) would, byte for byte. Destroyed without
// write() (a cancelled or failed render) it writes nothing, and stops before
// the first row not yet final. `image` must outlive it and keep its size.
class PngStream {
 public:
  PngStream(const Image& image, const WriteOptions& options = {});
  ~PngStream();
  PngStream(const PngStream&) = delete;
  PngStream& operator=(const PngStream&) = delete;
  // Rows 0 .. rows - 1 of the image are final. Any thread; rows only grow.
  void rows_final(int rows);
  // After rows_final(image height), once: the file, as write_image writes
  // it. Throws glint::Error("<path>: cannot write: <reason>").
  void write(const std::filesystem::path& path);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The bytes write_image writes for `format`, in memory (no file involved).
std::vector<unsigned char> encode_image(const Image& image, ImageFormat format, const WriteOptions& options = {});

// One channel of a multi-channel EXR: component `component` (0..2) of `image`.
struct ExrChannel {
  std::string name;  // e.g. "R", "diffuse.G", "depth.Z"
  const Image* image = nullptr;
  int component = 0;
};
// Writes the channels (any order; EXR stores them sorted by name) as one
// float32 ZIP-compressed EXR. All images must have the same size. Atomic.
void write_exr_channels(const std::vector<ExrChannel>& channels, const std::filesystem::path& path);
// Every channel of an EXR file by name (float planes, row-major from the top),
// and its size. For tests and tools.
struct ExrPlanes {
  int width = 0, height = 0;
  std::map<std::string, std::vector<float>> planes;
};
ExrPlanes read_exr_channels(const std::filesystem::path& path);

// Reads any of the six formats back into linear floats (8-bit formats are
// sRGB-decoded). For tests and tools. Throws glint::Error("<path>: cannot read: <reason>").
Image read_image(const std::filesystem::path& path);

}  // namespace glint
