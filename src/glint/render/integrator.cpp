#include "glint/render/integrator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "glint/geometry/shapes.h"
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

Integrator::Integrator(const Scene& scene, const Accelerator& accel)
    : scene_(scene), accel_(accel), epsilon_(scene.render.epsilon.value_or(auto_epsilon(scene))) {
  for (const Light& light : scene.lights)
    cos_cutoff_.push_back(std::cos(light.cutoff * std::numbers::pi / 180.0));
}

Color Integrator::cast_ray(const Ray& ray, int depth, TraceContext& ctx, RayTrace* trace) const {
  const std::optional<Hit> hit = accel_.intersect(ray);
  if (hit && depth == 1) ctx.stats.camera_hits++;
  Color color = scene_.render.background;
  if (hit) color = shade_surface(ray, *hit, depth, ctx, trace).sum();
  if (trace) {
    trace->ray = ray;
    trace->depth = depth;
    trace->hit = hit;
    trace->color = color;
  }
  return color;
}

Color Integrator::cast_ray_with_hit(const Ray& ray, const std::optional<Hit>& hit, int depth,
                                    TraceContext& ctx) const {
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

namespace {

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

}  // namespace

void Integrator::add_light_sample(const Light& light, double cos_cutoff, const Vec3& to_light,
                                  double shadow_t_max, double distance, const SurfacePoint& sp, const Vec3& n,
                                  const Vec3& v, const Vec3& shadow_origin, double weight, ShadeTerms& out,
                                  TraceContext& ctx, LightTrace* trace) const {
  const Vec3 l = normalize(to_light);
  const double n_dot_l = dot(n, l);
  if (!(n_dot_l > 0.0)) return;

  double scale = weight;
  if (light.type == LightType::spot) {
    const double cos_angle = -dot(l, light.direction);
    // The cone's edge counts as inside; the tolerance absorbs rounding.
    if (cos_angle < cos_cutoff - 1e-12) {
      if (trace) trace->spot_factor = 0;
      return;
    }
    if (light.falloff != 0.0) {
      const double factor = std::pow(std::max(0.0, cos_angle), light.falloff);
      scale *= factor;
      if (trace) trace->spot_factor = factor;
    }
  }
  if (light.type != LightType::directional) {
    const Vec3& a = light.attenuation;
    const double denominator = a.x + a.y * distance + a.z * distance * distance;
    scale /= denominator;
    if (trace) trace->attenuation = 1.0 / denominator;
  }

  Ray shadow;
  shadow.origin = shadow_origin;
  shadow.direction = light.type == LightType::directional ? l : to_light + (sp.p - shadow_origin);
  shadow.t_min = 0.0;
  shadow.t_max = shadow_t_max;
  ctx.stats.shadow++;
  if (trace) {
    // The same any-hit query, asked for the blocker's name.
    if (const auto blocker = accel_.first_blocker(shadow)) {
      if (!trace->blocker) trace->blocker = blocker;
      return;
    }
  } else {
    const size_t li = static_cast<size_t>(&light - scene_.lights.data());
    if (li < ctx.shadow_cache.size() ? accel_.occluded_cached(shadow, ctx.shadow_cache[li]) : accel_.occluded(shadow))
      return;
  }

  const Material& m = scene_.materials[sp.material];
  out.diffuse += (scale * n_dot_l) * (sp.reflectance.diffuse * light.diffuse);
  double cos_spec = 0.0;  // r.v or n.h, before clamping
  if (scene_.render.shading_model == ShadingModel::phong) {
    const Vec3 r = 2.0 * n_dot_l * n - l;
    cos_spec = dot(r, v);
  } else {
    const Vec3 half = l + v;
    const double len = length(half);
    if (len > 0.0) cos_spec = dot(n, half / len);
  }
  const double s = std::max(0.0, cos_spec);
  if (s > 0.0 && !is_black(sp.reflectance.specular * light.specular))
    out.specular += (scale * shininess_pow(s, m.shininess)) * (sp.reflectance.specular * light.specular);
  if (trace) {
    trace->lit_samples++;
    if (!trace->specular_cos) trace->specular_cos = cos_spec;
  }
}

ShadeTerms Integrator::shade_surface(const Ray& ray, const Hit& hit, int depth, TraceContext& ctx,
                                     RayTrace* trace) const {
  const SurfacePoint sp = evaluate_hit(scene_, ray, hit);
  const Material& m = scene_.materials[sp.material];
  const Vec3 d = normalize(ray.direction);
  const Vec3 v = -d;
  // Two-sided surfaces: shade with the normal on the viewer's side.
  const Vec3 n = dot(sp.shading_normal, d) < 0.0 ? sp.shading_normal : -sp.shading_normal;
  // Inside and outside come from the geometric normal (the contract): a
  // smooth normal may face the other way than the surface near silhouettes.
  const bool entering = dot(sp.geometric_normal, d) < 0.0;
  const Vec3 ng = entering ? sp.geometric_normal : -sp.geometric_normal;
  // Secondary rays leave from just off the surface: shadow and reflected rays
  // on the incoming side, refracted rays on the far side.
  const Vec3 above = sp.p + epsilon_ * ng;
  const Vec3 below = sp.p - epsilon_ * ng;
  if (trace) {
    trace->surface = sp;
    trace->normal = n;
  }
  ShadeTerms out;
  if (m.unlit) {  // MTL illum 0: the color is Kd, no lights, no shadows, no rays
    out.ambient = sp.reflectance.diffuse;
    return out;
  }

  // Each light's terms are summed on their own, then added: the contract's
  // "sum over lights", in the same order whether or not a trace is kept.
  for (uint32_t li = 0; li < scene_.lights.size(); ++li) {
    const Light& light = scene_.lights[li];
    ShadeTerms terms;
    LightTrace* light_trace = nullptr;
    if (trace) {
      trace->lights.emplace_back();
      light_trace = &trace->lights.back();
      light_trace->index = li;
    }
    terms.ambient = sp.reflectance.ambient * light.ambient;
    switch (light.type) {
      case LightType::ambient:
        break;
      case LightType::point:
      case LightType::spot: {
        const Vec3 to_light = light.position - sp.p;
        add_light_sample(light, cos_cutoff_[li], to_light, 1.0, length(to_light), sp, n, v, above, 1.0, terms,
                         ctx, light_trace);
        if (light_trace) light_trace->l = normalize(to_light);
        break;
      }
      case LightType::directional:
        add_light_sample(light, cos_cutoff_[li], -light.direction, kInfinity, 0.0, sp, n, v, above, 1.0, terms,
                         ctx, light_trace);
        if (light_trace) light_trace->l = -light.direction;
        break;
      case LightType::area: {
        // Stratified jittered points on the parallelogram, one per cell of an
        // nu x nv grid (nu * nv == samples), each a point light of weight 1/N.
        int nu = static_cast<int>(std::sqrt(static_cast<double>(light.samples)));
        while (light.samples % nu != 0) --nu;
        const int nv = light.samples / nu;
        const double weight = 1.0 / light.samples;
        for (int j = 0; j < nv; ++j) {
          for (int i = 0; i < nu; ++i) {
            const double su = (i + ctx.rng.next_double()) / nu;
            const double sv = (j + ctx.rng.next_double()) / nv;
            const Vec3 pos = light.corner + su * light.edge_u + sv * light.edge_v;
            const Vec3 to_light = pos - sp.p;
            add_light_sample(light, cos_cutoff_[li], to_light, 1.0, length(to_light), sp, n, v, above, weight,
                             terms, ctx, light_trace);
          }
        }
        if (light_trace) {
          light_trace->samples = light.samples;
          light_trace->l = normalize(light.corner + 0.5 * (light.edge_u + light.edge_v) - sp.p);
        }
        break;
      }
    }
    if (light_trace) {
      light_trace->terms = terms;
      if (light.type != LightType::ambient) {
        light_trace->n_dot_l = dot(n, light_trace->l);
        light_trace->shadowed = light_trace->blocker.has_value() && light_trace->lit_samples == 0;
      }
    }
    out.ambient += terms.ambient;
    out.diffuse += terms.diffuse;
    out.specular += terms.specular;
  }

  // Weights of the reflected and refracted rays (contract: materials, fresnel).
  const double cos_theta = std::clamp(dot(v, n), 0.0, 1.0);
  Color reflect_weight = m.reflectivity;
  Color refract_weight(m.transparency);
  if (m.fresnel) {
    const double r0 = (m.ior - 1.0) / (m.ior + 1.0);
    const double s_glass = schlick(Color(r0 * r0), cos_theta).x;
    reflect_weight = schlick(m.reflectivity, cos_theta) + Color(m.transparency * s_glass);
    refract_weight = Color(m.transparency * (1.0 - s_glass));
  }
  if (depth + 1 <= scene_.render.max_depth) {
    Vec3 refracted_dir;
    bool refracts = false;
    if (!is_black(refract_weight)) {
      // Snell's law; the inside has index ior, the outside 1.
      const double eta = entering ? 1.0 / m.ior : m.ior;
      const double k = 1.0 - eta * eta * (1.0 - cos_theta * cos_theta);
      if (k < 0.0) {
        reflect_weight += refract_weight;  // total internal reflection
      } else {
        refracted_dir = eta * d + (eta * cos_theta - std::sqrt(k)) * n;
        refracts = true;
      }
    }
    if (!is_black(reflect_weight)) {
      ctx.stats.reflection++;
      const Ray reflected{above, reflect(d, n)};
      RayTrace* child = nullptr;
      if (trace) {
        trace->reflection_weight = reflect_weight;
        trace->reflection = std::make_unique<RayTrace>();
        child = trace->reflection.get();
      }
      out.reflection = reflect_weight * cast_ray(reflected, depth + 1, ctx, child);
    }
    if (refracts) {
      ctx.stats.refraction++;
      const Ray refracted{below, refracted_dir};
      RayTrace* child = nullptr;
      if (trace) {
        trace->refraction_weight = refract_weight;
        trace->refraction = std::make_unique<RayTrace>();
        child = trace->refraction.get();
      }
      out.transmission = refract_weight * cast_ray(refracted, depth + 1, ctx, child);
    }
  }
  return out;
}

}  // namespace glint
