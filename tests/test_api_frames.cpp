// The public frame loop (include/glint/frames.h): files equal to the
// renderer's images, animation frames by pattern and range, cancel leaving a
// partial image and a resume file, resume finishing it bit-identically, and
// a resume key over the canonical JSON and every file the scene read.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/api/scene_state.h"
#include "glint/frames.h"
#include "glint/glint.h"
#include "glint/io/file_io.h"
#include "glint/render/renderer.h"
#include "glint/render/resume.h"
#include "glint/render/tile_size.h"
#include "glint/scene/animation.h"

namespace fs = std::filesystem;
using glint::api::FrameReport;
using glint::api::FramesOptions;
using glint::api::Scene;

namespace {

// A plane and an instanced mesh file, lit: what the mesh file holds shows.
const char* kMeshScene = R"({
  "render": { "width": 72, "height": 40, "background": [0.1, 0.2, 0.3] },
  "camera": { "position": [0, 9, 26], "look_at": [0, 4, 0], "fov_y": 32 },
  "materials": { "clay": { "diffuse": [0.75, 0.6, 0.5], "specular": 0.5, "shininess": 60 } },
  "lights": [ { "type": "point", "position": [-10, 20, 18] }, { "type": "ambient", "ambient": 0.2 } ],
  "objects": [
    { "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0] },
    { "type": "mesh", "file": "bunny.obj", "material": "clay" }
  ]
})";

class ApiFrames : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("glint-api-frames-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "-" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(fs::path(GLINT_SOURCE_DIR) / "scenes" / "meshes" / "bunny.obj", dir_ / "bunny.obj");
  }
  void TearDown() override { fs::remove_all(dir_); }

  Scene mesh_scene() const { return Scene::from_json(kMeshScene, dir_, "mesh scene"); }

  // A resume file for `output` with the even tiles done, as a render
  // interrupted half way leaves it.
  static void write_half_done(const Scene& scene, const fs::path& output) {
    const glint::Scene& s = *scene.state()->scene;
    const int w = s.render.width, h = s.render.height;
    const auto accel = glint::build_accelerator(s);
    glint::Image image(w, h);
    glint::TileProgress first(w, h, glint::kTileSize), tiles(w, h, glint::kTileSize);
    for (size_t t = 0; t < first.done.size(); ++t) first.done[t] = t % 2;  // render the even tiles only
    ASSERT_TRUE(glint::render_tiles(s, *accel, image, first));
    for (size_t t = 0; t < tiles.done.size(); ++t) tiles.done[t] = t % 2 == 0;
    glint::write_resume_file(glint::api::resume_file_for(output),
                             glint::ResumeState{glint::api::resume_key(scene), tiles, image, {}});
  }

  fs::path dir_;
};

TEST_F(ApiFrames, FileHoldsTheRenderersImage) {
  const Scene scene = mesh_scene();
  FramesOptions options;
  options.output = dir_ / "out.pfm";
  options.passes = {"depth"};
  std::vector<FrameReport> reports;
  ASSERT_TRUE(glint::api::render_frames(scene, options, [&](const FrameReport& r) { reports.push_back(r); }));
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_TRUE(reports[0].complete);
  EXPECT_FALSE(reports[0].resumed);
  EXPECT_EQ(reports[0].tiles_done, reports[0].tiles_total);
  EXPECT_EQ(reports[0].tiles_total, 5u * 3u);  // 72x40 in 16-pixel tiles
  EXPECT_EQ(reports[0].stats.camera_rays, 72u * 40u);
  glint::api::RenderOptions with_depth;
  with_depth.passes = {"depth"};
  const glint::api::RenderResult expected = glint::api::Renderer(scene).render(with_depth);
  EXPECT_EQ(glint::api::read_image(dir_ / "out.pfm").rgb, expected.image.rgb);
  EXPECT_EQ(glint::api::read_image(dir_ / "out.depth.pfm").rgb, expected.passes.at("depth").rgb);
  EXPECT_FALSE(fs::exists(dir_ / "out.pfm.glint-resume"));
}

TEST_F(ApiFrames, AnimationFramesByPatternAndRange) {
  const Scene scene = Scene::load(std::string(GLINT_SOURCE_DIR) + "/tests/mpi/anim4.json");
  FramesOptions options;
  options.output = dir_ / "f_%02d.pfm";
  options.frames = "1-2";
  std::vector<int> frames;
  ASSERT_TRUE(glint::api::render_frames(scene, options, [&](const FrameReport& r) { frames.push_back(r.frame); }));
  EXPECT_EQ(frames, (std::vector<int>{1, 2}));
  EXPECT_FALSE(fs::exists(dir_ / "f_00.pfm"));
  for (int f : {1, 2}) {
    glint::api::PrepareOptions at_frame;
    at_frame.frame = f;
    const glint::api::RenderResult expected = glint::api::Renderer(scene, at_frame).render();
    EXPECT_EQ(glint::api::read_image(dir_ / ("f_0" + std::to_string(f) + ".pfm")).rgb, expected.image.rgb);
  }
  EXPECT_NE(glint::api::resume_key(scene, 1), glint::api::resume_key(scene, 2));

  // Done frames are skipped; several frames need a number in the name.
  options.frames.clear();
  options.skip_existing = true;
  std::vector<bool> skipped;
  ASSERT_TRUE(glint::api::render_frames(scene, options, [&](const FrameReport& r) { skipped.push_back(r.skipped); }));
  EXPECT_EQ(skipped, (std::vector<bool>{false, true, true, false}));
  options.output = dir_ / "f.pfm";
  EXPECT_THROW(glint::api::render_frames(scene, options), glint::Error);
}

TEST_F(ApiFrames, CancelLeavesAPartialImageThatResumesBitIdentically) {
  const Scene scene = mesh_scene();
  FramesOptions options;
  options.output = dir_ / "ref.pfm";
  ASSERT_TRUE(glint::api::render_frames(scene, options));

  // Cancelled before its first tile: the output is background, a resume file beside it.
  const std::atomic<bool> cancel{true};
  options.output = dir_ / "out.pfm";
  options.cancel = &cancel;
  FrameReport report;
  EXPECT_FALSE(glint::api::render_frames(scene, options, [&](const FrameReport& r) { report = r; }));
  EXPECT_FALSE(report.complete);
  EXPECT_EQ(report.tiles_done, 0u);
  const glint::api::Image partial = glint::api::read_image(dir_ / "out.pfm");
  EXPECT_EQ(partial.rgb[0], static_cast<float>(0.1));
  EXPECT_EQ(partial.rgb[2], static_cast<float>(0.3));
  ASSERT_TRUE(fs::exists(dir_ / "out.pfm.glint-resume"));

  // Half the tiles done, then resumed: the bytes of the uninterrupted render.
  write_half_done(scene, dir_ / "out.pfm");
  options.cancel = nullptr;
  options.resume = true;
  ASSERT_TRUE(glint::api::render_frames(scene, options, [&](const FrameReport& r) { report = r; }));
  EXPECT_TRUE(report.resumed);
  // Only the odd tiles were rendered: of the 5 x 3 tiles of 72x40, four whole
  // ones (16x16) and three at the right or bottom edge (8x16, 16x8, 16x8).
  EXPECT_EQ(report.stats.camera_rays, 4u * 256u + 3u * 128u);
  EXPECT_EQ(glint::read_file(dir_ / "out.pfm"), glint::read_file(dir_ / "ref.pfm"));
  EXPECT_FALSE(fs::exists(dir_ / "out.pfm.glint-resume"));
}

TEST_F(ApiFrames, AnEditedMeshFileRefusesTheResume) {
  const Scene scene = mesh_scene();
  write_half_done(scene, dir_ / "out.pfm");
  // One vertex of the mesh moves; the scene, loaded again, reads the new file.
  std::string obj;
  {
    std::ifstream in(dir_ / "bunny.obj");
    obj.assign(std::istreambuf_iterator<char>(in), {});
  }
  const size_t vertex = obj.find("\nv ");
  ASSERT_NE(vertex, std::string::npos);
  obj.insert(vertex + 3, "1");
  std::ofstream(dir_ / "bunny.obj") << obj;
  const Scene edited = mesh_scene();
  ASSERT_EQ(edited.to_json(), scene.to_json());  // the same JSON: only the file differs
  EXPECT_NE(glint::api::resume_key(edited), glint::api::resume_key(scene));

  FramesOptions options;
  options.output = dir_ / "out.pfm";
  options.resume = true;
  try {
    glint::api::render_frames(edited, options);
    ADD_FAILURE() << "resumed into a mixed image";
  } catch (const glint::Error& e) {
    EXPECT_NE(std::string(e.what()).find("different scene files (meshes, textures)"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(dir_ / "out.pfm.glint-resume"));
  // The scene as it was (its mesh still in memory) resumes.
  EXPECT_TRUE(glint::api::render_frames(scene, options));
}

TEST_F(ApiFrames, KeyIsOverTheCanonicalJsonAndTheSettings) {
  const Scene scene = mesh_scene();
  // Spacing, key order and 18 for 18.0 are not content: the same key.
  std::string spaced = kMeshScene;
  spaced.insert(spaced.find("\"render\""), "\n\n   ");
  EXPECT_EQ(glint::api::resume_key(Scene::from_json(spaced, dir_)), glint::api::resume_key(scene));
  const std::string reordered = R"({ "objects": [
      { "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0] },
      { "material": "clay", "type": "mesh", "file": "bunny.obj" } ],
    "camera": { "look_at": [0, 4, 0], "position": [0, 9, 26], "fov_y": 32.0 },
    "lights": [ { "type": "point", "position": [-10, 20, 18] }, { "type": "ambient", "ambient": 0.2 } ],
    "render": { "width": 72, "height": 40, "background": [0.1, 0.2, 0.3] },
    "materials": { "clay": { "diffuse": [0.75, 0.6, 0.5], "specular": 0.5, "shininess": 60 } } })";
  EXPECT_EQ(glint::api::resume_key(Scene::from_json(reordered, dir_)), glint::api::resume_key(scene));
  // An edit in code is content: another key; edited back, the same one.
  Scene edited = scene;
  edited.set("lights[0].position", std::array<double, 3>{-10, 20, 17});
  EXPECT_NE(glint::api::resume_key(edited), glint::api::resume_key(scene));
  edited.set("lights[0].position", std::array<double, 3>{-10, 20, 18});
  EXPECT_EQ(glint::api::resume_key(edited), glint::api::resume_key(scene));
  Scene finer = scene;
  finer.set("render.samples_per_pixel", 4);
  EXPECT_NE(glint::api::resume_key(finer), glint::api::resume_key(scene));
  EXPECT_THROW(glint::api::resume_key(scene, 1), glint::Error);  // a still scene has frame 0 only
}

}  // namespace
