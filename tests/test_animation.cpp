// Animation: interpolation (lerp, slerp) at known parameters with exact
// endpoints, the scene of a frame (a frame on a key renders exactly like the
// static scene it describes), and the loader's errors for bad animations.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "glint/accel/accelerator.h"
#include "glint/io/scene_loader.h"
#include "glint/render/renderer.h"
#include "glint/scene/animation.h"

namespace glint {
namespace {

TEST(Animation, LerpIsExactAtBothEnds) {
  const Vec3 a{0.1, -3.7, 1e-3}, b{7.3, 0.3, -2.9};
  EXPECT_EQ(lerp(a, b, 0.0), a);
  EXPECT_EQ(lerp(a, b, 1.0), b);  // a + 1 * (b - a) would round away from b
  const Vec3 mid = lerp(a, b, 0.25);
  EXPECT_NEAR(mid.x, 0.1 + 0.25 * 7.2, 1e-12);
  EXPECT_NEAR(mid.y, -3.7 + 0.25 * 4.0, 1e-12);
  EXPECT_DOUBLE_EQ(lerp(10.0, 20.0, 0.5), 15.0);
}

// The angle (degrees) of rotation q about the z axis, from what it does to x.
double z_angle(const Quat& q) {
  const Vec3 x = rotation_from_quat(q).vector({1, 0, 0});
  return std::atan2(x.y, x.x) * 180.0 / std::numbers::pi;
}

TEST(Animation, SlerpFollowsTheArcAtConstantSpeed) {
  const Quat a = quat_from_axis_angle({0, 0, 1}, 0), b = quat_from_axis_angle({0, 0, 1}, 90);
  EXPECT_NEAR(z_angle(slerp(a, b, 0.5)), 45.0, 1e-9);
  EXPECT_NEAR(z_angle(slerp(a, b, 0.25)), 22.5, 1e-9);
  EXPECT_NEAR(z_angle(slerp(a, b, 0.9)), 81.0, 1e-9);
  const Quat q0 = slerp(a, b, 0.0), q1 = slerp(a, b, 1.0);
  EXPECT_EQ(q0.w, a.w);
  EXPECT_EQ(q0.z, a.z);
  EXPECT_EQ(q1.w, b.w);
  EXPECT_EQ(q1.z, b.z);
}

TEST(Animation, SlerpTakesTheShortArc) {
  // 0 to 270 degrees is -90 the short way: halfway is -45, not +135.
  const Quat a = quat_from_axis_angle({0, 0, 1}, 0), b = quat_from_axis_angle({0, 0, 1}, 270);
  EXPECT_NEAR(z_angle(slerp(a, b, 0.5)), -45.0, 1e-9);
}

TEST(Animation, SlerpBetweenTwoAxesStaysARotation) {
  const Quat a = quat_from_axis_angle(normalize(Vec3{1, 2, 3}), 40), b = quat_from_axis_angle({0, 1, 0}, -70);
  const Transform r = rotation_from_quat(slerp(a, b, 0.37));
  const Vec3 v = r.vector({0.3, -0.4, 1.2});
  EXPECT_NEAR(length(v), length(Vec3{0.3, -0.4, 1.2}), 1e-12);
}

TEST(Animation, QuaternionMatrixMatchesRodrigues) {
  const Vec3 axis = normalize(Vec3{1, -2, 0.5});
  const Transform a = rotation_from_quat(quat_from_axis_angle(axis, 33));
  const Transform b = Transform::rotate(axis, 33);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(a.m[i][j], b.m[i][j], 1e-14);
}

TEST(Animation, TracksClampOutsideTheirKeysAndInterpolateInside) {
  const std::vector<Key<Vec3>> keys = {{1.0, {0, 0, 0}}, {2.0, {4, 0, 0}}, {4.0, {4, 8, 0}}};
  EXPECT_EQ(sample_track(keys, 0.0), (Vec3{0, 0, 0}));
  EXPECT_EQ(sample_track(keys, 9.0), (Vec3{4, 8, 0}));
  EXPECT_EQ(sample_track(keys, 2.0), (Vec3{4, 0, 0}));
  EXPECT_EQ(sample_track(keys, 1.5), (Vec3{2, 0, 0}));
  EXPECT_EQ(sample_track(keys, 3.0), (Vec3{4, 4, 0}));
}

constexpr const char* kAnimated = R"({
  "render": {"width": 32, "height": 24},
  "camera": {"position": [0, 1, 6], "look_at": [0, 0.5, 0]},
  "lights": [{"type": "point", "position": [3, 4, 4]}],
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "name": "floor"},
    {"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "name": "ball",
     "transform": {"scale": 1.5, "translate": [0, 0.75, 0]}},
    {"type": "box", "min": [-0.5, 0, -0.5], "max": [0.5, 1, 0.5], "name": "crate",
     "transform": {"translate": [1.5, 0, 0]}}
  ],
  "animation": {"frames": 5, "fps": 2, "keys": [
    {"time": 0, "camera": {"position": [0, 1, 6]},
     "objects": {"ball": {"translate": [-1, 0.75, 0]}, "crate": {"rotate": {"axis": [0, 1, 0], "angle": 0}}}},
    {"time": 2, "camera": {"position": [1, 2, 6], "fov_y": 50},
     "objects": {"ball": {"translate": [1, 0.75, 0]}, "crate": {"rotate": {"axis": [0, 1, 0], "angle": 90}}}}
  ]}
})";

// kAnimated's frame 4 (t = 2 s, the last key) written as a static scene.
constexpr const char* kLastKeyStatic = R"({
  "render": {"width": 32, "height": 24},
  "camera": {"position": [1, 2, 6], "look_at": [0, 0.5, 0], "fov_y": 50},
  "lights": [{"type": "point", "position": [3, 4, 4]}],
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "name": "floor"},
    {"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "name": "ball",
     "transform": {"scale": 1.5, "translate": [1, 0.75, 0]}},
    {"type": "box", "min": [-0.5, 0, -0.5], "max": [0.5, 1, 0.5], "name": "crate",
     "transform": {"rotate": {"axis": [0, 1, 0], "angle": 90}, "translate": [1.5, 0, 0]}}
  ]
})";

TEST(Animation, LoaderReadsFramesAndKeys) {
  const Scene scene = parse_scene(kAnimated, "anim.json");
  EXPECT_EQ(frame_count(scene), 5);
  EXPECT_EQ(scene.animation.fps, 2.0);
  ASSERT_EQ(scene.animation.objects.size(), 2u);
  EXPECT_EQ(scene.animation.objects[0].object, 1u);
  EXPECT_EQ(frame_count(parse_scene(kLastKeyStatic, "static.json")), 1);
}

TEST(Animation, FrameOnAKeyRendersLikeTheStaticScene) {
  const Scene frame = scene_at_frame(parse_scene(kAnimated, "anim.json"), 4);
  const Scene still = parse_scene(kLastKeyStatic, "static.json");
  EXPECT_EQ(render_image(frame, *build_accelerator(frame)).rgb, render_image(still, *build_accelerator(still)).rgb);
}

TEST(Animation, FrameBetweenKeysIsInterpolated) {
  const Scene base = parse_scene(kAnimated, "anim.json");
  const Scene mid = scene_at_frame(base, 2);  // t = 1 s, halfway
  EXPECT_EQ(mid.camera.position, (Vec3{0.5, 1.5, 6}));
  EXPECT_DOUBLE_EQ(mid.camera.fov_y, 50);  // keyed at t = 2 only: a one-key track is constant
  const Object& ball = mid.objects[1];
  ASSERT_NE(ball.transform, kNoTransform);
  const Vec3 c = mid.transforms[ball.transform].point({0, 0, 0});
  EXPECT_NEAR(c.x, 0.0, 1e-12);
  EXPECT_NEAR(c.y, 0.75, 1e-12);
  // The crate turned 45 degrees about y: its local x axis points along (1, 0, -1)/sqrt 2.
  const Vec3 x = mid.transforms[mid.objects[2].transform].vector({1, 0, 0});
  EXPECT_NEAR(x.x, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(x.z, -std::sqrt(0.5), 1e-12);
  EXPECT_EQ(mid.objects.size(), base.objects.size());
}

// The first error of kAnimated with `replace` substituted for `find` (and
// `replace2` for `find2`).
std::string error_of(const std::string& find, const std::string& replace, const std::string& find2 = "",
                     const std::string& replace2 = "") {
  std::string text = kAnimated;
  for (const auto& [f, r] : {std::pair{find, replace}, std::pair{find2, replace2}}) {
    if (f.empty()) continue;
    const size_t at = text.find(f);
    EXPECT_NE(at, std::string::npos) << f;
    if (at != std::string::npos) text.replace(at, f.size(), r);
  }
  try {
    parse_scene(text, "anim.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Animation, LoaderErrors) {
  EXPECT_EQ(error_of(R"("ball": {"translate": [1)", R"("bal": {"translate": [1)"),
            "anim.json:16:18: animation.keys[1].objects.bal: unknown object \"bal\" (did you mean \"ball\"?)");
  EXPECT_EQ(error_of(R"({"time": 2,)", R"({"time": 0,)"),
            "anim.json:15:14: animation.keys[1].time: key times must increase (the previous key is at 0)");
  EXPECT_EQ(error_of(R"("frames": 5)", R"("frames": 0)"), "anim.json:12:27: animation.frames: must be >= 1 (got 0)");
  EXPECT_EQ(error_of(R"("fps": 2)", R"("fps": -2)"), "anim.json:12:37: animation.fps: must be > 0 (got -2)");
  EXPECT_EQ(error_of(R"("camera": {"position": [1, 2, 6])", R"("camera": {"positon": [1, 2, 6])"),
            "anim.json:15:28: animation.keys[1].camera: unknown key \"positon\" (did you mean \"position\"?)");
  EXPECT_EQ(error_of(R"("fov_y": 50)", R"("fov_y": 180)"),
            "anim.json:15:60: animation.keys[1].camera.fov_y: must be between 0 and 180 degrees, exclusive (got 180)");
  EXPECT_EQ(error_of(R"({"translate": [1, 0.75, 0]})", R"({"matrix": [1, 0.75, 0]})"),
            "anim.json:16:27: animation.keys[1].objects.ball: unknown key \"matrix\" "
            "(expected one of \"scale\", \"rotate\", \"translate\")");
  EXPECT_EQ(error_of(R"("transform": {"translate": [1.5, 0, 0]})",
                     R"("transform": {"matrix": [1,0,0,1.5, 0,1,0,0, 0,0,1,0, 0,0,0,1]})"),
            "anim.json:14:56: animation.keys[0].objects.crate: object \"crate\" has a \"matrix\" transform, which "
            "cannot be animated (write it as scale, rotate and translate)");
  EXPECT_EQ(error_of(R"("name": "floor")", R"("name": "ball")"),
            "anim.json:14:18: animation.keys[0].objects.ball: 2 objects are named \"ball\"; an animated object "
            "needs a name of its own");
  EXPECT_EQ(error_of(R"("frames": 5)", R"("frames": 2.5)"),
            "anim.json:12:27: animation.frames: expected a whole number, got 2.5");
  EXPECT_EQ(error_of(R"("keys": [)", R"("keys": [], "k": [)"),
            "anim.json:12:52: animation: unknown key \"k\" (expected one of \"frames\", \"fps\", \"keys\")");
  // Camera straight down with y up: fine at the keys' ends, parallel at frame 0.
  EXPECT_EQ(
      error_of(R"("camera": {"position": [0, 1, 6]})", R"("camera": {"position": [0, 9, 0], "look_at": [0, 0, 0]})"),
      "anim.json:12:16: animation: frame 0: the camera's up vector is parallel to the view direction");
  EXPECT_EQ(error_of(R"("ball": {"translate": [-1, 0.75, 0]})", R"("ball": {"scale": -1})",
                     R"("ball": {"translate": [1, 0.75, 0]})", R"("ball": {"scale": 1})"),
            "anim.json:12:16: animation: frame 2: the transform of object \"ball\" is singular");
}

}  // namespace
}  // namespace glint
