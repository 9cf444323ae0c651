// The public API (include/glint/): loading, edits checked by the loader's
// rules, JSON written back, renders equal to the internal pipeline's, reuse
// of the acceleration structure, ownership.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/api/scene_state.h"
#include "glint/glint.h"
#include "glint/io/scene_loader.h"
#include "glint/render/renderer.h"
#include "glint/scene/animation.h"

namespace fs = std::filesystem;
using glint::api::Renderer;
using glint::api::Scene;

namespace {

const char* kTwoSpheres = R"({
  "render": { "width": 48, "height": 32, "background": [0.1, 0.2, 0.3] },
  "camera": { "position": [0, 1, 6], "look_at": [0, 0.5, 0] },
  "materials": {
    "red":  { "ambient": 0.1, "diffuse": [0.8, 0.2, 0.1], "specular": 0.6, "shininess": 40 },
    "floor": { "diffuse": 0.5, "reflectivity": 0.25 }
  },
  "lights": [ { "type": "point", "position": [-3, 5, 4], "ambient": 0.2 } ],
  "objects": [
    { "type": "sphere", "center": [-0.8, 0.8, 0], "radius": 0.8, "material": "red" },
    { "type": "sphere", "center": [1, 0.5, -0.5], "radius": 0.5, "material": "red" },
    { "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor" }
  ]
})";

// The same scene through the internal pipeline: load, build, render.
glint::Image internal_render(const std::string& text, const fs::path& base = {}) {
  const glint::Scene scene = glint::parse_scene(text, "t.json", base);
  const auto accel = glint::build_accelerator(scene);
  return glint::render_image(scene, *accel);
}

}  // namespace

TEST(Api, RenderEqualsTheInternalPipeline) {
  const Scene scene = Scene::from_json(kTwoSpheres);
  const glint::api::RenderResult r = glint::api::render(scene);
  const glint::Image expected = internal_render(kTwoSpheres);
  ASSERT_EQ(r.image.width, 48);
  ASSERT_EQ(r.image.height, 32);
  EXPECT_EQ(r.image.rgb, expected.rgb);
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(r.stats.camera_rays, 48u * 32u);
  EXPECT_GT(r.stats.shadow_rays, 0u);
}

TEST(Api, BadEditIsRefusedWithTheLoadersMessageAndChangesNothing) {
  Scene scene = Scene::from_json(kTwoSpheres, {}, "two.json");
  const std::string before = scene.to_json();
  try {
    scene.set("materials.red.shininess", -3.0);
    FAIL() << "a negative shininess was accepted";
  } catch (const glint::Error& e) {
    EXPECT_EQ(e.message(), "materials.red.shininess: must be > 0 (got -3)");
    EXPECT_EQ(e.location().file, "two.json");
  }
  EXPECT_EQ(scene.to_json(), before);
  EXPECT_THROW(scene.set_string("objects[0].material", "gold"), glint::Error);                 // unknown material
  EXPECT_THROW(scene.set("camera.position", std::array<double, 3>{0, 0.5, 0}), glint::Error);  // = look_at
  EXPECT_THROW(scene.set_json("lights[0].position", "[1, 2]"), glint::Error);
  EXPECT_THROW(scene.set_json("lights[0].position", "[1, 2"), glint::Error);  // not JSON
  EXPECT_THROW(scene.set("materials.red.shinyness", 3.0), glint::Error);      // unknown key
  EXPECT_THROW(scene.erase("materials.red"), glint::Error);                   // still in use
  EXPECT_THROW(scene.set("objects[7].radius", 1.0), glint::Error);            // no such object
  EXPECT_EQ(scene.to_json(), before);
}

TEST(Api, EditsChangeTheRenderAsTheFileWould) {
  Scene scene = Scene::from_json(kTwoSpheres);
  scene.set("materials.red.shininess", 7.0);
  scene.set("lights[0].position", std::array<double, 3>{2, 4, 3});
  scene.set("render.samples_per_pixel", 4);
  EXPECT_EQ(scene.get("materials.red.shininess"), "7.0");
  EXPECT_EQ(scene.get("render.samples_per_pixel"), "4");
  std::string edited = kTwoSpheres;
  edited.replace(edited.find("\"shininess\": 40"), 15, "\"shininess\": 7");
  edited.replace(edited.find("[-3, 5, 4]"), 10, "[2, 4, 3]");
  edited.replace(edited.find("\"width\": 48"), 11, "\"samples_per_pixel\": 4, \"width\": 48");
  EXPECT_EQ(glint::api::render(scene).image.rgb, internal_render(edited).rgb);
}

TEST(Api, RenderCameraAndLightEditsReadThoseAloneToTheSameScene) {
  // An edit inside render, camera or lights reads those three alone into a
  // copy of the scene before; what it gives is what loading the edited
  // document whole gives (here with a mesh file and textures beside them),
  // and so are its refusals.
  const fs::path dir = fs::path(GLINT_SOURCE_DIR) / "scenes" / "textures";
  std::ifstream in(dir / "textures.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Scene scene = Scene::from_json(text, dir, "textures.json");
  const size_t key = scene.geometry_key();
  scene.set("render.width", 64);
  scene.set("render.height", 40);
  scene.set("camera.fov_y", 35.0);
  scene.set("camera.position", std::array<double, 3>{1, 3, 9});
  scene.set_json("lights[0]", R"({"type": "spot", "position": [2, 6, 4], "direction": [0, -1, -0.3], "cutoff": 40})");
  scene.append_json("lights", R"({"type": "directional", "direction": [0.2, -1, 0.1], "color": 0.3})");
  scene.update_json("render", R"({"shading_model": "blinn-phong", "max_depth": 3})");
  scene.erase("lights[1]");
  EXPECT_EQ(scene.geometry_key(), key);
  const Scene whole = Scene::from_json(scene.to_json(), dir, "textures.json");
  EXPECT_EQ(whole.geometry_key(), key);
  EXPECT_EQ(scene.light_count(), whole.light_count());
  EXPECT_EQ(glint::api::render(scene).image.rgb, glint::api::render(whole).image.rgb);
  const std::string before = scene.to_json();
  for (const auto& [path, value, message] : std::vector<std::array<std::string, 3>>{
           {"camera.fov_y", "180", "camera.fov_y: must be between 0 and 180 degrees, exclusive (got 180)"},
           {"render.width", "0", "render.width: must be >= 1 (got 0)"},
           {"lights[0].cutoff", "-1", "lights[0].cutoff: must be in (0, 180] degrees (got -1)"},
           {"camera.up", "[0, 0, 0]", "camera.up: must be a non-zero vector"}}) {
    try {
      scene.set_json(path, value);
      ADD_FAILURE() << path << " = " << value << " was accepted";
    } catch (const glint::Error& e) {
      EXPECT_EQ(e.message(), message);
      EXPECT_EQ(e.path(), path);
      EXPECT_EQ(e.location().file, "textures.json");
    }
  }
  EXPECT_EQ(scene.to_json(), before);
}

TEST(Api, MaterialAndLightEditsReuseTheAccelerationStructure) {
  Scene scene = Scene::from_json(kTwoSpheres);
  Renderer renderer(scene);
  const auto first = renderer.render();
  EXPECT_EQ(first.stats.builds, 1);
  scene.set("materials.red.diffuse", std::array<double, 3>{0.1, 0.9, 0.1});
  scene.set("lights[0].diffuse", 2.0);
  scene.set("camera.position", std::array<double, 3>{0.5, 1, 6});
  renderer.update(scene);
  const auto second = renderer.render();
  EXPECT_EQ(second.stats.builds, 1);  // no rebuild
  EXPECT_EQ(second.image.rgb, glint::api::render(scene).image.rgb);
  EXPECT_NE(second.image.rgb, first.image.rgb);
  scene.set("objects[1].radius", 0.7);  // geometry: rebuilt
  renderer.update(scene);
  const auto third = renderer.render();
  EXPECT_EQ(third.stats.builds, 2);
  EXPECT_EQ(third.image.rgb, glint::api::render(scene).image.rgb);
}

TEST(Api, AddingAndRemovingLightsObjectsAndMaterials) {
  Scene scene = Scene::from_json(kTwoSpheres);
  scene.append_json("lights", R"({ "type": "directional", "direction": [0, -1, -1], "diffuse": 0.3 })");
  EXPECT_EQ(scene.light_count(), 2u);
  scene.set_json("materials.blue", R"({ "diffuse": [0.1, 0.1, 0.9] })");
  scene.append_json("objects", R"({ "type": "sphere", "center": [0, 2, -2], "radius": 0.4, "material": "blue" })");
  EXPECT_EQ(scene.object_count(), 4u);
  EXPECT_EQ(scene.material_names(), (std::vector<std::string>{"red", "floor", "blue"}));
  scene.erase("objects[3]");
  scene.erase("materials.blue");
  scene.erase("lights[1]");
  EXPECT_EQ(Scene::from_json(scene.to_json()).to_json(), Scene::from_json(kTwoSpheres).to_json());
  EXPECT_THROW(scene.append_json("objects", R"({ "type": "sphere", "radius": 1 })"), glint::Error);
  EXPECT_EQ(scene.object_count(), 3u);
}

TEST(Api, ToJsonLoadsBackToTheSameImageForEveryExampleScene) {
  const fs::path root = fs::path(GLINT_SOURCE_DIR) / "scenes";
  int checked = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    Scene scene = Scene::load(entry.path());
    // Small, so the test stays quick; the same for both.
    scene.set("render.width", 40);
    scene.set("render.height", 30);
    if (scene.has("render.adaptive")) scene.erase("render.adaptive");
    const Scene again = Scene::from_json(scene.to_json(), scene.base_dir(), "again.json");
    EXPECT_EQ(again.to_json(), scene.to_json());
    EXPECT_EQ(glint::api::render(again).image.rgb, glint::api::render(scene).image.rgb);
    ++checked;
  }
  EXPECT_GE(checked, 10);
}

TEST(Api, ARendererOutlivesTheSceneItWasMadeFrom) {
  std::unique_ptr<Renderer> renderer;
  {
    Scene scene = Scene::from_json(kTwoSpheres);
    renderer = std::make_unique<Renderer>(scene);
    scene.set("materials.red.shininess", 3.0);  // an edit after prepare does not reach the renderer
  }
  EXPECT_EQ(renderer->render().image.rgb, internal_render(kTwoSpheres).rgb);
  Renderer from_temporary(Scene::from_json(kTwoSpheres));
  EXPECT_EQ(from_temporary.render().image.rgb, internal_render(kTwoSpheres).rgb);
}

TEST(Api, ExplainGivesThePixelsColor) {
  const Scene scene = Scene::from_json(kTwoSpheres);
  const Renderer renderer(scene);
  const auto image = renderer.render().image;
  const nlohmann::json explained = nlohmann::json::parse(renderer.explain_json(20, 12));
  const float* px = &image.rgb[3 * (12 * 48 + 20)];
  EXPECT_EQ(explained["pixel"], nlohmann::json::array({20, 12}));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(explained["color"][c].get<float>(), px[c]);
  EXPECT_GT(px[0], 0.0f);
  EXPECT_NE(renderer.explain_text(20, 12).find("pixel"), std::string::npos);
  EXPECT_THROW(renderer.explain_json(48, 0), glint::Error);
}

TEST(Api, RegionsAndPassesAreThoseOfTheWholeImage) {
  const Scene scene = Scene::from_json(kTwoSpheres);
  const Renderer renderer(scene);
  const auto whole = renderer.render();
  glint::api::RenderOptions options;
  options.x0 = 5, options.y0 = 3, options.x1 = 30, options.y1 = 20;
  options.passes = {"ambient", "diffuse", "specular", "reflection", "transmission", "depth"};
  const auto part = renderer.render(options);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x)
      for (int c = 0; c < 3; ++c) {
        const size_t i = 3 * (static_cast<size_t>(y) * 48 + x) + c;
        const bool inside = x >= 5 && x < 30 && y >= 3 && y < 20;
        ASSERT_EQ(part.image.rgb[i], inside ? whole.image.rgb[i] : 0.0f) << x << "," << y;
        double sum = 0;
        for (const char* p : {"ambient", "diffuse", "specular", "reflection", "transmission"})
          sum += part.passes.at(p).rgb[i];
        ASSERT_NEAR(sum, part.image.rgb[i], 1e-5);
      }
  EXPECT_EQ(part.passes.size(), 6u);
  options.passes = {"difuse"};
  EXPECT_THROW(renderer.render(options), glint::Error);
}

TEST(Api, ImagesRoundTripThroughFiles) {
  const auto image = glint::api::render(Scene::from_json(kTwoSpheres)).image;
  const fs::path dir = fs::temp_directory_path() / "glint_api_test";
  fs::create_directories(dir);
  glint::api::write_image(image, dir / "a.pfm");
  EXPECT_EQ(glint::api::read_image(dir / "a.pfm").rgb, image.rgb);
  glint::api::Image bad{2, 2, std::vector<float>(5)};
  EXPECT_THROW(glint::api::write_image(bad, dir / "b.pfm"), glint::Error);
  EXPECT_FALSE(fs::exists(dir / "b.pfm"));
  fs::remove_all(dir);
}

TEST(Api, VersionIsTheProjects) {
  EXPECT_STREQ(glint::version(), GLINT_VERSION_STRING);
  EXPECT_EQ(std::string(glint::version()).substr(0, 2), std::to_string(GLINT_VERSION_MAJOR) + ".");
}

TEST(Api, ErrorsCarryTheirPathApartFromTheMessage) {
  Scene scene = Scene::from_json(kTwoSpheres, {}, "two.json");
  try {
    scene.set("materials.red.shininess", -3.0);
    FAIL() << "accepted";
  } catch (const glint::Error& e) {
    EXPECT_EQ(e.path(), "materials.red.shininess");
    EXPECT_EQ(e.message(), "materials.red.shininess: must be > 0 (got -3)");
  }
  try {
    scene.set_json("lights[0].position", "[1, 2]");
    FAIL() << "accepted";
  } catch (const glint::Error& e) {
    EXPECT_EQ(e.path(), "lights[0].position");
  }
  try {
    (void)Scene::from_json("{ \"camera\": {} }", {}, "t.json");
    FAIL() << "accepted";
  } catch (const glint::Error& e) {
    EXPECT_EQ(e.path(), "camera");
    EXPECT_EQ(e.location().file, "t.json");
    EXPECT_EQ(e.location().line, 1);
  }
  try {
    (void)Scene::from_json("{ not json", {}, "t.json");
    FAIL() << "accepted";
  } catch (const glint::Error& e) {
    EXPECT_EQ(e.path(), "");  // a syntax error is at a place in the text, not a value
  }
}

namespace {

// A 3 x 3 grid of vertices, bumped in the middle: 8 triangles, smooth normals
// computed from its faces. Coordinates are short dyadic fractions, written
// exactly by both the OBJ text and the JSON.
const char* kGridVertices = "[[-1,0,-1],[0,0,-1],[1,0,-1],[-1,0,0],[0,0.5,0],[1,0,0],[-1,0,1],[0,0,1],[1,0,1]]";
const char* kGridTriangles = "[[0,3,1],[1,3,4],[1,4,2],[2,4,5],[3,6,4],[4,6,7],[4,7,5],[5,7,8]]";

std::string grid_scene(const std::string& mesh_keys) {
  return std::string(R"({ "render": { "width": 40, "height": 30 },
    "camera": { "position": [0, 2.5, 3], "look_at": [0, 0, 0] },
    "lights": [ { "type": "point", "position": [-2, 4, 3] } ],
    "objects": [ { "type": "mesh", )") +
         mesh_keys + " } ] }";
}

}  // namespace

TEST(Api, InlineMeshRendersAsTheSameMeshFromAnObjFile) {
  const fs::path dir = fs::temp_directory_path() / "glint_api_inline_mesh";
  fs::create_directories(dir);
  {
    std::ofstream obj(dir / "grid.obj");
    const nlohmann::json v = nlohmann::json::parse(kGridVertices), t = nlohmann::json::parse(kGridTriangles);
    for (const auto& p : v)
      obj << "v " << p[0].get<double>() << " " << p[1].get<double>() << " " << p[2].get<double>() << "\n";
    for (const auto& f : t)
      obj << "f " << f[0].get<int>() + 1 << " " << f[1].get<int>() + 1 << " " << f[2].get<int>() + 1 << "\n";
  }
  for (const char* smooth : {"true", "false"}) {
    SCOPED_TRACE(smooth);
    const std::string s = std::string(", \"smooth\": ") + smooth;
    const Scene from_file = Scene::from_json(grid_scene(R"("file": "grid.obj")" + s), dir);
    const Scene inline_mesh = Scene::from_json(
        grid_scene(std::string("\"vertices\": ") + kGridVertices + ", \"triangles\": " + kGridTriangles + s));
    const auto a = glint::api::render(from_file).image.rgb, b = glint::api::render(inline_mesh).image.rgb;
    EXPECT_EQ(a, b);
    EXPECT_GT(*std::max_element(b.begin(), b.end()), 0.1f);
    // And written back, it is the same scene.
    EXPECT_EQ(glint::api::render(Scene::from_json(inline_mesh.to_json())).image.rgb, b);
  }
  fs::remove_all(dir);
}

TEST(Api, InlineMeshProblemsAreNamedByTheirPath) {
  const std::string v = std::string("\"vertices\": ") + kGridVertices;
  const std::string t = std::string("\"triangles\": ") + kGridTriangles;
  auto error_of = [](const std::string& keys) -> std::string {
    try {
      (void)Scene::from_json(grid_scene(keys), {}, "t.json");
    } catch (const glint::Error& e) {
      return e.message();
    }
    return "accepted";
  };
  EXPECT_EQ(error_of(v + R"(, "triangles": [[0, 1, 9]])"),
            "objects[0].triangles[0][2]: vertex index 9 out of range (9 vertices)");
  EXPECT_EQ(error_of(v + R"(, "triangles": [[0, 1, -1]])"),
            "objects[0].triangles[0][2]: vertex index -1 out of range (9 vertices)");
  EXPECT_EQ(error_of(v + R"(, "triangles": [[0, 1.5, 2]])"),
            "objects[0].triangles[0][1]: expected a whole number, got 1.5");
  EXPECT_EQ(error_of(v + R"(, "triangles": [[0, 1]])"),
            "objects[0].triangles[0]: expected [i, j, k] (three vertex indices), got an array of 2");
  EXPECT_EQ(error_of(R"("vertices": [[0, 0, 0], [1, 0, 1e300], [0, 1, 0]], )" + t.substr(0, 0) +
                     R"("triangles": [[0, 1, 2]])"),
            "objects[0].vertices[1]: does not fit in a 32-bit float");
  EXPECT_EQ(error_of(R"("vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0]], "triangles": [[0, 1, 2]])"),
            "objects[0]: no triangles (the only one is degenerate)");
  EXPECT_EQ(error_of(v + ", " + t + R"(, "normals": [[0, 1, 0]])"),
            "objects[0].normals: expected one per vertex (9), got 1");
  EXPECT_EQ(error_of(v + ", " + t + R"(, "file": "x.obj")"),
            "objects[0].file: give either \"file\" or inline \"vertices\" and \"triangles\", not both");
  EXPECT_EQ(error_of(v), "objects[0]: missing required key \"triangles\"");
  EXPECT_EQ(error_of(v + ", " + t), "accepted");
}

// add_mesh: arrays held beside the document, read by the loader as they are,
// written out as the inline mesh they stand for.
TEST(Api, MeshArraysAreTheInlineMeshTheyStandFor) {
  const std::string keys = std::string("\"vertices\": ") + kGridVertices + ", \"triangles\": " + kGridTriangles;
  const Scene inline_mesh = Scene::from_json(grid_scene(R"("name": "grid", )" + keys));
  glint::api::MeshArrays arrays;
  for (const auto& p : nlohmann::json::parse(kGridVertices))
    for (int c = 0; c < 3; ++c) arrays.positions.push_back(p[c].get<float>());
  for (const auto& t : nlohmann::json::parse(kGridTriangles))
    for (int c = 0; c < 3; ++c) arrays.triangles.push_back(t[c].get<uint32_t>());
  Scene scene = Scene::from_json(grid_scene(keys));
  scene.erase("objects[0]");
  scene.add_mesh(arrays, R"({"name": "grid"})");
  const auto expected = glint::api::render(inline_mesh).image.rgb;
  EXPECT_EQ(glint::api::render(scene).image.rgb, expected);
  // The same document (numbers equal as numbers: 0 or 0.0), laid out or compact.
  using nlohmann::ordered_json;
  EXPECT_EQ(ordered_json::parse(scene.to_json()), ordered_json::parse(inline_mesh.to_json()));
  EXPECT_EQ(ordered_json::parse(scene.to_json(-1)), ordered_json::parse(inline_mesh.to_json(-1)));
  EXPECT_EQ(ordered_json::parse(scene.get("objects[0]")), ordered_json::parse(inline_mesh.get("objects[0]")));
  EXPECT_EQ(scene.get("objects[0].vertices[4]"), "[0.0,0.5,0.0]");
  EXPECT_TRUE(scene.has("objects[0].triangles[7]"));
  EXPECT_FALSE(scene.has("objects[0].$arrays"));
  EXPECT_EQ(scene.to_json().find("$arrays"), std::string::npos);
  // Loaded back from its JSON: the same scene.
  EXPECT_EQ(glint::api::render(Scene::from_json(scene.to_json())).image.rgb, expected);
  // Editing other keys keeps the arrays held and the geometry.
  Renderer renderer(scene);
  scene.set_json("objects[0].smooth", "false");
  scene.set_json("objects[0].smooth", "true");
  scene.update_json("objects[0]", R"({"name": "g2"})");
  renderer.update(scene);
  EXPECT_EQ(renderer.render().image.rgb, expected);
  EXPECT_EQ(scene.get("objects[0].name"), "\"g2\"");
  // Editing the arrays turns the object into plain JSON.
  scene.set_json("objects[0].vertices[4]", "[0, 0.75, 0]");
  EXPECT_EQ(scene.get("objects[0].vertices[4]"), "[0,0.75,0]");
  EXPECT_NE(glint::api::render(scene).image.rgb, expected);
  // Checks, named by the arrays' rows; a refused mesh changes nothing.
  auto error_of = [&](const glint::api::MeshArrays& a, const char* object = "{}") -> std::string {
    const std::string before = scene.to_json();
    try {
      scene.add_mesh(a, object);
    } catch (const glint::Error& e) {
      EXPECT_EQ(scene.to_json(), before);
      return e.message();
    }
    return "accepted";
  };
  glint::api::MeshArrays bad = arrays;
  bad.triangles[5] = 9;
  EXPECT_EQ(error_of(bad), "triangles[1]: vertex index 9 out of range (9 vertices)");
  bad = arrays;
  bad.positions[13] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(error_of(bad), "vertices[4]: not a finite number");
  bad = arrays;
  bad.normals = {0, 1, 0};
  EXPECT_EQ(error_of(bad), "normals: expected one per vertex (9), got 1");
  bad = arrays;
  bad.triangles.clear();
  EXPECT_EQ(error_of(bad), "triangles: no triangles");
  EXPECT_EQ(error_of(arrays, R"({"material": "gold"})"),
            "objects[1].material: unknown material \"gold\" (the scene defines no materials)");
  EXPECT_EQ(error_of(arrays, R"({"type": "sphere"})"), "type: add_mesh makes a mesh (got \"sphere\")");
  EXPECT_EQ(error_of(arrays, R"({"file": "x.obj"})"), "file: given by the arrays; not a key here");
  bad = arrays;
  bad.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  bad.triangles = {0, 1, 2};
  EXPECT_EQ(error_of(bad), "objects[1]: no triangles (the only one is degenerate)");
  EXPECT_EQ(error_of(arrays), "accepted");
  // A scene file cannot name arrays in memory.
  EXPECT_THROW((void)Scene::from_json(grid_scene(R"("$arrays": 1)")), glint::Error);
}

// An NFF file's view follows the rendered height (docs/nff.md) while its
// camera and height are the file's, edits elsewhere notwithstanding.
TEST(Api, AnNffViewHoldsWhileItsCameraAndHeightAreTheFiles) {
  const fs::path path = fs::path(GLINT_SOURCE_DIR) / "bench" / "spd" / "tetra.nff";
  Scene scene = Scene::load(path);
  EXPECT_TRUE(scene.state()->scene->camera.row_center_angle.has_value());
  glint::api::RenderOptions options;
  options.width = 40;
  options.height = 24;
  options.samples_per_pixel = 1;
  glint::Scene internal = glint::load_scene(path);
  internal.render.width = 40;
  internal.render.height = 24;
  internal.render.samples_per_pixel = 1;
  const auto expected = glint::render_image(internal, *glint::build_accelerator(internal)).rgb;
  EXPECT_EQ(glint::api::render(scene, options).image.rgb, expected);
  const std::string shininess = scene.get("materials.f1.shininess");
  scene.set("materials.f1.shininess", 3.0);
  EXPECT_TRUE(scene.state()->scene->camera.row_center_angle.has_value());
  scene.set_json("materials.f1.shininess", shininess);
  EXPECT_EQ(glint::api::render(scene, options).image.rgb, expected);
  scene.set("render.height", 24);
  EXPECT_FALSE(scene.state()->scene->camera.row_center_angle.has_value());
  scene.set("render.height", 512);
  EXPECT_TRUE(scene.state()->scene->camera.row_center_angle.has_value());
  scene.set("camera.fov_y", 40.0);
  EXPECT_FALSE(scene.state()->scene->camera.row_center_angle.has_value());
}

TEST(Api, AnAnimatedSceneRendersTheFrameAsked) {
  const fs::path path = fs::path(GLINT_SOURCE_DIR) / "scenes" / "animation" / "rolling.json";
  Scene scene = Scene::load(path);
  scene.set("render.width", 32);
  scene.set("render.height", 20);
  const glint::Scene internal = glint::parse_scene(scene.to_json(), "r.json", scene.base_dir());
  for (int frame : {0, 5}) {
    const glint::Scene posed = glint::scene_at_frame(internal, frame);
    const auto accel = glint::build_accelerator(posed);
    glint::api::PrepareOptions options;
    options.frame = frame;
    EXPECT_EQ(Renderer(scene, options).render().image.rgb, glint::render_image(posed, *accel).rgb) << frame;
  }
  glint::api::PrepareOptions outside;
  outside.frame = 100000;
  EXPECT_THROW(Renderer(scene, outside), glint::Error);
  // A material edit reaches the posed frame, over the same accelerator.
  glint::api::PrepareOptions at5;
  at5.frame = 5;
  Renderer renderer(scene, at5);
  const auto before = renderer.render().image.rgb;
  scene.set_json("render.background", "[1, 0, 0]");
  scene.set_json("materials.red.diffuse", "[0.1, 0.8, 0.1]");
  renderer.update(scene);
  const auto after = renderer.render();
  EXPECT_NE(after.image.rgb, before);
  EXPECT_EQ(after.stats.builds, 1);
  EXPECT_EQ(after.image.rgb, Renderer(scene, at5).render().image.rgb);
  scene.set_json("objects[1].radius", "0.9");  // geometry: built again
  renderer.update(scene);
  EXPECT_EQ(renderer.render().stats.builds, 2);
}

// The preview of `glint serve`: another size or sample count over the same
// accelerator gives exactly the render of the scene edited to that size.
TEST(Api, PreviewSizeAndSamplesEqualTheEditedScene) {
  Scene scene = Scene::from_json(kTwoSpheres);
  scene.set("render.samples_per_pixel", 4);
  Renderer renderer(scene);
  glint::api::RenderOptions options;
  options.width = 12;
  options.height = 8;
  options.samples_per_pixel = 1;
  const auto preview = renderer.render(options);
  Scene small = scene;
  small.set("render.width", 12);
  small.set("render.height", 8);
  small.set("render.samples_per_pixel", 1);
  const auto expected = glint::api::render(small);
  ASSERT_EQ(preview.image.width, 12);
  ASSERT_EQ(preview.image.height, 8);
  EXPECT_EQ(preview.image.rgb, expected.image.rgb);
  EXPECT_EQ(preview.stats.camera_rays, 12u * 8u);
  EXPECT_EQ(preview.stats.builds, 1);
  // The full render afterwards is untouched by the preview.
  EXPECT_EQ(renderer.render().image.rgb, glint::api::render(scene).image.rgb);
  options.width = 0;
  options.height = 0;
  options.samples_per_pixel = glint::kMaxSamplesPerPixel + 1;
  EXPECT_THROW(renderer.render(options), glint::Error);
}

TEST(Api, EncodeImageGivesTheBytesOfTheFile) {
  const Scene scene = Scene::from_json(kTwoSpheres);
  glint::api::RenderOptions options;
  options.passes = {"normal"};
  const auto result = glint::api::render(scene, options);
  const fs::path dir = fs::temp_directory_path() / "glint_api_encode";
  fs::create_directories(dir);
  auto file_bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
  };
  glint::api::WriteOptions exposed;
  exposed.exposure = 1.5;
  exposed.tonemap = glint::api::ToneMap::aces;
  for (const char* ext : {"png", "pfm", "ppm"}) {
    const fs::path file = dir / (std::string("a.") + ext);
    glint::api::write_image(result.image, file, exposed);
    EXPECT_EQ(glint::api::encode_image(result.image, ext, exposed), file_bytes(file)) << ext;
  }
  // A data pass in 8 bits: n * 0.5 + 0.5 as codes, so a normal (0, 1, 0)
  // from the floor's top reads (128, 255, 128) whatever the exposure.
  const auto png = glint::api::encode_image(result.passes.at("normal"), ".png", exposed, "normal");
  const fs::path normal = dir / "normal.png";
  {
    std::ofstream out(normal, std::ios::binary);
    out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  }
  const auto back = glint::api::read_image(normal);
  const float* bottom = &back.rgb[3 * static_cast<size_t>((back.height - 1) * back.width)];
  EXPECT_NEAR(bottom[1], 1.0f, 1e-6);
  EXPECT_THROW(glint::api::encode_image(result.image, "gif"), glint::Error);
  EXPECT_THROW(glint::api::encode_image(result.image, "png", {}, "shiny"), glint::Error);
  fs::remove_all(dir);
}

// A bare mesh file is a scene: the documented rig around its bounding sphere.
TEST(Api, MeshFileIsFramedByTheRig) {
  const fs::path dir = fs::temp_directory_path() / "glint_api_mesh_scene";
  fs::create_directories(dir);
  const fs::path obj = dir / "tri.obj";
  {
    std::ofstream out(obj);
    out << "v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n";
  }
  const Scene scene = Scene::load(obj);
  EXPECT_EQ(scene.object_count(), 1u);
  EXPECT_EQ(scene.light_count(), 3u);
  EXPECT_EQ(scene.width(), 800);
  EXPECT_EQ(scene.height(), 450);
  // Bounds [0,2]x[0,2]x[0,0]: center (1,1,0), radius sqrt(8)/2; the camera
  // is 1.15 r / sin(20 deg) away along (0, 0.5, 1) normalized.
  const auto at = nlohmann::json::parse(scene.get("camera.look_at"));
  EXPECT_DOUBLE_EQ(at[0].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(at[1].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(at[2].get<double>(), 0.0);
  const auto eye = nlohmann::json::parse(scene.get("camera.position"));
  const double d = 1.15 * (std::sqrt(8.0) / 2) / std::sin(20.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(eye[1].get<double>() - 1.0, d * 0.5 / std::sqrt(1.25), 1e-12);
  EXPECT_NEAR(eye[2].get<double>(), d / std::sqrt(1.25), 1e-12);
  EXPECT_EQ(scene.get("objects[0].file"), "\"tri.obj\"");
  // Its JSON loads back beside the mesh to the same scene.
  const Scene back = Scene::from_json(scene.to_json(), dir, "back.json");
  EXPECT_EQ(glint::api::render(back).image.rgb, glint::api::render(scene).image.rgb);
  fs::remove_all(dir);
}
