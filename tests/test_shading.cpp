// The shading contract checked against values computed here, in the test,
// from the formula: ambient, diffuse, specular (Phong and Blinn-Phong), shadows,
// reflection depth, refraction and total internal reflection, spot cones,
// attenuation, the orthographic camera and transforms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "glint/accel/accelerator.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

constexpr double kTol = 1e-5;

Color render_one(const Scene& scene, int x, int y) {
  const auto accel = build_accelerator(scene);
  const Image image = render_image(scene, *accel);
  const float* p = image.pixel(x, y);
  return {p[0], p[1], p[2]};
}

void expect_color(const Color& got, const Color& want, const char* what) {
  EXPECT_NEAR(got.x, want.x, kTol) << what;
  EXPECT_NEAR(got.y, want.y, kTol) << what;
  EXPECT_NEAR(got.z, want.z, kTol) << what;
}

// Camera ray through pixel (i, j) for a perspective camera, written out from
// the contract's words (independent of glint's camera code).
Vec3 contract_ray_dir(const Camera& c, int w, int h, int i, int j) {
  const double u = (i + 0.5) / w, v = (j + 0.5) / h;
  const Vec3 f = normalize(c.look_at - c.position);
  const Vec3 r = normalize(cross(f, c.up));
  const Vec3 up = cross(r, f);
  const double th = std::tan(c.fov_y * std::numbers::pi / 360.0);
  return normalize(f + (2 * u - 1) * th * (double(w) / h) * r + (1 - 2 * v) * th * up);
}

// First root of |o + t d - center| = radius (the test's own sphere test).
double sphere_t(const Vec3& o, const Vec3& d, const Vec3& center, double radius) {
  const Vec3 oc = o - center;
  const double b = dot(oc, d), c = dot(oc, oc) - radius * radius;
  return -b - std::sqrt(b * b - c);
}

struct OneSphere {
  Scene scene;
  Material mat;
  Light light;
  OneSphere(ShadingModel model) {
    scene.render.width = 40;
    scene.render.height = 30;
    scene.render.shading_model = model;
    scene.camera.position = {0, 0, 5};
    scene.camera.look_at = {0, 0, 0};
    mat.ambient = {0.1, 0.2, 0.3};
    mat.diffuse = {0.7, 0.5, 0.3};
    mat.specular = {0.9, 0.8, 0.7};
    mat.shininess = 20;
    light.type = LightType::point;
    light.position = {3, 4, 5};
    light.ambient = {0.5, 0.4, 0.3};
    light.diffuse = {1.0, 0.9, 0.8};
    light.specular = {0.6, 0.7, 1.0};
  }
  void build() {
    const uint32_t m = add_material(scene, mat);
    add_sphere(scene, Sphere{{0, 0, 0}, 1.0}, m);
    scene.lights.push_back(light);
  }
  // The formula at pixel (i, j), term by term.
  Color expected(int i, int j, bool ambient, bool diffuse, bool specular) const {
    const Vec3 d = contract_ray_dir(scene.camera, scene.render.width, scene.render.height, i, j);
    const double t = sphere_t(scene.camera.position, d, {0, 0, 0}, 1.0);
    const Vec3 p = scene.camera.position + t * d;
    const Vec3 n = normalize(p);
    const Vec3 v = -d;
    const Vec3 l = normalize(light.position - p);
    Color c(0.0);
    if (ambient) c += mat.ambient * light.ambient;
    const double ndl = dot(n, l);
    if (ndl > 0) {
      if (diffuse) c += mat.diffuse * light.diffuse * ndl;
      double s;
      if (scene.render.shading_model == ShadingModel::phong) {
        s = std::max(0.0, dot(2 * ndl * n - l, v));
      } else {
        s = std::max(0.0, dot(n, normalize(l + v)));
      }
      if (specular) c += mat.specular * light.specular * std::pow(s, mat.shininess);
    }
    return c;
  }
};

const int kPixels[][2] = {{20, 15}, {17, 12}, {24, 11}, {14, 18}, {22, 19}, {19, 9}};

class Formula : public ::testing::TestWithParam<ShadingModel> {};

TEST_P(Formula, EachTermAndTheirSum) {
  for (int term = 0; term < 4; ++term) {
    OneSphere s(GetParam());
    if (term != 0 && term != 3) s.mat.ambient = Color(0.0);
    if (term != 1 && term != 3) s.mat.diffuse = Color(0.0);
    if (term != 2 && term != 3) s.mat.specular = Color(0.0);
    s.build();
    const auto accel = build_accelerator(s.scene);
    const Image image = render_image(s.scene, *accel);
    for (const auto& px : kPixels) {
      const float* got = image.pixel(px[0], px[1]);
      const Color want =
          s.expected(px[0], px[1], term == 0 || term == 3, term == 1 || term == 3, term == 2 || term == 3);
      expect_color({got[0], got[1], got[2]}, want, ("term " + std::to_string(term)).c_str());
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Models, Formula, ::testing::Values(ShadingModel::phong, ShadingModel::blinn_phong),
                         [](const ::testing::TestParamInfo<ShadingModel>& info) {
                           return info.param == ShadingModel::phong ? "Phong" : "BlinnPhong";
                         });

TEST(Formula, SpecularHighlightIsBrightestWhereTheFormulaSaysSo) {
  OneSphere s(ShadingModel::phong);
  s.mat.ambient = s.mat.diffuse = Color(0.0);
  s.build();
  const auto accel = build_accelerator(s.scene);
  const Image image = render_image(s.scene, *accel);
  int best_x = 0, best_y = 0;
  double best = -1, best_expected = -1;
  int want_x = 0, want_y = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      if (image.pixel(x, y)[0] > best) {
        best = image.pixel(x, y)[0];
        best_x = x;
        best_y = y;
      }
      const Vec3 d = contract_ray_dir(s.scene.camera, 40, 30, x, y);
      const Vec3 oc = s.scene.camera.position;
      if (dot(oc, d) * dot(oc, d) - (dot(oc, oc) - 1) < 0) continue;
      const double e = s.expected(x, y, false, false, true).x;
      if (e > best_expected) {
        best_expected = e;
        want_x = x;
        want_y = y;
      }
    }
  EXPECT_EQ(best_x, want_x);
  EXPECT_EQ(best_y, want_y);
  EXPECT_GT(best, 0.1);
}

TEST(Background, MissesReturnTheBackground) {
  OneSphere s(ShadingModel::phong);
  s.scene.render.background = {0.25, 0.5, 0.75};
  s.build();
  expect_color(render_one(s.scene, 0, 0), {0.25, 0.5, 0.75}, "corner");
}

// A floor, a blocker sphere between it and a point light right above.
Scene shadow_scene(bool with_blocker, const Vec3& blocker = {}) {
  Scene scene;
  scene.render.width = 21;
  scene.render.height = 21;
  scene.camera.type = CameraType::orthographic;
  scene.camera.position = {0, 10, 0};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.up = {0, 0, -1};
  scene.camera.view_height = 4;
  Material floor;
  floor.ambient = Color(0.1);
  floor.diffuse = Color(0.6);
  const uint32_t m = add_material(scene, floor);
  add_plane(scene, Plane{{0, 0, 0}, {0, 1, 0}}, m);
  if (with_blocker) {
    Material black;
    black.diffuse = Color(0.0);
    // Off to the side of the pixel tested below, so the camera still sees the
    // floor there, but on that floor point's way to the light.
    add_sphere(scene, Sphere{blocker, 0.3}, add_material(scene, black));
  }
  Light light;
  light.position = {0, 5, 0};
  light.ambient = Color(1.0);
  scene.lights.push_back(light);
  return scene;
}

TEST(Shadows, BlockedLightLeavesOnlyAmbient) {
  // Pixel (15, 10) looks straight down at the floor point (x, 0, 0):
  const int px = 15, py = 10;
  const double x = (2.0 * (px + 0.5) / 21 - 1) * 2.0;  // view_height 4, aspect 1
  const Vec3 p{x, 0, 0};
  const Vec3 l = normalize(Vec3{0, 5, 0} - p);
  const Color lit = Color(0.1) + Color(0.6) * l.y;
  expect_color(render_one(shadow_scene(false), px, py), lit, "unblocked");
  // A blocker centered on the segment from p to the light.
  const Vec3 mid = p + 0.5 * (Vec3{0, 5, 0} - p);
  expect_color(render_one(shadow_scene(true, mid), px, py), Color(0.1), "blocked");
  // Moved off the segment, it no longer blocks.
  expect_color(render_one(shadow_scene(true, mid + Vec3{0, 0, 0.5}), px, py), lit, "beside the segment");
}

TEST(Shadows, DirectionalLightShadowReachesInfinity) {
  Scene scene = shadow_scene(false);
  scene.lights.clear();
  Light sun;
  sun.type = LightType::directional;
  sun.direction = {0, -1, 0};
  scene.lights.push_back(sun);
  Material m;
  add_sphere(scene, Sphere{{0, 1000, 0}, 1.5}, add_material(scene, m));  // far above, still blocks
  // Center pixel: the camera ray starts at y = 10 going down and hits the floor;
  // its shadow ray goes up to infinity and hits the sphere at y ~ 1000.
  expect_color(render_one(scene, 10, 10), Color(0.0), "shadowed by a far sphere");
  expect_color(render_one(scene, 0, 10), Color(0.6), "lit beside it");
}

// A mirror floor under an orthographic camera looking straight down: each
// depth adds k times what the reflected ray sees (the background here).
TEST(Reflection, DepthLimitsTheRecursion) {
  // One mirror: the reflected ray (depth 2) sees the background.
  for (int depth = 1; depth <= 3; ++depth) {
    Scene scene;
    scene.render.width = scene.render.height = 3;
    scene.render.max_depth = depth;
    scene.render.background = {0.2, 0.4, 0.8};
    scene.camera.type = CameraType::orthographic;
    scene.camera.position = {0, 1, 0};
    scene.camera.look_at = {0, 0, 0};
    scene.camera.up = {0, 0, -1};
    Material mirror;
    mirror.diffuse = Color(0.0);
    mirror.reflectivity = {0.5, 0.25, 1.0};
    add_plane(scene, Plane{{0, 0, 0}, {0, 1, 0}}, add_material(scene, mirror));
    const Color want = depth >= 2 ? Color{0.1, 0.1, 0.8} : Color(0.0);
    expect_color(render_one(scene, 1, 1), want, "one mirror");
  }
}

TEST(Reflection, EachBounceAddsItsAmbientWeightedByTheProductOfWeights) {
  // Two facing mirrors with ambient: depth d gives sum_{i<d} a * k^i.
  for (int depth = 1; depth <= 5; ++depth) {
    Scene scene;
    scene.render.width = scene.render.height = 3;
    scene.render.max_depth = depth;
    scene.camera.type = CameraType::orthographic;
    scene.camera.position = {0, 1, 0};
    scene.camera.look_at = {0, 0, 0};
    scene.camera.up = {0, 0, -1};
    Material mirror;
    mirror.diffuse = Color(0.0);
    mirror.ambient = Color(0.1);
    mirror.reflectivity = Color(0.5);
    const uint32_t m = add_material(scene, mirror);
    add_plane(scene, Plane{{0, 0, 0}, {0, 1, 0}}, m);
    add_plane(scene, Plane{{0, 2, 0}, {0, -1, 0}}, m);
    Light amb;
    amb.type = LightType::ambient;
    amb.ambient = Color(1.0);
    amb.diffuse = amb.specular = Color(0.0);
    scene.lights.push_back(amb);
    double want = 0, k = 1;
    for (int i = 0; i < depth; ++i, k *= 0.5) want += 0.1 * k;
    expect_color(render_one(scene, 1, 1), Color(want), "mirror corridor");
  }
}

// A big glass sphere (ior 2) with the camera inside it. From the center the
// rays leave (refract out to the background); from near the wall they meet it
// beyond the critical angle (30 degrees) and reflect totally.
Scene inside_glass(const Vec3& eye, int max_depth) {
  Scene scene;
  scene.render.width = scene.render.height = 1;
  scene.render.max_depth = max_depth;
  scene.render.background = Color(0.5);
  scene.camera.position = eye;
  scene.camera.look_at = eye + Vec3{1, 0, 0};
  Material glass;
  glass.ambient = Color(0.1);
  glass.diffuse = Color(0.0);
  glass.transparency = 1.0;
  glass.ior = 2.0;
  add_sphere(scene, Sphere{{0, 0, 0}, 10}, add_material(scene, glass));
  Light amb;
  amb.type = LightType::ambient;
  amb.ambient = Color(1.0);
  scene.lights.push_back(amb);
  return scene;
}

TEST(Refraction, LeavingRayReachesTheBackground) {
  expect_color(render_one(inside_glass({0, 1, 0}, 2), 0, 0), Color(0.1 + 0.5), "refracted out");
  expect_color(render_one(inside_glass({0, 1, 0}, 1), 0, 0), Color(0.1), "not cast at depth 1");
}

TEST(Refraction, TotalInternalReflectionMovesTheWeightToTheReflectedRay) {
  // cos(theta) = sqrt(19)/10 < cos(30 deg): TIR at every bounce (same angle).
  expect_color(render_one(inside_glass({0, 9, 0}, 2), 0, 0), Color(0.2), "one reflection");
  expect_color(render_one(inside_glass({0, 9, 0}, 3), 0, 0), Color(0.3), "two reflections");
}

TEST(Refraction, IndexOneGoesStraightThrough) {
  Scene scene;
  scene.render.width = scene.render.height = 1;
  scene.render.background = {0.3, 0.6, 0.9};
  scene.camera.position = {0, 0, 5};
  scene.camera.look_at = {0, 0, 0};
  Material clear;
  clear.diffuse = Color(0.0);
  clear.transparency = 1.0;
  clear.ior = 1.0;
  add_sphere(scene, Sphere{{0, 0, 0}, 1}, add_material(scene, clear));
  // Behind the sphere, off-axis: a straight ray misses it, a bent one would not.
  expect_color(render_one(scene, 0, 0), {0.3, 0.6, 0.9}, "in, through, out");
  scene.render.max_depth = 2;
  expect_color(render_one(scene, 0, 0), Color(0.0), "the exit ray is depth 3");
}

TEST(Refraction, FresnelWeightsFollowSchlick) {
  // Head-on (cos = 1) on a glass sphere with reflectivity 0: reflected weight
  // S(0) + T S(F0) = T F0, refracted T (1 - F0); the reflection returns the
  // background straight back, the refraction passes through (ior bends nothing head-on).
  Scene scene;
  scene.render.width = scene.render.height = 1;
  scene.render.background = Color(1.0);
  scene.render.max_depth = 2;
  scene.camera.type = CameraType::orthographic;
  scene.camera.position = {0, 0, 5};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.view_height = 1e-6;
  Material glass;
  glass.diffuse = Color(0.0);
  glass.transparency = 0.8;
  glass.ior = 1.5;
  glass.fresnel = true;
  add_sphere(scene, Sphere{{0, 0, 0}, 1}, add_material(scene, glass));
  const double f0 = 0.04;
  // depth 2: reflected ray sees the background (weight 0.8*f0); refracted ray
  // hits the sphere's back at depth 2 and shades to black (diffuse 0, no deeper rays).
  expect_color(render_one(scene, 0, 0), Color(0.8 * f0), "reflected part");
}

TEST(SpotLight, ConeAndFalloff) {
  Scene scene;
  scene.render.width = 41;
  scene.render.height = 1;
  scene.camera.type = CameraType::orthographic;
  scene.camera.position = {0, 10, 0};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.up = {0, 0, -1};
  scene.camera.view_height = 10.0 / 41;  // width 10 world units
  Material floor;
  floor.diffuse = Color(1.0);
  add_plane(scene, Plane{{0, 0, 0}, {0, 1, 0}}, add_material(scene, floor));
  Light spot;
  spot.type = LightType::spot;
  spot.position = {0, 2, 0};
  spot.direction = {0, -1, 0};
  spot.cutoff = 45;
  spot.falloff = 3;
  scene.lights.push_back(spot);
  const auto accel = build_accelerator(scene);
  const Image image = render_image(scene, *accel);
  for (int i = 0; i < 41; ++i) {
    const double x = (2.0 * (i + 0.5) / 41 - 1) * 5.0;
    const Vec3 p{x, 0, 0};
    const Vec3 l = normalize(spot.position - p);
    const double cos_angle = -dot(l, spot.direction);
    const double want = std::abs(x) <= 2.0 ? l.y * std::pow(cos_angle, 3) : 0.0;
    EXPECT_NEAR(image.pixel(i, 0)[0], want, kTol) << "x = " << x;
  }
}

TEST(Attenuation, ScalesDiffuseAndSpecularNotAmbient) {
  Scene scene;
  scene.render.width = scene.render.height = 1;
  scene.camera.type = CameraType::orthographic;
  scene.camera.position = {0, 10, 0};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.up = {0, 0, -1};
  Material floor;
  floor.ambient = Color(0.2);
  floor.diffuse = Color(0.5);
  floor.specular = Color(0.25);
  floor.shininess = 7;
  add_plane(scene, Plane{{0, 0, 0}, {0, 1, 0}}, add_material(scene, floor));
  Light light;
  light.position = {0, 3, 0};
  light.ambient = Color(0.5);
  light.attenuation = {1, 0.5, 0.25};
  scene.lights.push_back(light);
  // Head-on: n.l = 1, r.v = 1; distance 3.
  const double att = 1.0 / (1 + 0.5 * 3 + 0.25 * 9);
  expect_color(render_one(scene, 0, 0), Color(0.2 * 0.5 + att * (0.5 + 0.25)), "attenuated");
}

TEST(Camera, OrthographicRaysAreParallelAndStartOnThePlane) {
  // A sphere of radius 1 seen orthographically with view_height 4 over 40 rows:
  // a pixel is inside the disc exactly when its center is within radius 1.
  Scene scene;
  scene.render.width = 40;
  scene.render.height = 40;
  scene.camera.type = CameraType::orthographic;
  scene.camera.position = {0, 0, 10};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.view_height = 4;
  Material m;
  m.ambient = Color(1.0);
  m.diffuse = Color(0.0);
  add_sphere(scene, Sphere{{0, 0, 0}, 1}, add_material(scene, m));
  Light amb;
  amb.type = LightType::ambient;
  amb.ambient = Color(1.0);
  scene.lights.push_back(amb);
  const auto accel = build_accelerator(scene);
  const Image image = render_image(scene, *accel);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) {
      const double wx = (2.0 * (x + 0.5) / 40 - 1) * 2, wy = (1 - 2.0 * (y + 0.5) / 40) * 2;
      const bool inside = wx * wx + wy * wy < 1.0;
      EXPECT_EQ(image.pixel(x, y)[0], inside ? 1.0f : 0.0f) << x << "," << y;
    }
}

TEST(Transforms, ScaledTranslatedSphereEqualsTheSphereItBecomes) {
  auto render_with = [](bool transformed) {
    OneSphere s(ShadingModel::phong);
    const uint32_t m = add_material(s.scene, s.mat);
    if (transformed) {
      add_sphere(s.scene, Sphere{{0, 0, 0}, 1}, m,
                 compose(Transform::translate({0.3, -0.2, 0.1}), Transform::scale(Vec3(1.3))));
    } else {
      add_sphere(s.scene, Sphere{{0.3, -0.2, 0.1}, 1.3}, m);
    }
    s.scene.lights.push_back(s.light);
    const auto accel = build_accelerator(s.scene);
    return render_image(s.scene, *accel);
  };
  const Image a = render_with(true), b = render_with(false);
  for (size_t i = 0; i < a.rgb.size(); ++i) EXPECT_NEAR(a.rgb[i], b.rgb[i], kTol) << i;
}

TEST(Transforms, RotatedBoxNormalsFollowTheRotation) {
  // A unit cube rotated 90 degrees about y is the same cube: same image.
  auto render_with = [](double angle) {
    OneSphere s(ShadingModel::blinn_phong);
    const uint32_t m = add_material(s.scene, s.mat);
    add_box(s.scene, Box{{-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}}, m,
            compose(Transform::rotate({1, 0, 0}, 30), Transform::rotate({0, 1, 0}, angle)));
    s.scene.lights.push_back(s.light);
    const auto accel = build_accelerator(s.scene);
    return render_image(s.scene, *accel);
  };
  const Image a = render_with(0), b = render_with(90), c = render_with(45);
  double diff_ab = 0, diff_ac = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    diff_ab = std::max(diff_ab, double(std::abs(a.rgb[i] - b.rgb[i])));
    diff_ac = std::max(diff_ac, double(std::abs(a.rgb[i] - c.rgb[i])));
  }
  EXPECT_LT(diff_ab, 1e-4);
  EXPECT_GT(diff_ac, 1e-2);  // and a real rotation does change the picture
}

TEST(Determinism, SameBytesWhateverTheThreadCount) {
  OneSphere s(ShadingModel::phong);
  s.scene.render.samples_per_pixel = 5;
  s.mat.reflectivity = Color(0.3);
  s.build();
  Light area;
  area.type = LightType::area;
  area.corner = {-1, 3, 1};
  area.edge_u = {2, 0, 0};
  area.edge_v = {0, 0, 2};
  area.samples = 6;
  s.scene.lights.push_back(area);
  add_plane(s.scene, Plane{{0, -1, 0}, {0, 1, 0}});
  const auto accel = build_accelerator(s.scene);
  RenderOptions one, two, seven;
  one.threads = 1;
  two.threads = 2;
  seven.threads = 7;
  const Image a = render_image(s.scene, *accel, one);
  const Image b = render_image(s.scene, *accel, two);
  const Image c = render_image(s.scene, *accel, seven);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(a.rgb, c.rgb);
}

}  // namespace
}  // namespace glint
