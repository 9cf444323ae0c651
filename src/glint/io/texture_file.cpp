#include "glint/io/texture_file.h"

#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "glint/error.h"
#include "glint/io/file_io.h"
#include "glint/io/hdr_scan.h"
#include "glint/io/image_file.h"

namespace glint {
namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
  throw Error(SourceLocation{path.string(), 0, 0}, "cannot read texture: " + reason);
}

// The reason alone from an error of read_file / read_image ("cannot read: X" -> "X").
std::string reason_of(const Error& e) {
  const std::string& m = e.message();
  const std::string prefix = "cannot read: ";
  return m.rfind(prefix, 0) == 0 ? m.substr(prefix.size()) : m;
}

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

TextureImage from_image(const Image& image) {
  TextureImage out;
  out.width = image.width;
  out.height = image.height;
  out.texels.resize(static_cast<size_t>(image.width) * static_cast<size_t>(image.height));
  for (size_t i = 0; i < out.texels.size(); ++i)
    out.texels[i] = {image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]};
  return out;
}

// stb decodes everything it knows; which loader we call decides the transfer
// function: stbi_loadf for .hdr only (it would apply a 2.2 gamma to 8-bit
// files), and our exact sRGB decode for 8- and 16-bit ones.
TextureImage decode_with_stb(const fs::path& path, const std::vector<unsigned char>& bytes, size_t memory_budget) {
  if (bytes.size() > static_cast<size_t>(std::numeric_limits<int>::max())) fail(path, "file too large");
  const auto* data = bytes.data();
  const int size = static_cast<int>(bytes.size());
  int w = 0, h = 0, channels = 0;
  // The size the header claims, checked before stb allocates and decodes it
  // (a few bytes of TGA or Radiance RLE can claim a gigabyte): the texels
  // (12 bytes a pixel) and stb's buffer (up to 12 more).
  if (stbi_info_from_memory(data, size, &w, &h, &channels) && w > 0 && h > 0) {
    const std::string excess = exceeds_budget(24.0 * w * h, memory_budget);
    if (!excess.empty()) fail(path, "an image of " + std::to_string(w) + "x" + std::to_string(h) + " pixels " + excess);
  }
  TextureImage out;
  auto reason = [] {
    const char* r = stbi_failure_reason();
    return std::string("corrupt or unsupported image: ") + (r ? r : "unknown error");
  };
  auto allocate = [&] {
    out.width = w;
    out.height = h;
    out.texels.resize(static_cast<size_t>(w) * static_cast<size_t>(h));
  };
  if (stbi_is_hdr_from_memory(data, size)) {
    if (!hdr_decoding_ends(data, bytes.size())) fail(path, std::string("corrupt or unsupported image: ") + kHdrEndless);
    const std::unique_ptr<float, StbFree> p(stbi_loadf_from_memory(data, size, &w, &h, &channels, 3));
    if (!p) fail(path, reason());
    allocate();
    for (size_t i = 0; i < out.texels.size(); ++i)
      out.texels[i] = {p.get()[3 * i], p.get()[3 * i + 1], p.get()[3 * i + 2]};
  } else if (stbi_is_16_bit_from_memory(data, size)) {
    const std::unique_ptr<stbi_us, StbFree> p(stbi_load_16_from_memory(data, size, &w, &h, &channels, 3));
    if (!p) fail(path, reason());
    allocate();
    auto decode = [](stbi_us x) { return srgb_decode(static_cast<float>(x / 65535.0)); };
    for (size_t i = 0; i < out.texels.size(); ++i)
      out.texels[i] = {decode(p.get()[3 * i]), decode(p.get()[3 * i + 1]), decode(p.get()[3 * i + 2])};
  } else {
    const std::unique_ptr<stbi_uc, StbFree> p(stbi_load_from_memory(data, size, &w, &h, &channels, 3));
    if (!p) fail(path, reason());
    allocate();
    std::array<float, 256> linear;
    for (int i = 0; i < 256; ++i) linear[i] = srgb_decode(static_cast<float>(i / 255.0));
    for (size_t i = 0; i < out.texels.size(); ++i)
      out.texels[i] = {linear[p.get()[3 * i]], linear[p.get()[3 * i + 1]], linear[p.get()[3 * i + 2]]};
  }
  return out;
}

}  // namespace

const char* supported_texture_extensions() { return ".png, .jpg, .jpeg, .bmp, .tga, .hdr, .exr, .pfm"; }

TextureImage load_texture_image(const fs::path& path, size_t memory_budget) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  try {
    std::error_code ec;
    if (!fs::exists(path, ec)) fail(path, "file not found");
    if (fs::is_directory(path, ec)) fail(path, "is a directory");
    // Not a device or a pipe: those could be endless (/dev/zero).
    if (!fs::is_regular_file(path, ec)) fail(path, "not a regular file");
    TextureImage out;
    if (ext == ".exr" || ext == ".pfm") {
      try {
        out = from_image(read_image(path));
      } catch (const Error& e) {
        fail(path, reason_of(e));
      }
    } else if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tga" || ext == ".hdr") {
      std::vector<unsigned char> bytes;
      try {
        bytes = read_file(path);
      } catch (const Error& e) {
        fail(path, reason_of(e));
      }
      if (bytes.empty()) fail(path, "the file is empty");
      out = decode_with_stb(path, bytes, memory_budget);
    } else {
      fail(path, "unsupported format '" + path.extension().string() +
                     "' (supported: " + supported_texture_extensions() + ")");
    }
    if (out.width <= 0 || out.height <= 0) fail(path, "the image is empty");
    // A texel replaces a reflectance, which must be finite and >= 0 (as a
    // color in the scene): float formats (.exr, .pfm) can hold anything.
    for (size_t i = 0; i < out.texels.size(); ++i) {
      const Vec3f& t = out.texels[i];
      if (std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z) && t.x >= 0 && t.y >= 0 && t.z >= 0) continue;
      const size_t w = static_cast<size_t>(out.width);
      const bool finite = std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z);
      fail(path, "texel (" + std::to_string(i % w) + ", " + std::to_string(i / w) + ") from the top-left " +
                     (finite ? "is negative (a reflectance must be >= 0)" : "is not a finite number"));
    }
    out.file = path.string();
    return out;
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(path, "out of memory");
  }
}

}  // namespace glint
