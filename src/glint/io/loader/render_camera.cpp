// The scene's "render" settings (pixel filter, adaptive sampling) and "camera".
#include "glint/io/loader/scene_reader.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace glint::loader {

void SceneReader::read_render(const Value& r) {
  const Path path("render");
  expect_object(r, path);
  check_keys(r, path,
             {"width", "height", "samples_per_pixel", "max_depth", "shading_model", "background", "epsilon",
              "pixel_filter", "adaptive", "fog", "environment"});
  RenderSettings& s = scene_.render;
  if (auto v = r.find("width")) s.width = integer(*v, "render.width", 1, 1 << 20);
  if (auto v = r.find("height")) s.height = integer(*v, "render.height", 1, 1 << 20);
  if (auto v = r.find("samples_per_pixel"))
    s.samples_per_pixel = integer(*v, "render.samples_per_pixel", 1, kMaxSamplesPerPixel);
  if (auto v = r.find("max_depth")) s.max_depth = integer(*v, "render.max_depth", 1, kMaxDepthLimit);
  if (auto v = r.find("shading_model"))
    s.shading_model = choice(*v, "render.shading_model", {"phong", "blinn-phong"}, "shading model") == 0
                          ? ShadingModel::phong
                          : ShadingModel::blinn_phong;
  if (auto v = r.find("background")) s.background = color(*v, "render.background");
  if (auto v = r.find("epsilon")) s.epsilon = positive(*v, "render.epsilon");
  if (auto v = r.find("pixel_filter")) s.pixel_filter = pixel_filter(*v);
  if (auto v = r.find("adaptive")) s.adaptive = adaptive(*v, s.samples_per_pixel);
  if (auto v = r.find("fog")) s.fog = fog(*v, s.background);
  if (auto v = r.find("environment")) {
    if (r.find("background"))
      fail(*v, "render.environment", "give either \"background\" or \"environment\", not both");
    s.environment = environment(*v);
  }
  SourceLocation where = r.location();
  if (auto v = r.find("height")) where = v->location();
  if (auto v = r.find("width")) where = v->location();
  check_image_size(s.width, s.height, where);
}

// "gaussian", or {"type": "gaussian", "radius": 1.5, "sigma": 0.5}.
PixelFilter SceneReader::pixel_filter(const Value& v) const {
  const Path path("render.pixel_filter");
  const Keys names = {"box", "gaussian", "mitchell"};
  PixelFilter f;
  if (v.is_object()) {
    check_keys(v, path, {"type", "radius", "sigma", "b", "c"});
    const Value type = require(v, path, "type");
    f.type = static_cast<FilterType>(choice(type, "render.pixel_filter.type", names, "pixel filter"));
  } else {
    f.type = static_cast<FilterType>(choice(v, path, names, "pixel filter"));
  }
  if (f.type == FilterType::gaussian) f.radius = kGaussianRadius;
  if (f.type == FilterType::mitchell) f.radius = kMitchellRadius;
  if (!v.is_object()) return f;
  const Keys allowed = f.type == FilterType::box        ? Keys{"type"}
                       : f.type == FilterType::gaussian ? Keys{"type", "radius", "sigma"}
                                                        : Keys{"type", "radius", "b", "c"};
  for (size_t i = 0; i < v.size(); ++i)
    if (std::find(allowed.begin(), allowed.end(), v.key(i)) == allowed.end())
      throw Error(v.key_location(i), path.str(),
                  "key \"" + std::string(v.key(i)) + "\" does not apply to the " +
                      std::string(names[static_cast<size_t>(f.type)]) + " filter");
  if (auto r = v.find("radius")) {
    f.radius = positive(*r, "render.pixel_filter.radius");
    if (f.radius > kMaxFilterRadius)
      fail(*r, "render.pixel_filter.radius", "must be <= 16 (got " + format_number(f.radius) + ")");
  }
  if (auto x = v.find("sigma")) f.sigma = positive(*x, "render.pixel_filter.sigma");
  if (auto x = v.find("b")) f.b = unit_interval(*x, "render.pixel_filter.b");
  if (auto x = v.find("c")) f.c = unit_interval(*x, "render.pixel_filter.c");
  return f;
}

double SceneReader::unit_interval(const Value& v, const Path& path) const {
  const double x = number(v, path);
  if (x < 0 || x > 1) fail(v, path, "must be between 0 and 1 (got " + format_number(x) + ")");
  return x;
}

// {"max_samples_per_pixel": M, "threshold": T}
AdaptiveSampling SceneReader::adaptive(const Value& v, int samples_per_pixel) const {
  const Path path("render.adaptive");
  expect_object(v, path);
  check_keys(v, path, {"max_samples_per_pixel", "threshold"});
  AdaptiveSampling a;
  const Value m = require(v, path, "max_samples_per_pixel");
  a.max_samples_per_pixel = integer(m, "render.adaptive.max_samples_per_pixel", 1, kMaxSamplesPerPixel);
  if (a.max_samples_per_pixel < samples_per_pixel)
    fail(m, "render.adaptive.max_samples_per_pixel",
         "must be >= render.samples_per_pixel (" + std::to_string(samples_per_pixel) + ")");
  if (auto t = v.find("threshold")) a.threshold = non_negative(*t, "render.adaptive.threshold");
  return a;
}

// {"color": c, "type": "linear", "start": s, "end": e} or {"type": "exp" | "exp2", "density": k}.
Fog SceneReader::fog(const Value& v, const Color& background) const {
  const Path path("render.fog");
  expect_object(v, path);
  check_keys(v, path, {"color", "type", "start", "end", "density"});
  Fog f;
  f.color = background;  // fog that fades to the background unless told otherwise
  const Value type = require(v, path, "type");
  f.type = static_cast<FogType>(choice(type, "render.fog.type", {"linear", "exp", "exp2"}, "fog type"));
  const Keys allowed = f.type == FogType::linear ? Keys{"color", "type", "start", "end"}
                                                 : Keys{"color", "type", "density"};
  for (size_t i = 0; i < v.size(); ++i)
    if (std::find(allowed.begin(), allowed.end(), v.key(i)) == allowed.end())
      throw Error(v.key_location(i), path.str(),
                  "key \"" + std::string(v.key(i)) + "\" does not apply to " + std::string(type.as_string()) + " fog");
  if (auto x = v.find("color")) f.color = color(*x, "render.fog.color");
  if (f.type == FogType::linear) {
    if (auto x = v.find("start")) f.start = non_negative(*x, "render.fog.start");
    const Value end = require(v, path, "end");
    f.end = number(end, "render.fog.end");
    if (!(f.end > f.start))
      fail(end, "render.fog.end",
           "must be greater than \"start\" (" + format_number(f.start) + "; got " + format_number(f.end) + ")");
  } else {
    f.density = positive(require(v, path, "density"), "render.fog.density");
  }
  return f;
}

// {"file": "sky.hdr", "rotate": degrees, "scale": color}
Environment SceneReader::environment(const Value& v) {
  const Path path("render.environment");
  expect_object(v, path);
  check_keys(v, path, {"file", "rotate", "scale"});
  Environment e;
  if (auto x = v.find("rotate")) e.rotate = number(*x, "render.environment.rotate");
  if (auto x = v.find("scale")) e.scale = color(*x, "render.environment.scale");
  const Value file = require(v, path, "file");
  const std::string name = string(file, "render.environment.file");
  if (name.empty()) fail(file, "render.environment.file", "must name an image file");
  const std::filesystem::path full = beside_scene(name);
  std::error_code ec;
  if (!std::filesystem::exists(full, ec))
    fail(file, "render.environment.file", "environment file " + quote_text(full.string()) + " not found");
  try {
    e.image = texture_image(full);
  } catch (const Error& err) {
    fail(file, "render.environment.file", "environment file " + quote_text(full.string()) + ": " + err.message());
  }
  return e;
}

void SceneReader::read_camera(const Value& c) {
  const Path path("camera");
  expect_object(c, path);
  check_keys(c, path,
             {"type", "position", "look_at", "up", "fov_y", "view_height", "fov", "aperture", "focus_distance",
              "stereo"});
  Camera& cam = scene_.camera;
  static const Keys types = {"perspective", "orthographic", "fisheye", "equirectangular"};
  if (auto v = c.find("type")) cam.type = static_cast<CameraType>(choice(*v, "camera.type", types, "camera type"));
  // Keys of one projection given to another are mistakes, not no-ops.
  const auto only_for = [&](std::string_view key, CameraType type) {
    if (cam.type == type) return;
    for (size_t i = 0; i < c.size(); ++i)
      if (c.key(i) == key)
        throw Error(c.key_location(i), join(path, key).str(),
                    "applies to " + std::string(types[static_cast<size_t>(type)]) + " cameras only (this one is " +
                        std::string(types[static_cast<size_t>(cam.type)]) +
                        (key == "fov" && cam.type == CameraType::perspective ? "; did you mean \"fov_y\"?)" : ")"));
  };
  only_for("fov", CameraType::fisheye);
  only_for("aperture", CameraType::perspective);
  only_for("focus_distance", CameraType::perspective);
  if (auto v = c.find("fov")) {
    cam.fisheye_fov = number(*v, "camera.fov");
    if (!(cam.fisheye_fov > 0 && cam.fisheye_fov <= 360))
      fail(*v, "camera.fov", "must be in (0, 360] degrees (got " + format_number(cam.fisheye_fov) + ")");
  }
  if (auto v = c.find("aperture")) cam.aperture = non_negative(*v, "camera.aperture");
  if (auto v = c.find("focus_distance")) cam.focus_distance = positive(*v, "camera.focus_distance");
  if (auto v = c.find("stereo")) {
    const Path p = join(path, "stereo");
    expect_object(*v, p);
    check_keys(*v, p, {"eye_separation"});
    cam.eye_separation = positive(require(*v, p, "eye_separation"), join(p, "eye_separation"));
    // The file's width is each eye's; the image holds both side by side.
    scene_.render.width = image_width(cam, scene_.render.width);
    check_image_size(scene_.render.width, scene_.render.height, v->location());
  }
  cam.position = vec3(require(c, path, "position"), "camera.position");
  const Value look_at = require(c, path, "look_at");
  cam.look_at = vec3(look_at, "camera.look_at");
  if (cam.look_at == cam.position) fail(look_at, "camera.look_at", "must differ from camera.position");
  if (auto v = c.find("up")) cam.up = direction(*v, "camera.up");
  if (auto v = c.find("fov_y")) {
    cam.fov_y = number(*v, "camera.fov_y");
    if (!(cam.fov_y > 0 && cam.fov_y < 180))
      fail(*v, "camera.fov_y", "must be between 0 and 180 degrees, exclusive (got " + format_number(cam.fov_y) + ")");
  }
  if (auto v = c.find("view_height")) cam.view_height = positive(*v, "camera.view_height");
  const auto forward = unit(cam.look_at - cam.position);
  if (!forward) fail(look_at, "camera.look_at", "too far from camera.position (the distance overflows)");
  if (!(length(cross(*forward, cam.up)) > 1e-9)) {
    const auto up = c.find("up");
    fail(up ? *up : c, up ? "camera.up" : "camera", "up is parallel to the view direction");
  }
}

}  // namespace glint::loader
