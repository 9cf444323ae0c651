#include "glint/scene/animation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "glint/scene/scene.h"

namespace glint {

Quat quat_from_axis_angle(const Vec3& a, double degrees) {
  const double half = 0.5 * degrees * std::numbers::pi / 180.0;
  const double s = std::sin(half);
  return {std::cos(half), a.x * s, a.y * s, a.z * s};
}

namespace {

double dot(const Quat& a, const Quat& b) { return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z; }

Quat weighted_sum(double wa, const Quat& a, double wb, const Quat& b) {
  return {wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z};
}

Quat normalized(const Quat& q) {
  const double n = std::sqrt(dot(q, q));
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

// Index i of the segment [keys[i], keys[i+1]] holding t, with u in (0, 1);
// or a key index and u = 0 when t is on a key or outside all of them.
template <class T>
std::pair<size_t, double> locate(const std::vector<Key<T>>& keys, double t) {
  if (t <= keys.front().time) return {0, 0.0};
  if (t >= keys.back().time) return {keys.size() - 1, 0.0};
  const auto next =
      std::upper_bound(keys.begin(), keys.end(), t, [](double time, const Key<T>& k) { return time < k.time; });
  const size_t i = static_cast<size_t>(next - keys.begin()) - 1;
  if (keys[i].time == t) return {i, 0.0};
  return {i, (t - keys[i].time) / (keys[i + 1].time - keys[i].time)};
}

}  // namespace

Quat slerp(const Quat& a, const Quat& b_in, double u) {
  if (u == 0) return a;
  // q and -q are the same rotation: take the one on a's side (the short arc).
  const double d = dot(a, b_in);
  const Quat b = d < 0 ? Quat{-b_in.w, -b_in.x, -b_in.y, -b_in.z} : b_in;
  if (u == 1) return b;
  const double c = std::min(1.0, std::abs(d));
  if (c > 0.9995) return normalized(weighted_sum(1 - u, a, u, b));  // nearly equal: sin θ ≈ 0
  const double theta = std::acos(c), s = std::sin(theta);
  return weighted_sum(std::sin((1 - u) * theta) / s, a, std::sin(u * theta) / s, b);
}

Transform rotation_from_quat(const Quat& q_in) {
  const Quat q = normalized(q_in);
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  Transform t;
  t.m = {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y), 0},
          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x), 0},
          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y), 0}}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t.inv[i][j] = t.m[j][i];  // a rotation's inverse is its transpose
  return t;
}

Vec3 lerp(const Vec3& a, const Vec3& b, double u) { return (1 - u) * a + u * b; }
double lerp(double a, double b, double u) { return (1 - u) * a + u * b; }

Vec3 sample_track(const std::vector<Key<Vec3>>& keys, double t) {
  const auto [i, u] = locate(keys, t);
  return u == 0 ? keys[i].value : lerp(keys[i].value, keys[i + 1].value, u);
}

double sample_track(const std::vector<Key<double>>& keys, double t) {
  const auto [i, u] = locate(keys, t);
  return u == 0 ? keys[i].value : lerp(keys[i].value, keys[i + 1].value, u);
}

Rotation sample_track(const std::vector<Key<Rotation>>& keys, double t, bool* on_key) {
  const auto [i, u] = locate(keys, t);
  *on_key = u == 0;
  if (u == 0) return keys[i].value;
  Rotation r;
  r.q = slerp(keys[i].value.q, keys[i + 1].value.q, u);
  return r;
}

std::optional<Transform> object_transform_at(const ObjectTracks& tr, double t) {
  // The same sequence of compositions as the loader's read_transform, so a
  // frame on a key equals the static transform bit for bit.
  std::optional<Transform> out;
  if (!tr.scale.empty() || tr.has_scale)
    out = Transform::scale(tr.scale.empty() ? tr.scale0 : sample_track(tr.scale, t));
  if (!tr.rotate.empty() || tr.has_rotate) {
    bool on_key = true;
    const Rotation r = tr.rotate.empty() ? tr.rotate0 : sample_track(tr.rotate, t, &on_key);
    const Transform rot = on_key ? Transform::rotate(r.axis, r.degrees) : rotation_from_quat(r.q);
    out = compose(rot, out.value_or(Transform{}));
  }
  if (!tr.translate.empty() || tr.has_translate) {
    const Vec3 v = tr.translate.empty() ? tr.translate0 : sample_track(tr.translate, t);
    out = compose(Transform::translate(v), out.value_or(Transform{}));
  }
  return out;
}

double frame_time(const Animation& animation, int frame) { return frame / animation.fps; }

int frame_count(const Scene& scene) { return scene.animation.frames > 0 ? scene.animation.frames : 1; }

namespace {

Camera camera_at(const Camera& base, const CameraTracks& tr, double t) {
  Camera c = base;
  if (!tr.position.empty()) c.position = sample_track(tr.position, t);
  if (!tr.look_at.empty()) c.look_at = sample_track(tr.look_at, t);
  if (!tr.up.empty()) c.up = sample_track(tr.up, t);
  if (!tr.fov_y.empty()) c.fov_y = sample_track(tr.fov_y, t);
  return c;
}

// Re-adds the object through the scene builders (as the loader did) with its
// frame transform, and puts the result back at its own index.
void move_object(Scene& scene, const ObjectTracks& tr, const std::optional<Transform>& xf) {
  const Object old = scene.objects[tr.object];
  switch (old.type) {
    case ShapeType::sphere: add_sphere(scene, scene.spheres[old.shape], old.material, xf); break;
    case ShapeType::box: add_box(scene, scene.boxes[old.shape], old.material, xf); break;
    case ShapeType::mesh: add_mesh_object(scene, old.shape, old.material, old.smooth, xf); break;
    // Kept in object space like spheres: a copy of the shape with the frame's transform.
    case ShapeType::cylinder:
    case ShapeType::cone:
      add_cone(scene, Cone(scene.cones[old.shape]), old.material, xf, old.type == ShapeType::cylinder);
      break;
    case ShapeType::disk: add_disk(scene, Disk(scene.disks[old.shape]), old.material, xf); break;
    case ShapeType::polygon: add_polygon(scene, Polygon(scene.polygons[old.shape]), old.material, xf); break;
    case ShapeType::torus: add_torus(scene, Torus(scene.tori[old.shape]), old.material, xf); break;
    case ShapeType::csg: add_csg(scene, Csg(scene.csgs[old.shape]), old.material, xf); break;
    case ShapeType::plane: {
      const Plane p{tr.object_space[0], tr.object_space[1]};
      add_plane(scene, p, old.material, xf);
      break;
    }
    case ShapeType::triangle: {
      const Triangle tri{tr.object_space[0], tr.object_space[1], tr.object_space[2]};
      add_triangle(scene, tri, old.material, xf);
      break;
    }
  }
  scene.objects[tr.object] = scene.objects.back();
  scene.objects.pop_back();
}

}  // namespace

Scene scene_at_frame(const Scene& base, int frame) {
  Scene scene = base;
  const Animation& a = base.animation;
  if (a.frames == 0) return scene;
  const double t = frame_time(a, frame);
  scene.camera = camera_at(base.camera, a.camera, t);
  for (const ObjectTracks& tr : a.objects) move_object(scene, tr, object_transform_at(tr, t));
  return scene;
}

std::string check_animation(const Scene& scene) {
  const Animation& a = scene.animation;
  for (int f = 0; f < a.frames; ++f) {
    const double t = frame_time(a, f);
    const std::string at = "frame " + std::to_string(f) + ": ";
    const Camera c = camera_at(scene.camera, a.camera, t);
    const Vec3 view = c.look_at - c.position;
    if (!(length(view) > 0)) return at + "the camera's look_at equals its position";
    if (!(length(c.up) > 0)) return at + "the camera's up vector is zero";
    if (!(length(cross(normalize(view), normalize(c.up))) > 1e-9))
      return at + "the camera's up vector is parallel to the view direction";
    for (const ObjectTracks& tr : a.objects) {
      const auto xf = object_transform_at(tr, t);
      if (xf && !Transform::from_affine(xf->m)) {
        const auto name = scene.object_names.find(tr.object);
        return at + "the transform of object \"" + (name == scene.object_names.end() ? "" : name->second) +
               "\" is singular";
      }
    }
  }
  return {};
}

}  // namespace glint
