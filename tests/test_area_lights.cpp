// Area lights: the penumbra between umbra and full light. Seen from above
// (orthographic, from below the slab), a floor under a square area light, half of it shaded by a
// large slab whose edge runs across the middle: the fraction of light that
// reaches each floor point must rise monotonically across the edge, be
// exactly 0 (ambient alone) in the umbra, and be exactly the unshadowed value
// where no sample is blocked. Ratios against the same render without the slab
// take out the light's own falloff and cos terms.
#include <gtest/gtest.h>

#include <string>

#include "glint/accel/accelerator.h"
#include "glint/io/scene_loader.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

// Floor pixel x covers floor x in [-4, 4]: 128 pixels, one row.
std::string area_scene(bool with_slab, double light_size, int samples) {
  const double h = light_size / 2;
  std::string objects = R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"})";
  if (with_slab)  // covers x < 0 at height 2, between the floor and the light
    objects += R"(, {"type": "box", "min": [-50, 2, -50], "max": [0, 2.1, 50], "material": "floor"})";
  return R"({"render": {"width": 128, "height": 1, "background": [0, 0, 0]},
    "camera": {"type": "orthographic", "position": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "view_height": 0.0625},
    "materials": {"floor": {"ambient": 0.25, "diffuse": 0.5, "specular": 0}},
    "lights": [{"type": "ambient", "ambient": 0.4},
               {"type": "area", "corner": [)" +
         std::to_string(-h) + ", 4, " + std::to_string(-h) + R"(], "edge_u": [)" + std::to_string(light_size) +
         R"(, 0, 0], "edge_v": [0, 0, )" + std::to_string(light_size) + R"(], "samples": )" + std::to_string(samples) +
         R"(}],
    "objects": [)" +
         objects + "]}";
}

Image render_text(const std::string& text) {
  const Scene scene = parse_scene(text, "area.json");
  const auto accel = build_accelerator(scene);
  RenderOptions options;
  options.threads = 2;
  return render_image(scene, *accel, options);
}

struct Penumbra {
  std::vector<double> lit_fraction;  // (shaded - ambient) / (unshaded - ambient), per pixel
  Image shaded, unshaded;
};

Penumbra measure(double light_size, int samples) {
  Penumbra p;
  p.shaded = render_text(area_scene(true, light_size, samples));
  p.unshaded = render_text(area_scene(false, light_size, samples));
  const double ambient = 0.25 * 0.4;
  for (int x = 0; x < 128; ++x) {
    const double s = p.shaded.pixel(x, 0)[0], u = p.unshaded.pixel(x, 0)[0];
    p.lit_fraction.push_back((s - ambient) / (u - ambient));
  }
  return p;
}

TEST(AreaLightPenumbra, RisesMonotonicallyAcrossTheShadowEdge) {
  // 1024 samples: a 32 x 32 grid of strata, each jittered per pixel, so the
  // visible fraction may step back by about one column of strata at most.
  const Penumbra p = measure(2.0, 1024);
  int rising = 0;
  for (int x = 1; x < 128; ++x) {
    EXPECT_GE(p.lit_fraction[x], p.lit_fraction[x - 1] - 1.0 / 32) << "pixel " << x;
    rising += p.lit_fraction[x] > p.lit_fraction[x - 1];
  }
  EXPECT_GT(rising, 10);                      // there is a penumbra, not a step
  EXPECT_NEAR(p.lit_fraction[64], 0.5, 0.1);  // the middle sees about half the light
}

TEST(AreaLightPenumbra, UmbraIsAmbientOnlyAndFullLightIsTheUnshadowedValue) {
  const Penumbra p = measure(2.0, 64);
  int umbra = 0, lit = 0;
  // Floor x = -4 + (px + 0.5) / 16. A shadow ray from x to the light's
  // sample at lx crosses the slab's underside (y = 2) at (x + lx) / 2 and its
  // top (y = 2.1) at x + 0.525 (lx - x): left of x = -1 every sample is
  // blocked, right of x = 0.525 / 0.475 = 1.105 none is.
  for (int px = 0; px < 128; ++px) {
    const double x = -4.0 + (px + 0.5) / 16.0;
    const float* s = p.shaded.pixel(px, 0);
    const float* u = p.unshaded.pixel(px, 0);
    if (x < -1.05) {
      ++umbra;
      for (int c = 0; c < 3; ++c) EXPECT_EQ(s[c], static_cast<float>(0.25 * 0.4)) << "umbra pixel " << px;
    } else if (x > 1.15) {
      ++lit;
      for (int c = 0; c < 3; ++c) EXPECT_EQ(s[c], u[c]) << "lit pixel " << px;
    }
  }
  EXPECT_GT(umbra, 40);
  EXPECT_GT(lit, 40);
}

TEST(AreaLightPenumbra, GrowsWithTheLight) {
  auto penumbra_width = [](const Penumbra& p) {
    int n = 0;
    for (double f : p.lit_fraction) n += f > 0.02 && f < 0.98;
    return n;
  };
  const int small = penumbra_width(measure(0.5, 256));
  const int large = penumbra_width(measure(2.0, 256));
  EXPECT_GT(small, 0);
  EXPECT_GT(large, 3 * small);
}

}  // namespace
}  // namespace glint
