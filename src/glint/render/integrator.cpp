#include "glint/render/integrator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <new>
#include <numbers>
#include <type_traits>

#include "glint/accel/packet_slots.h"
#include "glint/geometry/shapes.h"
#include "glint/render/camera.h"
#include "glint/render/stratified.h"
#include "glint/render/texture.h"

namespace glint {


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
  void fog(double) {}
  void environment(const UV&) {}
  // Per light sample:
  void spot_factor(double) {}
  void attenuation_denominator(double) {}
  static bool blocked(const Accelerator& accel, const Ray& shadow, uint32_t* cache) {
    return cache ? accel.occluded_cached(shadow, *cache) : accel.occluded(shadow);
  }
  void visibility(double) {}
  void lit(double) {}
  void done(const Light&, const ShadingPoint&, const ShadeTerms&) {}
};

// Explain's recorder of one light: the facts of LightTrace. The shadow
// query is the same any-hit query, asked for the blocker's name.
struct LightTraceRecorder {
  LightTrace* t;
  void visibility(double v) { t->visibility = v; }
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
  void fog(double f) { t->fog = f; }
  void environment(const UV& uv) { t->environment_uv = uv; }
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
    // A batch of pixels shades light by light, so an area light's samples
    // would draw the random numbers in another order than pixel by pixel
    // (and from one stream, not each pixel's): those scenes shade one by one.
    const bool single_sample = light.type == LightType::ambient || light.type == LightType::point ||
                               light.type == LightType::spot || light.type == LightType::directional;
    // Occlusion rays draw random numbers too.
    if (!single_sample || light.occlusion_samples > 0) shades_packets_ = false;
  }
}

Color Integrator::miss_color(const Ray& ray, UV* uv) const {
  if (!scene_.render.environment) return scene_.render.background;
  const EnvironmentLookup e = sample_environment(scene_, *scene_.render.environment, ray.direction);
  if (uv) *uv = UV{e.u, e.v};
  return e.color;
}

double Integrator::fog_factor(const Ray& ray, double t) const {
  if (!scene_.render.fog) return 1.0;
  const Fog& fog = *scene_.render.fog;
  const double distance = t * length(ray.direction);  // world units along the ray
  switch (fog.type) {
    case FogType::linear: return std::clamp((fog.end - distance) / (fog.end - fog.start), 0.0, 1.0);
    case FogType::exp: return std::exp(-fog.density * distance);
    case FogType::exp2: {
      const double x = fog.density * distance;
      return std::exp(-(x * x));
    }
  }
  return 1.0;
}

template <class Recorder>
Color Integrator::cast(const Ray& ray, int depth, TraceContext& ctx, Recorder& rec) const {
  const std::optional<Hit> hit = accel_.intersect(ray);
  Color color;
  cast_batch<1>(&ray, &hit, 1, depth, ctx, &rec, &color);
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
  const std::optional<Hit> known(hit);
  const int point = 0;
  NoRecorder rec;
  ShadeTerms out;
  shade_batch<1>(&ray, &known, &point, 1, depth, ctx, &rec, &out);
  return out;
}

Color Integrator::cast_ray_with_hit(const Ray& ray, const std::optional<Hit>& hit, int depth, TraceContext& ctx) const {
  NoRecorder rec;
  Color color;
  cast_batch<1>(&ray, &hit, 1, depth, ctx, &rec, &color);
  return color;
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
    out.color = out.terms.ambient = miss_color(ray);
    return out;
  }
  ctx.stats.camera_hits++;
  out.terms = shade_surface(ray, *hit, 1, ctx);
  out.color = out.terms.sum();
  if (scene_.render.fog) {
    const double f = fog_factor(ray, hit->t);
    const Color haze = (1.0 - f) * scene_.render.fog->color;
    out.color = fogged(out.color, f);
    for (Color* term : {&out.terms.ambient, &out.terms.diffuse, &out.terms.specular, &out.terms.reflection,
                        &out.terms.transmission})
      *term = f * *term;
    out.terms.ambient += haze;
  }
  // Evaluated again (cheap, no random numbers) rather than widening
  // shade_surface's interface for the camera ray alone.
  const SurfacePoint sp = evaluate_hit(scene_, ray, *hit);
  const bool facing = dot(sp.shading_normal, normalize(ray.direction)) < 0.0;  // shade_surface's test
  out.normal = facing ? sp.shading_normal : -sp.shading_normal;
  out.depth = hit->t * length(ray.direction);
  out.albedo = scene_.materials[sp.material].diffuse;
  return out;
}

void Integrator::cast_camera_packet(const Ray* rays, const std::optional<Hit>* hits, int count, TraceContext& ctx,
                                    Color* colors) const {
  if (!shades_packets_ || count > kPacketSize) {
    for (int i = 0; i < count; ++i) colors[i] = cast_ray_with_hit(rays[i], hits[i], 1, ctx);
    return;
  }
  NoRecorder recs[kPacketSize];
  cast_batch<kPacketSize>(rays, hits, count, 1, ctx, recs, colors);
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

// --- The formula, once ------------------------------------------------------
// Slot i of every per-point array below belongs to ray i of the batch;
// `points` lists the slots in play (the rays that hit, then the points that
// are lit), in order. With MaxN = 1 every loop runs once and every array is
// one value: the scalar path, with nothing of the batch left after inlining.

namespace {

// The slot of the k-th entry of a list of slots: always 0 in a batch of one,
// where the compiler then drops the lists.
template <int MaxN>
int slot(const int* list, int k) {
  return MaxN == 1 ? 0 : list[k];
}

}  // namespace

template <int MaxN, class Recorder>
void Integrator::cast_batch(const Ray* rays, const std::optional<Hit>* hits, int count, int depth, TraceContext& ctx,
                            Recorder* recs, Color* colors) const {
  if constexpr (MaxN == 1) count = 1;  // a batch of one is always one ray
  int points[MaxN];
  int n = 0;
  for (int i = 0; i < count; ++i) {
    if (!hits[i]) continue;
    if (depth == 1) ctx.stats.camera_hits++;
    points[n++] = i;
  }
  PacketSlots<ShadeTerms, MaxN> terms;  // set for the rays that hit
  if (n > 0) shade_batch<MaxN>(rays, hits, points, n, depth, ctx, recs, terms.data());
  for (int i = 0; i < count; ++i) {
    if (!hits[i]) {
      UV uv;
      colors[i] = miss_color(rays[i], &uv);
      if (scene_.render.environment) recs[i].environment(uv);
    } else {
      colors[i] = terms[i].sum();
      if (scene_.render.fog) {  // for every ray that hits
        const double f = fog_factor(rays[i], hits[i]->t);
        colors[i] = fogged(colors[i], f);
        recs[i].fog(f);
      }
    }
    recs[i].ray(rays[i], depth, hits[i], colors[i]);
  }
}

template <int MaxN, class Recorder>
void Integrator::shade_batch(const Ray* rays, const std::optional<Hit>* hits, const int* points, int count, int depth,
                             TraceContext& ctx, Recorder* recs, ShadeTerms* out) const {
  PacketSlots<ShadingPoint, MaxN> at;
  int lit[MaxN];  // the points the lights shine on
  int n = 0;
  for (int k = 0; k < count; ++k) {
    const int i = slot<MaxN>(points, k);
    new (&at[i]) ShadingPoint(shading_point(scene_, rays[i], *hits[i], epsilon_));
    recs[i].surface(at[i]);
    new (&out[i]) ShadeTerms;
    if (scene_.materials[at[i].sp.material].unlit) {  // MTL illum 0: the color is Kd, no lights, no shadows, no rays
      out[i].ambient = at[i].sp.reflectance.diffuse;
      continue;
    }
    lit[n++] = i;
  }
  for (uint32_t li = 0; li < scene_.lights.size(); ++li) add_light<MaxN>(at.data(), lit, n, li, ctx, recs, out);
  add_secondary_rays<MaxN>(at.data(), lit, n, depth, ctx, recs, out);
}

// Inlined into shade_batch's loop over lights: otherwise GCC calls it per
// light and per point on the scalar path.
template <int MaxN, class Recorder>
[[gnu::always_inline]] inline void Integrator::add_light(const ShadingPoint* at, const int* points, int count,
                                                         uint32_t li, TraceContext& ctx, Recorder* recs,
                                                         ShadeTerms* out) const {
  const Light& light = scene_.lights[li];
  using LightRecorder = decltype(recs[0].light(li));
  LightRecorder light_recs[MaxN];
  PacketSlots<ShadeTerms, MaxN> terms;  // this light's, per point
  for (int k = 0; k < count; ++k) {
    const int i = slot<MaxN>(points, k);
    light_recs[i] = recs[i].light(li);
    new (&terms[i]) ShadeTerms;
    terms[i].ambient = at[i].sp.reflectance.ambient * light.ambient;
    if (light.occlusion_samples > 0) {
      const double visible = ambient_visibility(at[i], light, ctx);
      light_recs[i].visibility(visible);
      terms[i].ambient = visible * terms[i].ambient;
    }
  }
  switch (light.type) {
    case LightType::ambient: break;
    case LightType::point:
    case LightType::spot:
    case LightType::directional: add_single_samples<MaxN>(at, points, count, li, ctx, light_recs, terms.data()); break;
    case LightType::area:
      for (int k = 0; k < count; ++k) {
        const int i = slot<MaxN>(points, k);
        add_area_light(at[i], li, terms[i], ctx, light_recs[i]);
      }
      break;
  }
  // Each light's terms are summed on their own, then added: the contract's
  // "sum over lights", in the same order whether or not a trace is kept.
  for (int k = 0; k < count; ++k) {
    const int i = slot<MaxN>(points, k);
    light_recs[i].done(light, at[i], terms[i]);
    out[i].ambient += terms[i].ambient;
    out[i].diffuse += terms[i].diffuse;
    out[i].specular += terms[i].specular;
  }
}

template <int MaxN, class LightRecorder>
void Integrator::add_single_samples(const ShadingPoint* at, const int* points, int count, uint32_t li,
                                    TraceContext& ctx, LightRecorder* recs, ShadeTerms* terms) const {
  const Light& light = scene_.lights[li];
  PacketSlots<LightSample, MaxN> sample;
  PacketSlots<PreparedSample, MaxN> prepared;  // constructed, then filled by prepare_light_sample
  PacketSlots<Ray, MaxN> shadow;               // the shadow rays asked, in order
  int asking[MaxN];
  int asked = 0;
  for (int k = 0; k < count; ++k) {
    const int i = slot<MaxN>(points, k);
    new (&sample[i]) LightSample(single_light_sample(light, li, at[i]));
    new (&prepared[i]) PreparedSample;
    // The shadow ray written in its place in the packet: copied from
    // `prepared` it was loaded 64 bytes at once just after the call stored
    // it in parts, which stalls (store forwarding).
    if (!prepare_light_sample(at[i], sample[i], prepared[i], shadow[asked], recs[i])) continue;
    ctx.stats.shadow++;
    asking[asked++] = i;
  }
  if (asked == 0) return;
  bool blocked[MaxN];
  if constexpr (MaxN == 1) {
    uint32_t* cache = li < ctx.shadow_cache.size() ? &ctx.shadow_cache[li] : nullptr;
    blocked[0] = recs[0].blocked(accel_, shadow[0], cache);
  } else {
    static_assert(std::is_same_v<LightRecorder, NoRecorder>, "a recorded ray is shaded in a batch of one");
    uint32_t no_cache = kNoShadowBlocker;
    accel_.occluded_packet(shadow.data(), asked, blocked,
                           li < ctx.shadow_cache.size() ? ctx.shadow_cache[li] : no_cache);
  }
  for (int j = 0; j < asked; ++j) {
    const int i = slot<MaxN>(asking, j);
    if (!blocked[j]) add_lit_sample(at[i], sample[i], prepared[i], terms[i], recs[i]);
  }
}

template <int MaxN, class Recorder>
void Integrator::add_secondary_rays(const ShadingPoint* at, const int* points, int count, int depth, TraceContext& ctx,
                                    Recorder* recs, ShadeTerms* out) const {
  PacketSlots<SecondaryRays, MaxN> secondary;
  for (int k = 0; k < count; ++k) {
    const int i = slot<MaxN>(points, k);
    new (&secondary[i]) SecondaryRays(secondary_rays(at[i], depth));
  }
  // A batch's reflected rays find their first hits as one packet (off a
  // mirror floor they are as coherent as the camera rays); each is then
  // shaded on its own, and every refracted ray is cast on its own.
  PacketSlots<Ray, MaxN> reflected;                      // in the order of `points`
  PacketSlots<std::optional<Hit>, MaxN> reflected_hits;  // likewise
  if constexpr (MaxN > 1) {
    // Gathered in a second pass: read back right after secondary_rays
    // stored them in parts, the rays were loaded 64 bytes at once, which
    // stalls (store forwarding).
    int n = 0;
    for (int k = 0; k < count; ++k) {
      const SecondaryRays& s = secondary[points[k]];
      if (!s.reflects) continue;
      reflected[n] = s.reflected;
      new (&reflected_hits[n++]) std::optional<Hit>;
    }
    if (n > 0) accel_.intersect_packet(reflected.data(), n, reflected_hits.data());
  }
  for (int k = 0, j = 0; k < count; ++k) {
    const int i = slot<MaxN>(points, k);
    const SecondaryRays& s = secondary[i];
    if (!s.reflects) continue;
    ctx.stats.reflection++;
    auto child = recs[i].reflection(s.reflect_weight);
    Color color;
    if constexpr (MaxN == 1) {
      color = cast(s.reflected, depth + 1, ctx, child);
    } else {
      cast_batch<1>(&reflected[j], &reflected_hits[j], 1, depth + 1, ctx, &child, &color);
      ++j;
    }
    out[i].reflection = s.reflect_weight * color;
  }
  for (int k = 0; k < count; ++k) {
    const int i = slot<MaxN>(points, k);
    const SecondaryRays& s = secondary[i];
    if (!s.refracts) continue;
    ctx.stats.refraction++;
    auto child = recs[i].refraction(s.refract_weight);
    out[i].transmission = s.refract_weight * cast(s.refracted, depth + 1, ctx, child);
  }
}

// --- Per light sample ---------------------------------------------------------

template <class LightRecorder>
void Integrator::add_light_sample(const ShadingPoint& at, const LightSample& s, ShadeTerms& out, TraceContext& ctx,
                                  LightRecorder& rec) const {
  PreparedSample prepared;
  Ray shadow;
  if (!prepare_light_sample(at, s, prepared, shadow, rec)) return;
  ctx.stats.shadow++;
  // No shadow cache: an area light's samples spread over its surface and
  // mostly pass the last blocker by (with the cache, a soft-shadow scene
  // rendered 12% slower).
  if (rec.blocked(accel_, shadow, nullptr)) return;
  add_lit_sample(at, s, prepared, out, rec);
}

template <class LightRecorder>
bool Integrator::prepare_light_sample(const ShadingPoint& at, const LightSample& s, PreparedSample& out, Ray& shadow,
                                      LightRecorder& rec) const {
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

double Integrator::ambient_visibility(const ShadingPoint& at, const Light& light, TraceContext& ctx) const {
  // Stratified points of the unit square, mapped onto the disk (concentric)
  // and lifted onto the hemisphere about n: cosine-weighted directions.
  Vec3 e_u, e_v;
  plane_frame(at.n, e_u, e_v);
  const auto [nu, nv] = stratified_grid(light.occlusion_samples);
  int open = 0;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const double su = (i + ctx.rng.next_double()) / nu;
      const double sv = (j + ctx.rng.next_double()) / nv;
      const LensPoint d = concentric_disk(su, sv);
      const double z = std::sqrt(std::max(0.0, 1.0 - d.x * d.x - d.y * d.y));
      const Ray ray{at.above, d.x * e_u + d.y * e_v + z * at.n, 0.0, light.occlusion_distance};
      ctx.stats.shadow++;
      if (!accel_.occluded(ray)) ++open;
    }
  }
  return static_cast<double>(open) / light.occlusion_samples;
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

}  // namespace glint
