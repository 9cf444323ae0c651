// `glint validate` and `glint info`: validation lists every error (one per
// material, light, object or section) without stopping at the first; a valid
// scene validates cleanly; info reports what the scene holds.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "glint/io/scene_loader.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

fs::path write_temp(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("glint-validate-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

const char* kBrokenEverywhere = R"({"camera": {"position": [0,0,5], "look_at": [0,0,5]},
 "materials": {"a": {"shininess": -1}, "b": {"difuse": 1}},
 "lights": [{"type": "point"}, {"type": "spot", "position": [0,0,0], "direction": [0,0,0], "cutoff": 10}],
 "objects": [{"type": "sphere", "center": [0,0,0], "radius": 0, "material": "a"},
             {"type": "box", "min": [0,0,0], "max": [1,1,1], "material": "zz"},
             {"type": "teapot"}]})";

TEST(Validate, ListsEveryErrorInFileOrder) {
  const auto errors = validate_scene(write_temp("broken.json", kBrokenEverywhere));
  ASSERT_EQ(errors.size(), 8u);
  const char* expected[] = {"camera.look_at: must differ",
                            "materials.a.shininess: must be > 0",
                            "materials.b: unknown key \"difuse\" (did you mean \"diffuse\"?)",
                            "lights[0]: missing required key \"position\"",
                            "lights[1].direction: must be a non-zero",
                            "objects[0].radius: must be > 0",
                            "objects[1].material: unknown material \"zz\"",
                            "objects[2].type: unknown object type \"teapot\""};
  int last_line = 0;
  for (size_t i = 0; i < errors.size(); ++i) {
    EXPECT_NE(errors[i].message().find(expected[i]), std::string::npos) << errors[i].what();
    EXPECT_GE(errors[i].location().line, last_line);
    last_line = errors[i].location().line;
  }
  // "zz" is too far from "a" to be a typo: no hint.
  EXPECT_EQ(errors[6].message().find("did you mean"), std::string::npos);
  // The render path throws the first of them.
  try {
    load_scene(write_temp("broken.json", kBrokenEverywhere));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.what(), std::string(errors[0].what()));
  }
}

TEST(Validate, ABrokenMaterialDoesNotCascadeIntoItsObjects) {
  const auto errors = validate_scene(write_temp("cascade.json", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]},
    "materials": {"m": {"ior": 0}},
    "objects": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "m"}]})"));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].message().find("materials.m.ior"), std::string::npos);
}

TEST(Validate, SyntaxErrorsAndMissingFilesAreOneError) {
  EXPECT_EQ(validate_scene(write_temp("syntax.json", "{\"camera\": }")).size(), 1u);
  EXPECT_EQ(validate_scene("/nonexistent/scene.json").size(), 1u);
}

TEST(Validate, EveryExampleSceneIsValid) {
  for (const auto& e : fs::recursive_directory_iterator(std::string(GLINT_SOURCE_DIR) + "/scenes"))
    if (e.path().extension() == ".json") {
      const auto errors = validate_scene(e.path());
      EXPECT_TRUE(errors.empty()) << e.path() << ": " << (errors.empty() ? "" : errors[0].what());
    }
}

int run(const std::string& command, std::string* out = nullptr) {
  FILE* pipe = ::popen(command.c_str(), "r");
  std::string text;
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) text.append(buf, n);
  const int status = ::pclose(pipe);
  if (out) *out = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(ValidateCli, PrintsOneErrorLinePerProblemAndExitsNonZero) {
  const fs::path scene = write_temp("cli.json", kBrokenEverywhere);
  std::string out;
  EXPECT_EQ(run(std::string(GLINT_CLI_PATH) + " validate " + scene.string() + " 2>&1", &out), 1);
  int lines = 0;
  for (size_t at = 0; (at = out.find("error: ", at)) != std::string::npos; ++at) ++lines;
  EXPECT_EQ(lines, 8) << out;
  EXPECT_EQ(run(std::string(GLINT_CLI_PATH) + " validate " + GLINT_SOURCE_DIR + "/scenes/showcase.json", &out), 0);
  EXPECT_NE(out.find("valid"), std::string::npos);
}

TEST(InfoCli, CountsObjectsAndLights) {
  std::string out;
  ASSERT_EQ(run(std::string(GLINT_CLI_PATH) + " info " + GLINT_SOURCE_DIR + "/scenes/showcase.json", &out), 0);
  EXPECT_NE(out.find("objects    8: 4 spheres, 2 planes, 1 triangles, 1 boxes"), std::string::npos) << out;
  EXPECT_NE(out.find("lights     4:"), std::string::npos) << out;
  EXPECT_NE(out.find("memory"), std::string::npos) << out;
}

}  // namespace
}  // namespace glint
