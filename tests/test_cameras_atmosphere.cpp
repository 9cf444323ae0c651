// The contract's cameras, atmosphere and occlusion beyond the seed
// ("Cameras, atmosphere and solids beyond the seed"): fisheye and
// equirectangular directions, the thin lens, parallel stereo, fog, the
// environment map and ambient occlusion, each checked against its formula
// written out here, plus determinism for any thread count.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/image/image.h"
#include "glint/io/scene_loader.h"
#include "glint/render/camera.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

Image render_in(const std::string& text, const fs::path& dir = {}, int threads = 2) {
  const Scene scene = parse_scene(text, "scene.json", dir);
  const auto accel = build_accelerator(scene);
  RenderOptions options;
  options.threads = threads;
  return render_image(scene, *accel, options);
}

Color pixel(const Image& image, int x, int y) {
  const float* p = image.pixel(x, y);
  return {p[0], p[1], p[2]};
}

void expect_color(const Color& got, const Color& want, double tol = 1e-6) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

bool same_bits(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// --- cameras --------------------------------------------------------------

Camera looking(CameraType type) {
  Camera c;
  c.type = type;
  c.position = {1, 2, 3};
  c.look_at = {1, 2, -1};  // along -z, up +y, right +x
  return c;
}

TEST(FisheyeCamera, AngleOffTheAxisGrowsWithTheDistanceFromTheCenter) {
  Camera c = looking(CameraType::fisheye);
  c.fisheye_fov = 180;
  const int w = 200, h = 100;
  const CameraFrame f = make_camera_frame(c, w, h);
  // The contract: r = distance from the center over half the image height,
  // theta = r fov / 2; the direction leans toward the pixel.
  for (int y : {0, 10, 49, 50, 77, 99})
    for (int x : {0, 30, 99, 100, 150, 170, 199}) {
      const double px = x + 0.5 - 0.5 * w, py = y + 0.5 - 0.5 * h;  // pixels right and down of the center
      const double r = std::hypot(px, py) / (0.5 * h);
      const Ray ray = generate_camera_ray(f, (x + 0.5) / w, (y + 0.5) / h);
      if (r > 1) {
        EXPECT_FALSE(ray.t_max > ray.t_min) << x << "," << y << ": outside the circle looks at nothing";
        continue;
      }
      const double theta = r * kPi / 2;
      const double phi = std::atan2(-py, px);
      const Vec3 want(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta));
      EXPECT_NEAR(ray.direction.x, want.x, 1e-12) << x << "," << y;
      EXPECT_NEAR(ray.direction.y, want.y, 1e-12) << x << "," << y;
      EXPECT_NEAR(ray.direction.z, want.z, 1e-12) << x << "," << y;
      EXPECT_EQ(ray.origin, c.position);
    }
}

TEST(FisheyeCamera, A360DegreeFieldLooksBackwardAtTheRim) {
  Camera c = looking(CameraType::fisheye);
  c.fisheye_fov = 360;
  const CameraFrame f = make_camera_frame(c, 101, 101);
  // Pixel (50, 0)'s center is r = 100/101 from the center: theta = r pi.
  const Ray ray = generate_camera_ray(f, 50.5 / 101, 0.5 / 101);
  const double theta = (100.0 / 101.0) * kPi;
  EXPECT_NEAR(ray.direction.z, -std::cos(theta), 1e-12);
  EXPECT_NEAR(ray.direction.y, std::sin(theta), 1e-12);
  EXPECT_GT(ray.direction.z, 0.99);  // nearly straight backward
}

TEST(EquirectangularCamera, LongitudeAndLatitudeOfEachPixel) {
  const Camera c = looking(CameraType::equirectangular);
  const int w = 36, h = 18;
  const CameraFrame f = make_camera_frame(c, w, h);
  for (int y = 0; y < h; y += 5)
    for (int x = 0; x < w; x += 7) {
      const double u = (x + 0.5) / w, v = (y + 0.5) / h;
      const double lon = (u - 0.5) * 2 * kPi, lat = (0.5 - v) * kPi;
      // Right of the view direction (-z) is +x; up is +y.
      const Vec3 want(std::cos(lat) * std::sin(lon), std::sin(lat), -std::cos(lat) * std::cos(lon));
      const Ray ray = generate_camera_ray(f, u, v);
      EXPECT_NEAR(ray.direction.x, want.x, 1e-12);
      EXPECT_NEAR(ray.direction.y, want.y, 1e-12);
      EXPECT_NEAR(ray.direction.z, want.z, 1e-12);
    }
}

TEST(ThinLens, EveryLensRayMeetsThePinholeRayOnThePlaneInFocus) {
  Camera c = looking(CameraType::perspective);
  c.aperture = 0.3;
  c.focus_distance = 7;
  const CameraFrame f = make_camera_frame(c, 64, 48);
  for (double u : {0.1, 0.5, 0.93})
    for (double v : {0.2, 0.5, 0.8}) {
      const Ray pinhole = generate_camera_ray(f, u, v);
      const Vec3 focus = pinhole.origin + (7.0 / dot(pinhole.direction, Vec3(0, 0, -1))) * pinhole.direction;
      for (LensPoint lens : {LensPoint{1, 0}, LensPoint{0, -1}, LensPoint{0.3, 0.4}}) {
        const Ray ray = generate_camera_ray(f, u, v, lens);
        const Vec3 want_origin = c.position + Vec3(0.3 * lens.x, 0.3 * lens.y, 0);
        EXPECT_NEAR(length(ray.origin - want_origin), 0, 1e-12);
        const double t = 7.0 / dot(ray.direction, Vec3(0, 0, -1));
        EXPECT_NEAR(length(ray.at(t) - focus), 0, 1e-9);
        EXPECT_NEAR(length(ray.direction), 1, 1e-12);
      }
    }
}

TEST(ThinLens, ConcentricMapCoversTheDiskOnce) {
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      const LensPoint p = concentric_disk((i + 0.5) / 20, (j + 0.5) / 20);
      EXPECT_LE(std::hypot(p.x, p.y), 1.0 + 1e-12);
    }
  // The square's center is the disk's, its edge midpoints the rim's.
  const LensPoint c = concentric_disk(0.5, 0.5);
  EXPECT_EQ(c.x, 0);
  EXPECT_EQ(c.y, 0);
  const LensPoint e = concentric_disk(1, 0.5);
  EXPECT_NEAR(e.x, 1, 1e-15);
  EXPECT_NEAR(e.y, 0, 1e-15);
}

const char* kBalls = R"(
  "materials": {"red": {"ambient": [0.2, 0.05, 0.05], "diffuse": [0.7, 0.1, 0.1], "specular": 0.5},
                "floor": {"ambient": 0.1, "diffuse": 0.6, "reflectivity": 0.3}},
  "lights": [{"type": "ambient", "ambient": 0.5}, {"type": "point", "position": [3, 5, 4]}],
  "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
              {"type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "red"},
              {"type": "sphere", "center": [-2, 0.5, -3], "radius": 0.5, "material": "red"},
              {"type": "sphere", "center": [1.5, 0.4, 2], "radius": 0.4, "material": "red"}]})";

std::string balls(const std::string& render, const std::string& camera_extra) {
  return R"({"render": {"width": 48, "height": 32, "background": [0.1, 0.2, 0.3])" + render +
         R"(}, "camera": {"position": [0, 2, 8], "look_at": [0, 1, 0])" + camera_extra + "}," + kBalls;
}

TEST(ThinLens, OneSampleIsThePinholeAndManyAreTheSameForAnyThreadCount) {
  const Image pinhole = render_in(balls("", ""));
  EXPECT_TRUE(same_bits(render_in(balls("", R"(, "aperture": 0.4)")), pinhole)) << "spp 1: the lens center";
  const std::string blurred = balls(R"(, "samples_per_pixel": 16)", R"(, "aperture": 0.4, "focus_distance": 5)");
  const Image one = render_in(blurred, {}, 1), two = render_in(blurred, {}, 2);
  EXPECT_TRUE(same_bits(one, two));
  // Tiles of another size (the unit of interrupt and resume): the same bits.
  const Scene scene = parse_scene(blurred, "scene.json");
  RenderOptions small_tiles;
  small_tiles.threads = 2;
  small_tiles.tile_size = 8;
  EXPECT_TRUE(same_bits(render_image(scene, *build_accelerator(scene), small_tiles), two));
  EXPECT_FALSE(same_bits(one, render_in(balls(R"(, "samples_per_pixel": 16)", ""))));
}

TEST(Stereo, TwoImagesSideBySideFromEyesApart) {
  const Image pair = render_in(balls("", R"(, "stereo": {"eye_separation": 0.6})"));
  ASSERT_EQ(pair.width, 96);
  ASSERT_EQ(pair.height, 32);
  // Each half is a mono render from its eye, looking the same way.
  const auto eye = [&](double dx) {
    return render_in(R"({"render": {"width": 48, "height": 32, "background": [0.1, 0.2, 0.3]},
      "camera": {"position": [)" + std::to_string(dx) + R"(, 2, 8], "look_at": [)" + std::to_string(dx) +
                     R"(, 1, 0]},)" + kBalls);
  };
  const Image left = eye(-0.3), right = eye(0.3);
  for (int y = 0; y < 32; y += 3)
    for (int x = 0; x < 48; x += 5) {
      expect_color(pixel(pair, x, y), pixel(left, x, y), 1e-5);
      expect_color(pixel(pair, x + 48, y), pixel(right, x, y), 1e-5);
    }
}

// --- fog --------------------------------------------------------------------

// A sphere 9 units ahead of the center pixel's ray, lit by an ambient light
// alone: C = R_a L_a there, the background elsewhere.
std::string foggy(const std::string& fog) {
  return R"({"render": {"width": 9, "height": 9, "background": [0.1, 0.2, 0.3], "fog": )" + fog + R"(},
    "camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov_y": 10},
    "materials": {"m": {"ambient": [0.5, 0.25, 1], "diffuse": 0, "specular": 0}},
    "lights": [{"type": "ambient", "ambient": 1}],
    "objects": [{"type": "sphere", "center": [0, 0, -10], "radius": 1, "material": "m"}]})";
}

TEST(Fog, EachTypeMixesTheHitWithTheFogColorByItsFactor) {
  const Color c(0.5, 0.25, 1), fog(0.7, 0.6, 0.5), background(0.1, 0.2, 0.3);
  const double t = 9;
  struct Case {
    std::string json;
    double f;
  };
  const Case cases[] = {
      {R"({"color": [0.7, 0.6, 0.5], "type": "linear", "start": 2, "end": 20})", (20 - t) / 18},
      {R"({"color": [0.7, 0.6, 0.5], "type": "linear", "start": 10, "end": 20})", 1.0},
      {R"({"color": [0.7, 0.6, 0.5], "type": "linear", "end": 5})", 0.0},
      {R"({"color": [0.7, 0.6, 0.5], "type": "exp", "density": 0.1})", std::exp(-0.1 * t)},
      {R"({"color": [0.7, 0.6, 0.5], "type": "exp2", "density": 0.1})", std::exp(-(0.1 * t) * (0.1 * t))},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.json);
    const Image image = render_in(foggy(k.json));
    expect_color(pixel(image, 4, 4), k.f * c + (1 - k.f) * fog);
    expect_color(pixel(image, 0, 0), background);  // a miss is not fogged
  }
}

TEST(Fog, ReflectedRaysAreFoggedAlongTheirOwnLength) {
  // A mirror 9 units ahead reflects the camera ray straight back onto a
  // wall 4 units behind the camera: 13 units along the second ray.
  const std::string text = R"({"render": {"width": 9, "height": 9, "max_depth": 2,
      "fog": {"color": [0, 0, 1], "type": "exp", "density": 0.05}},
    "camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov_y": 1},
    "materials": {"mirror": {"ambient": 0, "diffuse": 0, "specular": 0, "reflectivity": 1},
                  "wall": {"ambient": [1, 0, 0], "diffuse": 0, "specular": 0}},
    "lights": [{"type": "ambient", "ambient": 1}],
    "objects": [{"type": "plane", "point": [0, 0, -9], "normal": [0, 0, 1], "material": "mirror"},
                {"type": "plane", "point": [0, 0, 4], "normal": [0, 0, -1], "material": "wall"}]})";
  const double f1 = std::exp(-0.05 * 9), f2 = std::exp(-0.05 * 13);
  const Color wall = f2 * Color(1, 0, 0) + (1 - f2) * Color(0, 0, 1);
  expect_color(pixel(render_in(text), 4, 4), f1 * wall + (1 - f1) * Color(0, 0, 1));
}

// --- environment ------------------------------------------------------------

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("glint-env-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// A little-endian PFM whose texel (i, j) (row j from the top) is (i, j, 1).
void write_map(const fs::path& file, int w, int h) {
  std::ofstream out(file, std::ios::binary);
  out << "PF\n" << w << " " << h << "\n-1\n";
  for (int j = h - 1; j >= 0; --j)  // PFM rows run from the bottom
    for (int i = 0; i < w; ++i) {
      const float rgb[3] = {static_cast<float>(i), static_cast<float>(j), 1.0f};
      out.write(reinterpret_cast<const char*>(rgb), sizeof rgb);
    }
}

// The contract's lookup, written out: u from atan2(d.x, -d.z) plus the
// rotation, v from the angle to +y; bilinear, u wrapping, v clamped.
Color environment_formula(const Vec3& d_in, int w, int h, double rotate, const Color& scale) {
  const Vec3 d = normalize(d_in);
  double u = 0.5 + std::atan2(d.x, -d.z) / (2 * kPi) + rotate / 360;
  u -= std::floor(u);
  const double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
  const double x = u * w - 0.5, y = v * h - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  const auto texel = [&](int i, int j) {
    i = ((i % w) + w) % w;
    j = std::clamp(j, 0, h - 1);
    return Color(i, j, 1);
  };
  const Color top = (1 - fx) * texel(x0, y0) + fx * texel(x0 + 1, y0);
  const Color bottom = (1 - fx) * texel(x0, y0 + 1) + fx * texel(x0 + 1, y0 + 1);
  return scale * ((1 - fy) * top + fy * bottom);
}

TEST(Environment, MissedRaysSeeTheMapInTheirDirection) {
  TempDir dir;
  write_map(dir.path() / "sky.pfm", 8, 4);
  for (double rotate : {0.0, 90.0, -180.0, 33.0}) {
    SCOPED_TRACE(rotate);
    const std::string text = R"({"render": {"width": 24, "height": 12,
        "environment": {"file": "sky.pfm", "rotate": )" + std::to_string(rotate) + R"(, "scale": [2, 1, 0.5]}},
      "camera": {"type": "equirectangular", "position": [0, 0, 0], "look_at": [0, 0, -1]},
      "objects": []})";
    const Image image = render_in(text, dir.path());
    for (int y = 0; y < 12; y += 1)
      for (int x = 0; x < 24; x += 1) {
        const double lon = ((x + 0.5) / 24 - 0.5) * 2 * kPi, lat = (0.5 - (y + 0.5) / 12) * kPi;
        const Vec3 d(std::cos(lat) * std::sin(lon), std::sin(lat), -std::cos(lat) * std::cos(lon));
        expect_color(pixel(image, x, y), environment_formula(d, 8, 4, rotate, Color(2, 1, 0.5)), 1e-5);
      }
  }
}

TEST(Environment, ReflectionsSeeItToo) {
  TempDir dir;
  write_map(dir.path() / "sky.pfm", 8, 4);
  // A mirror floor under a camera looking straight down: the reflected ray
  // goes straight up, where v = 0 (the top row, clamped).
  const std::string text = R"({"render": {"width": 3, "height": 3, "environment": {"file": "sky.pfm"}},
    "camera": {"position": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 1},
    "materials": {"mirror": {"ambient": 0, "diffuse": 0, "specular": 0, "reflectivity": 1}},
    "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "mirror"}]})";
  const Color c = pixel(render_in(text, dir.path()), 1, 1);
  EXPECT_NEAR(c.y, 0, 1e-6);  // row 0
  EXPECT_NEAR(c.z, 1, 1e-6);
}

// --- ambient occlusion ------------------------------------------------------

std::string occluded(const std::string& occlusion, const std::string& objects) {
  return R"({"render": {"width": 5, "height": 5},
    "camera": {"position": [0, 0.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 1},
    "materials": {"m": {"ambient": 1, "diffuse": 0, "specular": 0}},
    "lights": [{"type": "ambient", "ambient": 1)" + occlusion + R"(}],
    "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "m"})" + objects + "]}";
}

TEST(AmbientOcclusion, OpenSkyLeavesTheAmbientTermAsItIs) {
  EXPECT_TRUE(same_bits(render_in(occluded(R"(, "occlusion": {"samples": 16})", "")), render_in(occluded("", ""))));
}

TEST(AmbientOcclusion, UnderACeilingTheOpenFractionIsTheCosineLaw) {
  // A ceiling at height h: a cosine-weighted direction at angle theta meets
  // it at h / cos(theta), within D when cos(theta) > h / D; cos(theta) has
  // the distribution function c^2, so the open fraction is (h / D)^2.
  const double h = 1, d = 2;
  const std::string ceiling = R"(, {"type": "plane", "point": [0, 1, 0], "normal": [0, -1, 0], "material": "m"})";
  const Image image = render_in(occluded(R"(, "occlusion": {"samples": 4096, "distance": 2})", ceiling));
  EXPECT_NEAR(pixel(image, 2, 2).x, (h / d) * (h / d), 0.01);
  // Without a distance the ceiling hides every direction.
  EXPECT_EQ(pixel(render_in(occluded(R"(, "occlusion": {"samples": 64})", ceiling)), 2, 2).x, 0.0f);
  // And within a shorter distance none.
  EXPECT_EQ(pixel(render_in(occluded(R"(, "occlusion": {"samples": 64, "distance": 0.9})", ceiling)), 2, 2).x,
            1.0f);
}

TEST(AmbientOcclusion, SameImageForAnyThreadCount) {
  std::string s = balls(R"(, "samples_per_pixel": 4)", "");
  const std::string ambient = R"({"type": "ambient", "ambient": 0.5})";
  s.replace(s.find(ambient), ambient.size(),
            R"({"type": "ambient", "ambient": 0.5, "occlusion": {"samples": 9, "distance": 3}})");
  EXPECT_TRUE(same_bits(render_in(s, {}, 1), render_in(s, {}, 2)));
  EXPECT_FALSE(same_bits(render_in(s), render_in(balls(R"(, "samples_per_pixel": 4)", ""))));
}

}  // namespace
}  // namespace glint
