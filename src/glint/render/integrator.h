// Integrator: the shading contract of docs/scene-format.md, as two functions.
// cast_ray finds the first hit (or the background); shade_surface sums, over
// lights, ambient + unshadowed diffuse + specular (Phong or Blinn-Phong), then
// adds the weighted reflected and refracted rays, recursively up to max_depth.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/math/rng.h"
#include "glint/scene/scene.h"

namespace glint {

struct RayStats {
  uint64_t camera = 0, shadow = 0, reflection = 0, refraction = 0;
  uint64_t camera_hits = 0;  // camera rays (depth 1) that hit a surface: the SPD's "eye rays that hit"
  uint64_t total() const { return camera + shadow + reflection + refraction; }
  RayStats& operator+=(const RayStats& o) {
    camera += o.camera;
    shadow += o.shadow;
    reflection += o.reflection;
    refraction += o.refraction;
    camera_hits += o.camera_hits;
    return *this;
  }
};

// R_a, R_d, R_s at one point: the material's colors, or its textures' values.
struct Reflectances {
  Color ambient, diffuse, specular;
};

// The hit, evaluated: where it is, which way the surface faces there, and
// what it reflects there.
struct SurfacePoint {
  Vec3 p;
  Vec3 geometric_normal;  // unit, the shape's outward side (not yet flipped)
  Vec3 shading_normal;    // unit, likewise
  uint32_t material = 0;
  Reflectances reflectance;
  bool textured = false;  // the material has a texture: `uv` is set
  UV uv;                  // surface coordinates, before any texture's scale and offset
};
SurfacePoint evaluate_hit(const Scene& scene, const Ray& ray, const Hit& hit);

// The parts of one shaded point, in the order the contract sums them.
struct ShadeTerms {
  Color ambient, diffuse, specular, reflection, transmission;
  Color sum() const { return ambient + diffuse + specular + reflection + transmission; }
};

// A camera ray's color by its parts, with the facts of its first hit: what
// the passes (AOVs) store; without fog terms.sum() is `color`.
struct CameraSample {
  Color color;       // cast_ray's color, bit for bit
  ShadeTerms terms;  // a miss puts the background in `ambient`; fog scales
                     // each term by f and adds (1 - f) fog color to `ambient`
  Vec3 normal;       // shading normal as used (turned toward the ray); 0 on a miss
  double depth = 0;  // distance along the ray to the first hit; 0 on a miss
  Color albedo;      // R_d at the first hit; 0 on a miss
};

// Per-thread state a ray needs: random numbers (area lights), counters, and
// the shadow cache: for each of the first lights, the object that last
// blocked a shadow ray toward it (Accelerator::occluded_cached). Neighbouring
// points are mostly shadowed by the same object, so that one is asked first.
inline constexpr size_t kShadowCacheLights = 16;
struct TraceContext {
  Rng rng;
  RayStats stats;
  std::array<uint32_t, kShadowCacheLights> shadow_cache = make_shadow_cache();
  static constexpr std::array<uint32_t, kShadowCacheLights> make_shadow_cache() {
    std::array<uint32_t, kShadowCacheLights> cache{};
    cache.fill(kNoShadowBlocker);
    return cache;
  }
};

// What one light did at a shaded point: the facts `glint explain` reports.
struct LightTrace {
  uint32_t index = 0;  // into Scene::lights
  Vec3 l;              // unit vector to the light (an area light's center)
  double n_dot_l = 0;
  bool shadowed = false;               // every sample's shadow ray was blocked
  std::optional<uint32_t> blocker;     // the first blocker found (an object index)
  std::optional<double> specular_cos;  // r.v (phong) or n.h (blinn-phong), when lit
  double spot_factor = 1, attenuation = 1;
  int samples = 1, lit_samples = 0;  // area lights: shadow samples and unblocked ones
  std::optional<double> visibility;  // ambient occlusion: the fraction of open directions
  ShadeTerms terms;                  // this light's ambient, diffuse, specular
};

// The whole tree of rays behind one camera ray, filled when asked for.
struct RayTrace {
  Ray ray;
  int depth = 1;
  std::optional<Hit> hit;
  SurfacePoint surface;
  Vec3 normal;  // the shading normal as used: turned toward the incoming ray
  std::vector<LightTrace> lights;
  Color reflection_weight, refraction_weight;
  std::unique_ptr<RayTrace> reflection, refraction;  // null when not cast
  std::optional<double> fog;           // f: color = f (shaded sum) + (1 - f) fog color
  std::optional<UV> environment_uv;    // a miss that saw the environment: where
  Color color;
};

// The shaded point as its light samples and secondary rays see it, and one
// point (or direction) a light shines from (integrator.cpp).
struct ShadingPoint;
struct LightSample;
struct PreparedSample;
struct SecondaryRays;

class Integrator {
 public:
  Integrator(const Scene& scene, const Accelerator& accel);

  // Color seen along `ray`, a ray of the given depth (the camera ray is 1).
  Color cast_ray(const Ray& ray, int depth, TraceContext& ctx) const;
  // The same color, recording the ray tree into `trace` (`glint explain`):
  // the same code and arithmetic, through a recorder that keeps what the
  // render's no-op recorder drops.
  Color trace_ray(const Ray& ray, int depth, TraceContext& ctx, RayTrace& trace) const;
  ShadeTerms shade_surface(const Ray& ray, const Hit& hit, int depth, TraceContext& ctx) const;
  // cast_ray for a camera ray (depth 1), keeping the parts apart.
  CameraSample cast_camera_ray(const Ray& ray, TraceContext& ctx) const;
  // The same two, for a camera ray whose first hit is already known (found
  // with the other rays of its packet: Accelerator::intersect_packet).
  Color cast_ray_with_hit(const Ray& ray, const std::optional<Hit>& hit, int depth, TraceContext& ctx) const;
  CameraSample cast_camera_ray_with_hit(const Ray& ray, const std::optional<Hit>& hit, TraceContext& ctx) const;

  // cast_ray_with_hit for up to kPacketSize camera rays of neighbouring
  // pixels (their first hits found as a packet), shaded as one batch: the
  // shadow rays of all of them toward one light are asked as one packet
  // (Accelerator::occluded_packet), their reflected rays' first hits too.
  // colors[i] is cast_ray_with_hit's color for rays[i], bit for bit. Only
  // for scenes where shades_packets(): without area lights, whose samples
  // draw each pixel's random numbers in the pixel's order.
  bool shades_packets() const { return shades_packets_; }
  void cast_camera_packet(const Ray* rays, const std::optional<Hit>* hits, int count, TraceContext& ctx,
                          Color* colors) const;

  double epsilon() const { return epsilon_; }
  // What a ray that hits nothing returns: the background, or the environment
  // in its direction (its lookup's (u, v) into `uv`, when given).
  Color miss_color(const Ray& ray, UV* uv = nullptr) const;
  // Fog's f for a hit at distance t along `ray` (1: no fog).
  double fog_factor(const Ray& ray, double t) const;
  // f C + (1 - f) fog color.
  Color fogged(const Color& c, double f) const { return f * c + (1.0 - f) * scene_.render.fog->color; }

 private:
  // The formula's control flow, written once (integrator.cpp), for a batch
  // of up to MaxN rays whose first hits are known: cast_batch gives each ray
  // its color (the background on a miss), shade_batch the terms of the
  // points that were hit. cast_ray, trace_ray and shade_surface are batches
  // of one (MaxN = 1); cast_camera_packet is a batch of neighbouring camera
  // rays whose shadow rays toward each light are asked as one packet.
  // `Recorder` is the render's NoRecorder, whose hooks are empty and inline
  // away, or explain's TraceRecorder, which fills a RayTrace (batches of one).
  template <int MaxN, class Recorder>
  void cast_batch(const Ray* rays, const std::optional<Hit>* hits, int count, int depth, TraceContext& ctx,
                  Recorder* recs, Color* colors) const;
  template <int MaxN, class Recorder>
  void shade_batch(const Ray* rays, const std::optional<Hit>* hits, const int* points, int count, int depth,
                   TraceContext& ctx, Recorder* recs, ShadeTerms* out) const;
  // A batch of one ray, its hit found first.
  template <class Recorder>
  Color cast(const Ray& ray, int depth, TraceContext& ctx, Recorder& rec) const;
  // One light's ambient, diffuse and specular at each point, added to out.
  template <int MaxN, class Recorder>
  void add_light(const ShadingPoint* at, const int* points, int count, uint32_t light, TraceContext& ctx,
                 Recorder* recs, ShadeTerms* out) const;
  // A point, spot or directional light: one sample per point, the shadow
  // rays of a batch asked as one packet, a single one through the cache.
  template <int MaxN, class LightRecorder>
  void add_single_samples(const ShadingPoint* at, const int* points, int count, uint32_t light, TraceContext& ctx,
                          LightRecorder* recs, ShadeTerms* terms) const;
  // The weighted reflected and refracted rays, into out.reflection and out.transmission.
  template <int MaxN, class Recorder>
  void add_secondary_rays(const ShadingPoint* at, const int* points, int count, int depth, TraceContext& ctx,
                          Recorder* recs, ShadeTerms* out) const;
  // An area light's stratified samples at one point, added to `out`.
  template <class LightRecorder>
  void add_area_light(const ShadingPoint& at, uint32_t light, ShadeTerms& out, TraceContext& ctx,
                      LightRecorder& rec) const;
  // Diffuse + specular from one area light sample, shadow ray included, added to `out`.
  template <class LightRecorder>
  void add_light_sample(const ShadingPoint& at, const LightSample& sample, ShadeTerms& out, TraceContext& ctx,
                        LightRecorder& rec) const;
  // A light sample's two halves around its shadow query: the sample's scale
  // and its shadow ray, into `shadow` (false: it cannot light the point), and
  // its diffuse and specular once the ray is known unblocked.
  template <class LightRecorder>
  bool prepare_light_sample(const ShadingPoint& at, const LightSample& sample, PreparedSample& out, Ray& shadow,
                            LightRecorder& rec) const;
  template <class LightRecorder>
  void add_lit_sample(const ShadingPoint& at, const LightSample& sample, const PreparedSample& prepared,
                      ShadeTerms& out, LightRecorder& rec) const;
  // Ambient occlusion: the fraction of the light's cosine-weighted rays
  // from the point that hit nothing within its distance.
  double ambient_visibility(const ShadingPoint& at, const Light& light, TraceContext& ctx) const;
  // Which rays a point at `depth` casts on, their weights and rays.
  SecondaryRays secondary_rays(const ShadingPoint& at, int depth) const;

  const Scene& scene_;
  const Accelerator& accel_;
  double epsilon_;
  std::vector<double> cos_cutoff_;  // per light: cos of a spot light's cutoff
  bool shades_packets_ = true;
};

}  // namespace glint
