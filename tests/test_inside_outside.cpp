// Inside and outside for refraction (docs/scene-format.md): a ray enters
// when it travels against the GEOMETRIC normal, whatever the shading normal
// says; and the "Precisely" rule: a secondary ray is cast exactly when its
// final weight (after fresnel and total internal reflection) is above 0 in
// some channel, counted here ray by ray.
#include <gtest/gtest.h>

#include <cmath>

#include "glint/accel/accelerator.h"
#include "glint/geometry/polygon.h"
#include "glint/render/integrator.h"

namespace glint {
namespace {

// A glass square in z = 0 whose first three vertices wind counterclockwise
// seen from +z (geometric normal +z) but whose vertex normals all say -z.
Scene glass_square(bool fresnel, double transparency, double ior, Color reflectivity = Color(0.0)) {
  Scene scene;
  scene.render.max_depth = 2;
  scene.render.background = {0.2, 0.4, 0.6};
  Material glass;
  glass.diffuse = Color(0.0);
  glass.transparency = transparency;
  glass.ior = ior;
  glass.fresnel = fresnel;
  glass.reflectivity = reflectivity;
  const uint32_t m = add_material(scene, glass);
  const std::vector<Vec3> v = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  PolygonBuild b = make_polygon(v, std::vector<Vec3>(4, Vec3(0, 0, -1)));
  EXPECT_EQ(b.error, "");
  add_polygon(scene, std::move(b.polygon), m);
  return scene;
}

struct Traced {
  RayTrace trace;
  RayStats stats;
};

Traced trace(const Scene& scene, const Ray& ray) {
  const auto accel = build_accelerator(scene);
  const Integrator integrator(scene, *accel);
  TraceContext ctx{Rng(1), {}};
  Traced t;
  integrator.trace_ray(ray, 1, ctx, t.trace);
  t.stats = ctx.stats;
  return t;
}

TEST(InsideOutside, EnteringFollowsTheGeometricNormalNotTheShadingNormal) {
  // From +z at 45 degrees: against the geometric normal (+z), so the ray
  // enters and bends toward the normal with eta = 1/1.5. Deciding from the
  // shading normal (-z) would have it leave glass: eta = 1.5 and, at 45
  // degrees, total internal reflection with no refracted ray at all.
  const Scene scene = glass_square(false, 1.0, 1.5);
  const Vec3 d = normalize({1, 0, -1});
  const Traced t = trace(scene, {{-0.5, 0, 0.5}, d});
  ASSERT_TRUE(t.trace.hit);
  ASSERT_TRUE(t.trace.refraction) << "the ray was taken to leave the glass";
  EXPECT_EQ(t.stats.refraction, 1u);
  EXPECT_EQ(t.stats.reflection, 0u);
  // Snell with n the shading normal turned toward the viewer (+z here) and eta = 1/1.5.
  const double eta = 1 / 1.5, cos_i = std::sqrt(0.5);
  const double cos_t = std::sqrt(1 - eta * eta * (1 - cos_i * cos_i));
  const Vec3 want = eta * d + (eta * cos_i - cos_t) * Vec3(0, 0, 1);
  const Vec3 got = normalize(t.trace.refraction->ray.direction);
  EXPECT_NEAR(got.x, want.x, 1e-12);
  EXPECT_NEAR(got.y, want.y, 1e-12);
  EXPECT_NEAR(got.z, want.z, 1e-12);
  // The refracted ray starts on the far side (below the square).
  EXPECT_LT(t.trace.refraction->ray.origin.z, 0.0);

  // From below, along the geometric normal: leaving, eta = 1.5, total
  // internal reflection at 45 degrees (the shading normal would say entering).
  const Traced up = trace(scene, {{-0.5, 0, -0.5}, normalize({1, 0, 1})});
  EXPECT_FALSE(up.trace.refraction);
  ASSERT_TRUE(up.trace.reflection);
  EXPECT_EQ(up.trace.reflection_weight, Color(1.0));
  EXPECT_EQ(up.stats.refraction, 0u);
  EXPECT_EQ(up.stats.reflection, 1u);
}

TEST(PreciselyRule, FresnelGlassWithoutReflectivityCastsAReflectedRay) {
  // reflectivity 0, transparency 0.5, fresnel: the reflected weight is
  // S(0) + 0.5 S(0.04) > 0 at any angle, so the reflected ray is cast.
  const Scene scene = glass_square(true, 0.5, 1.5);
  const Traced t = trace(scene, {{0, 0, 1}, {0.3, 0.1, -1}});
  EXPECT_EQ(t.stats.reflection, 1u);
  EXPECT_EQ(t.stats.refraction, 1u);
  ASSERT_TRUE(t.trace.reflection);
  const double cos_t = 1 / std::sqrt(1.1), m = std::pow(1 - cos_t, 5);
  const double s_glass = 0.04 + 0.96 * m;
  EXPECT_NEAR(t.trace.reflection_weight.x, m + 0.5 * s_glass, 1e-15);
  EXPECT_NEAR(t.trace.refraction_weight.x, 0.5 * (1 - s_glass), 1e-15);
}

TEST(PreciselyRule, NoRayIsCastWithAWeightOfZero) {
  // Head on, ior 1 and fresnel: S(0) = (1 - cos)^5 = 0 and F0 = 0, so the
  // reflected weight is exactly 0: no reflected ray; the refracted one is cast.
  const Scene head_on = glass_square(true, 0.7, 1.0);
  Traced t = trace(head_on, {{0.2, 0.3, 1}, {0, 0, -1}});
  EXPECT_EQ(t.stats.reflection, 0u);
  EXPECT_EQ(t.stats.refraction, 1u);
  EXPECT_FALSE(t.trace.reflection);
  // No fresnel, nothing reflective or transparent: no secondary rays.
  t = trace(glass_square(false, 0.0, 1.5), {{0.2, 0.3, 1}, {0, 0, -1}});
  EXPECT_EQ(t.stats.reflection + t.stats.refraction, 0u);
  // A reflectivity above 0 in one channel only is enough.
  t = trace(glass_square(false, 0.0, 1.5, Color(0, 0, 0.25)), {{0.2, 0.3, 1}, {0, 0, -1}});
  EXPECT_EQ(t.stats.reflection, 1u);
  EXPECT_EQ(t.stats.refraction, 0u);
  // Total internal reflection moves the whole refracted weight to the
  // reflected ray: one reflected ray, no refracted one.
  t = trace(glass_square(false, 0.6, 1.5), {{-0.5, 0, -0.5}, normalize({1, 0, 1})});
  EXPECT_EQ(t.stats.reflection, 1u);
  EXPECT_EQ(t.stats.refraction, 0u);
  EXPECT_EQ(t.trace.reflection_weight, Color(0.6));
  // And at max_depth nothing more is cast, whatever the weights.
  Scene shallow = glass_square(true, 0.5, 1.5);
  shallow.render.max_depth = 1;
  t = trace(shallow, {{0, 0, 1}, {0.3, 0.1, -1}});
  EXPECT_EQ(t.stats.reflection + t.stats.refraction, 0u);
}

}  // namespace
}  // namespace glint
