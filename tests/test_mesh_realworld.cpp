// Real-world mesh files from Debian's assimp-testmodels package (assimp's
// own test models, exported by real tools): good OBJ, PLY and glTF models
// load with the triangle counts their files state, and the broken glTF
// models give one clear error naming the file, from the library and from the
// glint command. Skipped, visibly, when the package is not installed
// (scripts/install-deps.sh installs it).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "glint/error.h"
#include "glint/io/mesh_file.h"
#include "needs_assimp.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

const fs::path kModels = "/usr/share/assimp/models";

#define SKIP_WITHOUT_TESTMODELS()                                                  \
  if (!fs::is_directory(kModels / "glTF2"))                                        \
  GTEST_SKIP() << kModels                                                          \
               << " not found: install Debian's assimp-testmodels package to run " \
                  "the real-world mesh tests"

struct Model {
  const char* path;  // under kModels
  size_t triangles;  // as the file states them (face lines, face counts, index counts)
};

// Counts from the files themselves: WusonOBJ.obj has 3732 triangle 'f'
// lines and Wuson.ply says "element face 3732" (the same model, two
// exporters); box.obj and cube.ply are 6 quads, cube_binary.ply 12
// triangles; BoxTextured's index accessor counts 36, simple_skin's 24.
const Model kGoodModels[] = {
    {"OBJ/box.obj", 12},
    {"OBJ/WusonOBJ.obj", 3732},
    {"PLY/cube.ply", 12},
    {"PLY/cube_binary.ply", 12},
    {"PLY/Wuson.ply", 3732},
    {"glTF2/BoxTextured-glTF/BoxTextured.gltf", 12},
    {"glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", 12},
    {"glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf", 12},
    {"glTF2/simple_skin/simple_skin.gltf", 8},
};

TEST(MeshRealWorld, GoodModelsLoadWithTheirTriangleCounts) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  SKIP_WITHOUT_TESTMODELS();
  for (const Model& model : kGoodModels) {
    SCOPED_TRACE(model.path);
    try {
      const MeshFile m = load_mesh_file(kModels / model.path);
      EXPECT_EQ(m.triangle_count(), model.triangles);
      EXPECT_EQ(m.corner_normals.size(), m.indices.size());
    } catch (const Error& e) {
      ADD_FAILURE() << e.what();
    }
  }
}

struct BrokenModel {
  const char* path;
  const char* message;  // the error's message, exactly
};

const BrokenModel kBrokenModels[] = {
    // One index in range of nothing: assimp drops that face and says so only in its log.
    {"glTF2/IndexOutOfRange/IndexOutOfRange.gltf", "face with a vertex index out of range"},
    // Every index out of range: assimp drops all faces, then fails on the empty mesh.
    {"glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf", "face with a vertex index out of range"},
    {"glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "vertex 0 has a non-finite coordinate"},
};

TEST(MeshRealWorld, BrokenGltfModelsGiveOneClearErrorNamingTheFile) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  SKIP_WITHOUT_TESTMODELS();
  for (const BrokenModel& model : kBrokenModels) {
    SCOPED_TRACE(model.path);
    const fs::path path = kModels / model.path;
    try {
      load_mesh_file(path);
      ADD_FAILURE() << "loaded";
    } catch (const Error& e) {
      EXPECT_EQ(e.location().file, path.string());
      EXPECT_EQ(e.message(), model.message);
      EXPECT_EQ(std::string(e.what()), path.string() + ": " + model.message);
    }
  }
}

// Runs a shell command; its exit code, with stdout and stderr in `out`.
int run(const std::string& command, std::string& out) {
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  out.clear();
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) out.append(buf, n);
  const int status = ::pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(MeshRealWorld, CliRefusesScenesWithBrokenModelsWithOneErrorLine) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  SKIP_WITHOUT_TESTMODELS();
  const fs::path dir = fs::temp_directory_path() / ("glint-realworld-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const BrokenModel& model : kBrokenModels) {
    SCOPED_TRACE(model.path);
    const fs::path mesh = kModels / model.path;
    const fs::path scene = dir / "scene.json";
    std::ofstream(scene) << R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
 "lights": [{"type": "point", "position": [0, 5, 5], "color": [1, 1, 1]}],
 "objects": [{"type": "mesh", "file": ")"
                         << mesh.string() << R"("}]})";
    const std::string expected = "error: " + mesh.string() + ": " + model.message + "\n";
    std::string out;
    EXPECT_EQ(run(std::string(GLINT_CLI_PATH) + " validate " + scene.string(), out), 1);
    EXPECT_EQ(out, expected);
    const fs::path image = dir / "out.png";
    EXPECT_EQ(run(std::string(GLINT_CLI_PATH) + " render " + scene.string() + " -o " + image.string(), out), 1);
    EXPECT_EQ(out, expected);
    EXPECT_FALSE(fs::exists(image));
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace glint
