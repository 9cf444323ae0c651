// `glint info`: objects counted by type, meshes with their triangles (an
// instance counts its mesh again), on a mesh scene and on the new shapes.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct InfoRun {
  int exit_code = -1;
  std::string out;
};

InfoRun info(const fs::path& scene) {
  const fs::path out = fs::temp_directory_path() / ("glint-info-" + std::to_string(::getpid()) + ".txt");
  const std::string command =
      std::string("'") + GLINT_CLI_PATH + "' info '" + scene.string() + "' >'" + out.string() + "' 2>&1";
  InfoRun r;
  const int status = std::system(command.c_str());
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(out);
  std::stringstream s;
  s << in.rdbuf();
  r.out = s.str();
  fs::remove(out);
  return r;
}

std::string line_starting(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) return line;
  return "";
}

TEST(Info, CountsMeshesAndTheirTriangles) {
  const fs::path dir = fs::temp_directory_path() / ("glint-info-mesh-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string cube = std::string(GLINT_SOURCE_DIR) + "/tests/meshes/cube.obj";
  std::ofstream(dir / "scene.json") << R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": [
    {"type": "mesh", "file": ")" << cube
                                    << R"("},
    {"type": "mesh", "file": ")" << cube
                                    << R"(", "transform": {"translate": [2, 0, 0]}},
    {"type": "sphere", "center": [0, 3, 0], "radius": 1}]})";
  const InfoRun r = info(dir / "scene.json");
  fs::remove_all(dir);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  // The cube has 12 triangles; its two instances count 24.
  EXPECT_EQ(line_starting(r.out, "objects"),
            "objects    3: 1 spheres, 0 planes, 0 triangles, 0 boxes, 2 meshes (24 triangles), 0 cylinders, 0 cones, "
            "0 disks, 0 polygons");
  EXPECT_NE(line_starting(r.out, "memory").find("scene"), std::string::npos) << r.out;
}

TEST(Info, CountsTheNewShapes) {
  const InfoRun r = info(fs::path(GLINT_SOURCE_DIR) / "tests/schema/valid/new-shapes.json");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(line_starting(r.out, "objects"),
            "objects    6: 0 spheres, 0 planes, 0 triangles, 0 boxes, 0 meshes (0 triangles), 2 cylinders, 1 cones, "
            "1 disks, 2 polygons");
}

}  // namespace
