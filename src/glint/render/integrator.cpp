#include "glint/render/integrator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <new>
#include <numbers>
#include <type_traits>

#include "glint/accel/packet_slots.h"
#include "glint/geometry/shapes.h"
#include "glint/render/stratified.h"
#include "glint/render/texture.h"

namespace glint {

namespace {

const Transform* xf_of(const Scene& scene, const Object& object) {
  return object.transform == kNoTransform ? nullptr : &scene.transforms[object.transform];
}

// The hit point in the object's own space, from the ray (as the
// intersection test saw it: same t).
Vec3 object_point(const Scene& scene, const Object& object, const Ray& ray, double t) {
  const Transform* xf = xf_of(scene, object);
  return xf ? xf->inverse_point(ray.origin) + t * xf->inverse_vector(ray.direction) : ray.at(t);
}

// Point and normal from object space to world space (normal through the
// inverse transpose), into sp.
void to_world(const Transform* xf, const Vec3& p_obj, const Vec3& n_obj, SurfacePoint& sp) {
  sp.p = xf ? xf->point(p_obj) : p_obj;
  sp.geometric_normal = xf ? normalize(xf->normal(n_obj)) : n_obj;
}

// A cylinder's or cone's hit: the lateral surface's outward normal, or a
// cap's axis direction away from the solid (docs: "Quadric and polygon
// normals"). The point is put back on the surface it hit, which removes
// the rounding of the ray's arithmetic.
void cone_geometry(const Cone& c, int part, const Vec3& p_obj, const Transform* xf, SurfacePoint& sp) {
  const Vec3 rel = p_obj - c.base;
  const double h = dot(rel, c.axis);
  const Vec3 radial = rel - h * c.axis;
  const double rl = length(radial);
  if (part == kConeBaseCap || part == kConeApexCap) {
    const bool apex = part == kConeApexCap;
    to_world(xf, (apex ? c.apex : c.base) + radial, apex ? c.axis : -c.axis, sp);
    return;
  }
  const double k = (c.apex_radius - c.base_radius) / c.length;
  const double hc = std::clamp(h, 0.0, c.length);
  // The side's gradient: across the axis, tilted by the slope k (against the
  // axis where the cone narrows toward the apex).
  Vec3 out = rl > 0.0 ? radial / rl : c.ref_u;
  const Vec3 p_side = c.base + hc * c.axis + (c.base_radius + k * hc) * out;
  to_world(xf, rl > 0.0 ? p_side : p_obj, normalize(out - k * c.axis), sp);
}

// A polygon's hit: the point on the triangle that was hit, the polygon's
// normal (first three vertices, by the right-hand rule in world space, as for
// triangles) and, with vertex normals, their interpolation on that fan triangle.
void polygon_geometry(const Polygon& poly, const Hit& hit, const Transform* xf, SurfacePoint& sp) {
  const std::array<uint32_t, 3>& tri = poly.triangles[hit.primitive];
  const Vec3& v0 = poly.vertices[tri[0]];
  const Vec3 p_obj = v0 + hit.b1 * (poly.vertices[tri[1]] - v0) + hit.b2 * (poly.vertices[tri[2]] - v0);
  sp.p = xf ? xf->point(p_obj) : p_obj;
  if (xf) {
    const Vec3 e1 = xf->vector(poly.vertices[1] - poly.vertices[0]);
    const Vec3 e2 = xf->vector(poly.vertices[2] - poly.vertices[0]);
    sp.geometric_normal = normalize(cross(e1, e2));
  } else {
    sp.geometric_normal = poly.normal;
  }
  sp.shading_normal = sp.geometric_normal;
  if (poly.normals.empty()) return;
  Vec3 n[3];
  for (int i = 0; i < 3; ++i) {
    n[i] = poly.normals[tri[i]];  // unit (the loader normalized them)
    if (xf) n[i] = normalize(xf->normal(n[i]));
  }
  const Vec3 s = (1.0 - hit.b1 - hit.b2) * n[0] + hit.b1 * n[1] + hit.b2 * n[2];
  const double len = length(s);
  if (len > 0.0 && std::isfinite(len)) sp.shading_normal = s / len;
}

// Where the hit is and which way the surface faces there.
SurfacePoint evaluate_geometry(const Scene& scene, const Ray& ray, const Hit& hit) {
  const Object& object = scene.objects[hit.object];
  SurfacePoint sp;
  sp.material = object.material;
  switch (object.type) {
    case ShapeType::sphere: {
      const Sphere& s = scene.spheres[object.shape];
      Vec3 p_obj;
      if (object.transform == kNoTransform) {
        p_obj = ray.at(hit.t);
      } else {
        const Transform& xf = scene.transforms[object.transform];
        p_obj = xf.inverse_point(ray.origin) + hit.t * xf.inverse_vector(ray.direction);
      }
      // Project back onto the sphere: removes the hit point's rounding error.
      const Vec3 n_obj = normalize(p_obj - s.center);
      p_obj = s.center + s.radius * n_obj;
      if (object.transform == kNoTransform) {
        sp.p = p_obj;
        sp.geometric_normal = n_obj;
      } else {
        const Transform& xf = scene.transforms[object.transform];
        sp.p = xf.point(p_obj);
        sp.geometric_normal = normalize(xf.normal(n_obj));
      }
      break;
    }
    case ShapeType::box: {
      Vec3 n_obj = box_face_normal(hit.face);
      sp.p = ray.at(hit.t);
      if (object.transform != kNoTransform) n_obj = scene.transforms[object.transform].normal(n_obj);
      sp.geometric_normal = normalize(n_obj);
      break;
    }
    case ShapeType::triangle: {
      const Triangle& t = scene.triangles[object.shape];
      const Vec3 e1 = t.v1 - t.v0, e2 = t.v2 - t.v0;
      sp.p = t.v0 + hit.b1 * e1 + hit.b2 * e2;
      sp.geometric_normal = normalize(cross(e1, e2));
      break;
    }
    case ShapeType::mesh: {
      const Mesh& mesh = scene.meshes[object.shape];
      const Triangle t = to_triangle(hit.vertices);
      const Vec3 e1 = t.v1 - t.v0, e2 = t.v2 - t.v0;
      const Vec3 p_obj = t.v0 + hit.b1 * e1 + hit.b2 * e2;
      Vec3 ng = cross(e1, e2);
      const Transform* xf = object.transform == kNoTransform ? nullptr : &scene.transforms[object.transform];
      sp.p = xf ? xf->point(p_obj) : p_obj;
      sp.geometric_normal = normalize(xf ? xf->normal(ng) : ng);
      sp.shading_normal = sp.geometric_normal;
      // Meshes only shaded flat have no vertex normals (scene loader).
      if (object.smooth && mesh.corner_normals.size() == mesh.indices.size()) {
        const Vec3f* corner = &mesh.corner_normals[3 * static_cast<size_t>(hit.primitive)];
        Vec3 n0 = to_vec3(corner[0]), n1 = to_vec3(corner[1]), n2 = to_vec3(corner[2]);
        if (xf) {
          // Vertex normals through the inverse transpose, each normalized
          // before interpolation (the contract's order).
          n0 = normalize(xf->normal(n0));
          n1 = normalize(xf->normal(n1));
          n2 = normalize(xf->normal(n2));
        }
        const Vec3 n = (1.0 - hit.b1 - hit.b2) * n0 + hit.b1 * n1 + hit.b2 * n2;
        const double len = length(n);
        if (len > 0.0 && std::isfinite(len)) sp.shading_normal = n / len;
      }
      if (object.material == kMeshMaterials) sp.material = mesh.triangle_material[hit.primitive];
      return sp;
    }
    case ShapeType::cylinder:
    case ShapeType::cone:
      cone_geometry(scene.cones[object.shape], hit.face, object_point(scene, object, ray, hit.t), xf_of(scene, object),
                    sp);
      break;
    case ShapeType::disk: {
      const Disk& d = scene.disks[object.shape];
      Vec3 p_obj = object_point(scene, object, ray, hit.t);
      p_obj -= dot(p_obj - d.center, d.normal) * d.normal;  // onto the disk's plane exactly
      to_world(xf_of(scene, object), p_obj, d.normal, sp);
      break;
    }
    case ShapeType::polygon: {
      polygon_geometry(scene.polygons[object.shape], hit, xf_of(scene, object), sp);
      return sp;
    }
    case ShapeType::plane: {
      const Plane& pl = scene.planes[object.shape];
      sp.p = ray.at(hit.t);
      sp.p -= dot(sp.p - pl.point, pl.normal) * pl.normal;  // onto the plane exactly
      sp.geometric_normal = pl.normal;
      break;
    }
  }
  sp.shading_normal = sp.geometric_normal;
  return sp;
}

}  // namespace

SurfacePoint evaluate_hit(const Scene& scene, const Ray& ray, const Hit& hit) {
  SurfacePoint sp = evaluate_geometry(scene, ray, hit);
  const Material& m = scene.materials[sp.material];
  sp.reflectance = {m.ambient, m.diffuse, m.specular};
  if (m.textured()) {  // plain colors never get here: no uv, no lookups
    sp.textured = true;
    sp.uv = surface_uv(scene, hit, sp.p);
    if (m.ambient_texture != kNoTexture)
      sp.reflectance.ambient = evaluate_texture(scene, scene.textures[m.ambient_texture], sp.uv);
    if (m.diffuse_texture != kNoTexture)
      sp.reflectance.diffuse = evaluate_texture(scene, scene.textures[m.diffuse_texture], sp.uv);
    if (m.specular_texture != kNoTexture)
      sp.reflectance.specular = evaluate_texture(scene, scene.textures[m.specular_texture], sp.uv);
  }
  return sp;
}

// The point being shaded: the hit, evaluated, with the directions and
// offset origins every light sample and secondary ray uses.
struct ShadingPoint {
  SurfacePoint sp;
  Vec3 d;                 // the incoming ray's unit direction
  Vec3 v;                 // toward the viewer: -d
  Vec3 n;                 // the shading normal on the viewer's side (two-sided surfaces)
  bool entering = false;  // from the outside, by the geometric normal
  // Secondary rays leave from just off the surface: shadow and reflected
  // rays on the incoming side, refracted rays on the far side.
  Vec3 above, below;
};

// A point light, a spot, an area light's sample point, or a direction.
struct LightSample {
  uint32_t light = 0;         // into Scene::lights
  Vec3 to_light;              // from the surface point to the light's point, or toward a directional light
  double shadow_t_max = 1.0;  // 1: up to the light's point (to_light's length); infinity for a direction
  double distance = 0;        // for attenuation; 0 for a direction
  double weight = 1.0;        // 1 / samples for an area light
};

namespace {

// The render's recorder: records nothing. Every hook is empty and inlines
// away, so the render's shading compiles without a trace branch; the
// shadow query goes through the light's shadow cache.
struct NoRecorder {
  void surface(const ShadingPoint&) {}
  NoRecorder light(uint32_t) { return {}; }
  NoRecorder reflection(const Color&) { return {}; }
  NoRecorder refraction(const Color&) { return {}; }
  void ray(const Ray&, int, const std::optional<Hit>&, const Color&) {}
  // Per light sample:
  void spot_factor(double) {}
  void attenuation_denominator(double) {}
  static bool blocked(const Accelerator& accel, const Ray& shadow, uint32_t* cache) {
    return cache ? accel.occluded_cached(shadow, *cache) : accel.occluded(shadow);
  }
  void lit(double) {}
  void done(const Light&, const ShadingPoint&, const ShadeTerms&) {}
};

// Explain's recorder of one light: the facts of LightTrace. The shadow
// query is the same any-hit query, asked for the blocker's name.
struct LightTraceRecorder {
  LightTrace* t;
  void spot_factor(double f) { t->spot_factor = f; }
  void attenuation_denominator(double d) { t->attenuation = 1.0 / d; }
  bool blocked(const Accelerator& accel, const Ray& shadow, uint32_t*) {
    const std::optional<uint32_t> blocker = accel.first_blocker(shadow);
    if (blocker && !t->blocker) t->blocker = blocker;
    return blocker.has_value();
  }
  void lit(double cos_spec) {
    t->lit_samples++;
    if (!t->specular_cos) t->specular_cos = cos_spec;
  }
  void done(const Light& light, const ShadingPoint& at, const ShadeTerms& terms) {
    switch (light.type) {
      case LightType::ambient: break;
      case LightType::point:
      case LightType::spot: t->l = normalize(light.position - at.sp.p); break;
      case LightType::directional: t->l = -light.direction; break;
      case LightType::area:  // toward the center
        t->samples = light.samples;
        t->l = normalize(light.corner + 0.5 * (light.edge_u + light.edge_v) - at.sp.p);
        break;
    }
    t->terms = terms;
    if (light.type != LightType::ambient) {
      t->n_dot_l = dot(at.n, t->l);
      t->shadowed = t->blocker.has_value() && t->lit_samples == 0;
    }
  }
};

// Explain's recorder of one ray: fills its RayTrace node and makes the
// nodes of its lights and child rays.
struct TraceRecorder {
  RayTrace* t;
  void surface(const ShadingPoint& at) {
    t->surface = at.sp;
    t->normal = at.n;
  }
  LightTraceRecorder light(uint32_t index) {
    t->lights.emplace_back();
    t->lights.back().index = index;
    return {&t->lights.back()};
  }
  TraceRecorder reflection(const Color& weight) {
    t->reflection_weight = weight;
    t->reflection = std::make_unique<RayTrace>();
    return {t->reflection.get()};
  }
  TraceRecorder refraction(const Color& weight) {
    t->refraction_weight = weight;
    t->refraction = std::make_unique<RayTrace>();
    return {t->refraction.get()};
  }
  void ray(const Ray& r, int depth, const std::optional<Hit>& hit, const Color& color) {
    t->ray = r;
    t->depth = depth;
    t->hit = hit;
    t->color = color;
  }
};

// Schlick's approximation of the Fresnel reflectance, per color channel.
Color schlick(const Color& f0, double cos_theta) {
  const double m = std::pow(1.0 - cos_theta, 5.0);
  return f0 + (Color(1.0) - f0) * m;
}

// x^alpha. Whole exponents (the usual 32, 100, ...) by repeated squaring:
// several times cheaper than std::pow, within a few ulps of it.
double shininess_pow(double x, double alpha) {
  if (alpha <= 65536.0 && alpha == std::floor(alpha)) {
    auto n = static_cast<uint32_t>(alpha);
    double result = 1.0;
    while (n) {
      if (n & 1u) result *= x;
      x *= x;
      n >>= 1u;
    }
    return result;
  }
  return std::pow(x, alpha);
}

ShadingPoint shading_point(const Scene& scene, const Ray& ray, const Hit& hit, double epsilon) {
  ShadingPoint at;
  at.sp = evaluate_hit(scene, ray, hit);
  at.d = normalize(ray.direction);
  at.v = -at.d;
  at.n = dot(at.sp.shading_normal, at.d) < 0.0 ? at.sp.shading_normal : -at.sp.shading_normal;
  // Inside and outside come from the geometric normal (the contract): a
  // smooth normal may face the other way than the surface near silhouettes.
  at.entering = dot(at.sp.geometric_normal, at.d) < 0.0;
  const Vec3 ng = at.entering ? at.sp.geometric_normal : -at.sp.geometric_normal;
  at.above = at.sp.p + epsilon * ng;
  at.below = at.sp.p - epsilon * ng;
  return at;
}

// The one sample of a point, spot or directional light at the point (an
// area light has many: add_area_light).
LightSample single_light_sample(const Light& light, uint32_t index, const ShadingPoint& at) {
  if (light.type == LightType::directional) return LightSample{index, -light.direction, kInfinity, 0.0, 1.0};
  const Vec3 to_light = light.position - at.sp.p;
  return LightSample{index, to_light, 1.0, length(to_light), 1.0};
}

}  // namespace

Integrator::Integrator(const Scene& scene, const Accelerator& accel)
    : scene_(scene), accel_(accel), epsilon_(scene.render.epsilon.value_or(auto_epsilon(scene))) {
  for (const Light& light : scene.lights) {
    cos_cutoff_.push_back(std::cos(light.cutoff * std::numbers::pi / 180.0));
    // cast_camera_packet knows the lights of one sample (single_light_sample);
    // it also never seeds a pixel's random numbers, which only area lights draw.
    const bool single_sample = light.type == LightType::ambient || light.type == LightType::point ||
                               light.type == LightType::spot || light.type == LightType::directional;
    if (!single_sample) shades_packets_ = false;
  }
}

template <class Recorder>
Color Integrator::cast(const Ray& ray, int depth, TraceContext& ctx, Recorder& rec) const {
  return cast_with_hit(ray, accel_.intersect(ray), depth, ctx, rec);
}

template <class Recorder>
Color Integrator::cast_with_hit(const Ray& ray, const std::optional<Hit>& hit, int depth, TraceContext& ctx,
                                Recorder& rec) const {
  if (hit && depth == 1) ctx.stats.camera_hits++;
  Color color = scene_.render.background;
  if (hit) color = shade(ray, *hit, depth, ctx, rec).sum();
  rec.ray(ray, depth, hit, color);
  return color;
}

Color Integrator::cast_ray(const Ray& ray, int depth, TraceContext& ctx) const {
  NoRecorder rec;
  return cast(ray, depth, ctx, rec);
}

Color Integrator::trace_ray(const Ray& ray, int depth, TraceContext& ctx, RayTrace& trace) const {
  TraceRecorder rec{&trace};
  return cast(ray, depth, ctx, rec);
}

ShadeTerms Integrator::shade_surface(const Ray& ray, const Hit& hit, int depth, TraceContext& ctx) const {
  NoRecorder rec;
  return shade(ray, hit, depth, ctx, rec);
}

Color Integrator::cast_ray_with_hit(const Ray& ray, const std::optional<Hit>& hit, int depth, TraceContext& ctx) const {
  if (hit && depth == 1) ctx.stats.camera_hits++;
  return hit ? shade_surface(ray, *hit, depth, ctx).sum() : scene_.render.background;
}

CameraSample Integrator::cast_camera_ray(const Ray& ray, TraceContext& ctx) const {
  return cast_camera_ray_with_hit(ray, accel_.intersect(ray), ctx);
}

CameraSample Integrator::cast_camera_ray_with_hit(const Ray& ray, const std::optional<Hit>& hit,
                                                  TraceContext& ctx) const {
  CameraSample out;
  if (!hit) {
    // The background is the whole of a missed pixel; it goes to `ambient` so
    // the five color passes still sum to the image.
    out.terms.ambient = scene_.render.background;
    return out;
  }
  ctx.stats.camera_hits++;
  out.terms = shade_surface(ray, *hit, 1, ctx);
  // Evaluated again (cheap, no random numbers) rather than widening
  // shade_surface's interface for the camera ray alone.
  const SurfacePoint sp = evaluate_hit(scene_, ray, *hit);
  const bool facing = dot(sp.shading_normal, normalize(ray.direction)) < 0.0;  // shade_surface's test
  out.normal = facing ? sp.shading_normal : -sp.shading_normal;
  out.depth = hit->t * length(ray.direction);
  out.albedo = scene_.materials[sp.material].diffuse;
  return out;
}

// A light sample up to its shadow ray (Integrator::prepare_light_sample,
// which writes the shadow ray itself where the caller keeps it).
struct PreparedSample {
  Vec3 l;  // unit, toward the light
  double n_dot_l = 0;
  double scale = 1;  // the sample's weight, spot factor and attenuation
};

// The rays a shaded point casts on (add_secondary_rays): the reflected one
// and, through a transparent surface, the refracted one, with their weights.
struct SecondaryRays {
  Color reflect_weight, refract_weight;
  Ray reflected, refracted;
  bool reflects = false, refracts = false;
};

void Integrator::cast_camera_packet(const Ray* rays, const std::optional<Hit>* hits, int count, TraceContext& ctx,
                                   Color* colors) const {
  // shade() for each ray, light by light across the rays: the same terms
  // added in the same order for each pixel, and no pixel's numbers depend on
  // another's (without area lights nothing draws random numbers). Kept in
  // step with shade() and light_terms().
  if (!shades_packets_ || count > kPacketSize) {
    for (int i = 0; i < count; ++i) colors[i] = cast_ray_with_hit(rays[i], hits[i], 1, ctx);
    return;
  }
  NoRecorder rec;
  PacketSlots<ShadingPoint> at;  // set for the rays that hit
  PacketSlots<ShadeTerms> out;    // set for the rays that hit
  bool shaded[kPacketSize] = {};
  for (int i = 0; i < count; ++i) {
    if (!hits[i]) continue;
    new (&out[i]) ShadeTerms;
    ctx.stats.camera_hits++;
    new (&at[i]) ShadingPoint(shading_point(scene_, rays[i], *hits[i], epsilon_));
    if (scene_.materials[at[i].sp.material].unlit) {
      out[i].ambient = at[i].sp.reflectance.diffuse;
      continue;
    }
    shaded[i] = true;
  }
  for (uint32_t li = 0; li < scene_.lights.size(); ++li) {
    const Light& light = scene_.lights[li];
    PacketSlots<ShadeTerms> terms;  // set for the shaded points
    PacketSlots<LightSample> sample;
    PacketSlots<PreparedSample> prepared;  // constructed, then filled by prepare_light_sample
    PacketSlots<Ray> shadow;
    int pixel[kPacketSize];
    int asked = 0;
    for (int i = 0; i < count; ++i) {
      if (!shaded[i]) continue;
      new (&terms[i]) ShadeTerms;
      terms[i].ambient = at[i].sp.reflectance.ambient * light.ambient;
      if (light.type == LightType::ambient) continue;
      new (&sample[i]) LightSample(single_light_sample(light, li, at[i]));
      new (&prepared[i]) PreparedSample;
      // The shadow ray written in its place in the packet: copied from
      // `prepared` it was loaded 64 bytes at once just after the call stored
      // it in parts, which stalls (store forwarding).
      if (!prepare_light_sample(at[i], sample[i], prepared[i], shadow[asked], rec)) continue;
      ctx.stats.shadow++;
      pixel[asked++] = i;
    }
    if (asked > 0) {
      bool blocked[kPacketSize];
      uint32_t no_cache = kNoShadowBlocker;
      accel_.occluded_packet(shadow.data(), asked, blocked, li < ctx.shadow_cache.size() ? ctx.shadow_cache[li] : no_cache);
      for (int k = 0; k < asked; ++k)
        if (!blocked[k]) add_lit_sample(at[pixel[k]], sample[pixel[k]], prepared[pixel[k]], terms[pixel[k]], rec);
    }
    for (int i = 0; i < count; ++i) {
      if (!shaded[i]) continue;
      out[i].ambient += terms[i].ambient;
      out[i].diffuse += terms[i].diffuse;
      out[i].specular += terms[i].specular;
    }
  }
  // add_secondary_rays for each point, the reflected rays traced as one
  // packet (off a mirror floor they are as coherent as the camera rays);
  // refracted rays one by one.
  PacketSlots<SecondaryRays> secondary;
  PacketSlots<Ray> reflected;
  int reflecting[kPacketSize];
  int n = 0;
  for (int i = 0; i < count; ++i)
    if (shaded[i]) new (&secondary[i]) SecondaryRays(secondary_rays(at[i], 1));
  // Gathered in a second pass: read back right after secondary_rays stored
  // them in parts, the rays were loaded 64 bytes at once, which stalls
  // (store forwarding).
  for (int i = 0; i < count; ++i)
    if (shaded[i] && secondary[i].reflects) {
      reflected[n] = secondary[i].reflected;
      reflecting[n++] = i;
    }
  PacketHits reflected_hits(n);
  if (n > 0) accel_.intersect_packet(reflected.data(), n, reflected_hits.data());
  for (int k = 0; k < n; ++k) {
    const SecondaryRays& s = secondary[reflecting[k]];
    ctx.stats.reflection++;
    auto child = rec.reflection(s.reflect_weight);
    out[reflecting[k]].reflection = s.reflect_weight * cast_with_hit(reflected[k], reflected_hits[k], 2, ctx, child);
  }
  for (int i = 0; i < count; ++i) {
    if (shaded[i]) add_refraction(secondary[i], 1, ctx, rec, out[i]);
    colors[i] = hits[i] ? out[i].sum() : scene_.render.background;
  }
}

template <class LightRecorder>
void Integrator::add_light_sample(const ShadingPoint& at, const LightSample& s, ShadeTerms& out, TraceContext& ctx,
                                  LightRecorder& rec) const {
  PreparedSample prepared;
  Ray shadow;
  if (!prepare_light_sample(at, s, prepared, shadow, rec)) return;
  ctx.stats.shadow++;
  // The shadow cache serves point, spot and directional lights; an area
  // light's samples spread over its surface and mostly pass the last blocker
  // by (with the cache, a soft-shadow scene rendered 12% slower).
  const Light& light = scene_.lights[s.light];
  uint32_t* cache =
      light.type != LightType::area && s.light < ctx.shadow_cache.size() ? &ctx.shadow_cache[s.light] : nullptr;
  if (rec.blocked(accel_, shadow, cache)) return;
  add_lit_sample(at, s, prepared, out, rec);
}

template <class LightRecorder>
bool Integrator::prepare_light_sample(const ShadingPoint& at, const LightSample& s, PreparedSample& out,
                                      Ray& shadow, LightRecorder& rec) const {
  const Light& light = scene_.lights[s.light];
  const Vec3 l = normalize(s.to_light);
  const double n_dot_l = dot(at.n, l);
  if (!(n_dot_l > 0.0)) return false;

  double scale = s.weight;
  if (light.type == LightType::spot) {
    const double cos_angle = -dot(l, light.direction);
    // The cone's edge counts as inside; the tolerance absorbs rounding.
    if (cos_angle < cos_cutoff_[s.light] - 1e-12) {
      rec.spot_factor(0);
      return false;
    }
    if (light.falloff != 0.0) {
      const double factor = std::pow(std::max(0.0, cos_angle), light.falloff);
      scale *= factor;
      rec.spot_factor(factor);
    }
  }
  if (light.type != LightType::directional) {
    const Vec3& a = light.attenuation;
    const double denominator = a.x + a.y * s.distance + a.z * s.distance * s.distance;
    scale /= denominator;
    rec.attenuation_denominator(denominator);
  }

  out.l = l;
  out.n_dot_l = n_dot_l;
  out.scale = scale;
  shadow.origin = at.above;
  shadow.direction = light.type == LightType::directional ? l : s.to_light + (at.sp.p - at.above);
  shadow.t_min = 0.0;
  shadow.t_max = s.shadow_t_max;
  return true;
}

template <class LightRecorder>
void Integrator::add_lit_sample(const ShadingPoint& at, const LightSample& s, const PreparedSample& prepared,
                                ShadeTerms& out, LightRecorder& rec) const {
  const Light& light = scene_.lights[s.light];
  const Vec3& l = prepared.l;
  const double n_dot_l = prepared.n_dot_l, scale = prepared.scale;
  const Material& m = scene_.materials[at.sp.material];
  const Reflectances& r = at.sp.reflectance;
  out.diffuse += (scale * n_dot_l) * (r.diffuse * light.diffuse);
  double cos_spec = 0.0;  // r.v or n.h, before clamping
  if (scene_.render.shading_model == ShadingModel::phong) {
    const Vec3 reflected = 2.0 * n_dot_l * at.n - l;
    cos_spec = dot(reflected, at.v);
  } else {
    const Vec3 half = l + at.v;
    const double len = length(half);
    if (len > 0.0) cos_spec = dot(at.n, half / len);
  }
  const double c = std::max(0.0, cos_spec);
  if (c > 0.0 && !is_black(r.specular * light.specular))
    out.specular += (scale * shininess_pow(c, m.shininess)) * (r.specular * light.specular);
  rec.lit(cos_spec);
}

template <class LightRecorder>
void Integrator::add_area_light(const ShadingPoint& at, uint32_t li, ShadeTerms& out, TraceContext& ctx,
                                LightRecorder& rec) const {
  // Stratified jittered points on the parallelogram, one per grid cell, each
  // a point light of weight 1/N.
  const Light& light = scene_.lights[li];
  const auto [nu, nv] = stratified_grid(light.samples);
  const double weight = 1.0 / light.samples;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const double su = (i + ctx.rng.next_double()) / nu;
      const double sv = (j + ctx.rng.next_double()) / nv;
      const Vec3 pos = light.corner + su * light.edge_u + sv * light.edge_v;
      const Vec3 to_light = pos - at.sp.p;
      add_light_sample(at, LightSample{li, to_light, 1.0, length(to_light), weight}, out, ctx, rec);
    }
  }
}

template <class Recorder>
ShadeTerms Integrator::light_terms(const ShadingPoint& at, uint32_t li, TraceContext& ctx, Recorder& rec) const {
  const Light& light = scene_.lights[li];
  auto light_rec = rec.light(li);
  ShadeTerms terms;
  terms.ambient = at.sp.reflectance.ambient * light.ambient;
  switch (light.type) {
    case LightType::ambient: break;
    case LightType::point:
    case LightType::spot:
    case LightType::directional:
      add_light_sample(at, single_light_sample(light, li, at), terms, ctx, light_rec);
      break;
    case LightType::area: add_area_light(at, li, terms, ctx, light_rec); break;
  }
  light_rec.done(light, at, terms);
  return terms;
}

SecondaryRays Integrator::secondary_rays(const ShadingPoint& at, int depth) const {
  SecondaryRays out;
  // Weights of the reflected and refracted rays (contract: materials, fresnel).
  const Material& m = scene_.materials[at.sp.material];
  const double cos_theta = std::clamp(dot(at.v, at.n), 0.0, 1.0);
  Color reflect_weight = m.reflectivity;
  Color refract_weight(m.transparency);
  if (m.fresnel) {
    const double r0 = (m.ior - 1.0) / (m.ior + 1.0);
    const double s_glass = schlick(Color(r0 * r0), cos_theta).x;
    reflect_weight = schlick(m.reflectivity, cos_theta) + Color(m.transparency * s_glass);
    refract_weight = Color(m.transparency * (1.0 - s_glass));
  }
  if (depth + 1 > scene_.render.max_depth) return out;
  if (!is_black(refract_weight)) {
    // Snell's law; the inside has index ior, the outside 1.
    const double eta = at.entering ? 1.0 / m.ior : m.ior;
    const double k = 1.0 - eta * eta * (1.0 - cos_theta * cos_theta);
    if (k < 0.0) {
      reflect_weight += refract_weight;  // total internal reflection
    } else {
      out.refracted = Ray{at.below, eta * at.d + (eta * cos_theta - std::sqrt(k)) * at.n};
      out.refract_weight = refract_weight;
      out.refracts = true;
    }
  }
  if (!is_black(reflect_weight)) {
    out.reflected = Ray{at.above, reflect(at.d, at.n)};
    out.reflect_weight = reflect_weight;
    out.reflects = true;
  }
  return out;
}

template <class Recorder>
void Integrator::add_secondary_rays(const ShadingPoint& at, int depth, TraceContext& ctx, Recorder& rec,
                                    ShadeTerms& out) const {
  const SecondaryRays s = secondary_rays(at, depth);
  if (s.reflects) {
    ctx.stats.reflection++;
    auto child = rec.reflection(s.reflect_weight);
    out.reflection = s.reflect_weight * cast(s.reflected, depth + 1, ctx, child);
  }
  add_refraction(s, depth, ctx, rec, out);
}

template <class Recorder>
void Integrator::add_refraction(const SecondaryRays& s, int depth, TraceContext& ctx, Recorder& rec,
                                ShadeTerms& out) const {
  if (!s.refracts) return;
  ctx.stats.refraction++;
  auto child = rec.refraction(s.refract_weight);
  out.transmission = s.refract_weight * cast(s.refracted, depth + 1, ctx, child);
}

template <class Recorder>
ShadeTerms Integrator::shade(const Ray& ray, const Hit& hit, int depth, TraceContext& ctx, Recorder& rec) const {
  const ShadingPoint at = shading_point(scene_, ray, hit, epsilon_);
  rec.surface(at);
  ShadeTerms out;
  if (scene_.materials[at.sp.material].unlit) {  // MTL illum 0: the color is Kd, no lights, no shadows, no rays
    out.ambient = at.sp.reflectance.diffuse;
    return out;
  }
  // Each light's terms are summed on their own, then added: the contract's
  // "sum over lights", in the same order whether or not a trace is kept.
  for (uint32_t li = 0; li < scene_.lights.size(); ++li) {
    const ShadeTerms terms = light_terms(at, li, ctx, rec);
    out.ambient += terms.ambient;
    out.diffuse += terms.diffuse;
    out.specular += terms.specular;
  }
  add_secondary_rays(at, depth, ctx, rec, out);
  return out;
}

}  // namespace glint
