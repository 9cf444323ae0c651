// A PNG compressed while its image is rendered (PngStream, and the rows the
// renderer announces final through RenderOptions::rows_final): the same
// bytes as writing the finished image, nothing written when abandoned.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "glint/error.h"
#include "glint/io/file_io.h"
#include "glint/io/image_file.h"
#include "glint/io/scene_loader.h"
#include "glint/render/frame_job.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

// The frames here are never resumed or stopped: their key is never asked.
uint64_t no_resume_key() { return 0; }

fs::path temp_path(const std::string& name) {
  return fs::path(::testing::TempDir()) / ("glint-png-stream-" + std::to_string(::getpid()) + "-" + name);
}

// Values over the whole 8-bit range and beyond, different in every row.
Image pattern(int width, int height) {
  Image image(width, height);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = static_cast<float>(std::fmod(i * 0.0137, 1.3));
  return image;
}

TEST(PngStream, RowsAnnouncedFromAnotherThreadGiveWriteImagesBytes) {
  for (const WriteOptions options : {WriteOptions{}, WriteOptions{1.5, ToneMap::aces, false}}) {
    const Image finished = pattern(301, 1000);  // rows not a multiple of the 16-row bands
    const fs::path expected = temp_path("expected.png"), streamed = temp_path("streamed.png");
    write_image(finished, expected, options);
    {
      // Starts black and is filled 7 rows at a time, each step announced
      // after its rows are written: a stream that did not wait would take
      // black rows.
      Image image(finished.width, finished.height);
      PngStream png(image, options);
      std::thread renderer([&] {
        const size_t row = 3 * static_cast<size_t>(image.width);
        for (int rows = 0; rows < image.height;) {
          const int next = std::min(image.height, rows + 7);
          std::copy(finished.rgb.begin() + static_cast<std::ptrdiff_t>(row * size_t(rows)),
                    finished.rgb.begin() + static_cast<std::ptrdiff_t>(row * size_t(next)),
                    image.rgb.begin() + static_cast<std::ptrdiff_t>(row * size_t(rows)));
          png.rows_final(rows = next);
        }
      });
      renderer.join();
      png.write(streamed);
    }
    EXPECT_EQ(read_file(streamed), read_file(expected));
    fs::remove(expected);
    fs::remove(streamed);
  }
}

TEST(PngStream, AbandonedItStopsAndWritesNothing) {
  const Image image = pattern(64, 64);
  { PngStream never_started(image); }  // no row ever final: the destructor must not wait for one
  {
    PngStream half(image);
    half.rows_final(32);
  }
  const fs::path out = temp_path("early.png");
  PngStream early(image);
  early.rows_final(48);
  EXPECT_THROW(early.write(out), Error);  // rows 48..63 are not final
  EXPECT_FALSE(fs::exists(out));
}

TEST(PngStream, WriteChecksItsTargetAsWriteImageDoes) {
  const Image image = pattern(16, 16);
  PngStream png(image);
  png.rows_final(16);
  try {
    png.write(temp_path("no-such-folder") / "x.png");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}

Scene small_scene(bool adaptive) {
  Scene scene = load_scene(std::string(GLINT_SOURCE_DIR) + "/scenes/showcase.json");
  scene.render.width = 70;
  scene.render.height = 45;  // not a multiple of the tile size
  scene.render.samples_per_pixel = 1;
  if (adaptive) scene.render.adaptive = AdaptiveSampling{4, 0.05};
  return scene;
}

// The renderer's announcements: increasing, whole bands of tiles (or the
// image's last row), and the height once complete; pixels of announced rows
// never change again.
TEST(PngStream, RendererAnnouncesFinalRowsInOrder) {
  for (bool adaptive : {false, true}) {
    for (int threads : {1, 2}) {
      const Scene scene = small_scene(adaptive);
      const auto accel = build_accelerator(scene);
      const Image whole = render_image(scene, *accel);
      Image image(scene.render.width, scene.render.height);
      TileProgress tiles(scene.render.width, scene.render.height, 16);
      std::mutex mutex;
      std::vector<int> announced;
      bool rows_matched = true;
      RenderOptions options;
      options.threads = threads;
      options.rows_final = [&](int rows) {
        const std::lock_guard lock(mutex);
        const int from = announced.empty() ? 0 : announced.back();
        const size_t begin = 3 * size_t(from) * size_t(image.width), end = 3 * size_t(rows) * size_t(image.width);
        rows_matched = rows_matched && std::memcmp(image.rgb.data() + begin, whole.rgb.data() + begin,
                                                   (end - begin) * sizeof(float)) == 0;
        announced.push_back(rows);
      };
      RenderStats stats;
      ASSERT_TRUE(render_tiles(scene, *accel, image, tiles, options, &stats));
      if (adaptive) {
        EXPECT_GT(stats.refined_pixels, 0u);  // else the second stage would prove nothing
      }
      ASSERT_FALSE(announced.empty());
      EXPECT_EQ(announced.back(), scene.render.height);
      EXPECT_TRUE(std::is_sorted(announced.begin(), announced.end()));
      EXPECT_EQ(std::adjacent_find(announced.begin(), announced.end()), announced.end());  // strictly increasing
      for (int rows : announced) EXPECT_TRUE(rows % 16 == 0 || rows == scene.render.height) << rows;
      EXPECT_TRUE(rows_matched) << "a row announced final changed afterwards";
    }
  }
}

// Tiles finished by an earlier run count as final from the start.
TEST(PngStream, ResumedTilesAreFinalAtOnce) {
  const Scene scene = small_scene(false);
  const auto accel = build_accelerator(scene);
  Image image(scene.render.width, scene.render.height);
  TileProgress tiles(scene.render.width, scene.render.height, 16);
  for (int t = 0; t < tiles.tiles_x; ++t) tiles.done[static_cast<size_t>(t)] = 1;  // the top band
  std::vector<int> announced;
  RenderOptions options;
  options.threads = 1;
  options.rows_final = [&](int rows) { announced.push_back(rows); };
  ASSERT_TRUE(render_tiles(scene, *accel, image, tiles, options));
  ASSERT_GE(announced.size(), 2u);
  EXPECT_EQ(announced.front(), 16);  // before any tile was rendered
  EXPECT_EQ(announced.back(), scene.render.height);
}

// End to end through the frame job (what `glint render` runs): the streamed
// PNG is the file write_image makes of render_image's image.
TEST(PngStream, FrameJobWritesTheSameBytesAsWriteImage) {
  const Scene scene = small_scene(false);
  const auto accel = build_accelerator(scene);
  const fs::path expected = temp_path("frame-expected.png"), streamed = temp_path("frame.png");
  write_image(render_image(scene, *accel), expected);
  for (int threads : {1, 2}) {
    FrameJob job;
    job.output.path = streamed.string();
    job.render.threads = threads;
    const FrameReport report = render_frame_to_files(scene, no_resume_key, job);
    EXPECT_TRUE(report.complete);
    EXPECT_TRUE(report.png_streamed);  // else this would compare write_image with itself
    EXPECT_EQ(read_file(streamed), read_file(expected)) << threads << " threads";
  }
  fs::remove(expected);
  fs::remove(streamed);
}

// A size the output's format cannot hold is an error before the render.
TEST(PngStream, FrameJobRefusesAJpegTooWideBeforeRendering) {
  Scene scene = small_scene(false);
  scene.render.width = 65536;
  scene.render.height = 1;
  FrameJob job;
  job.output.path = temp_path("wide.jpg").string();
  bool rendered = false;
  job.render.progress = [&rendered](double) { rendered = true; };
  try {
    render_frame_to_files(scene, no_resume_key, job);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              job.output.path + ": cannot write: a JPEG is at most 65535 pixels wide and high, not 65536x1");
  }
  EXPECT_FALSE(rendered);
  EXPECT_FALSE(fs::exists(job.output.path));
}

// Other outputs are written after the render: a PNG with passes (several
// files) and the float formats.
TEST(PngStream, FrameJobStreamsOnlyAPngWithoutPasses) {
  const Scene scene = small_scene(false);
  struct Case {
    const char* name;
    std::vector<Pass> passes;
  };
  for (const Case& c :
       {Case{"plain.png", {}}, Case{"passes.png", {Pass::diffuse}}, Case{"plain.exr", {}}, Case{"plain.pfm", {}}}) {
    FrameJob job;
    job.output.path = temp_path(c.name).string();
    job.output.passes = c.passes;
    job.render.threads = 1;
    const FrameReport report = render_frame_to_files(scene, no_resume_key, job);
    EXPECT_TRUE(report.complete) << c.name;
    EXPECT_EQ(report.png_streamed, std::string_view(c.name) == "plain.png") << c.name;
    EXPECT_TRUE(fs::exists(job.output.path)) << c.name;
    fs::remove(job.output.path);
    for (const Pass pass : c.passes) fs::remove(pass_file_name(job.output.path, pass));
  }
}

}  // namespace
}  // namespace glint
