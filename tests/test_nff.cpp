// NFF scenes (io/nff_file.h, docs/nff.md): the document the reader makes of
// every entity, value by value from the contract's formulas; every class of
// bad input as one error at its file:line:col; loader errors reported at the
// NFF entity behind them; the view's fov following the rendered height; ray
// counts on scenes small enough to count by hand; `glint convert` and
// `--stats-json`; and, once polygons load, the SPD's published ray counts.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/error.h"
#include "glint/glint.h"
#include "glint/image/image.h"
#include "glint/io/image_file.h"
#include "glint/io/json.h"
#include "glint/io/nff_file.h"
#include "glint/io/scene_loader.h"
#include "glint/render/camera.h"
#include "glint/render/renderer.h"

namespace {

namespace fs = std::filesystem;
using namespace glint;
using Json = nlohmann::ordered_json;

const fs::path kNffDir = fs::path(GLINT_SOURCE_DIR) / "tests" / "nff";
const fs::path kSpdDir = fs::path(GLINT_SOURCE_DIR) / "bench" / "spd";

constexpr double kPi = std::numbers::pi;
double degrees(double radians) { return radians * 180.0 / kPi; }
double radians(double degrees) { return degrees * kPi / 180.0; }

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}
void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

Vec3 vec3_of(const Json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }

// The contract's fov_y for a view angle between the centers of the first and
// last of H rows: tan(fov_y/2) = tan(angle/2) * H/(H - 1).
double contract_fov_y(double angle, int rows) {
  return degrees(2.0 * std::atan(std::tan(radians(angle) / 2.0) * rows / (rows - 1.0)));
}

// --- the document, entity by entity ------------------------------------------

class NffEveryEntity : public ::testing::Test {
 protected:
  void SetUp() override { nff = read_nff_file(kNffDir / "every-entity.nff"); }
  const Json& doc() const { return nff.document; }
  NffScene nff;
};

TEST_F(NffEveryEntity, ViewBecomesRenderAndCamera) {
  const Json& r = doc().at("render");
  EXPECT_EQ(r.at("width").get<int>(), 64);
  EXPECT_EQ(r.at("height").get<int>(), 48);
  EXPECT_EQ(r.at("samples_per_pixel").get<int>(), 1);
  EXPECT_EQ(r.at("max_depth").get<int>(), 5);
  EXPECT_EQ(vec3_of(r.at("background")), Vec3(0.1, 0.2, 0.3));

  const Json& c = doc().at("camera");
  const Vec3 from(0, -10, 2), at(0, 0, 1), up(0, -2.55836e-17, 1);
  EXPECT_EQ(vec3_of(c.at("position")), from);
  EXPECT_EQ(vec3_of(c.at("look_at")), at);
  // up, orthogonalized against the view direction (Gram-Schmidt).
  const Vec3 d = normalize(at - from);
  const Vec3 u = normalize(up);
  const Vec3 expected_up = normalize(u - dot(u, d) * d);
  const Vec3 got_up = vec3_of(c.at("up"));
  EXPECT_NEAR(got_up.x, expected_up.x, 1e-15);
  EXPECT_NEAR(got_up.y, expected_up.y, 1e-15);
  EXPECT_NEAR(got_up.z, expected_up.z, 1e-15);
  EXPECT_NEAR(dot(got_up, d), 0.0, 1e-15);
  EXPECT_NEAR(c.at("fov_y").get<double>(), contract_fov_y(40, 48), 1e-12);
  EXPECT_EQ(nff.angle, 40.0);
}

TEST_F(NffEveryEntity, LightsGetTheSpdIntensityUnlessColored) {
  const Json& lights = doc().at("lights");
  ASSERT_EQ(lights.size(), 3u);  // two `l` and the ambient light
  const double gray = std::sqrt(2.0) / (2.0 * 2.0);
  EXPECT_EQ(lights[0].at("type"), "point");
  EXPECT_EQ(vec3_of(lights[0].at("position")), Vec3(5, -5, 10));
  EXPECT_EQ(lights[0].at("diffuse").get<double>(), gray);
  EXPECT_EQ(lights[0].at("specular").get<double>(), gray);
  EXPECT_FALSE(lights[0].contains("ambient"));  // 0, the default
  EXPECT_EQ(lights[1].at("type"), "point");
  EXPECT_EQ(vec3_of(lights[1].at("position")), Vec3(-5, -5, 10));
  EXPECT_EQ(vec3_of(lights[1].at("diffuse")), Vec3(0.9, 0.8, 0.7));
  EXPECT_EQ(vec3_of(lights[1].at("specular")), Vec3(0.9, 0.8, 0.7));
  EXPECT_EQ(lights[2], Json({{"type", "ambient"}, {"ambient", gray}}));
}

TEST_F(NffEveryEntity, MaterialsFollowTheMapping) {
  const Json& m = doc().at("materials");
  ASSERT_EQ(m.size(), 2u);
  // f 1 0.5 0.25 0.8 0.2 0.5 0 0
  const Json& f1 = m.at("f1");
  const Vec3 kd_rgb1 = 0.8 * Vec3(1, 0.5, 0.25);
  EXPECT_EQ(vec3_of(f1.at("ambient")), kd_rgb1);
  EXPECT_EQ(vec3_of(f1.at("diffuse")), kd_rgb1);
  EXPECT_EQ(f1.at("specular").get<double>(), 0.2);
  EXPECT_EQ(f1.at("shininess").get<double>(), 1.0);  // max(0.5, 1)
  EXPECT_EQ(f1.at("reflectivity").get<double>(), 0.2);
  EXPECT_EQ(f1.at("transparency").get<double>(), 0.0);
  EXPECT_FALSE(f1.contains("ior"));  // only when T > 0
  EXPECT_FALSE(f1.contains("fresnel"));
  // f 0.9 0.9 1 0.1 0.9 2.5e2 0.75 1.5
  const Json& f2 = m.at("f2");
  const Vec3 kd_rgb2 = 0.1 * Vec3(0.9, 0.9, 1);
  EXPECT_EQ(vec3_of(f2.at("ambient")), kd_rgb2);
  EXPECT_EQ(vec3_of(f2.at("diffuse")), kd_rgb2);
  EXPECT_EQ(f2.at("specular").get<double>(), 0.9);
  EXPECT_EQ(f2.at("shininess").get<double>(), 250.0);
  EXPECT_EQ(f2.at("reflectivity").get<double>(), 0.9);
  EXPECT_EQ(f2.at("transparency").get<double>(), 0.75);
  EXPECT_EQ(f2.at("ior").get<double>(), 1.5);
  EXPECT_EQ(f2.at("fresnel").get<bool>(), true);
}

TEST_F(NffEveryEntity, ObjectsInFileOrder) {
  const Json& o = doc().at("objects");
  ASSERT_EQ(o.size(), 6u);
  // Before the first f: no material (the default one); a negative radius read as |r|.
  EXPECT_EQ(o[0], Json({{"type", "sphere"}, {"center", {0.0, 0.0, 0.0}}, {"radius", 0.5}}));
  EXPECT_EQ(o[1], Json({{"type", "cone"},
                        {"base", {1.0, 0.0, 0.0}},
                        {"apex", {1.0, 0.0, 1.5}},
                        {"base_radius", 0.5},
                        {"apex_radius", 0.125},
                        {"caps", false},
                        {"material", "f1"}}));
  // Base and apex on the lines after `c`, both radii negative and equal: a cylinder.
  EXPECT_EQ(o[2], Json({{"type", "cylinder"},
                        {"base", {-1.0, 0.0, 0.0}},
                        {"apex", {-1.0, 0.0, 1.5}},
                        {"radius", 0.25},
                        {"caps", false},
                        {"material", "f1"}}));
  EXPECT_EQ(o[3], Json({{"type", "sphere"}, {"center", {0.0, 2.0, 0.5}}, {"radius", 0.75}, {"material", "f1"}}));
  EXPECT_EQ(o[4], Json({{"type", "polygon"},
                        {"vertices", {{-2.5, -1.0, 0.0}, {2.5, -1.0, 0.0}, {0.0, 10.0, 0.0}}},
                        {"material", "f2"}}));
  EXPECT_EQ(o[5], Json({{"type", "polygon"},
                        {"vertices", {{-1.0, -1.0, 3.0}, {1.0, -1.0, 3.0}, {1.0, 1.0, 3.0}, {-1.0, 1.0, 3.0}}},
                        {"normals", {{0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}, {0.0, 0.6, 0.8}, {0.0, 0.0, 1.0}}},
                        {"material", "f2"}}));
}

TEST_F(NffEveryEntity, RemembersWhereEachPartCameFrom) {
  auto where = [&](const std::string& path) {
    const NffOrigin& o = nff.origins.at(path);
    EXPECT_EQ(o.where.file, (kNffDir / "every-entity.nff").string());
    return std::make_pair(o.where.line, o.where.column);
  };
  EXPECT_EQ(where("camera.position"), std::make_pair(3, 1));  // the "from" line
  EXPECT_EQ(where("camera.up"), std::make_pair(5, 1));
  EXPECT_EQ(where("render.width"), std::make_pair(8, 1));
  EXPECT_EQ(where("render.background"), std::make_pair(9, 1));
  EXPECT_EQ(where("lights[1]"), std::make_pair(11, 1));
  EXPECT_EQ(where("materials.f2"), std::make_pair(22, 1));
  EXPECT_EQ(where("objects[0]"), std::make_pair(13, 1));
  EXPECT_EQ(where("objects[2]"), std::make_pair(18, 1));  // the `c` whose numbers follow on two lines
  EXPECT_EQ(where("objects[5]"), std::make_pair(27, 1));
  EXPECT_EQ(nff.origins.at("objects[5]").entity, "pp");
}

TEST_F(NffEveryEntity, JsonTextIsTheDocumentOnePartPerLine) {
  const NffJsonText text = nff_json_text(nff);
  EXPECT_EQ(Json::parse(text.text), doc());
  EXPECT_NO_THROW(json::parse(text.text, "x.json"));
  // Each object on a line of its own, named by line_paths.
  size_t objects = 0;
  for (size_t i = 0; i < text.line_paths.size(); ++i)
    if (text.line_paths[i].starts_with("objects[")) ++objects;
  EXPECT_EQ(objects, 6u);
}

// The scene load_scene builds from an NFF file's parts, and the scene of the
// JSON text `glint convert` writes for it: the same, value for value, and the
// same image to the bit.
void expect_same_scene(const Scene& a, const Scene& b) {
  auto same = [](const Vec3& x, const Vec3& y) { return x.x == y.x && x.y == y.y && x.z == y.z; };
  EXPECT_EQ(a.render.width, b.render.width);
  EXPECT_EQ(a.render.height, b.render.height);
  EXPECT_EQ(a.render.samples_per_pixel, b.render.samples_per_pixel);
  EXPECT_EQ(a.render.max_depth, b.render.max_depth);
  EXPECT_TRUE(same(a.render.background, b.render.background));
  EXPECT_TRUE(same(a.camera.position, b.camera.position));
  EXPECT_TRUE(same(a.camera.look_at, b.camera.look_at));
  EXPECT_TRUE(same(a.camera.up, b.camera.up));
  EXPECT_EQ(a.camera.fov_y, b.camera.fov_y);
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    SCOPED_TRACE("material " + std::to_string(i));
    const Material &x = a.materials[i], &y = b.materials[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_TRUE(same(x.ambient, y.ambient) && same(x.diffuse, y.diffuse) && same(x.specular, y.specular));
    EXPECT_TRUE(same(x.reflectivity, y.reflectivity));
    EXPECT_EQ(x.shininess, y.shininess);
    EXPECT_EQ(x.transparency, y.transparency);
    EXPECT_EQ(x.ior, y.ior);
    EXPECT_EQ(x.fresnel, y.fresnel);
  }
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (size_t i = 0; i < a.lights.size(); ++i) {
    SCOPED_TRACE("light " + std::to_string(i));
    const Light &x = a.lights[i], &y = b.lights[i];
    EXPECT_EQ(x.type, y.type);
    EXPECT_TRUE(same(x.position, y.position));
    EXPECT_TRUE(same(x.ambient, y.ambient) && same(x.diffuse, y.diffuse) && same(x.specular, y.specular));
    EXPECT_TRUE(same(x.attenuation, y.attenuation));
  }
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].type, b.objects[i].type) << i;
    EXPECT_EQ(a.objects[i].shape, b.objects[i].shape) << i;
    EXPECT_EQ(a.objects[i].material, b.objects[i].material) << i;
    EXPECT_EQ(a.objects[i].transform, b.objects[i].transform) << i;
  }
  ASSERT_EQ(a.spheres.size(), b.spheres.size());
  for (size_t i = 0; i < a.spheres.size(); ++i)
    EXPECT_TRUE(same(a.spheres[i].center, b.spheres[i].center) && a.spheres[i].radius == b.spheres[i].radius) << i;
  ASSERT_EQ(a.cones.size(), b.cones.size());
  for (size_t i = 0; i < a.cones.size(); ++i)
    EXPECT_TRUE(same(a.cones[i].base, b.cones[i].base) && same(a.cones[i].apex, b.cones[i].apex) &&
                a.cones[i].base_radius == b.cones[i].base_radius && a.cones[i].apex_radius == b.cones[i].apex_radius &&
                a.cones[i].caps == b.cones[i].caps)
        << i;
  ASSERT_EQ(a.polygons.size(), b.polygons.size());
  for (size_t i = 0; i < a.polygons.size(); ++i) {
    ASSERT_EQ(a.polygons[i].vertices.size(), b.polygons[i].vertices.size()) << i;
    for (size_t k = 0; k < a.polygons[i].vertices.size(); ++k)
      EXPECT_TRUE(same(a.polygons[i].vertices[k], b.polygons[i].vertices[k])) << i;
    ASSERT_EQ(a.polygons[i].normals.size(), b.polygons[i].normals.size()) << i;
    for (size_t k = 0; k < a.polygons[i].normals.size(); ++k)
      EXPECT_TRUE(same(a.polygons[i].normals[k], b.polygons[i].normals[k])) << i;
    EXPECT_EQ(a.polygons[i].triangles, b.polygons[i].triangles) << i;
  }
}

TEST(Nff, SceneIsTheConvertedJsonsScene) {
  for (const fs::path& file : {kNffDir / "every-entity.nff", kNffDir / "spheres.nff", kNffDir / "glass-sphere.nff",
                               kSpdDir / "balls.nff", kSpdDir / "tetra.nff"}) {
    SCOPED_TRACE(file.string());
    const NffScene nff = read_nff_file(file);
    Scene direct = load_scene(file);
    Scene converted = parse_scene(nff_json_text(nff).text, "x.json");
    EXPECT_EQ(direct.camera.row_center_angle, nff.angle);
    converted.camera.row_center_angle = nff.angle;  // what `glint render` of an NFF file sets
    expect_same_scene(direct, converted);
    for (Scene* s : {&direct, &converted}) s->render.width = s->render.height = 48;
    const Image a = render_image(direct, *build_accelerator(direct), {});
    const Image b = render_image(converted, *build_accelerator(converted), {});
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
  }
}

TEST(Nff, ReadsExponentsSignsAndLayouts) {
  // Numbers with exponents, a leading '+', CRLF line ends, tabs, a comment
  // at the end of a line, and a view written on one line.
  const NffScene s = read_nff(
      "v from 0 0 1e1 at 0 0 0 up 0 1 0 angle 4.5E1 hither 1 resolution 3 2\r\n"
      "s\t+1.5e-1 -2.55836e-17 0 .5 # a comment\r\n",
      "x.nff");
  const Json& o = s.document.at("objects").at(0);
  EXPECT_EQ(vec3_of(o.at("center")), Vec3(0.15, -2.55836e-17, 0));
  EXPECT_EQ(o.at("radius").get<double>(), 0.5);
  EXPECT_EQ(vec3_of(s.document.at("camera").at("position")), Vec3(0, 0, 10));
  EXPECT_EQ(s.angle, 45.0);
  EXPECT_FALSE(s.document.contains("lights"));  // no `l`: no lights at all, not even ambient
  EXPECT_FALSE(s.document.contains("materials"));
  EXPECT_EQ(vec3_of(s.document.at("render").at("background")), Vec3(0, 0, 0));
}

TEST(Nff, OneLightGetsHalfIntensity) {
  const NffScene s = read_nff("v from 0 0 1 at 0 0 0 up 0 1 0 angle 45 hither 1 resolution 3 2\nl 1 2 3\n", "x.nff");
  const Json& lights = s.document.at("lights");
  ASSERT_EQ(lights.size(), 2u);
  EXPECT_EQ(lights[0].at("diffuse").get<double>(), 0.5);  // sqrt(1)/(2*1)
  EXPECT_EQ(lights[1].at("ambient").get<double>(), 0.5);
}

TEST(Nff, ExtensionIsCaseInsensitive) {
  EXPECT_TRUE(is_nff_path("a/b.nff"));
  EXPECT_TRUE(is_nff_path("B.NFF"));
  EXPECT_TRUE(is_nff_path("c.Nff"));
  EXPECT_FALSE(is_nff_path("c.json"));
  EXPECT_FALSE(is_nff_path("nff"));
}

// --- errors --------------------------------------------------------------------

// Seven lines: a valid view.
const std::string kView = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 6\n";

struct ErrorCase {
  std::string text;
  int line, column;
  std::string message;  // the whole message after "t.nff:line:col: "
};

void expect_nff_error(const ErrorCase& c) {
  SCOPED_TRACE(c.text);
  try {
    read_nff(c.text, "t.nff");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.location().file, "t.nff");
    EXPECT_EQ(e.location().line, c.line);
    EXPECT_EQ(e.location().column, c.column);
    EXPECT_EQ(e.message(), c.message);
    EXPECT_EQ(std::string(e.what()),
              "t.nff:" + std::to_string(c.line) + ":" + std::to_string(c.column) + ": " + c.message);
  }
}

TEST(NffErrors, UnknownEntities) {
  expect_nff_error({kView + "x 1 2 3\n", 8, 1, "unknown entity \"x\" (expected v, b, l, f, c, s, p or pp)"});
  expect_nff_error({kView + "tpp 3\n", 8, 1, "unknown entity \"tpp\" (expected v, b, l, f, c, s, p or pp)"});
  expect_nff_error(
      {"\xEF\xBB\xBF"
       "sphere 1\n",
       1, 1, "unknown entity \"sphere\" (expected v, b, l, f, c, s, p or pp)"});
  expect_nff_error({kView + "  \t q\n", 8, 5, "unknown entity \"q\" (expected v, b, l, f, c, s, p or pp)"});
  // A control byte or broken UTF-8 is shown escaped.
  expect_nff_error({kView + "\x01\xFF\n", 8, 1, "unknown entity \"\\x01\\xFF\" (expected v, b, l, f, c, s, p or pp)"});
}

TEST(NffErrors, MalformedNumbers) {
  expect_nff_error({kView + "s 0 0 abc 1\n", 8, 7, "s: expected a number (center z), got \"abc\""});
  expect_nff_error({kView + "s 0 0 1.2.3 1\n", 8, 7, "s: expected a number (center z), got \"1.2.3\""});
  expect_nff_error({kView + "s 0 0 1e 1\n", 8, 7, "s: expected a number (center z), got \"1e\""});
  expect_nff_error({kView + "s 0 0 +-1 1\n", 8, 7, "s: expected a number (center z), got \"+-1\""});
  expect_nff_error({kView + "s 0 0 0x10 1\n", 8, 7, "s: expected a number (center z), got \"0x10\""});
  expect_nff_error(
      {kView + "s 0 0 0 1" + std::string(1, '\0') + "\n", 8, 9, "s: expected a number (radius), got \"1\\x00\""});
  expect_nff_error({kView + "s 0 nan 0 1\n", 8, 5, "s: center y must be a finite number, got \"nan\""});
  expect_nff_error({kView + "s 0 0 0 -inf\n", 8, 9, "s: radius must be a finite number, got \"-inf\""});
  expect_nff_error({kView + "s 0 0 0 1e999\n", 8, 9, "s: radius: the number \"1e999\" is out of range"});
  expect_nff_error({kView + "b 0 0 x\n", 8, 7, "b: expected a number (background blue), got \"x\""});
  expect_nff_error({kView + "f 1 1 1 1 0 10 0 q\n", 8, 18, "f: expected a number (index of refraction), got \"q\""});
}

TEST(NffErrors, MissingOrRepeatedView) {
  expect_nff_error({"s 0 0 0 1\n", 2, 1, "no view: an NFF file needs a \"v\" entity (the camera)"});
  expect_nff_error({"", 1, 1, "no view: an NFF file needs a \"v\" entity (the camera)"});
  expect_nff_error({"# only a comment", 1, 17, "no view: an NFF file needs a \"v\" entity (the camera)"});
  expect_nff_error({kView + kView, 8, 1, "v: a second view (an NFF file has one \"v\")"});
  expect_nff_error({"b 0 0 0\nb 1 1 1\n" + kView, 2, 1, "b: a second background (an NFF file has at most one \"b\")"});
}

TEST(NffErrors, MalformedView) {
  expect_nff_error({"v\n", 1, 1, "v: the file ends before its \"from\" line"});
  expect_nff_error({"v\nat 0 0 0\n", 2, 1, "v: expected \"from\", got \"at\""});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nresolution 8 6\n", 6, 1,
                    "v: expected \"hither\", got \"resolution\""});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 0\nhither 1\nresolution 8 6\n", 5, 7,
                    "v: angle must be between 0 and 180 degrees, exclusive (got 0)"});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 180\nhither 1\nresolution 8 6\n", 5, 7,
                    "v: angle must be between 0 and 180 degrees, exclusive (got 180)"});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 5\nup 0 1 0\nangle 40\nhither 1\nresolution 8 6\n", 3, 1,
                    "v: \"at\" must differ from \"from\" (the view needs a direction)"});
  expect_nff_error({"v\nfrom -1e308 0 0\nat 1e308 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 6\n", 3, 1,
                    "v: \"at\" is too far from \"from\" (the distance overflows)"});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 0\nup 0 0 -3\nangle 40\nhither 1\nresolution 8 6\n", 4, 1,
                    "v: up is parallel to the view direction"});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 0\nup 0 0 0\nangle 40\nhither 1\nresolution 8 6\n", 4, 1,
                    "v: up must be a non-zero vector"});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 0 6\n", 7, 12,
                    "v: resolution width must be between 1 and 1048576 (got 0)"});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 -6\n", 7, 14,
                    "v: resolution height must be between 1 and 1048576 (got -6)"});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 2.5\n", 7, 14,
                    "v: expected a whole number (resolution height), got \"2.5\""});
  expect_nff_error({"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 99999999999999999999\n", 7, 14,
                    "v: resolution height \"99999999999999999999\" is out of range (at most 1048576)"});
}

TEST(NffErrors, TruncatedEntities) {
  expect_nff_error({kView + "s 0 0\n", 8, 1, "s: the file ends before its center z"});
  expect_nff_error({kView + "l 1 2 3 0.5\n", 8, 1, "l: the file ends before its color green"});
  expect_nff_error({kView + "l 1 2 3 0.5 x\n", 8, 13, "l: expected a number (color green), got \"x\""});
  expect_nff_error({kView + "f 1 1 1 0.5 0.5\n", 8, 1, "f: the file ends before its Shine"});
  expect_nff_error({kView + "c 0 0 0 1 0 0 1\ns 0 0 0 1\n", 9, 1, "c: expected a number (apex radius), got \"s\""});
  expect_nff_error({kView + "c\n0 0 0 1\n0 0 1\n", 8, 1, "c: the file ends before its apex radius"});
  expect_nff_error({kView + "p 3\n0 0 0\n1 0 0\n", 8, 1, "p: the file ends before its vertex 3 of 3 x"});
  expect_nff_error({kView + "pp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0\n", 8, 1,
                    "pp: the file ends before its vertex 3 of 3 normal z"});
  // A count smaller than the vertex lines that follow: the extra line is no entity.
  expect_nff_error({kView + "p 3\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n", 12, 1,
                    "expected an entity (v, b, l, f, c, s, p or pp), got the number \"0\" (more numbers than the "
                    "entity before it takes?)"});
}

TEST(NffErrors, BadCounts) {
  const std::string range = "p: vertex count must be between 3 and 16777216";
  expect_nff_error({kView + "p 0\n", 8, 3, range + " (got 0)"});
  expect_nff_error({kView + "p -3\n", 8, 3, range + " (got -3)"});
  expect_nff_error({kView + "p 2\n0 0 0\n1 0 0\n", 8, 3, range + " (got 2)"});
  expect_nff_error({kView + "p 16777217\n", 8, 3, range + " (got 16777217)"});
  expect_nff_error({kView + "pp 99999999999999999999\n", 8, 4,
                    "pp: vertex count \"99999999999999999999\" is out of range (at most 16777216)"});
  expect_nff_error({kView + "p 3.0\n", 8, 3, "p: expected a whole number (vertex count), got \"3.0\""});
  expect_nff_error({kView + "p three\n", 8, 3, "p: expected a whole number (vertex count), got \"three\""});
  expect_nff_error({kView + "p\n", 8, 1, "p: the file ends before its vertex count"});
  // A huge count in a small file: an error at the end, nothing allocated for it.
  expect_nff_error({kView + "p 16777216\n0 0 0\n", 8, 1, "p: the file ends before its vertex 2 of 16777216 x"});
}

TEST(NffErrors, PositionsCountBytesAndLines) {
  // CRLF counts like LF; a tab is one column; a BOM is not counted.
  std::string crlf = kView;
  for (size_t at = 0; (at = crlf.find('\n', at)) != std::string::npos; at += 2) crlf.replace(at, 1, "\r\n");
  expect_nff_error({crlf + "s 0 0 0 zz\r\n", 8, 9, "s: expected a number (radius), got \"zz\""});
  expect_nff_error({"\xEF\xBB\xBF" + kView + "s\t0 0 0 zz\n", 8, 9, "s: expected a number (radius), got \"zz\""});
}

// Loader errors in the converted document, at the NFF entity that made them.
class NffLoaderErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("glint-nff-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // load_scene's one error and validate_scene's list on `text` as t.nff.
  std::string load_error(const std::string& text) {
    write_text(dir_ / "t.nff", text);
    try {
      load_scene(dir_ / "t.nff");
    } catch (const Error& e) {
      return relative(e.what());
    }
    return "no error";
  }
  std::vector<std::string> validate_errors(const std::string& text) {
    write_text(dir_ / "t.nff", text);
    std::vector<std::string> out;
    for (const Error& e : validate_scene(dir_ / "t.nff")) out.push_back(relative(e.what()));
    return out;
  }
  std::string relative(const std::string& what) const {
    const std::string prefix = (dir_ / "").string();
    return what.starts_with(prefix) ? what.substr(prefix.size()) : what;
  }
  fs::path dir_;
};

TEST_F(NffLoaderErrors, ReportedAtTheEntity) {
  EXPECT_EQ(load_error(kView + "s 0 0 0 0\n"), "t.nff:8:1: s: radius: must be > 0 (got 0)");
  EXPECT_EQ(load_error(kView + "l 0 5 5 -1 0 0\n"), "t.nff:8:1: l: diffuse: color components must be >= 0");
  EXPECT_EQ(load_error(kView + "f 1 1 1 -0.5 0 1 0 1\n"), "t.nff:8:1: f: ambient: color components must be >= 0");
  EXPECT_EQ(load_error(kView + "f 1 1 1 0.5 -0.2 1 0 1\n"), "t.nff:8:1: f: specular: color components must be >= 0");
  EXPECT_EQ(load_error(kView + "f 1 1 1 0.5 0 1 -0.5 1\n"), "t.nff:8:1: f: transparency: must be >= 0 (got -0.5)");
  EXPECT_EQ(load_error(kView + "f 1 1 1 0.5 0 1 0.5 0\n"), "t.nff:8:1: f: ior: must be > 0 (got 0)");
  EXPECT_EQ(load_error("b -1 0 0\n" + kView), "t.nff:1:1: b: color components must be >= 0");
  // An image the machine cannot hold: at the resolution line.
  const std::string huge = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 1048576 1048576\n";
  const std::string error = load_error(huge);
  EXPECT_TRUE(error.starts_with("t.nff:7:1: v: resolution: image of 1048576x1048576 pixels ")) << error;
}

TEST_F(NffLoaderErrors, TheJsonLoadersWordsAtTheEntity) {
  // load_scene builds an NFF scene itself; the JSON text of `glint convert`
  // goes through the JSON loader. Each problem the loader finds in that text,
  // translated to the entity (nff_error), is the error load_scene gives.
  const std::string huge = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 1048576 1048576\n";
  for (const std::string& text : {kView + "s 0 0 0 0\n",
                                  kView + "s 1 2 3 -0\n",
                                  kView + "l 0 5 5 -1 0 0\n",
                                  kView + "l 0 5 5 1 0 -1\n",
                                  kView + "f 1 1 1 -0.5 0 1 0 1\n",
                                  kView + "f 1 1 1 0.5 -0.2 1 0 1\n",
                                  kView + "f 1 1 1 0.5 0 1 -0.5 1\n",
                                  kView + "f 1 1 1 0.5 0 1 0.5 0\n",
                                  kView + "f 1 1 1 0.5 0 1 0.5 -2\n",
                                  "b -1 0 0\n" + kView,
                                  "b 0 -0.5 0\n" + kView,
                                  huge,
                                  kView + "s 0 0 0 1\np 3\n0 0 0\n1 0 0\n2 0 0\n",
                                  kView + "p 4\n0 0 0\n1 1 0\n1 0 0\n0 1 0\n",
                                  kView + "pp 3\n0 0 0 0 0 0\n1 0 0 0 0 1\n0 1 0 0 0 1\n",
                                  kView + "pp 3\n0 0 0 0 0 1\n1 0 0 0 0 -1\n0 1 0 0 0 1\n",
                                  kView + "c\n0 0 0 1\n0 0 0 0.5\n",
                                  kView + "c 0 0 0 0 0 0 1 0\n",
                                  kView + "c\n1e308 0 0 1\n-1e308 0 0 1\n",
                                  kView + "c 0 0 0 1 0 0 1 0\np 3 0 0 0 1 0 0 0 1 0\n"}) {
    SCOPED_TRACE(text);
    const NffScene nff = read_nff(text, (dir_ / "t.nff").string());
    const NffJsonText json = nff_json_text(nff);
    std::string expected = "no error";
    try {
      parse_scene(json.text, (dir_ / "t.json").string());
    } catch (const Error& e) {
      expected = relative(nff_error(nff, json, e).what());
    }
    EXPECT_EQ(load_error(text), expected);
  }
  // Kd times a color beyond a double: the JSON text can only write null there.
  EXPECT_EQ(load_error(kView + "f 1e300 1 1 1e300 0 1 0 1\n"), "t.nff:8:1: f: ambient[0]: must be a finite number");
}

TEST_F(NffLoaderErrors, ShapesReportedAtTheirEntity) {
  // The loader's own wording after "<entity>: <key>: ", at the entity's line.
  auto starts = [](const std::string& s, const std::string& prefix) { return s.starts_with(prefix); };
  std::string e = load_error(kView + "s 0 0 0 1\np 3\n0 0 0\n1 0 0\n2 0 0\n");
  EXPECT_TRUE(starts(e, "t.nff:9:1: p: vertices: ")) << e;
  e = load_error(kView + "p 4\n0 0 0\n1 1 0\n1 0 0\n0 1 0\n");
  EXPECT_TRUE(starts(e, "t.nff:8:1: p: vertices: ")) << e;
  e = load_error(kView + "pp 3\n0 0 0 0 0 0\n1 0 0 0 0 1\n0 1 0 0 0 1\n");
  EXPECT_TRUE(starts(e, "t.nff:8:1: pp: normals")) << e;
  e = load_error(kView + "c\n0 0 0 1\n0 0 0 0.5\n");
  EXPECT_TRUE(starts(e, "t.nff:8:1: c: apex: ")) << e;
  e = load_error(kView + "c 0 0 0 0 0 0 1 0\n");
  EXPECT_EQ(e, "t.nff:8:1: c: radius: must be > 0 (got 0)");
  EXPECT_EQ(load_error(kView + "c 0 0 0 1 0 0 1 0\np 3 0 0 0 1 0 0 0 1 0\n"), "no error");
}

TEST_F(NffLoaderErrors, ValidateListsEveryOneBySection) {
  const std::vector<std::string> errors =
      validate_errors(kView + "f 1 1 1 0.5 0 1 0.5 0\ns 0 0 0 1\ns 0 0 0 -0\nl 0 5 5 -1 0 0\n");
  EXPECT_EQ(errors, (std::vector<std::string>{"t.nff:8:1: f: ior: must be > 0 (got 0)",
                                              "t.nff:11:1: l: diffuse: color components must be >= 0",
                                              "t.nff:10:1: s: radius: must be > 0 (got 0)"}));
  EXPECT_EQ(validate_errors(kView + "s 0 0 0 1\n"), std::vector<std::string>{});
  EXPECT_EQ(validate_errors(kView + "s 0 0 0 1 2\n"),
            std::vector<std::string>{"t.nff:8:11: expected an entity (v, b, l, f, c, s, p or pp), got the number "
                                     "\"2\" (more numbers than the entity before it takes?)"});
  EXPECT_EQ(relative(validate_scene(dir_ / "missing.nff").at(0).what()).find("missing.nff: cannot read: "), 0u);
}

// --- the view follows the rendered height ---------------------------------------

// Angle, degrees, between the camera rays through the centers of the first
// and last pixel rows (middle of the image across).
double row_center_span(const Camera& camera, int width, int height) {
  const CameraFrame f = make_camera_frame(camera, width, height);
  const Ray top = generate_camera_ray(f, 0.5, 0.5 / height);
  const Ray bottom = generate_camera_ray(f, 0.5, (height - 0.5) / height);
  return degrees(std::acos(std::clamp(dot(normalize(top.direction), normalize(bottom.direction)), -1.0, 1.0)));
}

TEST(NffView, FovFollowsTheRenderedHeight) {
  const Scene scene = load_scene(kNffDir / "spheres.nff");
  ASSERT_TRUE(scene.camera.row_center_angle.has_value());
  EXPECT_EQ(*scene.camera.row_center_angle, 35.0);
  EXPECT_NEAR(scene.camera.fov_y, contract_fov_y(35, 40), 1e-12);  // the file's own 40 rows
  for (const int h : {40, 2, 7, 513, 1000}) {
    SCOPED_TRACE(h);
    EXPECT_NEAR(camera_fov_y(scene.camera, h), contract_fov_y(35, h), 1e-12);
    EXPECT_NEAR(row_center_span(scene.camera, 48, h), 35.0, 1e-9);
    EXPECT_NEAR(row_center_span(scene.camera, 3 * h, h), 35.0, 1e-9);  // whatever the width
  }
  EXPECT_EQ(camera_fov_y(scene.camera, 1), 35.0);  // one row has no span: edge to edge
  // A JSON camera keeps its fov_y whatever the height.
  Camera json_camera = scene.camera;
  json_camera.row_center_angle.reset();
  EXPECT_EQ(camera_fov_y(json_camera, 513), json_camera.fov_y);
}

TEST(NffView, ImageXRunsAlongViewCrossUp) {
  // Right-handed: with +z up and the eye on -y looking at the origin, +x is to the right.
  const Scene scene = load_scene(kNffDir / "spheres.nff");
  const CameraFrame f = make_camera_frame(scene.camera, 48, 40);
  const Vec3 d = normalize(scene.camera.look_at - scene.camera.position);
  const Vec3 right = normalize(cross(d, Vec3(0, 0, 1)));
  EXPECT_NEAR(dot(f.right, right), 1.0, 1e-12);
  EXPECT_GT(f.right.x, 0.0);
}

// --- ray counts by hand ------------------------------------------------------------

RayStats render_counts(const fs::path& file, int max_depth = 0, Image* image = nullptr) {
  Scene scene = load_scene(file);
  if (max_depth) scene.render.max_depth = max_depth;
  const auto accel = build_accelerator(scene);
  RenderStats stats;
  Image out = render_image(scene, *accel, {}, &stats);
  if (image) *image = std::move(out);
  return stats.rays;
}

TEST(NffRayCounts, MirrorSphereSeenByFourPixels) {
  Image image;
  const RayStats rays = render_counts(kNffDir / "one-sphere.nff", 0, &image);
  EXPECT_EQ(rays.camera, 16u);
  EXPECT_EQ(rays.camera_hits, 4u);  // the middle 2x2 pixels
  EXPECT_EQ(rays.shadow, 4u);       // one per hit, toward the one light (the ambient one casts none)
  EXPECT_EQ(rays.reflection, 4u);   // Ks 0.5: one mirror ray per hit, which leaves the sphere
  EXPECT_EQ(rays.refraction, 0u);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      const bool middle = (x == 1 || x == 2) && (y == 1 || y == 2);
      EXPECT_EQ(image.pixel(x, y)[0] > 0.0f, middle) << x << "," << y;  // black background elsewhere
    }
}

TEST(NffRayCounts, GlassSphereAtDepthTwo) {
  const RayStats rays = render_counts(kNffDir / "glass-sphere.nff", 2);
  EXPECT_EQ(rays.camera, 16u);
  EXPECT_EQ(rays.camera_hits, 4u);
  EXPECT_EQ(rays.reflection, 4u);  // fresnel: a transmitting surface reflects too, though Ks is 0
  EXPECT_EQ(rays.refraction, 4u);
  // The 4 hits, and the 4 refracted rays' hits on the far side from inside,
  // whose normal (turned toward the ray) faces the light behind the camera.
  EXPECT_EQ(rays.shadow, 8u);
}

// --- the command line -----------------------------------------------------------------

class NffCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    work_ =
        fs::temp_directory_path() / ("glint-nff-cli-" + std::string(info->name()) + "-" + std::to_string(::getpid()));
    fs::remove_all(work_);
    fs::create_directories(work_);
    for (const char* name : {"spheres.nff", "one-sphere.nff"}) fs::copy_file(kNffDir / name, work_ / name);
  }
  void TearDown() override { fs::remove_all(work_); }

  // Runs `glint ARGS` in the work folder; returns the exit code, stderr in `err`.
  int run(const std::string& args, std::string* err = nullptr) const {
    const std::string command = "cd '" + work_.string() + "' && '" + GLINT_CLI_PATH + "' " + args + " 2>stderr.txt";
    const int status = std::system(command.c_str());
    if (err) *err = read_text(work_ / "stderr.txt");
    fs::remove(work_ / "stderr.txt");
    return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  fs::path work_;
};

TEST_F(NffCli, ConvertWritesJsonThatRendersIdenticallyForEveryEntity) {
  // Cones, cylinders, polygons with and without normals, glass and the default material.
  std::string err;
  fs::copy_file(kNffDir / "every-entity.nff", work_ / "every-entity.nff");
  ASSERT_EQ(run("convert every-entity.nff -o every-entity.json", &err), 0) << err;
  EXPECT_EQ(Json::parse(read_text(work_ / "every-entity.json")), read_nff_file(kNffDir / "every-entity.nff").document);
  ASSERT_EQ(run("render every-entity.nff -o a.pfm -q", &err), 0) << err;
  ASSERT_EQ(run("render every-entity.json -o b.pfm -q", &err), 0) << err;
  EXPECT_EQ(read_text(work_ / "a.pfm"), read_text(work_ / "b.pfm"));
  const Image image = read_image(work_ / "a.pfm");
  EXPECT_EQ(image.width, 64);
  EXPECT_EQ(image.height, 48);
}

TEST_F(NffCli, ConvertWritesJsonThatRendersIdentically) {
  std::string err;
  ASSERT_EQ(run("convert spheres.nff -o spheres.json", &err), 0) << err;
  EXPECT_EQ(err, "");
  const Json doc = Json::parse(read_text(work_ / "spheres.json"));
  EXPECT_NEAR(doc.at("camera").at("fov_y").get<double>(), contract_fov_y(35, 40), 1e-12);
  EXPECT_EQ(doc, read_nff_file(work_ / "spheres.nff").document);
  ASSERT_EQ(run("render spheres.nff -o a.pfm -q", &err), 0) << err;
  ASSERT_EQ(run("render spheres.json -o b.pfm -q", &err), 0) << err;
  EXPECT_EQ(read_text(work_ / "a.pfm"), read_text(work_ / "b.pfm"));
  EXPECT_EQ(read_image(work_ / "a.pfm").width, 48);
  // Another height: the NFF keeps its view (the JSON, a fixed fov_y, does not).
  ASSERT_EQ(run("render spheres.nff -o c.pfm -q --height 81 --width 97", &err), 0) << err;
  Scene scene = load_scene(work_ / "spheres.nff");
  scene.render.width = 97;
  scene.render.height = 81;
  const auto accel = build_accelerator(scene);
  const Image expected = render_image(scene, *accel);
  EXPECT_EQ(read_image(work_ / "c.pfm").rgb, expected.rgb);
}

TEST_F(NffCli, ExplainFollowsTheHeightToo) {
  std::string err;
  const std::string top = "explain spheres.nff --json --width 97 --height 81 --pixel 48 0 > top.json";
  const std::string bottom = "explain spheres.nff --json --width 97 --height 81 --pixel 48 80 > bottom.json";
  ASSERT_EQ(run(top, &err), 0) << err;
  ASSERT_EQ(run(bottom, &err), 0) << err;
  const Vec3 a = vec3_of(Json::parse(read_text(work_ / "top.json")).at("ray").at("direction"));
  const Vec3 b = vec3_of(Json::parse(read_text(work_ / "bottom.json")).at("ray").at("direction"));
  EXPECT_NEAR(degrees(std::acos(dot(normalize(a), normalize(b)))), 35.0, 1e-9);
}

TEST_F(NffCli, ConvertRefusesBadInputAndWritesNothing) {
  std::string err;
  write_text(work_ / "bad.nff", kView + "s 0 0 0 0\n");
  EXPECT_EQ(run("convert bad.nff -o bad.json", &err), 1);
  EXPECT_EQ(err, "error: bad.nff:8:1: s: radius: must be > 0 (got 0)\n");
  EXPECT_FALSE(fs::exists(work_ / "bad.json"));
  write_text(work_ / "bad2.nff", kView + "s 0 0 0 q\n");
  EXPECT_EQ(run("convert bad2.nff -o bad.json", &err), 1);
  EXPECT_EQ(err, "error: bad2.nff:8:9: s: expected a number (radius), got \"q\"\n");
  EXPECT_EQ(run("convert spheres.nff -o out.png", &err), 1);
  EXPECT_EQ(err, "error: out.png: convert writes glint JSON: the output must end in .json\n");
  EXPECT_EQ(run("convert spheres.json -o out.json", &err), 1);
  EXPECT_EQ(err, "error: spheres.json: convert reads NFF scenes (.nff)\n");
  EXPECT_EQ(run("convert spheres.nff -o nowhere/out.json", &err), 1);
  EXPECT_EQ(err, "error: nowhere/out.json: output folder nowhere does not exist\n");
  // An existing output is replaced only by a complete file.
  write_text(work_ / "keep.json", "precious");
  EXPECT_EQ(run("convert bad.nff -o keep.json", &err), 1);
  EXPECT_EQ(read_text(work_ / "keep.json"), "precious");
}

TEST_F(NffCli, StatsJsonHasTheSpdCountsAndPhaseTimes) {
  std::string err;
  ASSERT_EQ(run("render one-sphere.nff -o out.pfm --stats-json stats.json", &err), 0) << err;
  // The stats line names the hits too.
  EXPECT_NE(err.find("rays: 16 camera, 4 shadow, 4 reflection, 0 refraction; 4 camera rays hit; "), std::string::npos)
      << err;
  const Json stats = Json::parse(read_text(work_ / "stats.json"));
  EXPECT_EQ(stats.at("scene"), "one-sphere.nff");
  EXPECT_EQ(stats.at("output"), "out.pfm");
  EXPECT_EQ(stats.at("width"), 4);
  EXPECT_EQ(stats.at("height"), 4);
  EXPECT_EQ(stats.at("max_depth"), 5);
  EXPECT_EQ(stats.at("samples_per_pixel"), 1);
  const Json& rays = stats.at("rays");
  EXPECT_EQ(rays.at("camera"), 16);
  EXPECT_EQ(rays.at("camera_hits"), 4);
  EXPECT_EQ(rays.at("shadow"), 4);
  EXPECT_EQ(rays.at("reflection"), 4);
  EXPECT_EQ(rays.at("refraction"), 0);
  EXPECT_EQ(rays.at("total"), 24);
  for (const char* phase : {"load", "build", "render", "write", "total"})
    EXPECT_GE(stats.at("seconds").at(phase).get<double>(), 0.0) << phase;
  // Quiet renders write it too; overrides show in it.
  ASSERT_EQ(run("render one-sphere.nff -o out.pfm -q --width 8 --height 8 --stats-json stats.json", &err), 0) << err;
  EXPECT_EQ(err, "");
  EXPECT_EQ(Json::parse(read_text(work_ / "stats.json")).at("rays").at("camera"), 64);
  // A folder that does not exist: an error before rendering, no output.
  EXPECT_EQ(run("render one-sphere.nff -o new.pfm --stats-json nowhere/stats.json", &err), 1);
  EXPECT_EQ(err, "error: nowhere/stats.json: --stats-json folder nowhere does not exist\n");
  EXPECT_FALSE(fs::exists(work_ / "new.pfm"));
}

TEST_F(NffCli, ValidateAndInfoReadNff) {
  std::string err;
  EXPECT_EQ(run("validate spheres.nff > out.txt", &err), 0) << err;
  EXPECT_EQ(read_text(work_ / "out.txt"), "spheres.nff: valid\n");
  fs::copy_file(work_ / "spheres.nff", work_ / "UPPER.NFF");
  EXPECT_EQ(run("info UPPER.NFF > out.txt", &err), 0) << err;
  EXPECT_NE(read_text(work_ / "out.txt").find("objects    4: 4 spheres"), std::string::npos);
  write_text(work_ / "bad.nff", kView + "s 0 0 0 0\nl 1 1 1 -1 -1 -1\n");
  EXPECT_EQ(run("validate bad.nff", &err), 1);
  EXPECT_EQ(err,
            "error: bad.nff:9:1: l: diffuse: color components must be >= 0\n"
            "error: bad.nff:8:1: s: radius: must be > 0 (got 0)\n");
}

TEST(NffApi, SceneLoadReadsNff) {
  // The public API's Scene::load takes NFF too; its document is the reader's.
  const glint::api::Scene scene = glint::api::Scene::load(kNffDir / "spheres.nff");
  EXPECT_EQ(Json::parse(scene.to_json()), read_nff_file(kNffDir / "spheres.nff").document);
  EXPECT_NEAR(std::stod(scene.get("camera.fov_y")), contract_fov_y(35, 40), 1e-12);
  const Scene internal = load_scene(kNffDir / "spheres.nff");
  const auto accel = build_accelerator(internal);
  EXPECT_EQ(glint::api::render(scene).image.rgb, render_image(internal, *accel).rgb);
}

// --- the SPD scenes, against their published statistics ---------------------------

struct Published {
  const char* file;
  uint64_t camera_hits, reflection, refraction, shadow;
};

// Renders an SPD scene as the SPD statistics count it: 513 x 513 eye rays
// (one through each corner of the 512 x 512 grid), depth 5, one sample.
// Skipped while glint's loader knows no polygons.
std::optional<RayStats> spd_counts(const char* file, Image* image = nullptr) {
  Scene scene;
  try {
    scene = load_scene(kSpdDir / file);
  } catch (const Error& e) {
    if (std::string(e.what()).find("unknown object type \"polygon\"") != std::string::npos) return std::nullopt;
    throw;
  }
  scene.render.width = scene.render.height = 513;
  scene.render.max_depth = 5;
  scene.render.samples_per_pixel = 1;
  const auto accel = build_accelerator(scene);
  RenderStats stats;
  Image out = render_image(scene, *accel, {}, &stats);
  if (image) *image = std::move(out);
  return stats.rays;
}

TEST(NffSpd, RayCountsWithinTenPercentOfPublished) {
  // The SPD README's table (bench/spd/README.md, docs/nff.md).
  for (const Published& p :
       {Published{"balls.nff", 263169, 175095, 0, 954368}, Published{"tetra.nff", 49788, 0, 0, 46112}}) {
    SCOPED_TRACE(p.file);
    const std::optional<RayStats> rays = spd_counts(p.file);
    if (!rays) GTEST_SKIP() << "polygons do not load yet";
    EXPECT_EQ(rays->camera, 513u * 513u);
    auto near = [](uint64_t ours, uint64_t published) {
      return published == 0 ? ours == 0 : std::abs(double(ours) - double(published)) <= 0.1 * double(published);
    };
    EXPECT_TRUE(near(rays->camera_hits, p.camera_hits)) << rays->camera_hits << " vs " << p.camera_hits;
    EXPECT_TRUE(near(rays->reflection, p.reflection)) << rays->reflection << " vs " << p.reflection;
    EXPECT_TRUE(near(rays->refraction, p.refraction)) << rays->refraction << " vs " << p.refraction;
    EXPECT_TRUE(near(rays->shadow, p.shadow)) << rays->shadow << " vs " << p.shadow;
  }
}

// Luminance of `image` averaged over an n x n grid of blocks, optionally mirrored left-right.
std::vector<double> block_luminance(const Image& image, int n, bool mirrored) {
  std::vector<double> sums(static_cast<size_t>(n) * n, 0.0), counts(sums.size(), 0.0);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float* p = image.pixel(mirrored ? image.width - 1 - x : x, y);
      const size_t k = static_cast<size_t>(y * n / image.height) * n + static_cast<size_t>(x * n / image.width);
      sums[k] += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      counts[k] += 1;
    }
  for (size_t k = 0; k < sums.size(); ++k) sums[k] /= counts[k];
  return sums;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= a.size();
  mb /= b.size();
  double ab = 0, aa = 0, bb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ab += (a[i] - ma) * (b[i] - mb);
    aa += (a[i] - ma) * (a[i] - ma);
    bb += (b[i] - mb) * (b[i] - mb);
  }
  return ab / std::sqrt(aa * bb);
}

TEST(NffSpd, NotTheMirrorImageOfThePublishedPictures) {
  for (const char* name : {"balls", "tetra"}) {
    SCOPED_TRACE(name);
    Image ours;
    if (!spd_counts((std::string(name) + ".nff").c_str(), &ours)) GTEST_SKIP() << "polygons do not load yet";
    const Image published = read_image(kSpdDir / (std::string(name) + "-published.png"));
    const std::vector<double> theirs = block_luminance(published, 16, false);
    const double same = correlation(block_luminance(ours, 16, false), theirs);
    const double mirrored = correlation(block_luminance(ours, 16, true), theirs);
    // The shading differs (the published renders are darker and more
    // saturated), so the match is loose; the mirror image is clearly worse.
    // Measured: balls 0.76 against 0.54 mirrored, tetra 0.99 against 0.58.
    EXPECT_GT(same, 0.6) << "mirrored: " << mirrored;
    EXPECT_GT(same, mirrored + 0.15);
  }
}

}  // namespace
