#include "glint/render/explain.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "glint/error.h"
#include "glint/render/camera.h"
#include "glint/render/renderer.h"

namespace glint {

PixelExplanation explain_pixel(const Scene& scene, const Accelerator& accel, int x, int y) {
  const int w = scene.render.width, h = scene.render.height;
  if (x < 0 || y < 0 || x >= w || y >= h)
    throw Error("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " + std::to_string(w) +
                "x" + std::to_string(h) + " image");
  const Integrator integrator(scene, accel);
  const CameraFrame frame = make_camera_frame(scene.camera, w, h);
  TraceContext ctx{pixel_rng(x, y), {}};
  PixelExplanation e;
  e.x = x;
  e.y = y;
  // Exactly the spp-1 path of render_image: the center ray, depth 1.
  const Ray ray = generate_camera_ray(frame, (x + 0.5) / w, (y + 0.5) / h);
  const Color c = integrator.trace_ray(ray, 1, ctx, e.ray);
  e.color = {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
  return e;
}

namespace {

using Json = nlohmann::ordered_json;

Json vec(const Vec3& v) { return Json::array({v.x, v.y, v.z}); }

const char* light_type_name(LightType t) {
  switch (t) {
    case LightType::ambient: return "ambient";
    case LightType::point: return "point";
    case LightType::directional: return "directional";
    case LightType::spot: return "spot";
    case LightType::area: return "area";
  }
  return "?";
}

Json object_name(const Scene& scene, uint32_t object) {
  auto it = scene.object_names.find(object);
  return it == scene.object_names.end() ? Json(nullptr) : Json(it->second);
}

// The textured reflectances of a material: (slot name, texture index, value at the hit).
struct TextureLookup {
  const char* slot;
  uint32_t texture;
  Color value;
};
std::vector<TextureLookup> texture_lookups(const Scene& scene, const SurfacePoint& sp) {
  std::vector<TextureLookup> out;
  if (!sp.textured) return out;
  const Material& m = scene.materials[sp.material];
  if (m.ambient_texture != kNoTexture) out.push_back({"ambient", m.ambient_texture, sp.reflectance.ambient});
  if (m.diffuse_texture != kNoTexture) out.push_back({"diffuse", m.diffuse_texture, sp.reflectance.diffuse});
  if (m.specular_texture != kNoTexture) out.push_back({"specular", m.specular_texture, sp.reflectance.specular});
  return out;
}

std::string texture_source(const Scene& scene, uint32_t texture) {
  const Texture& t = scene.textures[texture];
  return t.kind == TextureKind::checker ? std::string("checker") : scene.texture_images[t.image].file;
}

Json node_json(const Scene& scene, const RayTrace& t) {
  Json node;
  node["origin"] = vec(t.ray.origin);
  node["direction"] = vec(t.ray.direction);
  node["depth"] = t.depth;
  if (!t.hit) {
    node["hit"] = nullptr;
  } else {
    Json hit;
    hit["object"] = t.hit->object;
    hit["name"] = object_name(scene, t.hit->object);
    hit["type"] = shape_type_name(scene.objects[t.hit->object].type);  // a glint addition
    hit["t"] = t.hit->t;
    hit["point"] = vec(t.surface.p);
    hit["normal"] = vec(t.normal);
    hit["material"] = scene.materials[t.surface.material].name;
    if (scene.objects[t.hit->object].type == ShapeType::csg) {  // which solid of the tree made this surface
      const CsgLeaf& leaf = scene.csgs[scene.objects[t.hit->object].shape].leaves[t.hit->primitive];
      hit["csg"] = {{"child", t.hit->primitive},
                    {"name", leaf.name.empty() ? Json(nullptr) : Json(leaf.name)},
                    {"flipped", (t.hit->face & 1) != 0}};
    }
    if (t.surface.textured) {
      hit["uv"] = Json::array({t.surface.uv.u, t.surface.uv.v});
      Json textures = Json::array();
      for (const TextureLookup& l : texture_lookups(scene, t.surface))
        textures.push_back(
            {{"reflectance", l.slot}, {"texture", texture_source(scene, l.texture)}, {"value", vec(l.value)}});
      hit["textures"] = std::move(textures);
    }
    Json lights = Json::array();
    for (const LightTrace& lt : t.lights) {
      const Light& light = scene.lights[lt.index];
      Json lj;
      lj["index"] = lt.index;
      lj["type"] = light_type_name(light.type);
      const bool directed = light.type != LightType::ambient;
      lj["l"] = directed ? vec(lt.l) : Json(nullptr);
      lj["n_dot_l"] = directed ? Json(lt.n_dot_l) : Json(nullptr);
      lj["shadowed"] = lt.shadowed;
      lj["blocker"] = lt.blocker ? Json(*lt.blocker) : Json(nullptr);
      lj["specular_cos"] = lt.specular_cos ? Json(*lt.specular_cos) : Json(nullptr);
      lj["ambient"] = vec(lt.terms.ambient);
      lj["diffuse"] = vec(lt.terms.diffuse);
      lj["specular"] = vec(lt.terms.specular);
      if (light.type == LightType::spot) lj["spot_factor"] = lt.spot_factor;
      if (directed && light.type != LightType::directional) lj["attenuation"] = lt.attenuation;
      if (light.type == LightType::area) {
        lj["samples"] = lt.samples;
        lj["unblocked_samples"] = lt.lit_samples;
      }
      if (lt.visibility) lj["occlusion"] = {{"samples", light.occlusion_samples}, {"visibility", *lt.visibility}};
      lights.push_back(std::move(lj));
    }
    hit["lights"] = std::move(lights);
    auto child = [&](const Color& weight, const std::unique_ptr<RayTrace>& ray) {
      if (!ray) return Json(nullptr);
      Json c;
      c["weight"] = vec(weight);
      c["ray"] = node_json(scene, *ray);
      return c;
    };
    hit["reflection"] = child(t.reflection_weight, t.reflection);
    hit["refraction"] = child(t.refraction_weight, t.refraction);
    node["hit"] = std::move(hit);
  }
  // color = f (the sum above) + (1 - f) fog color
  if (t.fog) node["fog"] = {{"f", *t.fog}, {"color", vec(scene.render.fog->color)}};
  if (t.environment_uv) node["environment"] = {{"uv", {t.environment_uv->u, t.environment_uv->v}}};
  node["color"] = vec(t.color);
  return node;
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
std::string fmt(const Vec3& v) { return "(" + fmt(v.x) + ", " + fmt(v.y) + ", " + fmt(v.z) + ")"; }

std::string object_label(const Scene& scene, uint32_t object) {
  std::string s = "object " + std::to_string(object);
  auto it = scene.object_names.find(object);
  if (it != scene.object_names.end()) s += " \"" + it->second + "\"";
  return s;
}

void node_text(const Scene& scene, const RayTrace& t, const std::string& indent, std::string& out) {
  out += indent + "ray (depth " + std::to_string(t.depth) + ") from " + fmt(t.ray.origin) + " toward " +
         fmt(t.ray.direction) + "\n";
  if (!t.hit) {
    if (t.environment_uv)
      out += indent + "  hits nothing: environment at uv (" + fmt(t.environment_uv->u) + ", " +
             fmt(t.environment_uv->v) + ") " + fmt(t.color) + "\n";
    else
      out += indent + "  hits nothing: background " + fmt(t.color) + "\n";
    return;
  }
  const Material& m = scene.materials[t.surface.material];
  out += indent + "  hits " + object_label(scene, t.hit->object) + " at t = " + fmt(t.hit->t) + ", point " +
         fmt(t.surface.p) + ", normal " + fmt(t.normal) + ", material \"" + m.name + "\"\n";
  if (scene.objects[t.hit->object].type == ShapeType::csg) {
    const CsgLeaf& leaf = scene.csgs[scene.objects[t.hit->object].shape].leaves[t.hit->primitive];
    out += indent + "  csg solid " + std::to_string(t.hit->primitive) +
           (leaf.name.empty() ? std::string() : " \"" + leaf.name + "\"") +
           ((t.hit->face & 1) ? " (subtracted: its normal turned)" : "") + "\n";
  }
  for (const TextureLookup& l : texture_lookups(scene, t.surface))
    out += indent + "  texture " + l.slot + " at uv (" + fmt(t.surface.uv.u) + ", " + fmt(t.surface.uv.v) +
           "): " + fmt(l.value) + " from " + texture_source(scene, l.texture) + "\n";
  const bool phong = scene.render.shading_model == ShadingModel::phong;
  for (const LightTrace& lt : t.lights) {
    const Light& light = scene.lights[lt.index];
    std::string line = indent + "  light " + std::to_string(lt.index) + " (" + light_type_name(light.type) + "): ";
    if (light.type == LightType::ambient) {
      line += "ambient " + fmt(lt.terms.ambient);
      if (lt.visibility) line += ", occlusion: " + fmt(*lt.visibility) + " of the directions open";
    } else {
      line += "l " + fmt(lt.l) + ", n.l " + fmt(lt.n_dot_l);
      if (!(lt.n_dot_l > 0) && light.type != LightType::area) {
        line += ": faces away";
      } else if (light.type == LightType::spot && lt.spot_factor == 0) {
        line += ": outside the cone";
      } else if (lt.shadowed) {
        line += ": shadowed by " + (lt.blocker ? object_label(scene, *lt.blocker) : std::string("?"));
      } else {
        if (light.type == LightType::area)
          line += ", " + std::to_string(lt.lit_samples) + " of " + std::to_string(lt.samples) + " samples unblocked";
        if (lt.specular_cos) line += std::string(phong ? ", r.v " : ", n.h ") + fmt(*lt.specular_cos);
        if (light.type == LightType::spot) line += ", spot factor " + fmt(lt.spot_factor);
        if (light.type != LightType::directional && lt.attenuation != 1) line += ", attenuation " + fmt(lt.attenuation);
      }
      line += "\n" + indent + "      ambient " + fmt(lt.terms.ambient) + " + diffuse " + fmt(lt.terms.diffuse) +
              " + specular " + fmt(lt.terms.specular);
    }
    out += line + "\n";
  }
  if (t.reflection) {
    out += indent + "  reflection, weight " + fmt(t.reflection_weight) + ":\n";
    node_text(scene, *t.reflection, indent + "    ", out);
  }
  if (t.refraction) {
    out += indent + "  refraction, weight " + fmt(t.refraction_weight) + ":\n";
    node_text(scene, *t.refraction, indent + "    ", out);
  }
  if (t.fog)
    out += indent + "  fog: f " + fmt(*t.fog) + " of the sum, " + fmt(1.0 - *t.fog) + " of " +
           fmt(scene.render.fog->color) + "\n";
  out += indent + "  = " + fmt(t.color) + "\n";
}

}  // namespace

std::string explanation_json(const Scene& scene, const PixelExplanation& e) {
  Json j;
  j["pixel"] = Json::array({e.x, e.y});
  j["color"] = vec(e.color);
  j["ray"] = node_json(scene, e.ray);
  return j.dump(2) + "\n";
}

std::string explanation_text(const Scene& scene, const PixelExplanation& e) {
  std::string out = "pixel (" + std::to_string(e.x) + ", " + std::to_string(e.y) + ") = " + fmt(e.color) + "  [" +
                    (scene.render.shading_model == ShadingModel::phong ? "phong" : "blinn-phong") + "]\n";
  node_text(scene, e.ray, "", out);
  return out;
}

}  // namespace glint
