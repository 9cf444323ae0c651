// Tests for glint/image: the sRGB transfer functions, the exact byte layout of
// PFM, round trips through all five formats, and the atomic-write guarantees
// (an existing output survives a failed write; no temp files are left behind).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "glint/error.h"
#include "glint/image/image.h"
#include "glint/io/image_file.h"

namespace fs = std::filesystem;
using glint::Image;
using glint::ImageFormat;

namespace {

using Bytes = std::vector<unsigned char>;

Bytes read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_bytes(const fs::path& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void write_text(const fs::path& path, const std::string& text) { write_bytes(path, Bytes(text.begin(), text.end())); }

std::string read_text(const fs::path& path) {
  const Bytes b = read_bytes(path);
  return std::string(b.begin(), b.end());
}

void append_text(Bytes& out, const std::string& text) { out.insert(out.end(), text.begin(), text.end()); }
void append_u32_le(Bytes& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
}
void append_u32_be(Bytes& out, std::uint32_t v) {
  for (int i = 3; i >= 0; --i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
}
void append_u64_le(Bytes& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

// A non-square image (catches swapped axes) whose values cover what float
// formats must keep exactly: > 1, tiny, denormal, zero, negative.
Image float_test_image() {
  Image image(7, 5);
  const float specials[] = {0.0f, 1.0f, 37.5f, 1.0e6f, 1.0e-30f, 1.0e-40f, 0.1f, -2.5f, 65504.0f, 3.4e38f};
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    image.rgb[i] = i < std::size(specials) ? specials[i] : 0.001f * static_cast<float>(i * i) + 1.0f / 3.0f;
  }
  return image;
}

// In [0,1], smooth enough that JPEG's block transform has little to lose.
Image ldr_test_image(int w = 16, int h = 8) {
  Image image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float* p = image.pixel(x, y);
      p[0] = static_cast<float>(x) / static_cast<float>(w - 1);
      p[1] = static_cast<float>(y) / static_cast<float>(h - 1);
      p[2] = 0.25f;
    }
  }
  return image;
}

// Each test gets its own folder, removed afterwards.
class ImageIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("glint-test-image-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }

  // Every entry of the folder, sorted: a leftover temp file shows up here.
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  // Asserts that writing fails with a glint::Error naming the path; returns its message.
  std::string expect_write_error(const Image& image, const fs::path& path) {
    try {
      glint::write_image(image, path);
    } catch (const glint::Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path.string() + ": cannot write: ", 0), 0u) << what;
      return what;
    } catch (...) {
      ADD_FAILURE() << "an exception other than glint::Error escaped";
      return {};
    }
    ADD_FAILURE() << "no error writing " << path;
    return {};
  }

  std::string expect_read_error(const fs::path& path) {
    try {
      glint::read_image(path);
    } catch (const glint::Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path.string() + ": cannot read: ", 0), 0u) << what;
      return what;
    } catch (...) {
      ADD_FAILURE() << "an exception other than glint::Error escaped";
      return {};
    }
    ADD_FAILURE() << "no error reading " << path;
    return {};
  }

  fs::path dir_;
};

// An uncompressed scanline OpenEXR file, built by hand so the reader can be
// tested on channel sets and types our writer never produces.
struct ExrChannel {
  std::string name;
  int type;                            // 1 half, 2 float
  std::vector<std::uint32_t> samples;  // raw bits, row-major; half uses the low 16
};

Bytes handmade_exr(int w, int h, const std::vector<ExrChannel>& channels) {
  Bytes out = {0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0};
  auto attribute = [&](const std::string& name, const std::string& type, const Bytes& value) {
    append_text(out, name);
    out.push_back(0);
    append_text(out, type);
    out.push_back(0);
    append_u32_le(out, static_cast<std::uint32_t>(value.size()));
    out.insert(out.end(), value.begin(), value.end());
  };
  Bytes chlist;
  for (const auto& c : channels) {  // must already be sorted by name
    append_text(chlist, c.name);
    chlist.push_back(0);
    append_u32_le(chlist, static_cast<std::uint32_t>(c.type));
    chlist.insert(chlist.end(), {0, 0, 0, 0});
    append_u32_le(chlist, 1);
    append_u32_le(chlist, 1);
  }
  chlist.push_back(0);
  Bytes box;
  for (int v : {0, 0, w - 1, h - 1}) append_u32_le(box, static_cast<std::uint32_t>(v));
  Bytes one_float, two_zero_floats;
  append_u32_le(one_float, std::bit_cast<std::uint32_t>(1.0f));
  append_u32_le(two_zero_floats, 0);
  append_u32_le(two_zero_floats, 0);
  attribute("channels", "chlist", chlist);
  attribute("compression", "compression", {0});
  attribute("dataWindow", "box2i", box);
  attribute("displayWindow", "box2i", box);
  attribute("lineOrder", "lineOrder", {0});
  attribute("pixelAspectRatio", "float", one_float);
  attribute("screenWindowCenter", "v2f", two_zero_floats);
  attribute("screenWindowWidth", "float", one_float);
  out.push_back(0);

  std::size_t line_bytes = 0;
  for (const auto& c : channels) line_bytes += static_cast<std::size_t>(w) * (c.type == 1 ? 2 : 4);
  const std::size_t table_end = out.size() + 8 * static_cast<std::size_t>(h);
  for (int y = 0; y < h; ++y) append_u64_le(out, table_end + static_cast<std::size_t>(y) * (8 + line_bytes));
  for (int y = 0; y < h; ++y) {
    append_u32_le(out, static_cast<std::uint32_t>(y));
    append_u32_le(out, static_cast<std::uint32_t>(line_bytes));
    for (const auto& c : channels) {
      for (int x = 0; x < w; ++x) {
        const std::uint32_t v = c.samples[static_cast<std::size_t>(y * w + x)];
        out.push_back(static_cast<unsigned char>(v));
        out.push_back(static_cast<unsigned char>(v >> 8));
        if (c.type == 2) {
          out.push_back(static_cast<unsigned char>(v >> 16));
          out.push_back(static_cast<unsigned char>(v >> 24));
        }
      }
    }
  }
  return out;
}

}  // namespace

// --- sRGB -------------------------------------------------------------------

TEST(ImageSrgb, EncodeKnownValues) {
  EXPECT_EQ(glint::srgb_encode(0.0f), 0.0f);
  EXPECT_EQ(glint::srgb_encode(1.0f), 1.0f);
  EXPECT_NEAR(glint::srgb_encode(0.5f), 0.7353569f, 1e-6f);
  EXPECT_NEAR(glint::srgb_encode(0.18f), 0.4613561f, 1e-6f);
  // Linear segment below the threshold, and the two pieces meet at it.
  EXPECT_NEAR(glint::srgb_encode(0.001f), 0.01292f, 1e-8f);
  EXPECT_NEAR(glint::srgb_encode(0.0031308f), 0.0404500f, 1e-6f);
  EXPECT_NEAR(glint::srgb_encode(0.0031307f), glint::srgb_encode(0.0031309f), 3e-6f);
  EXPECT_NEAR(glint::srgb_encode(0.0031309f), 0.0404513f, 1e-6f);
  // Clamping, and NaN is black.
  EXPECT_EQ(glint::srgb_encode(-1.0f), 0.0f);
  EXPECT_EQ(glint::srgb_encode(7.0f), 1.0f);
  EXPECT_EQ(glint::srgb_encode(std::numeric_limits<float>::infinity()), 1.0f);
  EXPECT_EQ(glint::srgb_encode(std::numeric_limits<float>::quiet_NaN()), 0.0f);
}

TEST(ImageSrgb, DecodeIsTheInverse) {
  EXPECT_EQ(glint::srgb_decode(0.0f), 0.0f);
  EXPECT_EQ(glint::srgb_decode(1.0f), 1.0f);
  EXPECT_NEAR(glint::srgb_decode(0.7353569f), 0.5f, 1e-6f);
  EXPECT_NEAR(glint::srgb_decode(0.02f), 0.02f / 12.92f, 1e-9f);
  EXPECT_NEAR(glint::srgb_decode(0.04045f), 0.0031308f, 1e-7f);
  EXPECT_EQ(glint::srgb_decode(std::numeric_limits<float>::quiet_NaN()), 0.0f);
  for (int i = 0; i <= 1000; ++i) {
    const float x = static_cast<float>(i) / 1000.0f;
    EXPECT_NEAR(glint::srgb_decode(glint::srgb_encode(x)), x, 2e-6f) << x;
    EXPECT_NEAR(glint::srgb_encode(glint::srgb_decode(x)), x, 2e-6f) << x;
  }
}

TEST(ImageSrgb, ToSrgb8RoundsAndClamps) {
  EXPECT_EQ(glint::to_srgb8(0.0f), 0);
  EXPECT_EQ(glint::to_srgb8(1.0f), 255);
  EXPECT_EQ(glint::to_srgb8(0.5f), 188);  // 0.7353569 * 255 = 187.52
  EXPECT_EQ(glint::to_srgb8(-3.0f), 0);
  EXPECT_EQ(glint::to_srgb8(12.0f), 255);
  EXPECT_EQ(glint::to_srgb8(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(glint::to_srgb8(-std::numeric_limits<float>::infinity()), 0);
  EXPECT_EQ(glint::to_srgb8(std::numeric_limits<float>::quiet_NaN()), 0);
  // 12.92 * x * 255 crosses 0.5 at x = 1.5176e-4: round to nearest, not truncate.
  EXPECT_EQ(glint::to_srgb8(1.50e-4f), 0);
  EXPECT_EQ(glint::to_srgb8(1.53e-4f), 1);
  // Every 8-bit level survives decode then encode.
  for (int k = 0; k <= 255; ++k) {
    EXPECT_EQ(glint::to_srgb8(glint::srgb_decode(static_cast<float>(k) / 255.0f)), k) << k;
  }
}

// --- formats by extension -----------------------------------------------------

TEST(ImageFormats, ByExtensionCaseInsensitive) {
  EXPECT_EQ(glint::image_format_for_path("a.png"), ImageFormat::png);
  EXPECT_EQ(glint::image_format_for_path("dir.exr/a.JPG"), ImageFormat::jpg);
  EXPECT_EQ(glint::image_format_for_path("a.Ppm"), ImageFormat::ppm);
  EXPECT_EQ(glint::image_format_for_path("/x/y/render.PFM"), ImageFormat::pfm);
  EXPECT_EQ(glint::image_format_for_path("a.b.exr"), ImageFormat::exr);
  EXPECT_FALSE(glint::image_format_for_path("a.bmp"));
  EXPECT_FALSE(glint::image_format_for_path("png"));
  EXPECT_FALSE(glint::image_format_for_path("a.png.tmp"));
  EXPECT_FALSE(glint::image_format_for_path(""));
  EXPECT_EQ(glint::supported_image_extensions(), ".png, .jpg, .ppm, .pfm, .exr, .hdr");
}

TEST(ImageBasics, ConstructionAndPixelAccess) {
  Image image(3, 2);
  EXPECT_EQ(image.rgb.size(), 18u);
  EXPECT_TRUE(std::all_of(image.rgb.begin(), image.rgb.end(), [](float v) { return v == 0.0f; }));
  image.pixel(2, 1)[1] = 5.0f;
  EXPECT_EQ(image.rgb[3 * (1 * 3 + 2) + 1], 5.0f);
  const Image& c = image;
  EXPECT_EQ(c.pixel(2, 1)[1], 5.0f);
  EXPECT_THROW(Image(-1, 4), glint::Error);
  EXPECT_THROW(Image(1 << 20, 1 << 20), glint::Error);
}

// --- exact layout ---------------------------------------------------------------

TEST_F(ImageIo, PfmByteLayout) {
  Image image(2, 2);
  const float values[12] = {1, 2, 3, 4,  5,  6,       // top row: (0,0), (1,0)
                            7, 8, 9, 10, 11, -0.5f};  // bottom row: (0,1), (1,1)
  std::copy(std::begin(values), std::end(values), image.rgb.begin());
  const fs::path path = dir_ / "layout.pfm";
  glint::write_image(image, path);
  const Bytes bytes = read_bytes(path);

  const std::string header = "PF\n2 2\n-1.0\n";
  ASSERT_EQ(bytes.size(), header.size() + 12 * 4);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(header.size())), header);
  // Spelled out: 7.0f is 0x40E00000, little-endian, and it comes first because
  // PFM starts with the bottom row.
  const unsigned char seven[4] = {0x00, 0x00, 0xE0, 0x40};
  EXPECT_EQ(std::memcmp(bytes.data() + header.size(), seven, 4), 0);
  const unsigned char minus_half[4] = {0x00, 0x00, 0x00, 0xBF};  // -0.5f = 0xBF000000, last of the bottom row
  EXPECT_EQ(std::memcmp(bytes.data() + header.size() + 5 * 4, minus_half, 4), 0);
  const unsigned char six[4] = {0x00, 0x00, 0xC0, 0x40};  // 6.0f = 0x40C00000, end of the top row, last in the file
  EXPECT_EQ(std::memcmp(bytes.data() + bytes.size() - 4, six, 4), 0);
  // And every sample, byte by byte.
  Bytes expected(header.begin(), header.end());
  for (int i : {6, 7, 8, 9, 10, 11, 0, 1, 2, 3, 4, 5}) append_u32_le(expected, std::bit_cast<std::uint32_t>(values[i]));
  EXPECT_EQ(bytes, expected);
}

TEST_F(ImageIo, PpmByteLayout) {
  Image image(2, 1);
  image.pixel(0, 0)[0] = 1.0f;   // 255
  image.pixel(0, 0)[1] = 0.5f;   // 188
  image.pixel(0, 0)[2] = -1.0f;  // 0
  image.pixel(1, 0)[0] = 9.0f;   // clamped: 255
  const fs::path path = dir_ / "layout.ppm";
  glint::write_image(image, path);
  const std::string header = "P6\n2 1\n255\n";
  Bytes expected(header.begin(), header.end());
  expected.insert(expected.end(), {255, 188, 0, 255, 0, 0});
  EXPECT_EQ(read_bytes(path), expected);
}

// --- round trips ------------------------------------------------------------------

TEST_F(ImageIo, FloatFormatsRoundTripBitExact) {
  const Image image = float_test_image();
  for (const char* name : {"out.pfm", "out.exr", "OUT.EXR"}) {
    const fs::path path = dir_ / name;
    glint::write_image(image, path);
    const Image back = glint::read_image(path);
    ASSERT_EQ(back.width, image.width) << name;
    ASSERT_EQ(back.height, image.height) << name;
    ASSERT_EQ(back.rgb.size(), image.rgb.size()) << name;
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
      EXPECT_TRUE(same_bits(back.rgb[i], image.rgb[i]))
          << name << " sample " << i << ": " << back.rgb[i] << " vs " << image.rgb[i];
    }
  }
}

TEST_F(ImageIo, ExrBigImageRoundTripBitExact) {
  // Several ZIP blocks (16 lines each) and a width that is not a power of two.
  Image image(333, 101);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = std::sin(static_cast<float>(i)) * 100.0f;
  const fs::path path = dir_ / "big.exr";
  glint::write_image(image, path);
  const Image back = glint::read_image(path);
  ASSERT_EQ(back.rgb.size(), image.rgb.size());
  EXPECT_EQ(std::memcmp(back.rgb.data(), image.rgb.data(), image.rgb.size() * sizeof(float)), 0);
}

// Largest and mean difference after sRGB encoding, in 8-bit levels.
std::pair<float, float> encoded_error_levels(const Image& a, const Image& b) {
  float worst = 0.0f, sum = 0.0f;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const float e = std::abs(glint::srgb_encode(a.rgb[i]) - glint::srgb_encode(b.rgb[i])) * 255.0f;
    worst = std::max(worst, e);
    sum += e;
  }
  return {worst, sum / static_cast<float>(a.rgb.size())};
}

TEST_F(ImageIo, EightBitFormatsRoundTripWithinOneLevel) {
  // PNG and PPM are lossless at 8 bits: at most half a level of rounding.
  const Image image = ldr_test_image();
  for (const char* name : {"out.png", "out.ppm", "OUT.PNG"}) {
    const fs::path path = dir_ / name;
    glint::write_image(image, path);
    const Image back = glint::read_image(path);
    ASSERT_EQ(back.width, image.width) << name;
    ASSERT_EQ(back.height, image.height) << name;
    EXPECT_LE(encoded_error_levels(back, image).first, 0.5f + 1e-3f) << name;
  }
}

TEST_F(ImageIo, JpegRoundTripIsClose) {
  // JPEG is lossy even at quality 95 (YCbCr rounding and quantization): a flat
  // colour comes back within ~1.5 levels, a steep ramp within a few.
  Image flat(32, 16);
  for (std::size_t i = 0; i < flat.rgb.size(); i += 3) {
    flat.rgb[i] = 0.2f;
    flat.rgb[i + 1] = 0.5f;
    flat.rgb[i + 2] = 0.8f;
  }
  glint::write_image(flat, dir_ / "flat.jpg");
  Image back = glint::read_image(dir_ / "flat.jpg");
  ASSERT_EQ(back.width, 32);
  ASSERT_EQ(back.height, 16);
  EXPECT_LE(encoded_error_levels(back, flat).first, 2.0f);

  const Image ramp = ldr_test_image(64, 32);
  glint::write_image(ramp, dir_ / "ramp.jpg");
  back = glint::read_image(dir_ / "ramp.jpg");
  const auto [worst, mean] = encoded_error_levels(back, ramp);
  EXPECT_LE(worst, 8.0f);
  EXPECT_LE(mean, 1.5f);
}

TEST_F(ImageIo, EightBitFormatsClamp) {
  Image image(2, 2);
  image.pixel(0, 0)[0] = 5.0f;
  image.pixel(1, 1)[2] = -5.0f;
  for (const char* name : {"c.png", "c.ppm"}) {
    glint::write_image(image, dir_ / name);
    const Image back = glint::read_image(dir_ / name);
    EXPECT_EQ(back.pixel(0, 0)[0], 1.0f) << name;
    EXPECT_EQ(back.pixel(1, 1)[2], 0.0f) << name;
  }
}

TEST_F(ImageIo, OverwritesAnExistingFile) {
  const fs::path path = dir_ / "out.pfm";
  write_text(path, "old contents");
  glint::write_image(float_test_image(), path);
  EXPECT_EQ(glint::read_image(path).width, 7);
  EXPECT_EQ(listing(), std::vector<std::string>{"out.pfm"});
}

TEST_F(ImageIo, RelativePathInCurrentFolder) {
  const fs::path old_cwd = fs::current_path();
  fs::current_path(dir_);
  glint::write_image(ldr_test_image(), "plain.ppm");
  fs::current_path(old_cwd);
  EXPECT_EQ(listing(), std::vector<std::string>{"plain.ppm"});
}

TEST_F(ImageIo, ConcurrentWritesToOneTarget) {
  const fs::path path = dir_ / "race.exr";
  const Image image = float_test_image();
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 5; ++i) glint::write_image(image, path);
    });
  }
  for (auto& thread : threads) thread.join();
  const Image back = glint::read_image(path);
  EXPECT_EQ(std::memcmp(back.rgb.data(), image.rgb.data(), image.rgb.size() * sizeof(float)), 0);
  EXPECT_EQ(listing(), std::vector<std::string>{"race.exr"});
}

// --- failed writes ------------------------------------------------------------------

TEST_F(ImageIo, UnsupportedExtensionLeavesExistingFile) {
  const fs::path path = dir_ / "out.bmp";
  write_text(path, "precious");
  const std::string what = expect_write_error(float_test_image(), path);
  EXPECT_NE(what.find(".png, .jpg, .ppm, .pfm, .exr, .hdr"), std::string::npos) << what;
  EXPECT_NE(what.find(".bmp"), std::string::npos) << what;
  EXPECT_EQ(read_text(path), "precious");
  expect_write_error(float_test_image(), dir_ / "no_extension");
  EXPECT_EQ(listing(), std::vector<std::string>{"out.bmp"});
}

TEST_F(ImageIo, InvalidImageLeavesExistingFile) {
  const fs::path path = dir_ / "out.png";
  write_text(path, "precious");
  expect_write_error(Image(), path);
  expect_write_error(Image(0, 3), path);
  Image wrong_size(2, 2);
  wrong_size.rgb.pop_back();
  expect_write_error(wrong_size, path);
  EXPECT_EQ(read_text(path), "precious");
  EXPECT_EQ(listing(), std::vector<std::string>{"out.png"});
}

TEST_F(ImageIo, DirectoryInTheWay) {
  for (const char* name : {"out.png", "out.exr", "out.pfm"}) {
    const fs::path path = dir_ / name;
    fs::create_directory(path);
    write_text(path / "inside.txt", "precious");
    expect_write_error(float_test_image(), path);
    EXPECT_TRUE(fs::is_directory(path));
    EXPECT_EQ(read_text(path / "inside.txt"), "precious");
  }
  EXPECT_EQ(listing(), (std::vector<std::string>{"out.exr", "out.pfm", "out.png"}));
}

TEST_F(ImageIo, FailureWhileWritingLeavesExistingFile) {
  // A file-size limit makes write() fail part-way (EFBIG) without needing
  // permissions, which root would ignore: this exercises the temp-file cleanup.
  const fs::path path = dir_ / "out.pfm";
  write_text(path, "precious");
  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  rlimit small = old_limit;
  small.rlim_cur = 1000;
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);  // else the kernel kills us
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string what;
  try {
    glint::write_image(Image(64, 64), path);  // 49 KB of floats
  } catch (const glint::Error& e) {
    what = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_EQ(what.rfind(path.string() + ": cannot write: ", 0), 0u) << what;
  EXPECT_EQ(read_text(path), "precious");
  EXPECT_EQ(listing(), std::vector<std::string>{"out.pfm"});
}

TEST_F(ImageIo, MissingFolder) {
  const fs::path path = dir_ / "no" / "such" / "out.exr";
  const std::string what = expect_write_error(float_test_image(), path);
  EXPECT_NE(what.find("does not exist"), std::string::npos) << what;
  EXPECT_FALSE(fs::exists(dir_ / "no"));
  // A file where the folder should be.
  write_text(dir_ / "file", "x");
  expect_write_error(float_test_image(), dir_ / "file" / "out.png");
  EXPECT_EQ(listing(), std::vector<std::string>{"file"});
}

TEST_F(ImageIo, NoTempFilesLeftBehind) {
  const Image image = float_test_image();
  for (const char* name : {"a.png", "a.jpg", "a.ppm", "a.pfm", "a.exr"}) glint::write_image(image, dir_ / name);
  for (const char* name : {"a.png", "a.jpg", "a.ppm", "a.pfm", "a.exr"}) glint::write_image(image, dir_ / name);
  fs::create_directory(dir_ / "z.exr");
  expect_write_error(image, dir_ / "z.exr");
  expect_write_error(image, dir_ / "z.tiff");
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.exr", "a.jpg", "a.pfm", "a.png", "a.ppm", "z.exr"}));
  EXPECT_TRUE(fs::is_empty(dir_ / "z.exr"));
}

// --- reading ----------------------------------------------------------------------

TEST_F(ImageIo, ReadsBigEndianAndGreyscalePfm) {
  // 2x2, positive scale = big-endian; rows bottom to top.
  Bytes file;
  append_text(file, "PF\n2 2\n1.0\n");
  for (int i = 0; i < 12; ++i) append_u32_be(file, std::bit_cast<std::uint32_t>(static_cast<float>(i)));
  write_bytes(dir_ / "be.pfm", file);
  Image image = glint::read_image(dir_ / "be.pfm");
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 2);
  EXPECT_EQ(image.pixel(0, 1)[0], 0.0f);  // first in the file: bottom left
  EXPECT_EQ(image.pixel(1, 1)[2], 5.0f);
  EXPECT_EQ(image.pixel(0, 0)[0], 6.0f);  // then the top row
  EXPECT_EQ(image.pixel(1, 0)[2], 11.0f);

  Bytes grey;
  append_text(grey, "Pf\n1 2\n-1\n");
  append_u32_le(grey, std::bit_cast<std::uint32_t>(0.25f));
  append_u32_le(grey, std::bit_cast<std::uint32_t>(4.0f));
  write_bytes(dir_ / "grey.pfm", grey);
  image = glint::read_image(dir_ / "grey.pfm");
  EXPECT_EQ(image.pixel(0, 1)[0], 0.25f);
  EXPECT_EQ(image.pixel(0, 1)[2], 0.25f);
  EXPECT_EQ(image.pixel(0, 0)[1], 4.0f);
}

TEST_F(ImageIo, ReadsPpmWithCommentsAnd16Bit) {
  Bytes file;
  append_text(file, "P6 # made by hand\n1 1\n# max\n65535\n");
  file.insert(file.end(), {0xFF, 0xFF, 0x00, 0x00, 0x80, 0x00});
  write_bytes(dir_ / "deep.ppm", file);
  const Image image = glint::read_image(dir_ / "deep.ppm");
  EXPECT_EQ(image.pixel(0, 0)[0], 1.0f);
  EXPECT_EQ(image.pixel(0, 0)[1], 0.0f);
  EXPECT_NEAR(image.pixel(0, 0)[2], glint::srgb_decode(32768.0f / 65535.0f), 1e-7f);
}

TEST_F(ImageIo, ReadsExrRgbaAndHalf) {
  // Channels A, B, G, R (file order is by name): the reader takes R, G, B and ignores A.
  const int w = 3, h = 2;
  auto floats = [](float base) {
    std::vector<std::uint32_t> v;
    for (int i = 0; i < 6; ++i) v.push_back(std::bit_cast<std::uint32_t>(base + static_cast<float>(i)));
    return v;
  };
  write_bytes(
      dir_ / "rgba.exr",
      handmade_exr(w, h, {{"A", 2, floats(100)}, {"B", 2, floats(30)}, {"G", 2, floats(20)}, {"R", 2, floats(10)}}));
  Image image = glint::read_image(dir_ / "rgba.exr");
  ASSERT_EQ(image.width, w);
  ASSERT_EQ(image.height, h);
  EXPECT_EQ(image.pixel(0, 0)[0], 10.0f);
  EXPECT_EQ(image.pixel(0, 0)[1], 20.0f);
  EXPECT_EQ(image.pixel(0, 0)[2], 30.0f);
  EXPECT_EQ(image.pixel(2, 1)[0], 15.0f);  // row 1 is the second scanline: top-down
  EXPECT_EQ(image.pixel(2, 1)[2], 35.0f);

  // Half channels: 0x3C00 = 1.0, 0x3800 = 0.5, 0x6400 = 1024, 0x0001 = smallest denormal.
  const std::vector<std::uint32_t> halves = {0x3C00, 0x3800, 0x6400, 0x0001, 0x0000, 0xC000};
  write_bytes(dir_ / "half.exr", handmade_exr(w, h, {{"B", 1, halves}, {"G", 1, halves}, {"R", 1, halves}}));
  image = glint::read_image(dir_ / "half.exr");
  EXPECT_EQ(image.pixel(0, 0)[0], 1.0f);
  EXPECT_EQ(image.pixel(1, 0)[1], 0.5f);
  EXPECT_EQ(image.pixel(2, 0)[2], 1024.0f);
  EXPECT_EQ(image.pixel(0, 1)[0], std::ldexp(1.0f, -24));
  EXPECT_EQ(image.pixel(2, 1)[0], -2.0f);

  write_bytes(dir_ / "no_rgb.exr", handmade_exr(w, h, {{"Y", 2, floats(1)}}));
  expect_read_error(dir_ / "no_rgb.exr");
}

TEST_F(ImageIo, ReadErrors) {
  EXPECT_NE(expect_read_error(dir_ / "missing.exr").find("No such file"), std::string::npos);
  expect_read_error(dir_ / "missing.png");
  fs::create_directory(dir_ / "folder.pfm");
  expect_read_error(dir_ / "folder.pfm");
  expect_read_error(dir_ / "image.bmp");

  for (const char* name : {"empty.png", "empty.exr", "empty.pfm"}) {
    write_text(dir_ / name, "");
    expect_read_error(dir_ / name);
  }
  for (const char* name : {"junk.png", "junk.jpg", "junk.ppm", "junk.pfm", "junk.exr"}) {
    write_text(dir_ / name, "this is not an image at all, just some text");
    expect_read_error(dir_ / name);
  }
  // Valid headers with the data cut short.
  write_text(dir_ / "short.pfm", "PF\n2 2\n-1.0\nabcd");
  EXPECT_NE(expect_read_error(dir_ / "short.pfm").find("truncated"), std::string::npos);
  write_text(dir_ / "short.ppm", "P6\n2 2\n255\nabc");
  expect_read_error(dir_ / "short.ppm");
  write_text(dir_ / "huge.pfm", "PF\n99999999 99999999\n-1.0\n");
  expect_read_error(dir_ / "huge.pfm");
  write_text(dir_ / "zero.pfm", "PF\n0 2\n-1.0\n");
  expect_read_error(dir_ / "zero.pfm");
  write_text(dir_ / "nan.pfm", "PF\n1 1\nnan\n123456789012");
  expect_read_error(dir_ / "nan.pfm");

  // Real files cut in half.
  const Image image = ldr_test_image(64, 32);
  for (const char* name : {"cut.png", "cut.exr", "cut.jpg"}) {
    glint::write_image(image, dir_ / name);
    Bytes bytes = read_bytes(dir_ / name);
    bytes.resize(bytes.size() / 2);
    write_bytes(dir_ / name, bytes);
    try {
      glint::read_image(dir_ / name);
      // stb_image decodes a truncated JPEG as far as it goes (grey after the cut):
      // that is its documented leniency, not a crash, so it is accepted here.
      EXPECT_EQ(std::string(name), "cut.jpg");
    } catch (const glint::Error&) {
    }
  }
}

namespace glint {
namespace {

// The table-driven to_srgb8 must agree with round(srgb_encode(x) * 255) over
// the whole [0, 1] float range (every 61st bit pattern, plus the ends).
TEST(ImageSrgbTable, MatchesTheFormulaAcrossTheFloatRange) {
  const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
  int mismatches = 0;
  for (std::uint32_t bits = 0; bits <= one; bits += 61) {
    const float x = std::bit_cast<float>(bits);
    const double exact = std::round(static_cast<double>(srgb_encode(x)) * 255.0);
    if (to_srgb8(x) != static_cast<int>(exact)) {
      // Only a value within float rounding of a code boundary may differ.
      const double scaled = static_cast<double>(srgb_encode(x)) * 255.0;
      if (std::abs(scaled - std::floor(scaled) - 0.5) > 1e-4) ++mismatches;
    }
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(to_srgb8(1.0f), 255);
  EXPECT_EQ(to_srgb8(7.0f), 255);
  EXPECT_EQ(to_srgb8(0.0f), 0);
  EXPECT_EQ(to_srgb8(-1.0f), 0);
}

}  // namespace
}  // namespace glint

// --- tone mapping, exposure, Radiance HDR, data encoding, EXR channels ----------

namespace {

// The PPM's 8-bit codes, straight from the file (no decoding).
Bytes ppm_codes(const fs::path& path) {
  const Bytes bytes = read_bytes(path);
  size_t pos = 0;
  for (int newlines = 0; newlines < 3; ++pos) newlines += bytes[pos] == '\n';
  return Bytes(bytes.begin() + static_cast<std::ptrdiff_t>(pos), bytes.end());
}

}  // namespace

TEST(ToneMap, KnownValuesFromTheFormulas) {
  using glint::tone_map;
  using glint::ToneMap;
  for (const float x : {0.0f, 0.01f, 0.18f, 0.5f, 1.0f, 2.0f, 7.5f, 100.0f, 1e6f}) {
    SCOPED_TRACE(x);
    EXPECT_EQ(tone_map(x, ToneMap::clamp), std::min(x, 1.0f));
    EXPECT_FLOAT_EQ(tone_map(x, ToneMap::reinhard), x / (1.0f + x));  // Reinhard
    // ACES: Narkowicz's fit (2015), clamped to [0, 1].
    const double d = x;
    const double aces = std::clamp(d * (2.51 * d + 0.03) / (d * (2.43 * d + 0.59) + 0.14), 0.0, 1.0);
    EXPECT_FLOAT_EQ(tone_map(x, ToneMap::aces), static_cast<float>(aces));
  }
  EXPECT_FLOAT_EQ(tone_map(1.0f, ToneMap::reinhard), 0.5f);
  EXPECT_NEAR(tone_map(1.0f, ToneMap::aces), 2.54 / 3.16, 1e-7);
  EXPECT_EQ(tone_map(1e6f, ToneMap::aces), 1.0f);  // the fit rises above 1 (2.51/2.43): clamped
  for (const ToneMap m : {ToneMap::clamp, ToneMap::reinhard, ToneMap::aces}) {
    EXPECT_EQ(tone_map(-1.0f, m), 0.0f);
    EXPECT_EQ(tone_map(std::numeric_limits<float>::quiet_NaN(), m), 0.0f);
    EXPECT_EQ(tone_map(std::numeric_limits<float>::infinity(), m), 1.0f);
  }
}

TEST_F(ImageIo, ExposureAndToneMapChangeOnlyEightBitOutputs) {
  Image image(3, 1);
  image.rgb = {0.25f, 1.0f, 3.0f, 0.05f, 0.5f, 20.0f, 0.0f, 0.18f, 1.5f};
  // Default options: the very bytes of the plain write (the contract's clamp).
  glint::write_image(image, dir_ / "plain.ppm");
  glint::write_image(image, dir_ / "default.ppm", glint::WriteOptions{});
  EXPECT_EQ(read_bytes(dir_ / "plain.ppm"), read_bytes(dir_ / "default.ppm"));

  glint::WriteOptions exposed;
  exposed.exposure = 1;  // x2
  glint::write_image(image, dir_ / "ev1.ppm", exposed);
  glint::WriteOptions reinhard;
  reinhard.tonemap = glint::ToneMap::reinhard;
  reinhard.exposure = -1;  // x0.5, then x/(1+x)
  glint::write_image(image, dir_ / "reinhard.ppm", reinhard);
  glint::WriteOptions aces;
  aces.tonemap = glint::ToneMap::aces;
  glint::write_image(image, dir_ / "aces.ppm", aces);
  const Bytes ev1 = ppm_codes(dir_ / "ev1.ppm"), rh = ppm_codes(dir_ / "reinhard.ppm"),
              ac = ppm_codes(dir_ / "aces.ppm");
  ASSERT_EQ(ev1.size(), image.rgb.size());
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const float x = image.rgb[i];
    EXPECT_EQ(ev1[i], glint::to_srgb8(2.0f * x)) << i;
    EXPECT_EQ(rh[i], glint::to_srgb8(0.5f * x / (1.0f + 0.5f * x))) << i;
    const double d = x;
    EXPECT_EQ(ac[i], glint::to_srgb8(static_cast<float>(
                         std::clamp(d * (2.51 * d + 0.03) / (d * (2.43 * d + 0.59) + 0.14), 0.0, 1.0))))
        << i;
  }
  EXPECT_NE(rh, ppm_codes(dir_ / "plain.ppm"));

  // Linear outputs ignore both: the exact floats.
  glint::write_image(image, dir_ / "x.pfm", reinhard);
  EXPECT_EQ(glint::read_image(dir_ / "x.pfm").rgb, image.rgb);
}

TEST_F(ImageIo, BigPngHasTheCodesOfPpm) {
  // Big enough (over 2^18 values, kCodesForThreads in image_file.cpp) that a
  // helper thread makes the PNG's rows in bands while libpng compresses, with
  // a last band of fewer rows: the codes must be those of the PPM, made in
  // one pass. (A row read before it is made shows only when libpng overtakes
  // the helper, which it did when the wait was taken out.)
  Image image(401, 299);
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    image.rgb[i] = i % 97 == 0 ? std::numeric_limits<float>::quiet_NaN()
                               : 1.5f * std::sin(0.37f * static_cast<float>(i)) + 0.25f;  // negatives, > 1
  ASSERT_GE(image.rgb.size(), std::size_t{1} << 18);
  glint::WriteOptions aces;
  aces.tonemap = glint::ToneMap::aces;
  aces.exposure = 0.5;
  glint::WriteOptions data;
  data.data = true;
  for (const glint::WriteOptions& options : {glint::WriteOptions{}, aces, data}) {
    glint::write_image(image, dir_ / "big.png", options);
    glint::write_image(image, dir_ / "big.ppm", options);
    const Image png = glint::read_image(dir_ / "big.png"), ppm = glint::read_image(dir_ / "big.ppm");
    ASSERT_EQ(png.width, image.width);
    ASSERT_EQ(png.height, image.height);
    EXPECT_EQ(png.rgb, ppm.rgb);
  }
}

// The sides each format holds: every valid size in a PNG (libpng alone stops
// at 1,000,000 pixels), at most 65535 in a JPEG, whose header has 16 bits for
// each (stb_image_write would write the side modulo 65536: a wrong image).
TEST_F(ImageIo, WidestImagesEachFormatHolds) {
  Image wide(static_cast<int>(glint::kMaxImageDimension), 1);
  for (std::size_t i = 0; i < wide.rgb.size(); ++i) wide.rgb[i] = static_cast<float>(i % 251) / 250.0f;
  glint::write_image(wide, dir_ / "wide.png");
  glint::write_image(wide, dir_ / "wide.ppm");
  const Image png = glint::read_image(dir_ / "wide.png"), ppm = glint::read_image(dir_ / "wide.ppm");
  EXPECT_EQ(png.width, wide.width);
  EXPECT_EQ(png.rgb, ppm.rgb);
  Image tall(1, static_cast<int>(glint::kMaxImageDimension));
  glint::write_image(tall, dir_ / "tall.png");
  EXPECT_EQ(glint::read_image(dir_ / "tall.png").height, tall.height);

  glint::write_image(Image(65535, 2), dir_ / "widest.jpg");
  EXPECT_EQ(glint::read_image(dir_ / "widest.jpg").width, 65535);
  for (const auto& [w, h] : {std::pair{65536, 1}, std::pair{1, 65536}}) {
    const Image too_big(w, h);
    const std::string what = expect_write_error(too_big, dir_ / "big.jpg");
    EXPECT_NE(what.find("a JPEG is at most 65535 pixels wide and high"), std::string::npos) << what;
    EXPECT_THROW(glint::encode_image(too_big, ImageFormat::jpg), glint::Error);
    EXPECT_NO_THROW(glint::encode_image(too_big, ImageFormat::png));
  }
  EXPECT_FALSE(fs::exists(dir_ / "big.jpg"));
}

TEST_F(ImageIo, DataEncodingSkipsTheSrgbCurve) {
  Image image(2, 1);
  image.rgb = {0.0f, 0.5f, 1.0f, 0.2f, -1.0f, 7.0f};
  glint::WriteOptions data;
  data.data = true;
  data.tonemap = glint::ToneMap::aces;  // ignored for data
  glint::write_image(image, dir_ / "d.ppm", data);
  EXPECT_EQ(ppm_codes(dir_ / "d.ppm"), (Bytes{0, 128, 255, 51, 0, 255}));
}

TEST_F(ImageIo, RadianceHdrRoundTripWithinItsPrecision) {
  // RGBE keeps 8 mantissa bits under a shared exponent 2^e >= the largest
  // channel, truncating: each channel comes back within 2^e/256 <= largest/128.
  Image image(37, 11);
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    image.rgb[i] = 0.001f + std::abs(std::sin(static_cast<float>(i))) * (i % 7 == 0 ? 500.0f : 2.0f);
  image.pixel(0, 0)[0] = image.pixel(0, 0)[1] = image.pixel(0, 0)[2] = 1000.0f;  // marks the top-left
  const fs::path path = dir_ / "out.hdr";
  glint::write_image(image, path);
  EXPECT_EQ(read_text(path).rfind("#?RADIANCE", 0), 0u);
  const Image back = glint::read_image(path);
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 11);
  for (std::size_t p = 0; p < image.rgb.size(); p += 3) {
    const float largest = std::max({image.rgb[p], image.rgb[p + 1], image.rgb[p + 2]});
    for (std::size_t c = 0; c < 3; ++c)
      ASSERT_NEAR(back.rgb[p + c], image.rgb[p + c], largest / 128.0f) << p << " " << c;
  }
  // Orientation: the top-left pixel stays top-left.
  EXPECT_EQ(back.pixel(0, 0)[1], 1000.0f);  // 1000 = 250 * 4: exact in RGBE
  // A PNG named .hdr is refused, not reinterpreted.
  glint::write_image(ldr_test_image(), dir_ / "x.png");
  fs::rename(dir_ / "x.png", dir_ / "fake.hdr");
  EXPECT_THROW(glint::read_image(dir_ / "fake.hdr"), glint::Error);
  EXPECT_EQ(glint::image_format_for_path("a.HDR"), ImageFormat::hdr);
}

TEST_F(ImageIo, ExrChannelsRoundTripByName) {
  const Image a = float_test_image();
  Image b(7, 5);
  for (std::size_t i = 0; i < b.rgb.size(); ++i) b.rgb[i] = static_cast<float>(i);
  const fs::path path = dir_ / "layers.exr";
  glint::write_exr_channels({{"R", &a, 0}, {"G", &a, 1}, {"B", &a, 2}, {"x.Z", &b, 1}}, path);
  const glint::ExrPlanes planes = glint::read_exr_channels(path);
  EXPECT_EQ(planes.width, 7);
  ASSERT_EQ(planes.planes.size(), 4u);
  EXPECT_EQ(planes.planes.at("x.Z")[3], b.rgb[3 * 3 + 1]);
  EXPECT_EQ(glint::read_image(path).rgb, a.rgb);  // the R, G, B channels are the image
  EXPECT_THROW(glint::write_exr_channels({{"R", &a, 0}, {"G", &b, 5}}, dir_ / "bad.exr"), glint::Error);
  EXPECT_FALSE(fs::exists(dir_ / "bad.exr"));
}
