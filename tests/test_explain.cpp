// `explain`: the ray tree of one pixel must add up (each node's color is the
// sum over lights plus the weighted children) and must equal the rendered
// pixel exactly, for every scene in scenes/ and for chosen pixels.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "glint/io/scene_loader.h"
#include "glint/render/explain.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

// Checks the contract's identity at every node; returns the number of nodes.
int check_sums(const Scene& scene, const RayTrace& t) {
  int nodes = 1;
  if (!t.hit) return nodes;
  Color sum(0.0);
  Color ambient(0.0), diffuse(0.0), specular(0.0);
  for (const LightTrace& l : t.lights) {
    ambient += l.terms.ambient;
    diffuse += l.terms.diffuse;
    specular += l.terms.specular;
  }
  sum = ambient + diffuse + specular;
  if (t.reflection) {
    sum += t.reflection_weight * t.reflection->color;
    nodes += check_sums(scene, *t.reflection);
  }
  if (t.refraction) {
    sum += t.refraction_weight * t.refraction->color;
    nodes += check_sums(scene, *t.refraction);
  }
  if (t.fog) sum = *t.fog * sum + (1.0 - *t.fog) * scene.render.fog->color;  // f C + (1 - f) c
  EXPECT_NEAR(sum.x, t.color.x, 1e-12);
  EXPECT_NEAR(sum.y, t.color.y, 1e-12);
  EXPECT_NEAR(sum.z, t.color.z, 1e-12);
  return nodes;
}

TEST(Explain, EqualsTheRenderedPixelForEveryExampleScene) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(std::string(GLINT_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json") continue;
    Scene scene = load_scene(entry.path());
    scene.render.samples_per_pixel = 1;
    scene.render.width = std::min(scene.render.width, 96);
    scene.render.height = std::min(scene.render.height, 64);
    const auto accel = build_accelerator(scene);
    const Image image = render_image(scene, *accel);
    for (int y = 0; y < scene.render.height; y += 7) {
      for (int x = 0; x < scene.render.width; x += 5) {
        const PixelExplanation e = explain_pixel(scene, *accel, x, y);
        const float* p = image.pixel(x, y);
        ASSERT_EQ(static_cast<float>(e.color.x), p[0]) << entry.path() << " " << x << "," << y;
        ASSERT_EQ(static_cast<float>(e.color.y), p[1]);
        ASSERT_EQ(static_cast<float>(e.color.z), p[2]);
        check_sums(scene, e.ray);
      }
    }
    ++scenes;
  }
  EXPECT_GE(scenes, 10);
}

TEST(Explain, JsonHasTheContractsKeys) {
  const Scene scene = load_scene(std::string(GLINT_SOURCE_DIR) + "/scenes/showcase.json");
  const auto accel = build_accelerator(scene);
  // A pixel on the glass ball: reflection and refraction both present.
  bool saw_refraction = false;
  for (int x = 480; x < 620 && !saw_refraction; x += 10) {
    const PixelExplanation e = explain_pixel(scene, *accel, x, 260);
    const auto j = nlohmann::json::parse(explanation_json(scene, e));
    ASSERT_EQ(j["pixel"], nlohmann::json::array({x, 260}));
    ASSERT_EQ(j["color"].size(), 3u);
    const auto& ray = j["ray"];
    for (const char* key : {"origin", "direction", "depth", "hit", "color"}) ASSERT_TRUE(ray.contains(key)) << key;
    const auto& hit = ray["hit"];
    if (hit.is_null()) continue;
    for (const char* key : {"object", "name", "t", "point", "normal", "material", "lights", "reflection", "refraction"})
      ASSERT_TRUE(hit.contains(key)) << key;
    for (const auto& l : hit["lights"])
      for (const char* key :
           {"index", "type", "l", "n_dot_l", "shadowed", "blocker", "specular_cos", "ambient", "diffuse", "specular"})
        ASSERT_TRUE(l.contains(key)) << key;
    if (!hit["refraction"].is_null()) {
      saw_refraction = true;
      EXPECT_TRUE(hit["refraction"].contains("weight"));
      EXPECT_EQ(hit["refraction"]["ray"]["depth"], 2);
    }
  }
  EXPECT_TRUE(saw_refraction);
}

TEST(Explain, NamesTheBlockerOfAShadowRay) {
  // Pixel (5, 4) sees the floor point (0.22, 0, 0); the pebble sits halfway
  // between that point and the light, off the camera's line of sight.
  const Scene scene = parse_scene(R"({
    "render": {"width": 9, "height": 9},
    "camera": {"type": "orthographic", "position": [0, 10, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "view_height": 2},
    "lights": [{"type": "point", "position": [0, 5, 0]}],
    "objects": [
      {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "name": "floor"},
      {"type": "sphere", "center": [0.11, 2.5, 0], "radius": 0.05, "name": "pebble"}
    ]})",
                                  "blocker.json");
  const auto accel = build_accelerator(scene);
  const PixelExplanation e = explain_pixel(scene, *accel, 5, 4);
  ASSERT_TRUE(e.ray.hit);
  EXPECT_EQ(e.ray.hit->object, 0u);
  ASSERT_EQ(e.ray.lights.size(), 1u);
  EXPECT_TRUE(e.ray.lights[0].shadowed);
  ASSERT_TRUE(e.ray.lights[0].blocker);
  EXPECT_EQ(*e.ray.lights[0].blocker, 1u);
  EXPECT_NE(explanation_text(scene, e).find("shadowed by object 1 \"pebble\""), std::string::npos);
}

TEST(Explain, PixelOutsideTheImageIsAnError) {
  const Scene scene = load_scene(std::string(GLINT_SOURCE_DIR) + "/scenes/figures/shadows.json");
  const auto accel = build_accelerator(scene);
  EXPECT_THROW(explain_pixel(scene, *accel, scene.render.width, 0), Error);
  EXPECT_THROW(explain_pixel(scene, *accel, 0, -1), Error);
}

}  // namespace
}  // namespace glint
