// The `glint` command line end to end, run as a real process: renders to every
// output format read back and compared with the library's own render, options
// overriding the scene, thread-count determinism, the stats line, and every
// error path (one `error:` line, non-zero exit, outputs untouched, no leftovers).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/image/image.h"
#include "glint/io/file_io.h"
#include "glint/io/image_file.h"
#include "glint/io/scene_loader.h"
#include "glint/render/passes.h"
#include "glint/render/renderer.h"
#include "glint/render/resume.h"
#include "glint/version.h"

namespace {

namespace fs = std::filesystem;

// A small scene with everything the integrator does: ambient, diffuse and
// specular terms, shadows, a mirror floor and a glass sphere.
constexpr const char* kScene = R"({
  "render": {"width": 24, "height": 16, "background": [0.1, 0.2, 0.3]},
  "camera": {"position": [0, 1, 5], "look_at": [0, 0.5, 0], "fov_y": 40},
  "materials": {
    "shiny": {"ambient": 0.1, "diffuse": [0.7, 0.2, 0.2], "specular": 0.8, "shininess": 20},
    "mirror": {"diffuse": 0.3, "reflectivity": 0.5},
    "glass": {"diffuse": 0.05, "specular": 0.5, "transparency": 0.9, "ior": 1.5}
  },
  "lights": [
    {"type": "ambient", "color": 0.2},
    {"type": "point", "position": [3, 4, 4], "color": 0.9}
  ],
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "mirror"},
    {"type": "sphere", "center": [-0.6, 0.6, 0], "radius": 0.6, "material": "shiny"},
    {"type": "sphere", "center": [0.8, 0.5, 0.5], "radius": 0.5, "material": "glass"}
  ]
}
)";

// A smooth gradient (a lit wall filling the view): JPEG keeps it to a couple of levels.
constexpr const char* kSmoothScene = R"({
  "render": {"width": 32, "height": 24},
  "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
  "materials": {"wall": {"ambient": 0.2, "diffuse": [0.6, 0.5, 0.4]}},
  "lights": [{"type": "ambient", "color": 0.5}, {"type": "point", "position": [1, 1, 2]}],
  "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1], "material": "wall"}]
}
)";

// Several 16-pixel tiles, 4 jittered samples and an area light: random numbers
// matter, so a thread-dependent seed would show.
constexpr const char* kAreaScene = R"({
  "render": {"width": 40, "height": 24, "samples_per_pixel": 4},
  "camera": {"position": [0, 2, 6], "look_at": [0, 0.5, 0]},
  "materials": {"shiny": {"diffuse": [0.2, 0.6, 0.3], "specular": 0.6, "shininess": 50}},
  "lights": [{"type": "area", "corner": [-1, 4, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "samples": 4}],
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]},
    {"type": "sphere", "center": [0, 0.8, 0], "radius": 0.8, "material": "shiny"}
  ]
}
)";

using Bytes = std::vector<char>;

Bytes read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string read_text(const fs::path& path) {
  const Bytes b = read_bytes(path);
  return std::string(b.begin(), b.end());
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// For /bin/sh: 'it'\''s'.
std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

int exit_code(int status) { return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1; }

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

// The library's own render of a scene file (after `edit`): what the CLI must write.
glint::Image library_render(const fs::path& scene_path, const std::function<void(glint::Scene&)>& edit = {},
                            glint::RenderStats* stats = nullptr) {
  glint::Scene scene = glint::load_scene(scene_path);
  if (edit) edit(scene);
  const auto accel = glint::build_accelerator(scene);
  return glint::render_image(scene, *accel, {}, stats);
}

bool same_pixels(const glint::Image& a, const glint::Image& b) {
  return a.width == b.width && a.height == b.height && a.rgb == b.rgb;
}

// Every test gets its own folder: `work` holds scenes and outputs (and is what
// "no leftovers" inspects); the captured stdout/stderr live beside it.
class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() / ("glint-cli-" + std::string(info->test_suite_name()) + "-" + info->name() +
                                         "-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    work_ = root_ / "work";
    fs::create_directories(work_);
    write_text(work_ / "scene.json", kScene);
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path path(const std::string& name) const { return work_ / name; }

  // Runs `glint ARGS` inside the work folder.
  RunResult run(const std::string& args) const {
    const std::string command = "cd " + shell_quote(work_.string()) + " && " + shell_quote(GLINT_CLI_PATH) + " " +
                                args + " >" + shell_quote((root_ / "stdout.txt").string()) + " 2>" +
                                shell_quote((root_ / "stderr.txt").string());
    RunResult r;
    r.exit_code = exit_code(std::system(command.c_str()));
    r.out = read_text(root_ / "stdout.txt");
    r.err = read_text(root_ / "stderr.txt");
    return r;
  }

  // Renders quietly to `out` and reads the image back.
  glint::Image render(const std::string& out, const std::string& options = "",
                      const std::string& scene = "scene.json") const {
    const RunResult r = run("render " + scene + " -o " + out + " --quiet " + options);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    return glint::read_image(path(out));
  }

  // Name -> contents of every entry of the work folder ("<dir>" for folders).
  std::map<std::string, std::string> listing() const {
    std::map<std::string, std::string> entries;
    for (const auto& e : fs::directory_iterator(work_))
      entries[e.path().filename().string()] = e.is_directory() ? "<dir>" : read_text(e.path());
    return entries;
  }

  // `args` ({out} stands for the output file name) must fail cleanly: one
  // `error:` line containing `message_part`, a non-zero exit, and the work
  // folder exactly as before. Run twice: over an existing output file with
  // known bytes (left untouched) and with no output file (none created).
  void expect_failure(const std::string& args, const std::string& message_part,
                      const std::string& out_name = "out.png") {
    SCOPED_TRACE("glint " + args);
    for (const bool existing : {true, false}) {
      SCOPED_TRACE(existing ? "over an existing output" : "with no output file");
      fs::remove_all(path(out_name));
      if (existing && path(out_name).parent_path() == work_) write_text(path(out_name), "precious bytes\n");
      const auto before = listing();
      std::string command = args;
      for (size_t at; (at = command.find("{out}")) != std::string::npos;) command.replace(at, 5, out_name);
      const RunResult r = run(command);
      EXPECT_NE(r.exit_code, 0);
      EXPECT_NE(r.exit_code, -1) << "did not exit normally";
      EXPECT_EQ(lines_of(r.err).size(), 1u) << "stderr:\n" << r.err;
      EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << "stderr:\n" << r.err;
      EXPECT_TRUE(!r.err.empty() && r.err.back() == '\n') << "stderr:\n" << r.err;
      EXPECT_NE(r.err.find(message_part), std::string::npos) << "stderr:\n" << r.err;
      EXPECT_EQ(r.out, "");
      EXPECT_EQ(listing(), before) << "the work folder changed";
      if (existing && path(out_name).parent_path() == work_) {
        EXPECT_EQ(read_text(path(out_name)), "precious bytes\n");
      }
      if (!existing) {
        EXPECT_FALSE(fs::exists(path(out_name)));
      }
    }
  }

  fs::path root_, work_;
};

using CliFormats = CliTest;
using CliOptions = CliTest;
using CliDeterminism = CliTest;
using CliErrors = CliTest;
using CliStats = CliTest;

// --- formats ----------------------------------------------------------------

TEST_F(CliFormats, FloatFormatsHoldExactlyTheLibraryRender) {
  const glint::Image want = library_render(path("scene.json"));
  ASSERT_EQ(want.width, 24);
  ASSERT_EQ(want.height, 16);
  for (const char* out : {"out.pfm", "out.exr"}) {
    SCOPED_TRACE(out);
    const glint::Image got = render(out);
    EXPECT_EQ(got.width, 24);
    EXPECT_EQ(got.height, 16);
    EXPECT_TRUE(same_pixels(got, want));
  }
}

// Largest and mean difference, in 8-bit sRGB levels, between an image read
// back from an 8-bit file and the clamped sRGB encoding of the exact render.
std::pair<int, double> srgb_level_error(const glint::Image& got, const glint::Image& want) {
  int worst = 0;
  double sum = 0;
  for (size_t i = 0; i < want.rgb.size(); ++i) {
    const int expected = glint::to_srgb8(want.rgb[i]);
    const int actual = static_cast<int>(std::lround(glint::srgb_encode(got.rgb[i]) * 255.0f));
    worst = std::max(worst, std::abs(expected - actual));
    sum += std::abs(expected - actual);
  }
  return {worst, sum / static_cast<double>(want.rgb.size())};
}

TEST_F(CliFormats, PngAndPpmAreTheClampedSrgbOfTheRender) {
  const glint::Image want = library_render(path("scene.json"));
  for (const char* out : {"out.png", "out.ppm"}) {
    SCOPED_TRACE(out);
    const glint::Image got = render(out);
    ASSERT_EQ(got.width, 24);
    ASSERT_EQ(got.height, 16);
    const auto [worst, mean] = srgb_level_error(got, want);
    EXPECT_LE(worst, 1);  // lossless: only rounding
    EXPECT_LE(mean, 0.01);
  }
}

TEST_F(CliFormats, JpegIsCloseToTheClampedSrgbOfTheRender) {
  write_text(path("smooth.json"), kSmoothScene);
  const glint::Image smooth = render("smooth.jpg", "", "smooth.json");
  ASSERT_EQ(smooth.width, 32);
  ASSERT_EQ(smooth.height, 24);
  const auto [worst, mean] = srgb_level_error(smooth, library_render(path("smooth.json")));
  EXPECT_LE(worst, 3);
  EXPECT_LE(mean, 1.0);
  // Sharp edges in a tiny image cost JPEG more, but on average it stays close.
  const glint::Image sharp = render("out.jpg");
  ASSERT_EQ(sharp.width, 24);
  ASSERT_EQ(sharp.height, 16);
  EXPECT_LE(srgb_level_error(sharp, library_render(path("scene.json"))).second, 4.0);
}

TEST_F(CliFormats, ExtensionIsCaseInsensitive) {
  const glint::Image got = render("OUT.PFM");
  EXPECT_TRUE(same_pixels(got, library_render(path("scene.json"))));
}

// --- options override the scene -----------------------------------------------

TEST_F(CliOptions, WidthAndHeight) {
  const glint::Image got = render("out.pfm", "--width 10 --height 7");
  EXPECT_EQ(got.width, 10);
  EXPECT_EQ(got.height, 7);
  EXPECT_TRUE(same_pixels(got, library_render(path("scene.json"), [](glint::Scene& s) {
                            s.render.width = 10;
                            s.render.height = 7;
                          })));
  const glint::Image wide = render("wide.pfm", "--width 30");
  EXPECT_EQ(wide.width, 30);
  EXPECT_EQ(wide.height, 16);
}

TEST_F(CliOptions, SamplesPerPixel) {
  write_text(path("area.json"), kAreaScene);
  auto with_spp = [&](int spp) {
    return library_render(path("area.json"), [spp](glint::Scene& s) { s.render.samples_per_pixel = spp; });
  };
  const glint::Image one = render("one.pfm", "--spp 1", "area.json");
  const glint::Image nine = render("nine.pfm", "--spp 9", "area.json");
  EXPECT_TRUE(same_pixels(one, with_spp(1)));
  EXPECT_TRUE(same_pixels(nine, with_spp(9)));
  EXPECT_FALSE(same_pixels(one, nine));
}

TEST_F(CliOptions, MaxDepth) {
  const glint::Image deep = render("deep.pfm");
  const glint::Image shallow = render("shallow.pfm", "--max-depth 1");
  EXPECT_TRUE(
      same_pixels(shallow, library_render(path("scene.json"), [](glint::Scene& s) { s.render.max_depth = 1; })));
  EXPECT_FALSE(same_pixels(deep, shallow));  // the mirror floor and the glass need depth > 1
}

TEST_F(CliOptions, ShadingModel) {
  const glint::Image phong = render("phong.pfm", "--shading-model phong");
  const glint::Image blinn = render("blinn.pfm", "--shading-model blinn-phong");
  EXPECT_TRUE(same_pixels(phong, library_render(path("scene.json"))));
  EXPECT_TRUE(same_pixels(blinn, library_render(path("scene.json"), [](glint::Scene& s) {
                            s.render.shading_model = glint::ShadingModel::blinn_phong;
                          })));
  EXPECT_FALSE(same_pixels(phong, blinn));  // the shiny sphere's highlight differs
}

TEST_F(CliOptions, ThreadsDoNotChangeTheImage) {
  const glint::Image got = render("out.pfm", "--threads 3");
  EXPECT_TRUE(same_pixels(got, library_render(path("scene.json"))));
}

TEST_F(CliOptions, AccelBackends) {
  // The test scene has analytic shapes only: both kernels run our double tests.
  const glint::Image ours = render("bvh.pfm", "--accel bvh");
  EXPECT_TRUE(same_pixels(ours, library_render(path("scene.json"))));
  if (glint::embree_available()) {
    EXPECT_TRUE(same_pixels(render("embree.pfm", "--accel embree"), ours));
  } else {
    expect_failure("render scene.json -o {out} --accel embree", "built without Embree");
  }
  expect_failure("render scene.json -o {out} --accel octree", "--accel: unknown accelerator \"octree\"");
}

// --- determinism ------------------------------------------------------------------

TEST_F(CliDeterminism, SameBytesWithOneTwoAndSevenThreads) {
  write_text(path("area.json"), kAreaScene);
  for (int threads : {1, 2, 7}) {
    const RunResult r =
        run("render area.json -o t" + std::to_string(threads) + ".pfm --quiet --threads " + std::to_string(threads));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const Bytes one = read_bytes(path("t1.pfm"));
  ASSERT_GT(one.size(), 40u * 24 * 12);
  EXPECT_EQ(read_bytes(path("t2.pfm")), one);
  EXPECT_EQ(read_bytes(path("t7.pfm")), one);
  EXPECT_TRUE(same_pixels(glint::read_image(path("t1.pfm")), library_render(path("area.json"))));
}

// --- the stats line -------------------------------------------------------------------

TEST_F(CliStats, LastLineCountsRaysByKind) {
  glint::RenderStats stats;
  library_render(path("scene.json"), {}, &stats);
  const RunResult r = run("render scene.json -o out.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  const auto lines = lines_of(r.err);
  ASSERT_FALSE(lines.empty());
  EXPECT_LE(lines.size(), 3u) << "stderr is not a terminal: a few plain lines at most";
  const std::string& last = lines.back();
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(last, m,
                        std::regex(R"(([0-9.]+[kM]?) camera, ([0-9.]+[kM]?) shadow, ([0-9.]+[kM]?) reflection, )"
                                   R"(([0-9.]+[kM]?) refraction.*[0-9.]+ Mrays/s)")))
      << last;
  // These counts are small enough to be printed in full.
  EXPECT_EQ(m[1].str(), std::to_string(stats.rays.camera));
  EXPECT_EQ(m[2].str(), std::to_string(stats.rays.shadow));
  EXPECT_EQ(m[3].str(), std::to_string(stats.rays.reflection));
  EXPECT_EQ(m[4].str(), std::to_string(stats.rays.refraction));
  EXPECT_EQ(stats.rays.camera, 24u * 16u);
  EXPECT_GT(stats.rays.shadow, 0u);
  EXPECT_GT(stats.rays.reflection, 0u);
  EXPECT_GT(stats.rays.refraction, 0u);
}

TEST_F(CliStats, QuietSuccessPrintsNothing) {
  const RunResult r = run("render scene.json -o out.png --quiet");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(fs::exists(path("out.png")));
  const RunResult q = run("render scene.json -q -o out.ppm");
  EXPECT_EQ(q.exit_code, 0);
  EXPECT_EQ(q.err, "");
}

TEST_F(CliStats, HelpExitsZero) {
  const auto before = listing();
  const RunResult top = run("--help");
  EXPECT_EQ(top.exit_code, 0);
  EXPECT_NE(top.out.find("render"), std::string::npos) << top.out;
  const RunResult sub = run("render --help");
  EXPECT_EQ(sub.exit_code, 0);
  for (const char* option : {"--output", "--width", "--height", "--spp", "--max-depth", "--shading-model", "--threads",
                             "--accel", "--quiet"})
    EXPECT_NE(sub.out.find(option), std::string::npos) << option;
  EXPECT_EQ(listing(), before);
}

TEST_F(CliStats, VersionIsTheLibrarysVersion) {
  const RunResult r = run("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, std::string("glint ") + GLINT_VERSION_STRING + "\n");
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(std::string(glint::version()), GLINT_VERSION_STRING);
  // MAJOR.MINOR.PATCH, as the project() of CMakeLists.txt gives it.
  EXPECT_EQ(std::string(GLINT_VERSION_STRING), std::to_string(GLINT_VERSION_MAJOR) + "." +
                                                   std::to_string(GLINT_VERSION_MINOR) + "." +
                                                   std::to_string(GLINT_VERSION_PATCH));
  const RunResult help = run("--help");
  EXPECT_NE(help.out.find("--version"), std::string::npos) << help.out;
}

// --- errors -------------------------------------------------------------------------

TEST_F(CliErrors, MalformedSceneSyntaxNamesFileLineColumn) {
  write_text(path("bad.json"),
             "{\n  \"camera\": {\"position\": [0, 0, 5] \"look_at\": [0, 0, 0]},\n  \"objects\": []\n}\n");
  expect_failure("render bad.json -o {out}", "error: bad.json:2:36: syntax error");
}

TEST_F(CliErrors, SceneValueOutOfDomainIsOneExactLine) {
  write_text(path("bad.json"),
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},\n"
             " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": -1}]}\n");
  expect_failure("render bad.json -o {out}", "error: bad.json:2:64: objects[0].radius: must be > 0 (got -1)\n");
  write_text(path("bad.json"),
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},\n"
             " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radus\": 1}]}\n");
  expect_failure("render bad.json -o {out}",
                 "bad.json:2:54: objects[0]: unknown key \"radus\" (did you mean \"radius\"?)");
}

TEST_F(CliErrors, MissingSceneFile) {
  expect_failure("render missing.json -o {out}", "missing.json");
  expect_failure("render missing.json -o {out}", "cannot open");
}

TEST_F(CliErrors, ErrorIsOneLineEvenForAFileNameWithALineBreak) {
  expect_failure("render 'two\nlines.json' -o {out}", "two\\nlines.json");
}

TEST_F(CliErrors, SceneIsAFolder) {
  fs::create_directory(path("folder.json"));
  expect_failure("render folder.json -o {out}", "folder.json");
}

// /dev/zero was read until memory ran out; "" said "cannot open" with no name.
TEST_F(CliErrors, SceneThatIsADeviceOrHasNoName) {
  expect_failure("render /dev/zero -o {out}", "error: /dev/zero: not a regular file (nor a pipe)");
  expect_failure("validate /dev/zero", "error: /dev/zero: not a regular file (nor a pipe)");
  expect_failure("render '' -o {out}", "error: the scene file name is empty");
}

TEST_F(CliErrors, UnknownOption) { expect_failure("render scene.json -o {out} --frobnicate", "--frobnicate"); }

TEST_F(CliErrors, MalformedOptionValues) {
  expect_failure("render scene.json -o {out} --width abc", "--width: expected a whole number, got \"abc\"");
  expect_failure("render scene.json -o {out} --width 0", "--width: must be between 1 and");
  expect_failure("render scene.json -o {out} --height 2.5", "--height: expected a whole number");
  expect_failure("render scene.json -o {out} --spp -1", "--spp");
  expect_failure("render scene.json -o {out} --spp 0", "--spp: must be between 1 and");
  expect_failure("render scene.json -o {out} --max-depth 0", "--max-depth: must be between 1 and");
  expect_failure("render scene.json -o {out} --threads 0", "--threads: must be between 1 and");
  expect_failure("render scene.json -o {out} --threads", "--threads");
}

TEST_F(CliErrors, UnknownShadingModel) {
  expect_failure("render scene.json -o {out} --shading-model bogus", "unknown shading model \"bogus\"");
  expect_failure("render scene.json -o {out} --shading-model blinn_phong", "did you mean \"blinn-phong\"?");
}

TEST_F(CliErrors, AbsurdImageSize) {
  expect_failure("render scene.json -o {out} --width 1000000 --height 1000000", "1000000x1000000 pixels");
}

TEST_F(CliErrors, UnsupportedOutputExtension) {
  expect_failure("render scene.json -o {out}", "unsupported output format", "out.bmp");
  expect_failure("render scene.json -o {out}", "unsupported output format", "out");
}

TEST_F(CliErrors, MissingOutputOption) { expect_failure("render scene.json", "--output"); }

TEST_F(CliErrors, MissingSceneArgument) { expect_failure("render -o {out}", "scene"); }

TEST_F(CliErrors, OutputFolderDoesNotExist) {
  expect_failure("render scene.json -o {out}", "does not exist", "nowhere/out.png");
  EXPECT_FALSE(fs::exists(path("nowhere")));
}

TEST_F(CliErrors, OutputIsAFolder) {
  fs::create_directory(path("taken.png"));
  expect_failure("render scene.json -o taken.png", "taken.png");
  EXPECT_TRUE(fs::is_directory(path("taken.png")));
}

TEST_F(CliErrors, NoOrUnknownCommand) {
  expect_failure("", "no command");
  expect_failure("draw scene.json -o {out}", "unknown command \"draw\"");
  expect_failure("rendr scene.json -o {out}", "did you mean \"render\"?");
}

// A write that fails after the temporary file exists (the file size limit is
// 0; SIGXFSZ is ignored so write() fails with EFBIG): the old output survives
// and the temporary file is gone.
TEST_F(CliErrors, FailedWriteLeavesNoTemporaryFile) {
  write_text(path("out.png"), "precious bytes\n");
  const auto before = listing();
  const std::string command = "cd " + shell_quote(work_.string()) + " && (trap '' XFSZ; ulimit -f 0; exec " +
                              shell_quote(GLINT_CLI_PATH) + " render scene.json -o out.png --quiet) 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string err;
  char buffer[256];
  while (size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) err.append(buffer, n);
  const int status = ::pclose(pipe);
  EXPECT_NE(exit_code(status), 0);
  EXPECT_NE(exit_code(status), -1) << "did not exit normally";
  EXPECT_EQ(lines_of(err).size(), 1u) << err;
  EXPECT_EQ(err.rfind("error: out.png: cannot write", 0), 0u) << err;
  EXPECT_EQ(listing(), before);
}

// --- passes ---------------------------------------------------------------

using CliPasses = CliTest;

constexpr const char* kColorPasses[] = {"ambient", "diffuse", "specular", "reflection", "transmission"};

TEST_F(CliPasses, OneFilePerPassInTheOutputsFormatSummingToTheImage) {
  for (const std::string ext : {"pfm", "exr"}) {
    SCOPED_TRACE(ext);
    const glint::Image beauty = render("out." + ext, "--spp 4 --passes all");
    EXPECT_TRUE(same_pixels(
        beauty, library_render(path("scene.json"), [](glint::Scene& s) { s.render.samples_per_pixel = 4; })));
    std::vector<double> sum(beauty.rgb.size(), 0.0);
    for (const char* pass : kColorPasses) {
      const glint::Image p = glint::read_image(path(std::string("out.") + pass + "." + ext));
      ASSERT_EQ(p.width, beauty.width);
      for (size_t i = 0; i < sum.size(); ++i) sum[i] += p.rgb[i];
    }
    for (size_t i = 0; i < sum.size(); ++i)
      ASSERT_NEAR(sum[i], beauty.rgb[i], 1e-6 * std::max(1.0f, beauty.rgb[i])) << i;
    for (const char* pass : {"normal", "depth", "albedo"})
      EXPECT_TRUE(fs::exists(path(std::string("out.") + pass + "." + ext))) << pass;
  }
  render("out.png", "--passes normal,diffuse");
  EXPECT_TRUE(fs::exists(path("out.normal.png")));
  EXPECT_TRUE(fs::exists(path("out.diffuse.png")));
  EXPECT_FALSE(fs::exists(path("out.depth.png")));
}

TEST_F(CliPasses, LayeredExrHoldsEveryPassAsChannels) {
  const glint::Image beauty = render("out.exr", "--passes-layered");
  const glint::ExrPlanes exr = glint::read_exr_channels(path("out.exr"));
  std::vector<std::string> names;
  for (const auto& [name, plane] : exr.planes) names.push_back(name);
  const std::vector<std::string> want = {"B",
                                         "G",
                                         "R",
                                         "albedo.B",
                                         "albedo.G",
                                         "albedo.R",
                                         "ambient.B",
                                         "ambient.G",
                                         "ambient.R",
                                         "depth.Z",
                                         "diffuse.B",
                                         "diffuse.G",
                                         "diffuse.R",
                                         "normal.X",
                                         "normal.Y",
                                         "normal.Z",
                                         "reflection.B",
                                         "reflection.G",
                                         "reflection.R",
                                         "specular.B",
                                         "specular.G",
                                         "specular.R",
                                         "transmission.B",
                                         "transmission.G",
                                         "transmission.R"};
  EXPECT_EQ(names, want);
  for (size_t i = 0; i < beauty.rgb.size() / 3; ++i) {
    double sum = 0;
    for (const char* pass : kColorPasses) sum += exr.planes.at(std::string(pass) + ".G")[i];
    ASSERT_NEAR(sum, beauty.rgb[3 * i + 1], 1e-6 * std::max(1.0f, beauty.rgb[3 * i + 1])) << i;
  }
  EXPECT_FALSE(fs::exists(path("out.diffuse.exr")));
}

TEST_F(CliPasses, Errors) {
  expect_failure("render scene.json -o {out} --passes diffuse,specularr", "did you mean \"specular\"");
  expect_failure("render scene.json -o {out} --passes-layered", "must be .exr");
}

TEST_F(CliPasses, InterruptedRenderResumesWithItsPasses) {
  // A resume file with half the tiles done (as an interrupted run leaves it),
  // then --resume: the passes equal an uninterrupted run's.
  render("ref.pfm", "--passes diffuse,depth");
  glint::Scene scene = glint::load_scene(path("scene.json"));
  const auto accel = glint::build_accelerator(scene);
  glint::Image image(24, 16);
  glint::PassImages passes({glint::Pass::diffuse, glint::Pass::depth}, 24, 16);
  glint::TileProgress tiles(24, 16, 16);
  tiles.done[1] = 1;  // the right tile is to be rendered now, the left one "was done"
  tiles.done[0] = 0;
  glint::TileProgress first = tiles;
  first.done = {0, 1};
  ASSERT_TRUE(glint::render_tiles(scene, *accel, image, first, {}, nullptr, &passes));
  tiles.done = {1, 0};
  const uint64_t digest = glint::scene_inputs_digest(glint::read_file(path("scene.json")), scene);
  glint::write_resume_file(path("out.pfm.glint-resume"),
                           glint::ResumeState{glint::resume_key(digest, scene.render), tiles, image, passes});
  // Other passes than the resume file's: refused, the resume file stays.
  const RunResult wrong = run("render scene.json -o out.pfm --quiet --resume --passes diffuse");
  EXPECT_NE(wrong.exit_code, 0);
  EXPECT_NE(wrong.err.find("other --passes"), std::string::npos) << wrong.err;
  ASSERT_TRUE(fs::exists(path("out.pfm.glint-resume")));
  render("out.pfm", "--resume --passes diffuse,depth");
  EXPECT_FALSE(fs::exists(path("out.pfm.glint-resume")));
  EXPECT_EQ(read_text(path("out.pfm")), read_text(path("ref.pfm")));
  EXPECT_EQ(read_text(path("out.diffuse.pfm")), read_text(path("ref.diffuse.pfm")));
  EXPECT_EQ(read_text(path("out.depth.pfm")), read_text(path("ref.depth.pfm")));
}

// --- tone mapping, exposure, Radiance HDR -------------------------------------

using CliToneMap = CliTest;

TEST_F(CliToneMap, ExposureAndToneMapShapeEightBitOutputs) {
  const glint::Image exact = library_render(path("scene.json"));
  for (const auto& [name, map] : {std::pair{"clamp", glint::ToneMap::clamp},
                                  {"reinhard", glint::ToneMap::reinhard},
                                  {"aces", glint::ToneMap::aces}}) {
    SCOPED_TRACE(name);
    const glint::Image got =
        render(std::string("out-") + name + ".png", std::string("--exposure 1.5 --tonemap ") + name);
    glint::Image want = exact;
    for (float& v : want.rgb) v = glint::tone_map(v * std::exp2(1.5f), map);
    EXPECT_EQ(srgb_level_error(got, want).first, 0);
  }
  // The default is the contract's clamp, byte for byte.
  render("default.png");
  render("clamp.png", "--tonemap clamp --exposure 0");
  EXPECT_EQ(read_bytes(path("default.png")), read_bytes(path("clamp.png")));
}

TEST_F(CliToneMap, LinearOutputsAreNeverToneMappedAndSayWhy) {
  render("plain.pfm");
  const RunResult r = run("render scene.json -o mapped.pfm --tonemap aces --exposure 2");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.err.find("warning: mapped.pfm holds linear values"), std::string::npos) << r.err;
  EXPECT_EQ(read_bytes(path("plain.pfm")), read_bytes(path("mapped.pfm")));
}

TEST_F(CliToneMap, RadianceHdrOutput) {
  const glint::Image want = library_render(path("scene.json"));
  const glint::Image got = render("out.hdr");
  ASSERT_EQ(got.width, want.width);
  for (size_t p = 0; p < want.rgb.size(); p += 3) {
    const float largest = std::max({want.rgb[p], want.rgb[p + 1], want.rgb[p + 2]});
    for (size_t c = 0; c < 3; ++c) ASSERT_NEAR(got.rgb[p + c], want.rgb[p + c], largest / 128.0f) << p;
  }
}

TEST_F(CliToneMap, Errors) {
  expect_failure("render scene.json -o {out} --tonemap acs", "did you mean \"aces\"");
  expect_failure("render scene.json -o {out} --exposure nan", "expected a number");
  expect_failure("render scene.json -o {out} --exposure 65", "between -64 and 64");
}

TEST_F(CliOptions, PixelFilterOverridesTheScene) {
  for (const auto& [name, type, radius] :
       {std::tuple{"gaussian", glint::FilterType::gaussian, glint::kGaussianRadius},
        std::tuple{"mitchell", glint::FilterType::mitchell, glint::kMitchellRadius}}) {
    SCOPED_TRACE(name);
    const glint::Image got = render(std::string(name) + ".pfm", std::string("--spp 4 --pixel-filter ") + name);
    // The filter as a plain local: clang 14 cannot capture a structured binding.
    const glint::PixelFilter filter{type, radius};
    EXPECT_TRUE(same_pixels(got, library_render(path("scene.json"), [&](glint::Scene& s) {
                              s.render.samples_per_pixel = 4;
                              s.render.pixel_filter = filter;
                            })));
  }
  expect_failure("render scene.json -o {out} --pixel-filter gausian", "did you mean \"gaussian\"");
}

TEST_F(CliOptions, AdaptiveSamplingWithPasses) {
  const RunResult r =
      run("render scene.json -o out.pfm --spp 2 --adaptive-max-spp 16 --adaptive-threshold 0.02 "
          "--passes all --threads 3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("glint: adaptive: "), std::string::npos) << r.err;
  const glint::Image beauty = glint::read_image(path("out.pfm"));
  EXPECT_TRUE(same_pixels(beauty, library_render(path("scene.json"), [](glint::Scene& s) {
                            s.render.samples_per_pixel = 2;
                            s.render.adaptive = glint::AdaptiveSampling{16, 0.02};
                          })));
  EXPECT_FALSE(
      same_pixels(beauty, library_render(path("scene.json"), [](glint::Scene& s) { s.render.samples_per_pixel = 2; })));
  std::vector<double> sum(beauty.rgb.size(), 0.0);
  for (const char* pass : kColorPasses) {
    const glint::Image p = glint::read_image(path(std::string("out.") + pass + ".pfm"));
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += p.rgb[i];
  }
  for (size_t i = 0; i < sum.size(); ++i) ASSERT_NEAR(sum[i], beauty.rgb[i], 1e-6 * std::max(1.0f, beauty.rgb[i])) << i;
  expect_failure("render scene.json -o {out} --spp 8 --adaptive-max-spp 4", "below samples_per_pixel");
}

}  // namespace

// --- explain -----------------------------------------------------------------

using CliExplain = CliTest;

TEST_F(CliExplain, JsonColorEqualsTheRenderedPixel) {
  const glint::Image image = render("out.pfm", "--spp 1");
  for (const auto& [x, y] : std::vector<std::pair<int, int>>{{0, 0}, {5, 7}, {12, 8}, {20, 3}}) {
    if (x >= image.width || y >= image.height) continue;
    const RunResult r = run("explain scene.json --pixel " + std::to_string(x) + " " + std::to_string(y) + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["pixel"], nlohmann::json::array({x, y}));
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(static_cast<float>(j["color"][c].get<double>()), image.pixel(x, y)[c]) << x << "," << y;
  }
}

TEST_F(CliExplain, TextNamesTheRayTree) {
  const RunResult r = run("explain scene.json --pixel 12 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("pixel (12, 8) = ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("ray (depth 1)"), std::string::npos) << r.out;
}

TEST_F(CliExplain, Errors) {
  expect_failure("explain scene.json --pixel 100000 0", "outside");
  expect_failure("explain scene.json --pixel 1", "pixel");
  expect_failure("explain missing.json --pixel 1 1", "missing.json");
}
