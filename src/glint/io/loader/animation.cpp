// The "animation" section (a glint addition, docs/scene-format.md): camera and
// object key frames.
#include "glint/io/loader/scene_reader.h"

#include <algorithm>
#include <map>
#include <string>
#include <utility>

namespace glint::loader {

void SceneReader::read_animation(const Value& a, const std::optional<Value>& objects) {
  const Path path("animation");
  expect_object(a, path);
  check_keys(a, path, {"frames", "fps", "keys"});
  Animation anim;
  anim.frames = integer(require(a, path, "frames"), join(path, "frames"), 1, kMaxFrames);
  if (auto f = a.find("fps")) anim.fps = positive(*f, join(path, "fps"));
  const Value keys = require(a, path, "keys");
  const Path keys_path = join(path, "keys");
  expect_array(keys, keys_path);
  if (keys.size() == 0) fail(keys, keys_path, "needs at least one key");
  std::map<std::string, size_t, std::less<>> tracks_of;  // object name -> anim.objects
  double previous = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    const Path kp = index(keys_path, i);
    const Value k = keys[i];
    expect_object(k, kp);
    check_keys(k, kp, {"time", "camera", "objects"});
    const Value tv = require(k, kp, "time");
    const double time = non_negative(tv, join(kp, "time"));
    if (i > 0 && !(time > previous))
      fail(tv, join(kp, "time"), "key times must increase (the previous key is at " + format_number(previous) + ")");
    previous = time;
    if (auto c = k.find("camera")) read_camera_key(*c, join(kp, "camera"), time, anim.camera);
    if (auto o = k.find("objects")) {
      const Path op = join(kp, "objects");
      expect_object(*o, op);
      for (size_t m = 0; m < o->size(); ++m) {
        const std::string_view name = o->key(m);
        auto it = tracks_of.find(name);
        if (it == tracks_of.end()) {
          ObjectTracks tracks;
          if (!find_animated_object(*o, m, op, objects, tracks)) continue;  // that object failed to load
          anim.objects.push_back(std::move(tracks));
          it = tracks_of.emplace(std::string(name), anim.objects.size() - 1).first;
        }
        read_object_key(o->member(m), Path(op, name), time, anim.objects[it->second]);
      }
    }
  }
  scene_.animation = std::move(anim);
  if (const std::string what = check_animation(scene_); !what.empty()) fail(a, path, what);
}

void SceneReader::read_camera_key(const Value& c, const Path& path, double time, CameraTracks& tracks) const {
  expect_object(c, path);
  check_keys(c, path, {"position", "look_at", "up", "fov_y"});
  if (auto v = c.find("position")) tracks.position.push_back({time, vec3(*v, join(path, "position"))});
  if (auto v = c.find("look_at")) tracks.look_at.push_back({time, vec3(*v, join(path, "look_at"))});
  if (auto v = c.find("up")) tracks.up.push_back({time, direction(*v, join(path, "up"))});
  if (auto v = c.find("fov_y")) {
    const double fov = number(*v, join(path, "fov_y"));
    if (!(fov > 0 && fov < 180))
      fail(*v, join(path, "fov_y"), "must be between 0 and 180 degrees, exclusive (got " + format_number(fov) + ")");
    tracks.fov_y.push_back({time, fov});
  }
}

Vec3 SceneReader::scale_factors(const Value& s, const Path& p) const {
  const Vec3 f = s.is_number() ? Vec3(number(s, p)) : vec3(s, p);
  if (f.x == 0 || f.y == 0 || f.z == 0) fail(s, p, "a zero scale makes the transform singular");
  return f;
}

Rotation SceneReader::rotation(const Value& r, const Path& p) const {
  expect_object(r, p);
  check_keys(r, p, {"axis", "angle"});
  Rotation rot;
  rot.axis = direction(require(r, p, "axis"), join(p, "axis"));
  rot.degrees = number(require(r, p, "angle"), join(p, "angle"));
  rot.q = quat_from_axis_angle(rot.axis, rot.degrees);
  return rot;
}

void SceneReader::read_object_key(const Value& v, const Path& path, double time, ObjectTracks& tracks) const {
  expect_object(v, path);
  check_keys(v, path, {"scale", "rotate", "translate"});
  if (auto s = v.find("scale")) tracks.scale.push_back({time, scale_factors(*s, join(path, "scale"))});
  if (auto r = v.find("rotate")) tracks.rotate.push_back({time, rotation(*r, join(path, "rotate"))});
  if (auto t = v.find("translate")) tracks.translate.push_back({time, vec3(*t, join(path, "translate"))});
}

// The object named by member m of a key's "objects": its index, static
// transform and object-space geometry. False when that object did not load
// (validate goes on without it).
bool SceneReader::find_animated_object(const Value& keyed, size_t m, const Path& path,
                                       const std::optional<Value>& objects, ObjectTracks& tracks) const {
  const std::string_view name = keyed.key(m);
  std::vector<size_t> named;
  Keys all_names;
  for (size_t j = 0; objects && objects->is_array() && j < objects->size(); ++j) {
    const Value o = (*objects)[j];
    const auto n = o.is_object() ? o.find("name") : std::nullopt;
    if (!n || !n->is_string()) continue;
    all_names.push_back(n->as_string());
    if (n->as_string() == name) named.push_back(j);
  }
  auto fail_name = [&](const std::string& what) { throw Error(keyed.key_location(m), Path(path, name).str(), what); };
  if (named.empty()) {
    std::string what = "unknown object " + quote_text(name);
    const std::string hint = closest_match(name, all_names);
    fail_name(what + (hint.empty() ? " (no object has this \"name\")" : " (did you mean \"" + hint + "\"?)"));
  }
  if (named.size() > 1)
    fail_name(std::to_string(named.size()) + " objects are named " + quote_text(name) +
              "; an animated object needs a name of its own");
  const auto it = std::find(object_json_index_.begin(), object_json_index_.end(), named[0]);
  if (it == object_json_index_.end()) return false;
  tracks.object = static_cast<uint32_t>(it - object_json_index_.begin());
  const Value o = (*objects)[named[0]];
  const Path op = index("objects", named[0]);
  if (auto t = o.find("transform")) {
    if (t->find("matrix"))
      fail_name("object " + quote_text(name) +
                " has a \"matrix\" transform, which cannot be animated "
                "(write it as scale, rotate and translate)");
    const Path tp = join(op, "transform");
    if (auto s = t->find("scale")) {
      tracks.has_scale = true;
      tracks.scale0 = scale_factors(*s, join(tp, "scale"));
    }
    if (auto r = t->find("rotate")) {
      tracks.has_rotate = true;
      tracks.rotate0 = rotation(*r, join(tp, "rotate"));
    }
    if (auto tr = t->find("translate")) {
      tracks.has_translate = true;
      tracks.translate0 = vec3(*tr, join(tp, "translate"));
    }
  }
  const ShapeType type = scene_.objects[tracks.object].type;
  if (type == ShapeType::plane) {
    tracks.object_space[0] = vec3(require(o, op, "point"), join(op, "point"));
    tracks.object_space[1] = direction(require(o, op, "normal"), join(op, "normal"));
  } else if (type == ShapeType::triangle) {
    const Value verts = require(o, op, "vertices");
    for (size_t i = 0; i < 3; ++i) tracks.object_space[i] = vec3(verts[i], index(join(op, "vertices"), i));
  }
  return true;
}

}  // namespace glint::loader
