// Image file I/O: every format is first encoded into memory, then one routine
// writes the bytes to a temp file beside the target and renames it over the
// target, so a failure at any step leaves an existing output file untouched.
#include "glint/io/image_file.h"

#include <fcntl.h>
#include <png.h>
#include <stb_image.h>
#include <stb_image_write.h>
#include <sys/stat.h>
#include <tinyexr.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cassert>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <new>
#include <span>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>

#include "glint/error.h"
#include "glint/image/srgb8.h"
#include "glint/io/file_io.h"
#include "glint/io/hdr_scan.h"

namespace glint {
namespace fs = std::filesystem;

namespace {

using Bytes = std::vector<unsigned char>;

// Runs `body`; any exception but a glint::Error becomes one naming `path`
// (through `fail`: fail_read or fail_write), so callers see one error type.
template <class Body>
auto naming_the_file(const fs::path& path, void (*fail)(const fs::path&, const std::string&), Body&& body)
    -> decltype(body()) {
  try {
    return body();
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(path, "out of memory");
  } catch (const std::exception& e) {
    fail(path, e.what());
  }
  __builtin_unreachable();  // fail_read and fail_write throw
}

std::string unsupported_extension_reason(const fs::path& path) {
  const std::string ext = path.extension().string();
  return (ext.empty() ? std::string("no file extension") : "unsupported image extension '" + ext + "'") +
         " (supported: " + std::string(supported_image_extensions()) + ")";
}

// --- encoders ---------------------------------------------------------------

// Fewer 8-bit codes than this are made on the calling thread alone.
constexpr size_t kCodesForThreads = size_t{1} << 18;

// Runs body(begin, end) over [0, n) in one piece per core. The 8-bit codes
// of a 1080p image are 6.2M table lookups, 10-20 ms on one core.
template <class Body>
void for_each_range(size_t n, const Body& body) {
  const size_t threads = n < kCodesForThreads ? 1 : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::jthread> pool;
  for (size_t t = 1; t < threads; ++t)
    pool.emplace_back([&body, n, t, threads] { body(n * t / threads, n * (t + 1) / threads); });
  body(0, n / threads);
}

// The 8-bit codes of values [begin, end) of an image into out[begin, end):
// sRGB-encoded light, or data scaled by 255.
void encode8(const Image& image, const WriteOptions& options, std::uint8_t* out, size_t begin, size_t end) {
  const float* in = image.rgb.data();
  if (!options.data && (options.exposure != 0.0 || options.tonemap != ToneMap::clamp)) {
    const float scale = static_cast<float>(std::exp2(options.exposure));
    const Srgb8Table& table = srgb8_table();
    for (size_t i = begin; i < end; ++i) out[i] = srgb8_with(table, tone_map(in[i] * scale, options.tonemap));
  } else if (options.data) {
    for (size_t i = begin; i < end; ++i) {
      const float v = in[i];
      out[i] = !(v > 0.0f) ? 0 : v >= 1.0f ? 255 : static_cast<std::uint8_t>(std::lround(v * 255.0f));
    }
  } else {
    const Srgb8Table& table = srgb8_table();
    for (size_t i = begin; i < end; ++i) out[i] = srgb8_with(table, in[i]);
  }
}

// The 8-bit codes of an image, on every core.
Bytes pixels8(const Image& image, const WriteOptions& options) {
  Bytes out(image.rgb.size());
  for_each_range(out.size(), [&](size_t begin, size_t end) { encode8(image, options, out.data(), begin, end); });
  return out;
}

// Waits until `value` is at least `n` or negative (abandoned); returns it.
int wait_for_at_least(const std::atomic<int>& value, int n) {
  int now = value.load(std::memory_order_acquire);
  for (; now >= 0 && now < n; now = value.load(std::memory_order_acquire)) value.wait(now, std::memory_order_acquire);
  return now;
}

// The 8-bit rows of an image for the PNG encoder, made by a helper thread a
// band at a time while libpng compresses the bands before: each of the two
// is about half of writing a big PNG, so they overlap instead of adding up.
// Small images are encoded at once. With `available` (a PngStream's), a band
// is made only once that many rows of the image are final; a negative
// value abandons the rows (row() then returns nullptr).
class PngRows {
 public:
  PngRows(const Image& image, const WriteOptions& options, const std::atomic<int>* available = nullptr)
      : stride_(3 * static_cast<size_t>(image.width)), codes_(new std::uint8_t[image.rgb.size()]) {
    if (!available && image.rgb.size() < kCodesForThreads) {
      encode8(image, options, codes_.get(), 0, image.rgb.size());
      ready_ = image.height;
      return;
    }
    srgb8_table();  // built here: the helper thread must not throw
    converter_ = std::jthread([this, &image, &options, available] {
      constexpr int kBandRows = 16;
      for (int y0 = 0; y0 < image.height; y0 += kBandRows) {
        const int y1 = std::min(image.height, y0 + kBandRows);
        if (available && wait_for_at_least(*available, y1) < 0) {
          ready_.store(-1, std::memory_order_release);
          ready_.notify_all();
          return;
        }
        encode8(image, options, codes_.get(), stride_ * static_cast<size_t>(y0), stride_ * static_cast<size_t>(y1));
        ready_.store(y1, std::memory_order_release);
        ready_.notify_all();
      }
    });
  }
  // Row y, once the helper has made it; nullptr when the rows were abandoned.
  const std::uint8_t* row(int y) {
    return wait_for_at_least(ready_, y + 1) < 0 ? nullptr : codes_.get() + stride_ * static_cast<size_t>(y);
  }

 private:
  size_t stride_;
  std::unique_ptr<std::uint8_t[]> codes_;  // not zeroed: each row is written once, by whoever makes it
  std::atomic<int> ready_{0};              // rows made so far; -1: abandoned
  std::jthread converter_;                 // last: joined before the rows are freed
};

void append(Bytes& out, std::string_view text) { out.insert(out.end(), text.begin(), text.end()); }

Bytes encode_ppm(const Image& image, const WriteOptions& options) {
  Bytes out;
  append(out, "P6\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n255\n");
  const Bytes pixels = pixels8(image, options);
  out.insert(out.end(), pixels.begin(), pixels.end());
  return out;
}

Bytes encode_pfm(const Image& image) {
  Bytes out;
  // Scale -1.0: little-endian samples, written byte by byte so the host's byte order doesn't matter.
  append(out, "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n");
  const std::size_t row_floats = 3 * static_cast<std::size_t>(image.width);
  out.reserve(out.size() + 4 * image.rgb.size());
  for (int y = image.height - 1; y >= 0; --y) {  // PFM stores the bottom row first
    const float* row = image.rgb.data() + row_floats * static_cast<std::size_t>(y);
    for (std::size_t i = 0; i < row_floats; ++i) {
      const auto bits = std::bit_cast<std::uint32_t>(row[i]);
      for (int b = 0; b < 4; ++b) out.push_back(static_cast<unsigned char>(bits >> (8 * b)));
    }
  }
  return out;
}

// stb_image_write calls back from C code: an exception must not unwind through
// it, so the sink records the failure instead of throwing.
struct StbSink {
  Bytes bytes;
  bool failed = false;
};

void stb_append(void* context, void* data, int size) noexcept {
  auto* sink = static_cast<StbSink*>(context);
  if (sink->failed || size <= 0) return;
  try {
    const auto* p = static_cast<const unsigned char*>(data);
    sink->bytes.insert(sink->bytes.end(), p, p + size);
  } catch (...) {
    sink->failed = true;
  }
}

Bytes encode_jpg(const Image& image, const WriteOptions& options) {
  const Bytes pixels = pixels8(image, options);
  StbSink sink;
  const int ok = stbi_write_jpg_to_func(stb_append, &sink, image.width, image.height, 3, pixels.data(), 95);
  if (sink.failed) throw std::bad_alloc();
  if (!ok || sink.bytes.empty()) throw std::runtime_error("JPEG encoding failed");
  return std::move(sink.bytes);
}

// libpng reports errors by longjmp: nothing with a destructor may be created
// between setjmp and the calls that can fail, and nothing may throw through it.
struct PngSink {
  Bytes bytes;
  bool failed = false;
  const char* message = "PNG encoding failed";
};

void png_append(png_structp png, png_bytep data, size_t size) noexcept {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  if (sink->failed) return;
  try {
    sink->bytes.insert(sink->bytes.end(), data, data + size);
  } catch (...) {
    sink->failed = true;
  }
}
void png_flush_nothing(png_structp) noexcept {}
void png_fail(png_structp png, png_const_charp message) {
  static_cast<PngSink*>(png_get_error_ptr(png))->message = message;
  png_longjmp(png, 1);
}
void png_ignore_warning(png_structp, png_const_charp) {}

// libpng at zlib level 1, the Up filter and run lengths only (Z_RLE): a
// render's PNG is written for speed, not size (stb_image_write was several
// times slower; docs/performance.md). False when `available` abandoned the
// rows before the last (nothing in `out` then).
bool encode_png_into(const Image& image, const WriteOptions& options, const std::atomic<int>* available, Bytes& out) {
  PngRows rows(image, options, available);  // before setjmp: a longjmp skips no destructor of it
  PngSink sink;
  sink.bytes.reserve(image.rgb.size() / 4);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, png_fail, png_ignore_warning);
  if (!png) throw std::bad_alloc();
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::bad_alloc();
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error(sink.message);
  }
  png_set_write_fn(png, &sink, png_append, png_flush_nothing);
  // libpng refuses sides over 1,000,000 pixels unless told otherwise; an
  // image may have up to kMaxImageDimension.
  png_set_user_limits(png, static_cast<png_uint_32>(kMaxImageDimension), static_cast<png_uint_32>(kMaxImageDimension));
  png_set_compression_level(png, 1);
  png_set_compression_strategy(png, Z_RLE);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* row = rows.row(y);
    if (!row) {
      png_destroy_write_struct(&png, &info);
      return false;
    }
    png_write_row(png, const_cast<png_bytep>(row));
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (sink.failed) throw std::bad_alloc();
  out = std::move(sink.bytes);
  return true;
}

Bytes encode_png(const Image& image, const WriteOptions& options) {
  Bytes out;
  encode_png_into(image, options, nullptr, out);
  return out;
}

struct FreeDeleter {
  void operator()(void* p) const { std::free(p); }
};
struct ExrErrorDeleter {
  void operator()(const char* p) const { FreeEXRErrorMessage(p); }
};
using ExrErrorText = std::unique_ptr<const char, ExrErrorDeleter>;

struct MallocBytes {
  std::unique_ptr<unsigned char, FreeDeleter> data;
  std::size_t size = 0;
};

// tinyexr (not OpenEXR): same ZIP compression and file size, bit-exact, 30x
// smaller dependency; OpenEXR is only faster when its thread pool is used.
MallocBytes encode_exr_channels(std::vector<ExrChannel> channels, int width, int height) {
  // tinyexr writes channels in the given order and EXR readers expect them
  // sorted by name (R, G, B go B, G, R).
  std::sort(channels.begin(), channels.end(),
            [](const ExrChannel& a, const ExrChannel& b) { return std::strcmp(a.name.c_str(), b.name.c_str()) < 0; });
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const std::size_t count = channels.size();
  std::vector<std::vector<float>> planes(count);
  std::vector<EXRChannelInfo> infos(count);
  for (std::size_t c = 0; c < count; ++c) {
    const ExrChannel& ch = channels[c];
    if (!ch.image || ch.image->width != width || ch.image->height != height || ch.component < 0 || ch.component > 2 ||
        ch.name.empty() || ch.name.size() >= sizeof(infos[c].name))
      throw std::runtime_error("invalid EXR channel '" + ch.name + "'");
    planes[c].resize(n);
    for (std::size_t i = 0; i < n; ++i) planes[c][i] = ch.image->rgb[3 * i + static_cast<std::size_t>(ch.component)];
    std::memcpy(infos[c].name, ch.name.c_str(), ch.name.size() + 1);
    infos[c].x_sampling = infos[c].y_sampling = 1;
  }
  // 32-bit float samples, so every value round-trips exactly.
  std::vector<int> pixel_types(count, TINYEXR_PIXELTYPE_FLOAT);
  std::vector<int> requested_types = pixel_types;

  // The header points at our arrays, so it must not be passed to FreeEXRHeader.
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = static_cast<int>(count);
  header.channels = infos.data();
  header.pixel_types = pixel_types.data();
  header.requested_pixel_types = requested_types.data();
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;  // lossless, OpenEXR's own default

  std::vector<unsigned char*> plane_pointers(count);
  for (std::size_t c = 0; c < count; ++c) plane_pointers[c] = reinterpret_cast<unsigned char*>(planes[c].data());
  EXRImage exr;
  InitEXRImage(&exr);
  exr.images = plane_pointers.data();
  exr.num_channels = static_cast<int>(count);
  exr.width = width;
  exr.height = height;

  unsigned char* memory = nullptr;
  const char* raw_error = nullptr;
  MallocBytes out;
  out.size = SaveEXRImageToMemory(&exr, &header, &memory, &raw_error);
  out.data.reset(memory);
  const ExrErrorText error(raw_error);
  if (out.size == 0 || !out.data) {
    throw std::runtime_error(std::string("EXR encoding failed") + (error ? ": " + std::string(error.get()) : ""));
  }
  return out;
}

MallocBytes encode_exr(const Image& image) {
  return encode_exr_channels({{"R", &image, 0}, {"G", &image, 1}, {"B", &image, 2}}, image.width, image.height);
}

Bytes encode_hdr(const Image& image) {
  StbSink sink;
  const int ok = stbi_write_hdr_to_func(stb_append, &sink, image.width, image.height, 3, image.rgb.data());
  if (sink.failed) throw std::bad_alloc();
  if (!ok || sink.bytes.empty()) throw std::runtime_error("Radiance HDR encoding failed");
  return std::move(sink.bytes);
}

// --- decoders ---------------------------------------------------------------

// Walks the text header shared by PPM and PFM: whitespace-separated tokens,
// '#' comments (a PPM feature; harmless for PFM), and the single whitespace
// byte that separates the header from binary data.
class NetpbmHeader {
 public:
  NetpbmHeader(const Bytes& bytes, std::size_t start) : bytes_(bytes), pos_(start) {}

  std::string token() {
    for (;;) {
      while (pos_ < bytes_.size() && std::isspace(bytes_[pos_])) ++pos_;
      if (pos_ < bytes_.size() && bytes_[pos_] == '#') {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n' && bytes_[pos_] != '\r') ++pos_;
        continue;
      }
      break;
    }
    const std::size_t begin = pos_;
    while (pos_ < bytes_.size() && !std::isspace(bytes_[pos_]) && pos_ - begin < 64) ++pos_;
    return std::string(bytes_.begin() + static_cast<std::ptrdiff_t>(begin),
                       bytes_.begin() + static_cast<std::ptrdiff_t>(pos_));
  }
  // Returns -1 unless the next token is a plain decimal number in [0, max].
  long number(long max) {
    const std::string t = token();
    if (t.empty() || t.size() > 9 || !std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return -1;
    }
    const long value = std::stol(t);
    return value <= max ? value : -1;
  }
  // The header ends with exactly one whitespace byte; returns where data starts.
  std::optional<std::size_t> data_start() const {
    if (pos_ >= bytes_.size() || !std::isspace(bytes_[pos_])) return std::nullopt;
    return pos_ + 1;
  }

 private:
  const Bytes& bytes_;
  std::size_t pos_;
};

void check_data_size(const fs::path& path, const char* format, std::size_t expected, std::size_t found) {
  if (found < expected) {
    fail_read(path, std::string("truncated ") + format + " data: expected " + std::to_string(expected) +
                        " bytes of pixels, found " + std::to_string(found));
  }
  if (found > expected) {
    fail_read(path, std::string("corrupt ") + format + " file: " + std::to_string(found - expected) +
                        " unexpected bytes after the pixels");
  }
}

Image decode_ppm(const fs::path& path, const Bytes& bytes) {
  if (bytes.size() < 2 || bytes[0] != 'P' || bytes[1] != '6') fail_read(path, "not a binary PPM (P6) file");
  NetpbmHeader header(bytes, 2);
  const long w = header.number(kMaxImageDimension);
  const long h = header.number(kMaxImageDimension);
  const long maxval = header.number(65535);
  const auto start = header.data_start();
  if (w < 0 || h < 0 || maxval < 1 || !start) fail_read(path, "corrupt PPM header");
  if (!valid_image_size(w, h)) fail_read(path, "invalid PPM size " + std::to_string(w) + "x" + std::to_string(h));

  const std::size_t sample_bytes = maxval > 255 ? 2 : 1;  // 16-bit samples are big-endian
  // The data first: a header of a few bytes can claim gigabytes.
  check_data_size(path, "PPM", 3 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * sample_bytes,
                  bytes.size() - *start);
  Image image(static_cast<int>(w), static_cast<int>(h));
  const unsigned char* p = bytes.data() + *start;
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    const unsigned value = sample_bytes == 2 ? (unsigned{p[2 * i]} << 8) | p[2 * i + 1] : p[i];
    image.rgb[i] = srgb_decode(static_cast<float>(std::min<unsigned>(value, maxval)) / static_cast<float>(maxval));
  }
  return image;
}

Image decode_pfm(const fs::path& path, const Bytes& bytes) {
  if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != 'F' && bytes[1] != 'f')) fail_read(path, "not a PFM file");
  const int channels = bytes[1] == 'F' ? 3 : 1;  // "Pf" is greyscale
  NetpbmHeader header(bytes, 2);
  const long w = header.number(kMaxImageDimension);
  const long h = header.number(kMaxImageDimension);
  const std::string scale_text = header.token();
  const auto start = header.data_start();
  char* end = nullptr;
  const double scale = scale_text.empty() ? 0.0 : std::strtod(scale_text.c_str(), &end);
  if (w < 0 || h < 0 || !start || scale_text.empty() || *end != '\0' || !std::isfinite(scale) || scale == 0.0) {
    fail_read(path, "corrupt PFM header");
  }
  if (!valid_image_size(w, h)) fail_read(path, "invalid PFM size " + std::to_string(w) + "x" + std::to_string(h));

  // The data the header claims must be there before the image is made: a
  // header of a few bytes can claim gigabytes.
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  check_data_size(path, "PFM", pixels * static_cast<std::size_t>(channels) * 4, bytes.size() - *start);
  Image image(static_cast<int>(w), static_cast<int>(h));
  const bool little_endian = scale < 0.0;  // the sign of the scale gives the byte order
  const unsigned char* p = bytes.data() + *start;
  for (long file_row = 0; file_row < h; ++file_row) {
    float* row = image.pixel(0, static_cast<int>(h - 1 - file_row));  // bottom row first
    for (long x = 0; x < w; ++x) {
      for (int c = 0; c < channels; ++c, p += 4) {
        std::uint32_t bits = 0;
        for (int b = 0; b < 4; ++b) bits |= std::uint32_t{p[little_endian ? b : 3 - b]} << (8 * b);
        const float value = std::bit_cast<float>(bits);
        if (channels == 3) {
          row[3 * x + c] = value;
        } else {
          row[3 * x] = row[3 * x + 1] = row[3 * x + 2] = value;
        }
      }
    }
  }
  return image;
}

Image decode_stb(const fs::path& path, const Bytes& bytes) {
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) fail_read(path, "file too large");
  int w = 0, h = 0, file_channels = 0;
  struct StbiDeleter {
    void operator()(stbi_uc* p) const { stbi_image_free(p); }
  };
  const std::unique_ptr<stbi_uc, StbiDeleter> pixels(
      stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &file_channels, 3));
  if (!pixels) {
    const char* reason = stbi_failure_reason();
    fail_read(path, std::string("corrupt image: ") + (reason ? reason : "unknown error"));
  }
  if (!valid_image_size(w, h)) fail_read(path, "invalid image size " + std::to_string(w) + "x" + std::to_string(h));
  std::array<float, 256> linear;
  for (int i = 0; i < 256; ++i) linear[i] = srgb_decode(static_cast<float>(i) / 255.0f);
  Image image(w, h);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = linear[pixels.get()[i]];
  return image;
}

// Every float (or half, widened exactly) channel of a scanline EXR; UINT
// channels are listed in `uint_channels` and not loaded as floats.
ExrPlanes decode_exr_planes(const fs::path& path, const Bytes& bytes, std::vector<std::string>* uint_channels) {
  EXRVersion version;
  if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS) {
    fail_read(path, "not an OpenEXR file");
  }
  if (version.multipart || version.non_image) fail_read(path, "multi-part and deep EXR files are not supported");

  struct HeaderGuard {
    EXRHeader header;
    HeaderGuard() { InitEXRHeader(&header); }
    ~HeaderGuard() { FreeEXRHeader(&header); }
  } parsed;
  EXRHeader& header = parsed.header;
  const char* raw_error = nullptr;
  if (ParseEXRHeaderFromMemory(&header, &version, bytes.data(), bytes.size(), &raw_error) != TINYEXR_SUCCESS) {
    const ExrErrorText error(raw_error);
    fail_read(path, std::string("corrupt EXR header") + (error ? ": " + std::string(error.get()) : ""));
  }
  if (header.tiled) fail_read(path, "tiled EXR files are not supported");
  // tinyexr sizes its tables from the data window before it reads a pixel:
  // a window whose size overflows an int asked for 2^63 bytes. Its size is
  // checked here, in 64 bits, as every image's is.
  const EXRBox2i& window = header.data_window;
  const long long w = static_cast<long long>(window.max_x) - window.min_x + 1;
  const long long h = static_cast<long long>(window.max_y) - window.min_y + 1;
  if (!valid_image_size(static_cast<long>(w), static_cast<long>(h)))
    fail_read(path, "invalid EXR data window " + std::to_string(w) + "x" + std::to_string(h));
  for (int c = 0; c < header.num_channels; ++c) {
    const EXRChannelInfo& channel = header.channels[c];
    if (channel.x_sampling != 1 || channel.y_sampling != 1)
      fail_read(path, "subsampled EXR channels are not supported");
    if (header.pixel_types[c] == TINYEXR_PIXELTYPE_UINT && uint_channels) uint_channels->push_back(channel.name);
    // Half channels widen to float exactly.
    if (header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF) header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  }

  struct ImageGuard {
    EXRImage image;
    ImageGuard() { InitEXRImage(&image); }
    ~ImageGuard() { FreeEXRImage(&image); }
  } loaded;
  raw_error = nullptr;
  // When the pixel data fail to decode, tinyexr (1.0.1) frees the image
  // itself, by its channel count, which it sets only on success, and leaves
  // the pointers set: the channels leaked and the guard freed the array a
  // second time. With the count given beforehand its free is whole, and the
  // image is reset after it.
  loaded.image.num_channels = header.num_channels;
  if (LoadEXRImageFromMemory(&loaded.image, &header, bytes.data(), bytes.size(), &raw_error) != TINYEXR_SUCCESS) {
    InitEXRImage(&loaded.image);
    const ExrErrorText error(raw_error);
    fail_read(path, std::string("corrupt EXR data") + (error ? ": " + std::string(error.get()) : ""));
  }
  const EXRImage& exr = loaded.image;
  if (!valid_image_size(exr.width, exr.height) || !exr.images) fail_read(path, "invalid EXR size");
  ExrPlanes out;
  out.width = exr.width;
  out.height = exr.height;
  const std::size_t n = static_cast<std::size_t>(exr.width) * static_cast<std::size_t>(exr.height);
  for (int c = 0; c < header.num_channels; ++c) {
    if (header.pixel_types[c] == TINYEXR_PIXELTYPE_UINT) continue;
    const auto* plane = reinterpret_cast<const float*>(exr.images[c]);
    out.planes[header.channels[c].name].assign(plane, plane + n);
  }
  return out;
}

Image decode_hdr(const fs::path& path, const Bytes& bytes) {
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) fail_read(path, "file too large");
  const int size = static_cast<int>(bytes.size());
  // stbi_loadf would also take a PNG and undo a gamma it guesses: only real
  // Radiance files are read here.
  if (!stbi_is_hdr_from_memory(bytes.data(), size)) fail_read(path, "not a Radiance HDR file");
  if (!hdr_decoding_ends(bytes.data(), bytes.size())) fail_read(path, std::string("corrupt image: ") + kHdrEndless);
  int w = 0, h = 0, file_channels = 0;
  struct StbiDeleter {
    void operator()(float* p) const { stbi_image_free(p); }
  };
  const std::unique_ptr<float, StbiDeleter> pixels(
      stbi_loadf_from_memory(bytes.data(), size, &w, &h, &file_channels, 3));
  if (!pixels) {
    const char* reason = stbi_failure_reason();
    fail_read(path, std::string("corrupt image: ") + (reason ? reason : "unknown error"));
  }
  if (!valid_image_size(w, h)) fail_read(path, "invalid image size " + std::to_string(w) + "x" + std::to_string(h));
  Image image(w, h);
  std::copy(pixels.get(), pixels.get() + image.rgb.size(), image.rgb.begin());
  return image;
}

Image decode_exr(const fs::path& path, const Bytes& bytes) {
  std::vector<std::string> uint_channels;
  const ExrPlanes exr = decode_exr_planes(path, bytes, &uint_channels);
  for (const std::string& name : uint_channels)
    if (name == "R" || name == "G" || name == "B") fail_read(path, "EXR channel R/G/B is UINT, not float");
  const auto r = exr.planes.find("R"), g = exr.planes.find("G"), b = exr.planes.find("B");
  if (r == exr.planes.end() || g == exr.planes.end() || b == exr.planes.end())
    fail_read(path, "EXR file has no R, G and B channels");
  Image image(exr.width, exr.height);
  const std::array<const std::vector<float>*, 3> planes = {&r->second, &g->second, &b->second};
  const std::size_t n = static_cast<std::size_t>(exr.width) * static_cast<std::size_t>(exr.height);
  for (std::size_t c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < n; ++i) image.rgb[3 * i + c] = (*planes[c])[i];
  return image;
}

}  // namespace

// --- public API -------------------------------------------------------------

std::optional<ImageFormat> image_format_for_path(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".png") return ImageFormat::png;
  if (ext == ".jpg") return ImageFormat::jpg;
  if (ext == ".ppm") return ImageFormat::ppm;
  if (ext == ".pfm") return ImageFormat::pfm;
  if (ext == ".exr") return ImageFormat::exr;
  if (ext == ".hdr") return ImageFormat::hdr;
  return std::nullopt;
}

std::optional<std::string> image_size_limit_reason(ImageFormat format, int width, int height) {
  constexpr int kMaxJpegSide = 65535;
  if (format == ImageFormat::jpg && (width > kMaxJpegSide || height > kMaxJpegSide))
    return "a JPEG is at most " + std::to_string(kMaxJpegSide) + " pixels wide and high, not " + std::to_string(width) +
           "x" + std::to_string(height);
  return std::nullopt;
}

std::string_view supported_image_extensions() { return ".png, .jpg, .ppm, .pfm, .exr, .hdr"; }

bool is_8bit_format(ImageFormat format) {
  return format == ImageFormat::png || format == ImageFormat::jpg || format == ImageFormat::ppm;
}

namespace {

// What write_image checks before it encodes: a known extension, an image of
// a valid size, an existing folder, no directory in the way.
ImageFormat check_image_target(const Image& image, const fs::path& path) {
  const auto format = image_format_for_path(path);
  if (!format) fail_write(path, unsupported_extension_reason(path));
  if (!valid_image_size(image.width, image.height)) {
    fail_write(path, "invalid image size " + std::to_string(image.width) + "x" + std::to_string(image.height));
  }
  if (image.rgb.size() != 3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
    fail_write(path, "image has " + std::to_string(image.rgb.size()) + " floats, expected 3*" +
                         std::to_string(image.width) + "*" + std::to_string(image.height));
  }
  if (auto reason = image_size_limit_reason(*format, image.width, image.height)) fail_write(path, *reason);
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  if (!fs::exists(folder, ec)) fail_write(path, "folder '" + folder.string() + "' does not exist");
  if (!fs::is_directory(folder, ec)) fail_write(path, "'" + folder.string() + "' is not a folder");
  if (fs::is_directory(path, ec)) fail_write(path, "it is a directory");
  return *format;
}

}  // namespace

void write_image(const Image& image, const fs::path& path, const WriteOptions& options) {
  return naming_the_file(path, fail_write, [&] {
    switch (check_image_target(image, path)) {
      case ImageFormat::ppm: write_file_atomically(path, encode_ppm(image, options), Flush::no); break;
      case ImageFormat::pfm: write_file_atomically(path, encode_pfm(image), Flush::no); break;
      case ImageFormat::png: write_file_atomically(path, encode_png(image, options), Flush::no); break;
      case ImageFormat::jpg: write_file_atomically(path, encode_jpg(image, options), Flush::no); break;
      case ImageFormat::exr: {
        const MallocBytes exr = encode_exr(image);
        write_file_atomically(path, {exr.data.get(), exr.size}, Flush::no);
        break;
      }
      case ImageFormat::hdr: write_file_atomically(path, encode_hdr(image), Flush::no); break;
    }
  });
}

struct PngStream::State {
  const Image& image;
  WriteOptions options;
  std::atomic<int> final_rows{0};  // -1: abandoned
  Bytes bytes;
  bool complete = false;
  std::exception_ptr error;
  std::jthread encoder;  // last: joined first
};

PngStream::PngStream(const Image& image, const WriteOptions& options)
    : state_(new State{image, options, {}, {}, false, {}, {}}) {
  State& s = *state_;
  s.encoder = std::jthread([&s] {
    try {
      s.complete = encode_png_into(s.image, s.options, &s.final_rows, s.bytes);
    } catch (...) {
      s.error = std::current_exception();
    }
  });
}

PngStream::~PngStream() {
  if (state_->encoder.joinable()) {
    state_->final_rows.store(-1, std::memory_order_release);
    state_->final_rows.notify_all();
  }
}

void PngStream::rows_final(int rows) {
  // The largest count so far, and never over an abandon (-1).
  int now = state_->final_rows.load(std::memory_order_relaxed);
  while (now >= 0 && now < rows &&
         !state_->final_rows.compare_exchange_weak(now, rows, std::memory_order_release, std::memory_order_relaxed)) {
  }
  state_->final_rows.notify_all();
}

void PngStream::write(const fs::path& path) {
  State& s = *state_;
  naming_the_file(path, fail_write, [&] {
    if (check_image_target(s.image, path) != ImageFormat::png) fail_write(path, "not a .png file");
    if (s.final_rows.load(std::memory_order_acquire) < s.image.height)
      throw std::logic_error("the image's rows are not all final");
    if (!s.encoder.joinable()) throw std::logic_error("the PNG was written already");
    s.encoder.join();
    if (s.error) std::rethrow_exception(s.error);
    if (!s.complete) throw std::logic_error("the PNG was abandoned");
    write_file_atomically(path, s.bytes, Flush::no);
  });
}

std::vector<unsigned char> encode_image(const Image& image, ImageFormat format, const WriteOptions& options) {
  if (!valid_image_size(image.width, image.height) ||
      image.rgb.size() != 3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
    throw Error("image: invalid size " + std::to_string(image.width) + "x" + std::to_string(image.height));
  if (auto reason = image_size_limit_reason(format, image.width, image.height)) throw Error("image: " + *reason);
  switch (format) {
    case ImageFormat::ppm: return encode_ppm(image, options);
    case ImageFormat::pfm: return encode_pfm(image);
    case ImageFormat::png: return encode_png(image, options);
    case ImageFormat::jpg: return encode_jpg(image, options);
    case ImageFormat::exr: {
      const MallocBytes exr = encode_exr(image);
      return {exr.data.get(), exr.data.get() + exr.size};
    }
    case ImageFormat::hdr: return encode_hdr(image);
  }
  return {};
}

void write_exr_channels(const std::vector<ExrChannel>& channels, const fs::path& path) {
  return naming_the_file(path, fail_write, [&] {
    if (channels.empty() || !channels[0].image) fail_write(path, "no channels");
    const Image& first = *channels[0].image;
    if (!valid_image_size(first.width, first.height)) fail_write(path, "invalid image size");
    const MallocBytes exr = encode_exr_channels(channels, first.width, first.height);
    write_file_atomically(path, {exr.data.get(), exr.size}, Flush::no);
  });
}

ExrPlanes read_exr_channels(const fs::path& path) {
  return naming_the_file(path, fail_read, [&] {
    const Bytes bytes = read_file(path);
    if (bytes.empty()) fail_read(path, "the file is empty");
    return decode_exr_planes(path, bytes, nullptr);
  });
}

Image read_image(const fs::path& path) {
  return naming_the_file(path, fail_read, [&] {
    const auto format = image_format_for_path(path);
    if (!format) fail_read(path, unsupported_extension_reason(path));
    const Bytes bytes = read_file(path);
    if (bytes.empty()) fail_read(path, "the file is empty");
    switch (*format) {
      case ImageFormat::ppm: return decode_ppm(path, bytes);
      case ImageFormat::pfm: return decode_pfm(path, bytes);
      case ImageFormat::png:
      case ImageFormat::jpg: return decode_stb(path, bytes);
      case ImageFormat::exr: return decode_exr(path, bytes);
      case ImageFormat::hdr: return decode_hdr(path, bytes);
    }
    fail_read(path, "unknown image format");
  });
}

}  // namespace glint
