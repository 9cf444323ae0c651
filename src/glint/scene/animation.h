// Animation: keyframed camera and object transforms (the scene file's
// "animation" section, docs/scene-format.md). Plain data plus the functions
// that interpolate it and build the Scene of one frame; the loader fills it.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "glint/math/transform.h"

namespace glint {

struct Scene;

// A rotation as a unit quaternion (w, x, y, z): what slerp interpolates.
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

Quat quat_from_axis_angle(const Vec3& unit_axis, double degrees);
// Shortest-arc spherical interpolation; exact at u = 0 and u = 1.
Quat slerp(const Quat& a, const Quat& b, double u);
Transform rotation_from_quat(const Quat& q);
// (1 - u) a + u b: exact at both ends (not a + u (b - a), which misses b).
Vec3 lerp(const Vec3& a, const Vec3& b, double u);
double lerp(double a, double b, double u);

template <class T>
struct Key {
  double time = 0;  // seconds
  T value;
};

// A rotation key keeps its axis and angle too, so a frame that falls on a key
// builds the very matrix a static `rotate` gives (bit-identical pixels).
struct Rotation {
  Vec3 axis{0, 1, 0};  // unit
  double degrees = 0;
  Quat q;
};

struct CameraTracks {
  std::vector<Key<Vec3>> position, look_at, up;
  std::vector<Key<double>> fov_y;
};

// One animated object. Components without keys keep the object's static
// transform's value (or are left out, as in a static transform).
struct ObjectTracks {
  uint32_t object = 0;
  std::vector<Key<Vec3>> scale, translate;
  std::vector<Key<Rotation>> rotate;
  bool has_scale = false, has_rotate = false, has_translate = false;  // static parts
  Vec3 scale0{1}, translate0{0};
  Rotation rotate0;
  // Planes and triangles are stored in world space: their geometry before any
  // transform (plane: point, normal; triangle: three vertices).
  std::array<Vec3, 3> object_space{};
};

struct Animation {
  int frames = 0;  // 0: the scene is not animated (one frame, frame 0)
  double fps = 24;
  CameraTracks camera;
  std::vector<ObjectTracks> objects;
};

// Value of a track at time t: clamped to the first/last key outside them,
// the key itself on a key, interpolated in between.
Vec3 sample_track(const std::vector<Key<Vec3>>& keys, double t);
double sample_track(const std::vector<Key<double>>& keys, double t);
Rotation sample_track(const std::vector<Key<Rotation>>& keys, double t, bool* on_key);

// The transform of an animated object at time t, composed as the loader
// composes a static one (scale, then rotate, then translate); nullopt: identity.
std::optional<Transform> object_transform_at(const ObjectTracks& tracks, double t);

double frame_time(const Animation& animation, int frame);  // frame / fps
int frame_count(const Scene& scene);                       // 1 for a static scene

// The scene as it is at `frame` (0-based): camera and animated objects moved.
// A static scene is returned unchanged. Object indices and names stay.
Scene scene_at_frame(const Scene& scene, int frame);

// What goes wrong at some frame (an up vector parallel to the view, a
// singular transform), as "frame N: what"; empty when every frame is fine.
std::string check_animation(const Scene& scene);

}  // namespace glint
