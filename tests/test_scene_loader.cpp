// The scene loader against the contract (shared/spec/scene-format.md): every key
// of render, camera, materials, lights, objects and transforms lands in the Scene
// with the right value or default, and every malformed input is a glint::Error
// whose message names the problem and whose file:line:column points at it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "glint/error.h"
#include "glint/io/json.h"
#include "glint/io/scene_loader.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

constexpr double kTol = 1e-12;
constexpr const char* kFile = "scene.json";
// A camera that every scene below can use.
constexpr const char* kCamera = R"("camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]})";

Scene parse(std::string_view text) { return parse_scene(std::string(text), kFile); }

// A scene with the standard camera and the given extra top-level members.
Scene parse_with(std::string_view members) {
  return parse(std::string("{") + kCamera + ", " + std::string(members) + "}");
}

void expect_vec(const Vec3& got, const Vec3& want, const char* what = "") {
  EXPECT_NEAR(got.x, want.x, kTol) << what;
  EXPECT_NEAR(got.y, want.y, kTol) << what;
  EXPECT_NEAR(got.z, want.z, kTol) << what;
}

// Scene text with one '@' marking where the error must point; the '@' is
// removed before parsing and its line and (byte) column are remembered.
struct Marked {
  std::string text;
  int line = 0, column = 0;
};

Marked mark(std::string_view marked) {
  const size_t at = marked.find('@');
  EXPECT_NE(at, std::string_view::npos) << "test bug: no '@' in " << marked;
  EXPECT_EQ(marked.find('@', at + 1), std::string_view::npos) << "test bug: two '@' in " << marked;
  Marked m;
  m.text = std::string(marked.substr(0, at)) + std::string(marked.substr(at + 1));
  m.line = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < at; ++i)
    if (marked[i] == '\n') ++m.line, line_start = i + 1;
  m.column = static_cast<int>(at - line_start) + 1;
  return m;
}

// Parsing `marked` must fail with a message containing `message_part`,
// located at the '@'.
void expect_error(std::string_view marked, std::string_view message_part) {
  SCOPED_TRACE(std::string("expected error: ") + std::string(message_part));
  const Marked m = mark(marked);
  try {
    parse(m.text);
    ADD_FAILURE() << "no error for:\n" << m.text;
  } catch (const Error& e) {
    EXPECT_NE(e.message().find(message_part), std::string::npos) << "what(): " << e.what();
    EXPECT_EQ(e.location().file, kFile);
    EXPECT_EQ(e.location().line, m.line) << "what(): " << e.what();
    EXPECT_EQ(e.location().column, m.column) << "what(): " << e.what();
    EXPECT_EQ(std::string(e.what()),
              std::string(kFile) + ":" + std::to_string(m.line) + ":" + std::to_string(m.column) + ": " + e.message());
  }
}

// The same, for a scene made of the standard camera plus `members` (which carry the '@').
void expect_error_with(std::string_view members, std::string_view message_part) {
  expect_error(std::string("{") + kCamera + ",\n" + std::string(members) + "}", message_part);
}

// One object (given as text, with the '@') in an otherwise valid scene.
void expect_object_error(std::string_view object, std::string_view message_part) {
  expect_error_with(std::string(R"("objects": [)") + std::string(object) + "]", message_part);
}

void expect_light_error(std::string_view light, std::string_view message_part) {
  expect_error_with(std::string(R"("objects": [], "lights": [)") + std::string(light) + "]", message_part);
}

// --- values ----------------------------------------------------------------

TEST(SceneLoaderDefaults, AbsentKeysTakeTheContractDefaults) {
  const Scene s = parse(R"({"camera": {"position": [1, 2, 3], "look_at": [0, 0, 0]},
                            "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]})");
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 480);
  EXPECT_EQ(s.render.samples_per_pixel, 1);
  EXPECT_EQ(s.render.max_depth, 5);
  EXPECT_EQ(s.render.shading_model, ShadingModel::phong);
  EXPECT_EQ(s.render.background, Color(0.0));
  EXPECT_FALSE(s.render.epsilon.has_value());
  EXPECT_EQ(s.camera.type, CameraType::perspective);
  EXPECT_EQ(s.camera.up, Vec3(0, 1, 0));
  EXPECT_EQ(s.camera.fov_y, 45.0);
  EXPECT_EQ(s.camera.view_height, 2.0);
  EXPECT_TRUE(s.lights.empty());
  ASSERT_EQ(s.objects.size(), 1u);
  // An object without `material` gets the default material, with the contract's values.
  const Material& m = s.materials.at(s.objects[0].material);
  EXPECT_EQ(m.ambient, Color(0.0));
  EXPECT_EQ(m.diffuse, Color(0.8));
  EXPECT_EQ(m.specular, Color(0.0));
  EXPECT_EQ(m.shininess, 32.0);
  EXPECT_EQ(m.reflectivity, Color(0.0));
  EXPECT_EQ(m.transparency, 0.0);
  EXPECT_EQ(m.ior, 1.5);
  EXPECT_FALSE(m.fresnel);
  EXPECT_EQ(s.objects[0].transform, kNoTransform);
}

TEST(SceneLoaderDefaults, EmptyRenderAndMaterialObjectsKeepDefaults) {
  const Scene s = parse_with(R"("render": {}, "materials": {"plain": {}}, "lights": [],
                                "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "plain"}])");
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 480);
  const Material& m = s.materials.at(s.objects.at(0).material);
  EXPECT_EQ(m.name, "plain");
  EXPECT_EQ(m.diffuse, Color(0.8));
  EXPECT_EQ(m.shininess, 32.0);
  EXPECT_EQ(m.ior, 1.5);
}

TEST(SceneLoaderRender, EveryKeyIsRead) {
  const Scene s = parse_with(R"("render": {"width": 320, "height": 200, "samples_per_pixel": 9,
      "max_depth": 7, "shading_model": "blinn-phong", "background": [0.1, 0.2, 0.3],
      "epsilon": 0.001}, "objects": [])");
  EXPECT_EQ(s.render.width, 320);
  EXPECT_EQ(s.render.height, 200);
  EXPECT_EQ(s.render.samples_per_pixel, 9);
  EXPECT_EQ(s.render.max_depth, 7);
  EXPECT_EQ(s.render.shading_model, ShadingModel::blinn_phong);
  EXPECT_EQ(s.render.background, Color(0.1, 0.2, 0.3));
  ASSERT_TRUE(s.render.epsilon.has_value());
  EXPECT_EQ(*s.render.epsilon, 0.001);

  const Scene p =
      parse_with(R"("render": {"shading_model": "phong", "background": 0.25, "width": 6.4e2}, "objects": [])");
  EXPECT_EQ(p.render.shading_model, ShadingModel::phong);
  EXPECT_EQ(p.render.background, Color(0.25));  // one number means gray
  EXPECT_EQ(p.render.width, 640);               // a whole number written as a float is fine
}

TEST(SceneLoaderCamera, PerspectiveKeys) {
  const Scene s = parse(R"({"camera": {"type": "perspective", "position": [1, 2, 3], "look_at": [4, 5, 6],
                            "up": [0, 0, 3], "fov_y": 60}, "objects": []})");
  EXPECT_EQ(s.camera.type, CameraType::perspective);
  EXPECT_EQ(s.camera.position, Vec3(1, 2, 3));
  EXPECT_EQ(s.camera.look_at, Vec3(4, 5, 6));
  expect_vec(s.camera.up, Vec3(0, 0, 1), "up is normalized");
  EXPECT_EQ(s.camera.fov_y, 60.0);
}

TEST(SceneLoaderCamera, OrthographicKeys) {
  const Scene s = parse(R"({"camera": {"type": "orthographic", "position": [0, 10, 0], "look_at": [0, 0, 0],
                            "up": [0, 0, -1], "view_height": 4.5}, "objects": []})");
  EXPECT_EQ(s.camera.type, CameraType::orthographic);
  EXPECT_EQ(s.camera.position, Vec3(0, 10, 0));
  expect_vec(s.camera.up, Vec3(0, 0, -1));
  EXPECT_EQ(s.camera.view_height, 4.5);
  EXPECT_EQ(s.camera.fov_y, 45.0);

  const Scene d = parse(R"({"camera": {"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0]},
                            "objects": []})");
  EXPECT_EQ(d.camera.view_height, 2.0);
}

TEST(SceneLoaderMaterials, EveryKeyIsRead) {
  const Scene s = parse_with(R"("materials": {
      "shiny": {"ambient": [0.1, 0.2, 0.3], "diffuse": [0.4, 0.5, 0.6], "specular": [0.7, 0.8, 0.9],
                "shininess": 100, "reflectivity": [0.25, 0.5, 0.75], "transparency": 0.5, "ior": 1.33,
                "fresnel": true},
      "gray": {"ambient": 0.05, "diffuse": 0.5, "specular": 1, "reflectivity": 0.3, "fresnel": false}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "gray"},
                {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "shiny"},
                {"type": "sphere", "center": [0, 0, 0], "radius": 1}])");
  ASSERT_EQ(s.objects.size(), 3u);
  const Material& shiny = s.materials.at(s.objects[1].material);
  EXPECT_EQ(shiny.name, "shiny");
  EXPECT_EQ(shiny.ambient, Color(0.1, 0.2, 0.3));
  EXPECT_EQ(shiny.diffuse, Color(0.4, 0.5, 0.6));
  EXPECT_EQ(shiny.specular, Color(0.7, 0.8, 0.9));
  EXPECT_EQ(shiny.shininess, 100.0);
  EXPECT_EQ(shiny.reflectivity, Color(0.25, 0.5, 0.75));
  EXPECT_EQ(shiny.transparency, 0.5);
  EXPECT_EQ(shiny.ior, 1.33);
  EXPECT_TRUE(shiny.fresnel);

  const Material& gray = s.materials.at(s.objects[0].material);
  EXPECT_EQ(gray.name, "gray");
  EXPECT_EQ(gray.ambient, Color(0.05));
  EXPECT_EQ(gray.diffuse, Color(0.5));
  EXPECT_EQ(gray.specular, Color(1.0));
  EXPECT_EQ(gray.reflectivity, Color(0.3));
  EXPECT_EQ(gray.shininess, 32.0);
  EXPECT_FALSE(gray.fresnel);

  const Material& none = s.materials.at(s.objects[2].material);
  EXPECT_EQ(none.diffuse, Color(0.8));
  EXPECT_NE(s.objects[2].material, s.objects[0].material);
  EXPECT_NE(s.objects[2].material, s.objects[1].material);
}

TEST(SceneLoaderLights, AmbientLight) {
  const Scene s = parse_with(R"("objects": [], "lights": [
      {"type": "ambient", "color": [0.1, 0.2, 0.3]},
      {"type": "ambient", "ambient": 0.4},
      {"type": "ambient", "color": 0.5, "name": "fill"}])");
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type, LightType::ambient);
  EXPECT_EQ(s.lights[0].ambient, Color(0.1, 0.2, 0.3));  // `color` sets L_a for an ambient light
  EXPECT_EQ(s.lights[1].ambient, Color(0.4));
  EXPECT_EQ(s.lights[2].ambient, Color(0.5));
  EXPECT_EQ(s.lights[2].name, "fill");
}

TEST(SceneLoaderLights, PointLightColorAndDefaults) {
  const Scene s = parse_with(R"("objects": [], "lights": [
      {"type": "point", "position": [1, 2, 3]},
      {"type": "point", "position": [0, 0, 0], "color": [0.5, 0.6, 0.7]},
      {"type": "point", "position": [0, 0, 0], "color": 0.25, "ambient": 0.125},
      {"type": "point", "position": [0, 0, 0], "ambient": [0.1, 0.2, 0.3], "diffuse": [0.4, 0.5, 0.6],
       "specular": 0.9, "attenuation": [1, 0.5, 0.25]},
      {"type": "point", "position": [0, 0, 0], "diffuse": 0.3}])");
  ASSERT_EQ(s.lights.size(), 5u);
  const Light& d = s.lights[0];
  EXPECT_EQ(d.type, LightType::point);
  EXPECT_EQ(d.position, Vec3(1, 2, 3));
  EXPECT_EQ(d.ambient, Color(0.0));
  EXPECT_EQ(d.diffuse, Color(1.0));
  EXPECT_EQ(d.specular, Color(1.0));
  EXPECT_EQ(d.attenuation, Vec3(1, 0, 0));

  EXPECT_EQ(s.lights[1].diffuse, Color(0.5, 0.6, 0.7));  // `color` sets diffuse and specular
  EXPECT_EQ(s.lights[1].specular, Color(0.5, 0.6, 0.7));
  EXPECT_EQ(s.lights[1].ambient, Color(0.0));
  EXPECT_EQ(s.lights[2].diffuse, Color(0.25));
  EXPECT_EQ(s.lights[2].specular, Color(0.25));
  EXPECT_EQ(s.lights[2].ambient, Color(0.125));

  const Light& e = s.lights[3];
  EXPECT_EQ(e.ambient, Color(0.1, 0.2, 0.3));
  EXPECT_EQ(e.diffuse, Color(0.4, 0.5, 0.6));
  EXPECT_EQ(e.specular, Color(0.9));
  EXPECT_EQ(e.attenuation, Vec3(1, 0.5, 0.25));

  EXPECT_EQ(s.lights[4].diffuse, Color(0.3));
  EXPECT_EQ(s.lights[4].specular, Color(1.0));  // untouched by `diffuse`
}

TEST(SceneLoaderLights, DirectionalLight) {
  const Scene s = parse_with(R"("objects": [], "lights": [
      {"type": "directional", "direction": [0, -2, 0], "color": 0.7},
      {"type": "directional", "direction": [1, -1, 0]}])");
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].type, LightType::directional);
  expect_vec(s.lights[0].direction, Vec3(0, -1, 0), "directions are normalized");
  EXPECT_EQ(s.lights[0].diffuse, Color(0.7));
  EXPECT_EQ(s.lights[0].specular, Color(0.7));
  expect_vec(s.lights[1].direction, Vec3(1, -1, 0) / std::sqrt(2.0));
  EXPECT_EQ(s.lights[1].ambient, Color(0.0));
  EXPECT_EQ(s.lights[1].diffuse, Color(1.0));
}

TEST(SceneLoaderLights, SpotLight) {
  const Scene s = parse_with(R"("objects": [], "lights": [
      {"type": "spot", "position": [0, 5, 0], "direction": [0, -3, 0], "cutoff": 30, "falloff": 2.5,
       "attenuation": [0.5, 0, 0.1], "specular": 0.4},
      {"type": "spot", "position": [1, 1, 1], "direction": [0, 0, -1], "cutoff": 180}])");
  ASSERT_EQ(s.lights.size(), 2u);
  const Light& a = s.lights[0];
  EXPECT_EQ(a.type, LightType::spot);
  EXPECT_EQ(a.position, Vec3(0, 5, 0));
  expect_vec(a.direction, Vec3(0, -1, 0));
  EXPECT_EQ(a.cutoff, 30.0);
  EXPECT_EQ(a.falloff, 2.5);
  EXPECT_EQ(a.attenuation, Vec3(0.5, 0, 0.1));
  EXPECT_EQ(a.diffuse, Color(1.0));
  EXPECT_EQ(a.specular, Color(0.4));
  EXPECT_EQ(s.lights[1].falloff, 0.0);  // default
  EXPECT_EQ(s.lights[1].cutoff, 180.0);
  EXPECT_EQ(s.lights[1].attenuation, Vec3(1, 0, 0));
}

TEST(SceneLoaderLights, AreaLight) {
  const Scene s = parse_with(R"("objects": [], "lights": [
      {"type": "area", "corner": [-1, 4, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "samples": 9,
       "color": [1, 0.9, 0.8], "attenuation": [1, 0.1, 0]},
      {"type": "area", "corner": [0, 4, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1]}])");
  ASSERT_EQ(s.lights.size(), 2u);
  const Light& a = s.lights[0];
  EXPECT_EQ(a.type, LightType::area);
  EXPECT_EQ(a.corner, Vec3(-1, 4, -1));
  EXPECT_EQ(a.edge_u, Vec3(2, 0, 0));  // edges are lengths, not directions: kept as given
  EXPECT_EQ(a.edge_v, Vec3(0, 0, 2));
  EXPECT_EQ(a.samples, 9);
  EXPECT_EQ(a.diffuse, Color(1, 0.9, 0.8));
  EXPECT_EQ(a.specular, Color(1, 0.9, 0.8));
  EXPECT_EQ(a.attenuation, Vec3(1, 0.1, 0));
  EXPECT_EQ(s.lights[1].samples, 16);  // default
  EXPECT_EQ(s.lights[1].attenuation, Vec3(1, 0, 0));
}

TEST(SceneLoaderObjects, EveryShapeIsRead) {
  const Scene s = parse_with(R"("materials": {"red": {"diffuse": [1, 0, 0]}}, "objects": [
      {"type": "sphere", "center": [1, 2, 3], "radius": 0.5, "material": "red", "name": "ball"},
      {"type": "plane", "point": [0, -1, 0], "normal": [0, 4, 0]},
      {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
      {"type": "box", "min": [-1, -2, -3], "max": [1, 2, 3]}])");
  ASSERT_EQ(s.objects.size(), 4u);
  const Object& o0 = s.objects[0];
  EXPECT_EQ(o0.type, ShapeType::sphere);
  EXPECT_EQ(s.spheres.at(o0.shape).center, Vec3(1, 2, 3));
  EXPECT_EQ(s.spheres.at(o0.shape).radius, 0.5);
  EXPECT_EQ(s.materials.at(o0.material).name, "red");
  EXPECT_EQ(s.materials.at(o0.material).diffuse, Color(1, 0, 0));
  EXPECT_EQ(s.object_names.at(0), "ball");

  const Object& o1 = s.objects[1];
  EXPECT_EQ(o1.type, ShapeType::plane);
  EXPECT_EQ(s.planes.at(o1.shape).point, Vec3(0, -1, 0));
  expect_vec(s.planes.at(o1.shape).normal, Vec3(0, 1, 0), "normals are normalized");

  const Object& o2 = s.objects[2];
  EXPECT_EQ(o2.type, ShapeType::triangle);
  const Triangle& t = s.triangles.at(o2.shape);
  EXPECT_EQ(t.v0, Vec3(0, 0, 0));
  EXPECT_EQ(t.v1, Vec3(1, 0, 0));
  EXPECT_EQ(t.v2, Vec3(0, 1, 0));

  const Object& o3 = s.objects[3];
  EXPECT_EQ(o3.type, ShapeType::box);
  EXPECT_EQ(s.boxes.at(o3.shape).lo, Vec3(-1, -2, -3));
  EXPECT_EQ(s.boxes.at(o3.shape).hi, Vec3(1, 2, 3));
  for (const Object& o : s.objects) EXPECT_EQ(o.transform, kNoTransform);
  EXPECT_EQ(s.object_names.size(), 1u);
}

TEST(SceneLoaderTransforms, ScaleThenRotateThenTranslateWhateverTheKeyOrder) {
  // (1,0,0) -scale [2,1,1]-> (2,0,0) -rotate 90 deg about +z-> (0,2,0) -translate-> (1,4,3).
  // Any other order gives another point. The keys are written in reverse order on purpose.
  const Scene s = parse_with(R"("objects": [
      {"type": "sphere", "center": [0, 0, 0], "radius": 1,
       "transform": {"translate": [1, 2, 3], "rotate": {"angle": 90, "axis": [0, 0, 7]}, "scale": [2, 1, 1]}}])");
  ASSERT_EQ(s.objects.size(), 1u);
  ASSERT_NE(s.objects[0].transform, kNoTransform);
  const Transform& t = s.transforms.at(s.objects[0].transform);
  expect_vec(t.point(Vec3(1, 0, 0)), Vec3(1, 4, 3));
  expect_vec(t.point(Vec3(0, 1, 0)), Vec3(0, 2, 3));  // rotate (0,1,0) -> (-1,0,0)
  expect_vec(t.point(Vec3(0, 0, 1)), Vec3(1, 2, 4));
  expect_vec(t.inverse_point(Vec3(1, 4, 3)), Vec3(1, 0, 0));
}

TEST(SceneLoaderTransforms, UniformScaleAndSingleParts) {
  const Scene s = parse_with(R"("objects": [
      {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {"scale": 3}},
      {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {"translate": [0, -1, 0]}},
      {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {"rotate": {"axis": [1, 0, 0], "angle": 90}}},
      {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {"scale": [-1, 2, 0.5]}}])");
  ASSERT_EQ(s.objects.size(), 4u);
  auto xf = [&](size_t i) -> const Transform& { return s.transforms.at(s.objects.at(i).transform); };
  expect_vec(xf(0).point(Vec3(1, 2, 3)), Vec3(3, 6, 9));
  expect_vec(xf(1).point(Vec3(1, 2, 3)), Vec3(1, 1, 3));
  expect_vec(xf(2).point(Vec3(0, 1, 0)), Vec3(0, 0, 1));  // right-hand rule about +x: y -> z
  expect_vec(xf(3).point(Vec3(1, 1, 1)), Vec3(-1, 2, 0.5));
}

TEST(SceneLoaderTransforms, MatrixIsRowByRowWithTranslationInElements3_7_11) {
  const Scene s = parse_with(R"("objects": [
      {"type": "sphere", "center": [0, 0, 0], "radius": 1,
       "transform": {"matrix": [1, 0, 0, 5,
                                0, 2, 0, 6,
                                0, 0, 3, 7,
                                0, 0, 0, 1]}},
      {"type": "sphere", "center": [0, 0, 0], "radius": 1,
       "transform": {"matrix": [0, -1, 0, 0,  1, 0, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1]}}])");
  ASSERT_EQ(s.objects.size(), 2u);
  const Transform& t = s.transforms.at(s.objects[0].transform);
  expect_vec(t.point(Vec3(1, 1, 1)), Vec3(6, 8, 10));
  expect_vec(t.vector(Vec3(1, 1, 1)), Vec3(1, 2, 3));
  // A matrix multiplies column vectors: row 0 = (0,-1,0) sends x to (0,1,0).
  const Transform& r = s.transforms.at(s.objects[1].transform);
  expect_vec(r.point(Vec3(1, 0, 0)), Vec3(0, 1, 0));
}

TEST(SceneLoaderTransforms, PlanesAndTrianglesAreMovedIntoWorldSpace) {
  const Scene s = parse_with(R"("objects": [
      {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0],
       "transform": {"rotate": {"axis": [0, 0, 1], "angle": 90}, "translate": [0, 3, 0]}},
      {"type": "plane", "point": [0, 0, 0], "normal": [1, 1, 0], "transform": {"scale": [2, 1, 1]}},
      {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
       "transform": {"scale": 2, "translate": [1, 1, 1]}}])");
  ASSERT_EQ(s.objects.size(), 3u);
  const Plane& p = s.planes.at(s.objects[0].shape);
  expect_vec(p.point, Vec3(0, 3, 0));
  expect_vec(p.normal, Vec3(-1, 0, 0));
  // Normals go through the inverse transpose: scaling x by 2 halves the normal's x.
  expect_vec(s.planes.at(s.objects[1].shape).normal, normalize(Vec3(0.5, 1, 0)));
  const Triangle& t = s.triangles.at(s.objects[2].shape);
  expect_vec(t.v0, Vec3(1, 1, 1));
  expect_vec(t.v1, Vec3(3, 1, 1));
  expect_vec(t.v2, Vec3(1, 3, 1));
}

TEST(SceneLoaderFiles, ByteOrderMarkIsSkipped) {
  const Scene s = parse("\xEF\xBB\xBF{\"camera\": {\"position\": [0, 0, 1], \"look_at\": [0, 0, 0]}, \"objects\": []}");
  EXPECT_EQ(s.camera.position, Vec3(0, 0, 1));
  // Positions after a BOM count from the first character after it.
  try {
    parse("\xEF\xBB\xBF[1]");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.location().line, 1);
    EXPECT_EQ(e.location().column, 1);
    EXPECT_NE(e.message().find("expected an object"), std::string::npos) << e.what();
  }
}

TEST(SceneLoaderFiles, LoadSceneReadsAFileAndNamesItInErrors) {
  const fs::path dir = fs::temp_directory_path() / ("glint-scene-loader-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path good = dir / "good.json", bad = dir / "bad.json";
  std::ofstream(good) << "{\"camera\": {\"position\": [0, 0, 1], \"look_at\": [0, 0, 0]},\r\n"
                         " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 2}]}\r\n";
  std::ofstream(bad) << "{\"camera\": {\"position\": [0, 0, 1], \"look_at\": [0, 0, 0]},\r\n"
                        " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": -1}]}\r\n";
  const Scene s = load_scene(good);
  ASSERT_EQ(s.spheres.size(), 1u);
  EXPECT_EQ(s.spheres[0].radius, 2.0);
  try {
    load_scene(bad);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    // CRLF line ends count as one line end.
    EXPECT_EQ(e.location().file, bad.string());
    EXPECT_EQ(e.location().line, 2);
    EXPECT_EQ(e.location().column, 64);
    EXPECT_EQ(e.message(), "objects[0].radius: must be > 0 (got -1)");
    EXPECT_EQ(std::string(e.what()), bad.string() + ":2:64: objects[0].radius: must be > 0 (got -1)");
  }
  const fs::path missing = dir / "missing.json";
  try {
    load_scene(missing);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.location().file, missing.string());
    EXPECT_NE(e.message().find("cannot open"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// --- errors ------------------------------------------------------------------

TEST(SceneLoaderErrors, JsonSyntax) {
  expect_error("{\"camera\": {\"position\": [0, 0, 5]\n   @\"look_at\": [0, 0, 0]}, \"objects\": []}", "syntax error");
  expect_error("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}, \"objects\": [1, 2]@]}",
               "syntax error");
  expect_error("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}, \"objects\": [@NaN]}", "syntax error");
  expect_error("{\"objects\": [], \"camera\": {} } @x", "syntax error");
}

TEST(SceneLoaderErrors, EmptyFileAndTopLevelNotAnObject) {
  expect_error("@", "empty file");
  expect_error("@  \n  \n", "empty file");
  expect_error("@[1, 2]", "expected an object, got array");
  expect_error("  @42", "expected an object, got number");
}

TEST(SceneLoaderErrors, DuplicateKey) {
  expect_object_error(R"({"type": "sphere", "radius": 1, "center": [0, 0, 0], @"radius": 2})",
                      "duplicate key \"radius\"");
}

TEST(SceneLoaderErrors, DeepNesting) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  try {
    parse(deep);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("nesting too deep"), std::string::npos) << e.message();
    EXPECT_EQ(e.location().line, 1);
    EXPECT_EQ(e.location().column, static_cast<int>(json::kMaxDepth) + 1);
  }
  // Deep inside a scene value, too.
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "name": )" +
                          std::string(json::kMaxDepth - 3, '[') + "@" + std::string(100, '[') +
                          std::string(json::kMaxDepth + 97, ']') + "}",
                      "nesting too deep");
}

TEST(SceneLoaderErrors, NonFiniteNumbers) {
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": @1e999})", "number out of range");
  expect_object_error(R"({"type": "sphere", "center": [@-1e999, 0, 0], "radius": 1})", "number out of range");
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": @Infinity})", "syntax error");
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": @"NaN"})", "expected a number, got string");
}

TEST(SceneLoaderErrors, WrongType) {
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": @"1"})",
                      "objects[0].radius: expected a number, got string");
  expect_object_error(R"({"type": "sphere", "center": @[0, 0], "radius": 1})",
                      "objects[0].center: expected [x, y, z], got an array of 2");
  expect_object_error(R"({"type": "sphere", "center": [0, @true, 0], "radius": 1})",
                      "objects[0].center[1]: expected a number, got boolean");
  expect_object_error(R"({"type": @1, "center": [0, 0, 0], "radius": 1})",
                      "objects[0].type: expected a string, got number");
  expect_error_with(R"("objects": @{})", "objects: expected an array, got object");
  expect_error_with(R"("objects": [@3])", "objects[0]: expected an object, got number");
  expect_error_with(R"("objects": [], "lights": @{})", "lights: expected an array, got object");
  expect_error_with(R"("objects": [], "materials": @[])", "materials: expected an object, got array");
  expect_error_with(R"("objects": [], "materials": {"m": @1})", "materials.m: expected an object, got number");
  expect_error_with(R"("objects": [], "materials": {"m": {"fresnel": @"yes"}})",
                    "materials.m.fresnel: expected true or false, got string");
  expect_error_with(R"("objects": [], "materials": {"m": {"diffuse": @[1, 0]}})",
                    "materials.m.diffuse: expected a color");
  expect_error_with(R"("objects": [], "render": @[])", "render: expected an object, got array");
  expect_error(R"({"camera": @null, "objects": []})", "camera: expected an object, got null");
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": @7})",
                      "objects[0].material: expected a string, got number");
}

TEST(SceneLoaderErrors, MissingRequiredKey) {
  expect_error(R"(@{"objects": []})", "missing required key \"camera\"");
  expect_error(std::string("@{") + kCamera + "}", "missing required key \"objects\"");
  expect_error(R"({"camera": @{"look_at": [0, 0, 0]}, "objects": []})", "camera: missing required key \"position\"");
  expect_error(R"({"camera": @{"position": [0, 0, 0]}, "objects": []})", "camera: missing required key \"look_at\"");
  expect_object_error(R"(@{"type": "sphere", "radius": 1})", "objects[0]: missing required key \"center\"");
  expect_object_error(R"(@{"type": "sphere", "center": [0, 0, 0]})", "objects[0]: missing required key \"radius\"");
  expect_object_error(R"(@{"center": [0, 0, 0], "radius": 1})", "objects[0]: missing required key \"type\"");
  expect_object_error(R"(@{"type": "plane", "normal": [0, 1, 0]})", "missing required key \"point\"");
  expect_object_error(R"(@{"type": "plane", "point": [0, 1, 0]})", "missing required key \"normal\"");
  expect_object_error(R"(@{"type": "triangle"})", "missing required key \"vertices\"");
  expect_object_error(R"(@{"type": "box", "max": [1, 1, 1]})", "missing required key \"min\"");
  expect_object_error(R"(@{"type": "box", "min": [1, 1, 1]})", "missing required key \"max\"");
  expect_object_error(R"({"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {"rotate": @{"angle": 3}}})",
                      "objects[0].transform.rotate: missing required key \"axis\"");
  expect_object_error(
      R"({"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {"rotate": @{"axis": [1, 0, 0]}}})",
      "objects[0].transform.rotate: missing required key \"angle\"");
  expect_light_error(R"(@{"position": [0, 0, 0]})", "lights[0]: missing required key \"type\"");
  expect_light_error(R"(@{"type": "point"})", "lights[0]: missing required key \"position\"");
  expect_light_error(R"(@{"type": "directional"})", "lights[0]: missing required key \"direction\"");
  expect_light_error(R"(@{"type": "spot", "position": [0, 0, 0], "direction": [0, -1, 0]})",
                     "lights[0]: missing required key \"cutoff\"");
  expect_light_error(R"(@{"type": "spot", "position": [0, 0, 0], "cutoff": 10})",
                     "lights[0]: missing required key \"direction\"");
  expect_light_error(R"(@{"type": "area", "edge_u": [1, 0, 0], "edge_v": [0, 0, 1]})",
                     "missing required key \"corner\"");
  expect_light_error(R"(@{"type": "area", "corner": [0, 0, 0], "edge_v": [0, 0, 1]})",
                     "missing required key \"edge_u\"");
  expect_light_error(R"(@{"type": "area", "corner": [0, 0, 0], "edge_u": [0, 0, 1]})",
                     "missing required key \"edge_v\"");
}

TEST(SceneLoaderErrors, UnknownKeysGetAHint) {
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], @"radus": 1})",
                      "objects[0]: unknown key \"radus\" (did you mean \"radius\"?)");
  expect_error(std::string("{") + kCamera + R"(, "objects": [], @"light": []})",
               "unknown key \"light\" (did you mean \"lights\"?)");
  expect_error(std::string("{") + kCamera + R"(, "objects": [],
                 @"frobnicate": 1})",
               "unknown key \"frobnicate\" (expected one of \"render\", \"camera\"");
  expect_error_with(R"("objects": [], "render": {@"widht": 10})",
                    "render: unknown key \"widht\" (did you mean \"width\"?)");
  expect_error(R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], @"fovy": 30}, "objects": []})",
               "camera: unknown key \"fovy\" (did you mean \"fov_y\"?)");
  // "fov" is the fisheye's key: on a perspective camera the hint is the same.
  expect_error(R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], @"fov": 30}, "objects": []})",
               "(this one is perspective; did you mean \"fov_y\"?)");
  expect_error_with(R"("objects": [], "materials": {"m": {@"shinyness": 3}})",
                    "materials.m: unknown key \"shinyness\" (did you mean \"shininess\"?)");
  expect_light_error(R"({"type": "point", "position": [0, 0, 0], @"colour": 1})",
                     "lights[0]: unknown key \"colour\" (did you mean \"color\"?)");
  expect_object_error(
      R"({"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {@"translation": [1, 0, 0]}})",
      "objects[0].transform: unknown key \"translation\" (did you mean \"translate\"?)");
  // Keys are shown escaped (a message is one line) and cut short when long.
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, @"a\nb\"c": 1})",
                      "unknown key \"a\\u000Ab\\\"c\"");
  expect_object_error(
      R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, @")" + std::string(100000, 'k') + R"(": 1})",
      "unknown key \"" + std::string(64, 'k') + "...\"");
  expect_error_with(R"("objects": [], "materials": {"x\ty": {"ior": @0}})", "materials.x\\u0009y.ior: must be > 0");
  // A key that belongs to another shape or light type.
  expect_object_error(R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], @"radius": 1})",
                      "objects[0]: unknown key \"radius\"");
  expect_light_error(R"({"type": "point", "position": [0, 0, 0], @"cutoff": 10})",
                     "lights[0].cutoff: not valid for a point light");
}

TEST(SceneLoaderErrors, UnknownNamesAndEnumValuesGetAHint) {
  expect_object_error(R"({"type": @"sphre", "center": [0, 0, 0], "radius": 1})",
                      "objects[0].type: unknown object type \"sphre\" (did you mean \"sphere\"?)");
  expect_object_error(R"({"type": @"teapot"})",
                      "objects[0].type: unknown object type \"teapot\" (expected one of \"sphere\"");
  expect_light_error(R"({"type": @"spott", "position": [0, 0, 0]})",
                     "lights[0].type: unknown light type \"spott\" (did you mean \"spot\"?)");
  expect_error(R"({"camera": {"type": @"orthografic", "position": [0, 0, 1], "look_at": [0, 0, 0]}, "objects": []})",
               "camera.type: unknown camera type \"orthografic\" (did you mean \"orthographic\"?)");
  expect_error_with(R"("objects": [], "render": {"shading_model": @"blinn_phong"})",
                    "render.shading_model: unknown shading model \"blinn_phong\" (did you mean \"blinn-phong\"?)");
  expect_error_with(R"("objects": [], "render": {"shading_model": @"gouraud"})",
                    "unknown shading model \"gouraud\" (expected one of \"phong\", \"blinn-phong\")");
}

TEST(SceneLoaderErrors, UnknownMaterial) {
  expect_error_with(R"("materials": {"gold": {}}, "objects": [
      {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": @"glod"}])",
                    "objects[0].material: unknown material \"glod\" (did you mean \"gold\"?)");
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": @"steel"})",
                      "unknown material \"steel\"");
}

TEST(SceneLoaderErrors, NonPositiveSizes) {
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": @-1})",
                      "objects[0].radius: must be > 0 (got -1)");
  expect_object_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": @0})",
                      "objects[0].radius: must be > 0 (got 0)");
  expect_object_error(R"({"type": "box", "min": [0, 0, 0], "max": @[1, 0, 1]})",
                      "objects[0].max: must be greater than \"min\"");
  expect_object_error(R"({"type": "box", "min": [0, 0, 0], "max": @[1, 1, -1]})",
                      "objects[0].max: must be greater than \"min\"");
  expect_error_with(R"("objects": [], "render": {"width": @0})", "render.width: must be >= 1 (got 0)");
  expect_error_with(R"("objects": [], "render": {"height": @-5})", "render.height: must be >= 1 (got -5)");
  expect_error_with(R"("objects": [], "render": {"samples_per_pixel": @0})",
                    "render.samples_per_pixel: must be >= 1 (got 0)");
  expect_error_with(R"("objects": [], "render": {"max_depth": @0})", "render.max_depth: must be >= 1 (got 0)");
  expect_error_with(R"("objects": [], "render": {"epsilon": @0})", "render.epsilon: must be > 0");
  expect_error_with(R"("objects": [], "materials": {"m": {"shininess": @0}})",
                    "materials.m.shininess: must be > 0 (got 0)");
  expect_error_with(R"("objects": [], "materials": {"m": {"ior": @-1.5}})", "materials.m.ior: must be > 0");
  expect_error_with(R"("objects": [], "materials": {"m": {"transparency": @-0.5}})",
                    "materials.m.transparency: must be >= 0");
  expect_error_with(R"("objects": [], "materials": {"m": {"diffuse": @[0.5, -0.1, 0]}})", "must be >= 0");
  expect_error(R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "fov_y": @0}, "objects": []})",
               "camera.fov_y: must be between 0 and 180");
  expect_error(R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "fov_y": @180}, "objects": []})",
               "camera.fov_y: must be between 0 and 180");
  expect_error(R"({"camera": {"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "view_height": @-2},
                   "objects": []})",
               "camera.view_height: must be > 0 (got -2)");
  expect_light_error(R"({"type": "spot", "position": [0, 0, 0], "direction": [0, -1, 0], "cutoff": @0})",
                     "lights[0].cutoff: must be in (0, 180]");
  expect_light_error(
      R"({"type": "spot", "position": [0, 0, 0], "direction": [0, -1, 0], "cutoff": 10, "falloff": @-1})",
      "lights[0].falloff: must be >= 0");
  expect_light_error(
      R"({"type": "area", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "samples": @0})",
      "lights[0].samples: must be >= 1 (got 0)");
  expect_light_error(R"({"type": "area", "corner": [0, 0, 0], "edge_u": @[1, 0, 0], "edge_v": [2, 0, 0]})",
                     "lights[0].edge_u: edge_u and edge_v must span a parallelogram of non-zero area");
  expect_light_error(R"({"type": "point", "position": [0, 0, 0], "attenuation": @[0, 0, 0]})",
                     "lights[0].attenuation: at least one coefficient must be > 0");
  expect_light_error(R"({"type": "point", "position": [0, 0, 0], "attenuation": @[1, -1, 0]})",
                     "lights[0].attenuation: coefficients must be >= 0");
}

TEST(SceneLoaderErrors, NonIntegerAndOutOfRangeCounts) {
  expect_error_with(R"("objects": [], "render": {"width": @640.5})",
                    "render.width: expected a whole number, got 640.5");
  expect_error_with(R"("objects": [], "render": {"samples_per_pixel": @1.5})",
                    "render.samples_per_pixel: expected a whole number");
  expect_error_with(R"("objects": [], "render": {"max_depth": @"5"})",
                    "render.max_depth: expected a number, got string");
  expect_error_with(R"("objects": [], "render": {"width": @1e300})", "render.width: expected a whole number");
  expect_error_with(R"("objects": [], "render": {"height": @3000000000})", "render.height: must be <= ");
  expect_light_error(
      R"({"type": "area", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "samples": @2.5})",
      "lights[0].samples: expected a whole number");
}

TEST(SceneLoaderErrors, AbsurdImageSizeIsACleanError) {
  // 1e6 x 1e6 pixels would need 12 TB: refused before anything is allocated.
  expect_error_with(R"("objects": [], "render": {"width": @1000000, "height": 1000000})",
                    "1000000x1000000 pixels needs");
  expect_error_with(R"("objects": [], "render": {"height": 1000000, "width": @1000000})",
                    "1000000x1000000 pixels needs");
}

TEST(SceneLoaderErrors, ZeroLengthDirections) {
  expect_object_error(R"({"type": "plane", "point": [0, 0, 0], "normal": @[0, 0, 0]})",
                      "objects[0].normal: must be a non-zero vector");
  expect_light_error(R"({"type": "directional", "direction": @[0, 0, 0]})",
                     "lights[0].direction: must be a non-zero vector");
  expect_light_error(R"({"type": "spot", "position": [0, 0, 0], "direction": @[0, 0, 0], "cutoff": 5})",
                     "lights[0].direction: must be a non-zero vector");
  expect_error(R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "up": @[0, 0, 0]}, "objects": []})",
               "camera.up: must be a non-zero vector");
  expect_object_error(R"({"type": "box", "min": [0, 0, 0], "max": [1, 1, 1],
                          "transform": {"rotate": {"axis": @[0, 0, 0], "angle": 30}}})",
                      "objects[0].transform.rotate.axis: must be a non-zero vector");
  // Huge but finite components are still a direction.
  const Scene s = parse_with(R"("objects": [], "lights": [{"type": "directional", "direction": [1e300, 1e300, 0]}])");
  expect_vec(s.lights.at(0).direction, Vec3(1, 1, 0) / std::sqrt(2.0));
  const Scene t = parse_with(R"("objects": [], "lights": [{"type": "directional", "direction": [0, -1e-300, 0]}])");
  expect_vec(t.lights.at(0).direction, Vec3(0, -1, 0));
}

TEST(SceneLoaderErrors, CameraGeometry) {
  expect_error(R"({"camera": {"position": [1, 2, 3], "look_at": @[1, 2, 3]}, "objects": []})",
               "camera.look_at: must differ from camera.position");
  expect_error(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "up": @[0, 0, -2]}, "objects": []})",
               "camera.up: up is parallel to the view direction");
  expect_error(R"({"camera": {"position": [1e308, 0, 0], "look_at": @[-1e308, 0, 0]}, "objects": []})",
               "camera.look_at: too far from camera.position");
  // The default up [0,1,0] with a camera looking straight down.
  expect_error(R"({"camera": @{"position": [0, 5, 0], "look_at": [0, 0, 0]}, "objects": []})",
               "up is parallel to the view direction");
}

TEST(SceneLoaderErrors, ColorWithDiffuseOrSpecular) {
  expect_light_error(R"({"type": "point", "position": [0, 0, 0], "color": @1, "diffuse": 0.5})",
                     "lights[0].color: give either \"color\" or \"diffuse\"/\"specular\", not both");
  expect_light_error(R"({"type": "spot", "position": [0, 0, 0], "direction": [0, -1, 0], "cutoff": 9,
                         "specular": 0.5, "color": @1})",
                     "not both");
  expect_light_error(R"({"type": "ambient", "color": @1, "ambient": 0.5})",
                     "lights[0].color: give either \"color\" or \"ambient\", not both");
}

TEST(SceneLoaderErrors, AttenuationOnDirectionalOrAmbientLight) {
  expect_light_error(R"({"type": "directional", "direction": [0, -1, 0], @"attenuation": [1, 0, 0]})",
                     "lights[0].attenuation: not valid for a directional light");
  expect_light_error(R"({"type": "ambient", "color": 0.1, @"attenuation": [1, 0, 0]})",
                     "lights[0].attenuation: not valid for an ambient light");
  expect_light_error(R"({"type": "ambient", @"diffuse": 1})", "lights[0].diffuse: not valid for an ambient light");
}

TEST(SceneLoaderErrors, SingularTransforms) {
  const std::string box = R"({"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": )";
  expect_object_error(box + R"({"scale": @0}})",
                      "objects[0].transform.scale: a zero scale makes the transform singular");
  expect_object_error(box + R"({"scale": @[1, 0, 1]}})", "singular");
  expect_object_error(box + R"({"matrix": @[1, 0, 0, 0,  0, 1, 0, 0,  1, 0, 0, 0,  0, 0, 0, 1]}})",
                      "objects[0].transform.matrix: the matrix is singular");
  expect_object_error(box + R"({"matrix": @[1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 1, 1]}})",
                      "objects[0].transform.matrix: the last row must be 0 0 0 1");
  expect_object_error(box + R"({"matrix": @[1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 2]}})",
                      "the last row must be 0 0 0 1");
  expect_object_error(box + R"({"matrix": @[1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0]}})", "expected 16 numbers");
  expect_object_error(box + R"(@{"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1], "scale": 2}})",
                      "\"matrix\" cannot be combined");
  // A singular transform of a plane or triangle, too.
  expect_object_error(
      R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "transform": {"scale": @[2, 0, 2]}})", "singular");
}

TEST(SceneLoaderErrors, DegenerateShapes) {
  expect_object_error(R"({"type": "triangle", "vertices": @[[0, 0, 0], [1, 1, 1], [2, 2, 2]]})",
                      "objects[0].vertices: degenerate triangle");
  expect_object_error(R"({"type": "triangle", "vertices": @[[0, 0, 0], [0, 0, 0], [0, 1, 0]]})", "degenerate triangle");
  expect_object_error(R"({"type": "triangle", "vertices": @[[0, 0, 0], [1, 0, 0]]})",
                      "objects[0].vertices: expected three vertices");
  expect_object_error(R"({"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], @[0, 1]]})",
                      "objects[0].vertices[2]: expected [x, y, z]");
}

// --- glint additions: pixel filter and adaptive sampling -----------------------

TEST(SceneLoaderRender, PixelFilterAndAdaptive) {
  EXPECT_EQ(parse_with(R"("objects": [])").render.pixel_filter.type, FilterType::box);
  EXPECT_FALSE(parse_with(R"("objects": [])").render.adaptive.has_value());
  const Scene g = parse_with(R"("render": {"pixel_filter": "gaussian"}, "objects": [])");
  EXPECT_EQ(g.render.pixel_filter.type, FilterType::gaussian);
  EXPECT_EQ(g.render.pixel_filter.radius, 1.5);
  EXPECT_EQ(g.render.pixel_filter.sigma, 0.5);
  const Scene m = parse_with(R"("render": {"pixel_filter": {"type": "mitchell", "radius": 3, "b": 0, "c": 0.5},
      "samples_per_pixel": 4, "adaptive": {"max_samples_per_pixel": 64, "threshold": 0.2}}, "objects": [])");
  EXPECT_EQ(m.render.pixel_filter.type, FilterType::mitchell);
  EXPECT_EQ(m.render.pixel_filter.radius, 3);
  EXPECT_EQ(m.render.pixel_filter.b, 0);
  EXPECT_EQ(m.render.pixel_filter.c, 0.5);
  ASSERT_TRUE(m.render.adaptive.has_value());
  EXPECT_EQ(m.render.adaptive->max_samples_per_pixel, 64);
  EXPECT_EQ(m.render.adaptive->threshold, 0.2);
  EXPECT_EQ(parse_with(R"("render": {"pixel_filter": {"type": "mitchell"}}, "objects": [])").render.pixel_filter.radius,
            2);
  EXPECT_EQ(
      parse_with(R"("render": {"adaptive": {"max_samples_per_pixel": 8}}, "objects": [])").render.adaptive->threshold,
      0.05);
}

TEST(SceneLoaderRender, PixelFilterAndAdaptiveErrors) {
  expect_error_with(R"("render": {"pixel_filter": @"gausian"}, "objects": [])", "did you mean \"gaussian\"");
  expect_error_with(R"("render": {"pixel_filter": {"type": "gaussian", "radius": @0}}, "objects": [])",
                    "render.pixel_filter.radius: must be > 0");
  expect_error_with(R"("render": {"pixel_filter": {"type": "gaussian", "radius": @17}}, "objects": [])",
                    "must be <= 16");
  expect_error_with(R"("render": {"pixel_filter": {"type": "mitchell", @"sigma": 1}}, "objects": [])",
                    "does not apply to the mitchell filter");
  expect_error_with(R"("render": {"pixel_filter": {"type": "mitchell", "c": @-0.1}}, "objects": [])",
                    "must be between 0 and 1");
  expect_error_with(R"("render": {"pixel_filter": @{"radius": 1}}, "objects": [])", "missing required key \"type\"");
  expect_error_with(R"("render": {"pixel_filter": {"type": "box", @"radius": 1}}, "objects": [])",
                    "does not apply to the box filter");
  expect_error_with(R"("render": {"samples_per_pixel": 16, "adaptive": {"max_samples_per_pixel": @8}}, "objects": [])",
                    "must be >= render.samples_per_pixel (16)");
  expect_error_with(R"("render": {"adaptive": @{"threshold": 1}}, "objects": [])",
                    "missing required key \"max_samples_per_pixel\"");
  expect_error_with(R"("render": {"adaptive": {"max_samples_per_pixel": 8, "threshold": @-1}}, "objects": [])",
                    "must be >= 0");
}

// Each mesh file fits the budget on its own; together they must fit too,
// or the object whose file tips them over is the error, at its "file" key.
TEST(SceneLoaderLimits, AllMeshesTogetherMustFitTheMemoryBudget) {
  const fs::path meshes = fs::path(GLINT_SOURCE_DIR) / "tests" / "meshes";
  const std::string text = std::string("{") + kCamera + R"(, "objects": [
  {"type": "mesh", "file": "cube.obj"},
  {"type": "mesh", "file": "cube.obj", "transform": {"translate": [3, 0, 0]}},
  {"type": "mesh", "file": "quads.obj"}]})";
  // The estimate the loader makes, from what it loads.
  const Scene scene = parse_scene(text, "s.json", meshes);
  ASSERT_EQ(scene.meshes.size(), 2u);  // cube.obj once, instanced twice
  double bytes[2];
  for (int i = 0; i < 2; ++i)
    bytes[i] = kBytesPerVertex * double(scene.meshes[i].positions.size()) +
               kBytesPerTriangle * double(scene.meshes[i].triangle_count());
  const size_t both = static_cast<size_t>(bytes[0] + bytes[1]);
  ASSERT_GT(both - 1, std::max({bytes[0], bytes[1], double(fs::file_size(meshes / "quads.obj"))}));
  EXPECT_NO_THROW(parse_scene(text, "s.json", meshes, both));
  try {
    parse_scene(text, "s.json", meshes, both - 1);
    ADD_FAILURE() << "loaded";
  } catch (const Error& e) {
    EXPECT_EQ(e.location().line, 4) << e.what();
    EXPECT_EQ(e.location().column, 28) << e.what();
    EXPECT_EQ(
        e.message().rfind("objects[2].file: with this mesh the scene's 2 mesh files hold " +
                              std::to_string(scene.meshes[0].triangle_count() + scene.meshes[1].triangle_count()) +
                              " triangles: that needs ",
                          0),
        0u)
        << e.what();
  }
}

}  // namespace
}  // namespace glint

// --- cameras, atmosphere and occlusion beyond the seed -----------------------

namespace glint {
namespace {

TEST(SceneLoaderBeyondSeed, NewCameraKeysAreRead) {
  const Scene fish = parse(R"({"camera": {"type": "fisheye", "fov": 220, "position": [0, 0, 5], "look_at": [0, 0, 0]},
                               "objects": []})");
  EXPECT_EQ(fish.camera.type, CameraType::fisheye);
  EXPECT_EQ(fish.camera.fisheye_fov, 220);
  EXPECT_EQ(parse(R"({"camera": {"type": "fisheye", "position": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": []})")
                .camera.fisheye_fov,
            180);  // the default
  const Scene lens = parse(R"({"render": {"width": 100},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "aperture": 0.5, "focus_distance": 3,
                 "stereo": {"eye_separation": 0.1}}, "objects": []})");
  EXPECT_EQ(lens.camera.aperture, 0.5);
  EXPECT_EQ(lens.camera.focus_distance, 3);
  EXPECT_EQ(lens.camera.eye_separation, 0.1);
  EXPECT_EQ(lens.render.width, 200);  // both eyes
  EXPECT_EQ(parse(R"({"camera": {"type": "equirectangular", "position": [0, 0, 5], "look_at": [0, 0, 0]},
                      "objects": []})")
                .camera.type,
            CameraType::equirectangular);
}

TEST(SceneLoaderBeyondSeed, FogAndOcclusionAreRead) {
  const Scene s = parse_with(R"("render": {"background": [0.1, 0.2, 0.3], "fog": {"type": "exp2", "density": 0.5}},
      "lights": [{"type": "ambient", "ambient": 1, "occlusion": {"samples": 8, "distance": 2.5}}], "objects": [])");
  ASSERT_TRUE(s.render.fog);
  EXPECT_EQ(s.render.fog->type, FogType::exp2);
  EXPECT_EQ(s.render.fog->density, 0.5);
  expect_vec(s.render.fog->color, {0.1, 0.2, 0.3}, "fog color defaults to the background");
  EXPECT_EQ(s.lights[0].occlusion_samples, 8);
  EXPECT_EQ(s.lights[0].occlusion_distance, 2.5);
  const Scene l = parse_with(R"("render": {"fog": {"type": "linear", "color": 1, "start": 1, "end": 4}}, "objects": [])");
  EXPECT_EQ(l.render.fog->start, 1);
  EXPECT_EQ(l.render.fog->end, 4);
}

TEST(SceneLoaderBeyondSeed, Errors) {
  const std::string p = R"("position": [0, 0, 5], "look_at": [0, 0, 0])";
  expect_error(R"({"camera": {"type": "fisheye", "fov": @361, )" + p + R"(}, "objects": []})", "(0, 360]");
  expect_error(R"({"camera": {"type": "fisheye", "fov": @0, )" + p + R"(}, "objects": []})", "(0, 360]");
  expect_error(R"({"camera": {"type": @"fishy", )" + p + R"(}, "objects": []})", "did you mean \"fisheye\"");
  expect_error(R"({"camera": {@"fov": 90, )" + p + R"(}, "objects": []})", "applies to fisheye cameras only");
  expect_error(R"({"camera": {"type": "orthographic", @"aperture": 1, )" + p + R"(}, "objects": []})",
               "applies to perspective cameras only");
  expect_error(R"({"camera": {"aperture": @-1, )" + p + R"(}, "objects": []})", "must be >= 0");
  expect_error(R"({"camera": {"focus_distance": @0, )" + p + R"(}, "objects": []})", "must be > 0");
  expect_error(R"({"camera": {"stereo": {"eye_separation": @0}, )" + p + R"(}, "objects": []})", "must be > 0");
  expect_error(R"({"camera": {"stereo": @{}, )" + p + R"(}, "objects": []})", "missing required key");
  expect_error_with(R"("render": {"fog": {"type": @"mist"}}, "objects": [])", "unknown fog type");
  expect_error_with(R"("render": {"fog": @{"color": 1}}, "objects": [])", "missing required key \"type\"");
  expect_error_with(R"("render": {"fog": {"type": "exp", @"start": 1, "density": 1}}, "objects": [])",
                    "does not apply to exp fog");
  expect_error_with(R"("render": {"fog": {"type": "exp", "density": @0}}, "objects": [])", "must be > 0");
  expect_error_with(R"("render": {"fog": @{"type": "exp2"}}, "objects": [])", "missing required key \"density\"");
  expect_error_with(R"("render": {"fog": {"type": "linear", "start": 5, "end": @5}}, "objects": [])",
                    "must be greater than \"start\"");
  expect_error_with(R"("render": {"fog": {"type": "linear", "start": @-1, "end": 5}}, "objects": [])", "must be >= 0");
  expect_error_with(R"("render": {"fog": {"type": "linear", "end": 5, "color": @[1, -1, 0]}}, "objects": [])",
                    "color components must be >= 0");
  expect_error_with(R"("render": {"background": 0, "environment": @{"file": "sky.hdr"}}, "objects": [])",
                    "either \"background\" or \"environment\"");
  expect_error_with(R"("render": {"environment": {"file": @"no-such-sky.hdr"}}, "objects": [])", "not found");
  expect_error_with(R"("render": {"environment": {@"rotat": 3, "file": "x.hdr"}}, "objects": [])",
                    "did you mean \"rotate\"");
  expect_light_error(R"({"type": "point", "position": [0, 1, 0], @"occlusion": {"samples": 4}})",
                     "not valid for a point light");
  expect_light_error(R"({"type": "ambient", "occlusion": {"samples": @0}})", "must be >= 1");
  expect_light_error(R"({"type": "ambient", "occlusion": {"samples": 4, "distance": @-2}})", "must be > 0");
  expect_light_error(R"({"type": "ambient", "occlusion": @{"distance": 2}})", "missing required key \"samples\"");
}

}  // namespace
}  // namespace glint
