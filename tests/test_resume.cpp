// Interrupt and resume: a render that stops part-way keeps its finished tiles
// and a resume file; finishing it gives the very bytes of an uninterrupted
// render. Checked in the library (tiles, resume files) and end to end with a
// real SIGINT to the glint command.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include "glint/io/file_io.h"
#include "glint/io/scene_loader.h"
#include "glint/render/renderer.h"
#include "glint/render/resume.h"
#include "glint/render/tile_size.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

Scene small_scene() {
  Scene scene = load_scene(std::string(GLINT_SOURCE_DIR) + "/scenes/showcase.json");
  scene.render.width = 70;
  scene.render.height = 40;
  scene.render.samples_per_pixel = 2;
  return scene;
}

TEST(Resume, FinishingMarkedTilesGivesTheSameImage) {
  const Scene scene = small_scene();
  const auto accel = build_accelerator(scene);
  const Image whole = render_image(scene, *accel);

  // Pretend every third tile was done by an earlier run (with its pixels).
  Image image(scene.render.width, scene.render.height);
  TileProgress tiles(scene.render.width, scene.render.height, 16);
  TileProgress first(scene.render.width, scene.render.height, 16);
  for (size_t t = 0; t < first.done.size(); ++t) first.done[t] = t % 3 != 0;  // tiles not to render now
  ASSERT_TRUE(render_tiles(scene, *accel, image, first));                     // renders the t % 3 == 0 tiles
  for (size_t t = 0; t < first.done.size(); ++t) tiles.done[t] = t % 3 == 0;
  EXPECT_TRUE(render_tiles(scene, *accel, image, tiles));
  EXPECT_EQ(image.rgb, whole.rgb);
}

TEST(Resume, CancelledRenderLeavesTilesUnfinishedAndFillsThemWithBackground) {
  const Scene scene = small_scene();
  const auto accel = build_accelerator(scene);
  std::atomic<bool> cancel{true};
  RenderOptions options;
  options.cancel = &cancel;
  Image image(scene.render.width, scene.render.height);
  TileProgress tiles(scene.render.width, scene.render.height, 16);
  EXPECT_FALSE(render_tiles(scene, *accel, image, tiles, options));
  EXPECT_EQ(tiles.count_done(), 0u);
  fill_unfinished_tiles(image, tiles, scene.render.background);
  EXPECT_EQ(image.pixel(69, 39)[2], static_cast<float>(scene.render.background.z));
}

TEST(Resume, FileRoundTripAndCorruptFiles) {
  const fs::path dir = fs::temp_directory_path() / ("glint-resume-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  ResumeState state;
  state.key = 0x1234567890abcdefULL;
  state.image = Image(20, 10);
  state.image.rgb[7] = 0.25f;
  state.progress = TileProgress(20, 10, 16);
  state.progress.done[1] = 1;
  const fs::path path = dir / "out.png.glint-resume";
  write_resume_file(path, state);
  const auto back = read_resume_file(path);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->key, state.key);
  EXPECT_EQ(back->progress.done, state.progress.done);
  EXPECT_EQ(back->image.rgb, state.image.rgb);
  EXPECT_FALSE(read_resume_file(dir / "missing").has_value());

  std::vector<unsigned char> bytes = read_file(path);
  bytes.pop_back();
  write_file_atomically(path, bytes);
  EXPECT_THROW(read_resume_file(path), Error);
  bytes[0] = 'X';
  write_file_atomically(path, bytes);
  EXPECT_THROW(read_resume_file(path), Error);
  fs::remove_all(dir);
}

std::span<const unsigned char> bytes_of(const std::string& text) {
  return std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size());
}

TEST(Resume, KeyChangesWithSceneSettingsAndFrame) {
  const Scene scene;
  const std::string a = "{\"x\": 1}", b = "{\"x\": 2}";
  const uint64_t digest = scene_inputs_digest(bytes_of(a), scene);
  EXPECT_EQ(digest, scene_inputs_digest(bytes_of(a), scene));
  EXPECT_NE(digest, scene_inputs_digest(bytes_of(b), scene));
  RenderSettings s;
  const uint64_t k = resume_key(digest, s);
  EXPECT_EQ(k, resume_key(digest, s, 0));
  EXPECT_NE(k, resume_key(digest, s, 1));
  RenderSettings more = s;
  more.samples_per_pixel = 4;
  EXPECT_NE(k, resume_key(digest, more));
  RenderSettings filtered = s;
  filtered.pixel_filter = {FilterType::gaussian, kGaussianRadius};
  EXPECT_NE(k, resume_key(digest, filtered));
  RenderSettings adaptive = s;
  adaptive.adaptive = AdaptiveSampling{};
  EXPECT_NE(k, resume_key(digest, adaptive));
}

// What the scene loaded from its other files is in the digest: a mesh's
// vertices, a texture's texels, a material (an .mtl's) all change it.
TEST(Resume, DigestCoversWhatTheSceneLoadedFromItsFiles) {
  Scene scene;
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  scene.meshes.push_back(mesh);
  TextureImage image;
  image.width = image.height = 1;
  image.texels = {{0.5f, 0.5f, 0.5f}};
  scene.texture_images.push_back(image);
  const std::string doc = "{}";
  const uint64_t digest = scene_inputs_digest(bytes_of(doc), scene);

  Scene moved = scene;
  moved.meshes[0].positions[2].y = std::nextafter(1.0f, 2.0f);  // one vertex, one ulp
  EXPECT_NE(scene_inputs_digest(bytes_of(doc), moved), digest);
  Scene repainted = scene;
  repainted.texture_images[0].texels[0].z = 0.25f;
  EXPECT_NE(scene_inputs_digest(bytes_of(doc), repainted), digest);
  Scene shinier = scene;
  shinier.materials[0].shininess = 33;
  EXPECT_NE(scene_inputs_digest(bytes_of(doc), shinier), digest);
  Scene rescaled = scene;
  rescaled.textures.push_back(Texture{});
  EXPECT_NE(scene_inputs_digest(bytes_of(doc), rescaled), digest);
  EXPECT_EQ(scene_inputs_digest(bytes_of(doc), Scene(scene)), digest);
}

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// glint with its standard streams on a pseudo-terminal, so that it draws its
// progress bar there: the bar is the event the test waits for.
struct TerminalChild {
  pid_t pid = -1;
  int terminal = -1;  // the master side: what glint writes to its stderr
};

TerminalChild spawn_on_terminal(std::vector<std::string> args) {
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  TerminalChild child;
  child.pid = ::forkpty(&child.terminal, nullptr, nullptr, nullptr);
  if (child.pid == 0) {
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return child;
}

// Reads the terminal until the progress bar shows at least `percent` (true)
// or glint closes it (false: it ended first). Everything read is kept in `seen`.
bool wait_for_progress(int terminal, int percent, std::string& seen) {
  char buffer[512];
  for (;;) {
    const ssize_t n = ::read(terminal, buffer, sizeof buffer);
    if (n <= 0) return false;  // EIO once the child has closed its side
    seen.append(buffer, static_cast<size_t>(n));
    // The bar's last update: "\r[####......]  25% ETA 3s".
    const size_t close = seen.rfind("] ");
    if (close != std::string::npos && seen.find('%', close) != std::string::npos) {
      const int shown = std::atoi(seen.c_str() + close + 2);
      if (shown >= percent && shown < 100) return true;
    }
  }
}

// The rest of what glint writes, until it closes the terminal.
void read_to_end(int terminal, std::string& seen) {
  char buffer[512];
  for (ssize_t n; (n = ::read(terminal, buffer, sizeof buffer)) > 0;) seen.append(buffer, static_cast<size_t>(n));
}

TEST(ResumeCli, InterruptedThenResumedRenderIsBitIdentical) {
  const fs::path dir = fs::temp_directory_path() / ("glint-resume-cli-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string glint = GLINT_CLI_PATH;
  const std::string scene = std::string(GLINT_SOURCE_DIR) + "/scenes/showcase.json";
  // With passes: their finished tiles go into the resume file too.
  const std::string size = " --width 240 --height 135 --spp 16 --threads 2 --passes diffuse,depth";
  const std::string ref = (dir / "ref.pfm").string(), out = (dir / "out.pfm").string();
  ASSERT_EQ(run(glint + " render " + scene + " -o " + ref + size + " --quiet"), 0);

  // SIGINT once the progress bar shows a tenth of the tiles done: glint
  // installs its handler before the render starts, and the signal lands
  // part-way on any machine, however loaded (unless this process is held
  // back for the rest of the render: then it finished, and the test cannot
  // tell). The render must stop within a second of the signal.
  const TerminalChild child = spawn_on_terminal({glint, "render", scene, "-o", out, "--width", "240", "--height", "135",
                                                 "--spp", "16", "--threads", "2", "--passes", "diffuse,depth"});
  ASSERT_GT(child.pid, 0);
  std::string seen;
  const bool part_way = wait_for_progress(child.terminal, 10, seen);
  const auto start = std::chrono::steady_clock::now();
  if (part_way) ::kill(child.pid, SIGINT);
  read_to_end(child.terminal, seen);
  int status = 0;
  ::waitpid(child.pid, &status, 0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ::close(child.terminal);
  ASSERT_TRUE(WIFEXITED(status)) << "glint died of a signal";
  if (WEXITSTATUS(status) == 0) GTEST_SKIP() << "the render finished before the signal";
  ASSERT_TRUE(part_way) << seen;
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);  // the shell convention for "stopped by SIGINT"
  EXPECT_LT(seconds, 1.2);
  EXPECT_NE(seen.find("error: interrupted: "), std::string::npos) << seen;
  ASSERT_TRUE(fs::exists(out));
  ASSERT_TRUE(fs::exists(out + ".glint-resume"));

  // A resume with other settings is refused, the files stay.
  EXPECT_NE(run(glint + " render " + scene + " -o " + out + size + " --max-depth 2 --resume --quiet 2>/dev/null"), 0);
  ASSERT_TRUE(fs::exists(out + ".glint-resume"));

  ASSERT_EQ(run(glint + " render " + scene + " -o " + out + size + " --resume --quiet"), 0);
  EXPECT_EQ(read_file(out), read_file(ref));
  EXPECT_EQ(read_file(dir / "out.diffuse.pfm"), read_file(dir / "ref.diffuse.pfm"));
  EXPECT_EQ(read_file(dir / "out.depth.pfm"), read_file(dir / "ref.depth.pfm"));
  EXPECT_FALSE(fs::exists(out + ".glint-resume"));
  fs::remove_all(dir);
}

// A resume file for `output` with the even tiles of `scene` done, as an
// interrupted render leaves it.
void write_half_done(const Scene& scene, uint64_t key, const fs::path& output) {
  const int w = scene.render.width, h = scene.render.height;
  const auto accel = build_accelerator(scene);
  Image image(w, h);
  TileProgress first(w, h, kTileSize), tiles(w, h, kTileSize);
  for (size_t t = 0; t < first.done.size(); ++t) first.done[t] = t % 2;  // odd tiles "done": render the even ones
  ASSERT_TRUE(render_tiles(scene, *accel, image, first));
  for (size_t t = 0; t < tiles.done.size(); ++t) tiles.done[t] = t % 2 == 0;
  write_resume_file(resume_path_for(output), ResumeState{key, tiles, image, {}});
}

// The resume key covers the mesh files a scene names, not only the scene
// file: an edited mesh refuses the resume (rather than finishing a mixed
// image), an unchanged one resumes to the bytes of an uninterrupted render.
TEST(ResumeCli, EditedMeshFileRefusesTheResume) {
  const fs::path dir = fs::temp_directory_path() / ("glint-resume-mesh-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string source = std::string(GLINT_SOURCE_DIR) + "/scenes/meshes/";
  fs::copy_file(source + "bunny.json", dir / "bunny.json");
  fs::copy_file(source + "bunny.obj", dir / "bunny.obj");
  const std::string glint = GLINT_CLI_PATH, scene_path = (dir / "bunny.json").string();
  const std::string out = (dir / "out.pfm").string(), ref = (dir / "ref.pfm").string();
  const std::string options = " --width 96 --height 48 --spp 1 --threads 2 --quiet";
  ASSERT_EQ(run(glint + " render " + scene_path + " -o " + ref + options), 0);

  // The key the command computes: the scene file's bytes, what it loaded, the settings.
  auto key_now = [&](Scene& scene) {
    scene = load_scene(scene_path);
    scene.render.width = 96;
    scene.render.height = 48;
    scene.render.samples_per_pixel = 1;
    return resume_key(scene_inputs_digest(read_file(scene_path), scene), scene.render);
  };
  Scene scene;
  const uint64_t key = key_now(scene);
  write_half_done(scene, key, out);
  ASSERT_EQ(run(glint + " render " + scene_path + " -o " + out + options + " --resume"), 0);
  EXPECT_EQ(read_file(out), read_file(ref));
  EXPECT_FALSE(fs::exists(out + ".glint-resume"));

  // The same half-done file, then one vertex of the mesh moves.
  write_half_done(scene, key, out);
  std::string obj;
  {
    std::ifstream in(dir / "bunny.obj");
    obj.assign(std::istreambuf_iterator<char>(in), {});
  }
  const size_t vertex = obj.find("\nv ");
  ASSERT_NE(vertex, std::string::npos);
  obj.insert(vertex + 3, "1");  // "v 1.30 ..." -> "v 11.30 ...": one vertex moves
  std::ofstream(dir / "bunny.obj") << obj;
  Scene edited;
  EXPECT_NE(key_now(edited), key);
  const std::string err = (dir / "err.txt").string();
  EXPECT_EQ(run(glint + " render " + scene_path + " -o " + out + options + " --resume 2> " + err), 1);
  std::ifstream in(err);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "error: " + out +
                      ".glint-resume: made for a different scene, different scene files (meshes, "
                      "textures) or different settings; delete it to render from the start");
  EXPECT_TRUE(fs::exists(out + ".glint-resume"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace glint
