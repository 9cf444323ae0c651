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
              "pixel_filter", "adaptive"});
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

void SceneReader::read_camera(const Value& c) {
  const Path path("camera");
  expect_object(c, path);
  check_keys(c, path, {"type", "position", "look_at", "up", "fov_y", "view_height"});
  Camera& cam = scene_.camera;
  if (auto v = c.find("type"))
    cam.type = choice(*v, "camera.type", {"perspective", "orthographic"}, "camera type") == 0
                   ? CameraType::perspective
                   : CameraType::orthographic;
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
