// Frames on the command line: --frames ranges, printf-style frame numbers in
// the output name, --skip-existing; every frame's file is the library's render
// of that frame's scene.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "glint/accel/accelerator.h"
#include "glint/image/image.h"
#include "glint/io/image_file.h"
#include "glint/io/scene_loader.h"
#include "glint/render/frames.h"
#include "glint/render/renderer.h"
#include "glint/render/resume.h"
#include "glint/scene/animation.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

TEST(FrameNames, PrintfStyleFrameNumbers) {
  EXPECT_EQ(frame_output_path("out_%04d.png", 7), "out_0007.png");
  EXPECT_EQ(frame_output_path("out_%04d.png", 123456), "out_123456.png");
  EXPECT_EQ(frame_output_path("%d.exr", 12), "12.exr");
  EXPECT_EQ(frame_output_path("a%%b_%02d.png", 3), "a%b_03.png");
  EXPECT_EQ(frame_output_path("out.png", 3), std::nullopt);
  EXPECT_EQ(frame_output_path("100%.png", 3), std::nullopt);
  EXPECT_EQ(frame_output_path("%d_%d.png", 3), std::nullopt);  // two numbers: not a frame pattern
  EXPECT_EQ(frame_output_path("%5d.png", 3), std::nullopt);
}

TEST(FrameNames, Ranges) {
  EXPECT_EQ(parse_frame_range("0-3", 4), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(parse_frame_range("2", 4), (std::vector<int>{2}));
  EXPECT_EQ(parse_frame_range("0", 1), (std::vector<int>{0}));
  auto error_of = [](const char* text, int count) -> std::string {
    try {
      parse_frame_range(text, count);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(error_of("3-1", 4), "--frames \"3-1\": the range is empty (3 > 1)");
  EXPECT_EQ(error_of("0-9", 4), "--frames \"0-9\": the scene has frames 0-3");
  EXPECT_EQ(error_of("1", 1), "--frames \"1\": the scene has frames 0-0 (it is not animated)");
  EXPECT_EQ(error_of("-1", 4), "--frames \"-1\": the scene has frames 0-3");
  EXPECT_EQ(error_of("a-b", 4), "--frames \"a-b\": expected a frame N or a range A-B");
  EXPECT_EQ(error_of("", 4), "--frames \"\": expected a frame N or a range A-B");
}

class CliFrames : public ::testing::Test {
 protected:
  void SetUp() override {
    work_ = fs::temp_directory_path() /
            ("glint-frames-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "-" +
             std::to_string(::getpid()));
    fs::remove_all(work_);
    fs::create_directories(work_);
    scene_ = std::string(GLINT_SOURCE_DIR) + "/tests/mpi/anim4.json";
  }
  void TearDown() override { fs::remove_all(work_); }

  // Runs `glint render <scene> ARGS` in the work folder; returns the exit code, stderr in err_.
  int render(const std::string& args) {
    const std::string command =
        "cd '" + work_.string() + "' && '" GLINT_CLI_PATH "' render '" + scene_ + "' " + args + " 2> stderr.txt";
    const int status = std::system(command.c_str());
    std::ifstream in(work_ / "stderr.txt");
    std::stringstream text;
    text << in.rdbuf();
    err_ = text.str();
    return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  Image library_frame(int frame) const {
    const Scene scene = scene_at_frame(load_scene(scene_), frame);
    return render_image(scene, *build_accelerator(scene));
  }

  fs::path work_;
  std::string scene_, err_;
};

TEST_F(CliFrames, EveryFrameIsTheLibraryRenderOfItsScene) {
  ASSERT_EQ(render("-o f_%02d.pfm -q"), 0) << err_;
  for (int f = 0; f < 4; ++f) {
    const Image image = read_image(work_ / ("f_0" + std::to_string(f) + ".pfm"));
    EXPECT_EQ(image.rgb, library_frame(f).rgb) << "frame " << f;
  }
  EXPECT_NE(read_image(work_ / "f_00.pfm").rgb, read_image(work_ / "f_03.pfm").rgb) << "nothing moved";
}

TEST_F(CliFrames, RangeRendersOnlyItsFrames) {
  ASSERT_EQ(render("-o f_%d.pfm --frames 1-2 -q"), 0) << err_;
  EXPECT_FALSE(fs::exists(work_ / "f_0.pfm"));
  EXPECT_TRUE(fs::exists(work_ / "f_1.pfm"));
  EXPECT_TRUE(fs::exists(work_ / "f_2.pfm"));
  EXPECT_FALSE(fs::exists(work_ / "f_3.pfm"));
  ASSERT_EQ(render("-o one.pfm --frames 3 -q"), 0) << err_;  // one frame: no pattern needed
  EXPECT_EQ(read_image(work_ / "one.pfm").rgb, library_frame(3).rgb);
}

TEST_F(CliFrames, SeveralFramesNeedAPattern) {
  EXPECT_EQ(render("-o out.png"), 1);
  EXPECT_EQ(err_,
            "error: out.png: 4 frames need a frame number in the output name, exactly one %d or %0Nd "
            "(e.g. out_%04d.png)\n");
  EXPECT_EQ(render("-o f_%d.png --frames 2-7"), 1);
  EXPECT_EQ(err_, "error: --frames \"2-7\": the scene has frames 0-3\n");
  EXPECT_FALSE(fs::exists(work_ / "f_2.png"));
}

TEST_F(CliFrames, SkipExistingRendersOnlyMissingOrUnfinishedFrames) {
  ASSERT_EQ(render("-o f_%d.pfm --frames 0-1 -q"), 0) << err_;
  // Frame 1 looks interrupted: a resume file beside it means its image is partial.
  std::ofstream(work_ / "f_1.pfm.glint-resume") << "x";
  ASSERT_EQ(resume_path_for(work_ / "f_1.pfm"), work_ / "f_1.pfm.glint-resume");
  const auto written = fs::last_write_time(work_ / "f_0.pfm");
  ASSERT_EQ(render("-o f_%d.pfm --skip-existing"), 0) << err_;
  EXPECT_NE(err_.find("f_0.pfm exists: skipped"), std::string::npos) << err_;
  EXPECT_EQ(err_.find("f_1.pfm exists: skipped"), std::string::npos) << err_;
  EXPECT_EQ(fs::last_write_time(work_ / "f_0.pfm"), written);
  for (int f = 1; f < 4; ++f)
    EXPECT_EQ(read_image(work_ / ("f_" + std::to_string(f) + ".pfm")).rgb, library_frame(f).rgb);
  EXPECT_FALSE(fs::exists(work_ / "f_1.pfm.glint-resume"));
}

TEST_F(CliFrames, ExplainFollowsTheFrame) {
  // A pixel that differs between frame 0 and frame 3 (the ball moved).
  auto spp1_frame = [&](int frame) {
    Scene scene = scene_at_frame(load_scene(scene_), frame);
    scene.render.samples_per_pixel = 1;
    return render_image(scene, *build_accelerator(scene));
  };
  const Image first = spp1_frame(0), last = spp1_frame(3);
  int x = 0, y = 0;
  while (y < last.height && first.pixel(x, y)[0] == last.pixel(x, y)[0]) {
    if (++x == last.width) x = 0, ++y;
  }
  ASSERT_LT(y, last.height) << "nothing moved";
  const std::string command = "'" GLINT_CLI_PATH "' explain '" + scene_ + "' --json --frame 3 --pixel " +
                              std::to_string(x) + " " + std::to_string(y) + " > '" + (work_ / "explain.json").string() +
                              "'";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream in(work_ / "explain.json");
  const auto color = nlohmann::json::parse(in)["color"];
  for (int c = 0; c < 3; ++c) EXPECT_EQ(static_cast<float>(color[c].get<double>()), last.pixel(x, y)[c]);
}

TEST_F(CliFrames, InfoNamesTheAnimation) {
  const std::string command = "'" GLINT_CLI_PATH "' info '" + scene_ + "' > '" + (work_ / "info.txt").string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream in(work_ / "info.txt");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("animation  4 frames at 2 fps, 2 animated objects, animated camera\n"), std::string::npos)
      << text.str();
}

}  // namespace
}  // namespace glint
