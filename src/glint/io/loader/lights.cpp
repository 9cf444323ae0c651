// The "lights" array: point, directional, ambient, spot and area lights.
#include "glint/io/loader/scene_reader.h"

#include <algorithm>
#include <iterator>
#include <string>

namespace glint::loader {

void SceneReader::read_lights(const Value& list) {
  expect_array(list, "lights");
  for (size_t i = 0; i < list.size(); ++i) collect([&] { read_light(list[i], index("lights", i)); });
}

void SceneReader::read_light(const Value& v, const Path& path) {
  expect_object(v, path);
  static const Keys types = {"point", "directional", "ambient", "spot", "area"};
  const LightType kinds[] = {LightType::point, LightType::directional, LightType::ambient, LightType::spot,
                             LightType::area};
  Light light;
  light.type = kinds[choice(require(v, path, "type"), join(path, "type"), types, "light type")];
  const std::string type_name(
      types[static_cast<size_t>(std::find(std::begin(kinds), std::end(kinds), light.type) - std::begin(kinds))]);

  Keys allowed = {"type", "name", "ambient", "color"};
  switch (light.type) {
    case LightType::ambient: allowed.push_back("occlusion"); break;
    case LightType::point: allowed.insert(allowed.end(), {"diffuse", "specular", "position", "attenuation"}); break;
    case LightType::directional: allowed.insert(allowed.end(), {"diffuse", "specular", "direction"}); break;
    case LightType::spot:
      allowed.insert(allowed.end(),
                     {"diffuse", "specular", "position", "direction", "cutoff", "falloff", "attenuation"});
      break;
    case LightType::area:
      allowed.insert(allowed.end(), {"diffuse", "specular", "corner", "edge_u", "edge_v", "samples", "attenuation"});
      break;
  }
  // Keys that belong to other light types get a precise message.
  for (size_t k = 0; k < v.size(); ++k) {
    const std::string_view key = v.key(k);
    static const Keys any_light = {"diffuse", "specular", "position", "direction", "cutoff",   "falloff",
                                   "attenuation", "corner", "edge_u", "edge_v", "samples", "occlusion"};
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end() &&
        std::find(any_light.begin(), any_light.end(), key) != any_light.end())
      throw Error(v.key_location(k), join(path, key).str(),
                  std::string("not valid for ") +
                      (light.type == LightType::ambient || light.type == LightType::area ? "an " : "a ") + type_name +
                      " light");
  }
  check_keys(v, path, allowed);

  if (auto x = v.find("name")) light.name = string(*x, join(path, "name"));
  const auto col = v.find("color");
  if (col && (v.find("diffuse") || v.find("specular")))
    fail(*col, join(path, "color"), "give either \"color\" or \"diffuse\"/\"specular\", not both");
  if (light.type == LightType::ambient) {
    light.diffuse = light.specular = Color(0.0);
    if (col && v.find("ambient")) fail(*col, join(path, "color"), "give either \"color\" or \"ambient\", not both");
    if (col) light.ambient = color(*col, join(path, "color"));
  } else if (col) {
    light.diffuse = light.specular = color(*col, join(path, "color"));
  }
  if (auto x = v.find("ambient")) light.ambient = color(*x, join(path, "ambient"));
  if (auto x = v.find("diffuse")) light.diffuse = color(*x, join(path, "diffuse"));
  if (auto x = v.find("specular")) light.specular = color(*x, join(path, "specular"));

  if (light.type == LightType::point || light.type == LightType::spot)
    light.position = vec3(require(v, path, "position"), join(path, "position"));
  if (light.type == LightType::directional || light.type == LightType::spot)
    light.direction = direction(require(v, path, "direction"), join(path, "direction"));
  if (light.type == LightType::spot) {
    const Value c = require(v, path, "cutoff");
    light.cutoff = number(c, join(path, "cutoff"));
    if (!(light.cutoff > 0 && light.cutoff <= 180))
      fail(c, join(path, "cutoff"), "must be in (0, 180] degrees (got " + format_number(light.cutoff) + ")");
    if (auto x = v.find("falloff")) light.falloff = non_negative(*x, join(path, "falloff"));
  }
  if (light.type == LightType::area) {
    light.corner = vec3(require(v, path, "corner"), join(path, "corner"));
    const Value eu = require(v, path, "edge_u");
    light.edge_u = vec3(eu, join(path, "edge_u"));
    light.edge_v = vec3(require(v, path, "edge_v"), join(path, "edge_v"));
    if (!(length(cross(light.edge_u, light.edge_v)) > 0))
      fail(eu, join(path, "edge_u"), "edge_u and edge_v must span a parallelogram of non-zero area");
    if (auto x = v.find("samples")) light.samples = integer(*x, join(path, "samples"), 1, kMaxAreaLightSamples);
  }
  if (auto x = v.find("occlusion")) {  // {"samples": N, "distance": D}
    const Path p = join(path, "occlusion");
    expect_object(*x, p);
    check_keys(*x, p, {"samples", "distance"});
    light.occlusion_samples = integer(require(*x, p, "samples"), join(p, "samples"), 1, kMaxAreaLightSamples);
    if (auto d = x->find("distance")) light.occlusion_distance = positive(*d, join(p, "distance"));
  }
  if (auto x = v.find("attenuation")) {
    const Path p = join(path, "attenuation");
    const Vec3 a = vec3(*x, p);
    if (a.x < 0 || a.y < 0 || a.z < 0) fail(*x, p, "coefficients must be >= 0");
    if (!(a.x > 0 || a.y > 0 || a.z > 0)) fail(*x, p, "at least one coefficient must be > 0");
    light.attenuation = a;
  }
  scene_.lights.push_back(std::move(light));
}

}  // namespace glint::loader
