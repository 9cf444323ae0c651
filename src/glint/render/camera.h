// Camera rays: the camera's orthonormal frame and image-plane extent, computed
// once, and the ray through image-plane coordinates (u, v) in [0,1]^2, with
// (0,0) the top-left corner. Pixel (i,j)'s center is ((i+0.5)/W, (j+0.5)/H).
// The projections are docs/scene-format.md's ("Camera", "Cameras, atmosphere
// and solids beyond the seed"): perspective, orthographic, fisheye
// (equidistant) and equirectangular, a thin lens, parallel stereo.
#pragma once

#include <cmath>
#include <numbers>

#include "glint/math/ray.h"
#include "glint/scene/scene.h"

namespace glint {

struct CameraFrame {
  CameraType type = CameraType::perspective;
  Vec3 origin, forward, right, up;         // unit, right-handed: right = forward x up
  double half_width = 1, half_height = 1;  // tan(fov/2) or view_height/2, times aspect for width; fisheye: aspect, 1
  double fisheye_half_angle = 0;           // radians at r = 1 (fov/2)
  double aperture = 0, focus_distance = 1;  // thin lens: radius (0: pinhole), distance to the plane in focus
  double eye_offset = 0;                    // stereo: half the eye separation (0: mono)
};

// camera_fov_y (the vertical field of view at a given height) is in scene/scene.h.
// With stereo, `width` is the whole image's (both eyes).
CameraFrame make_camera_frame(const Camera& camera, int width, int height);

// A point of the unit disk where a camera sample crosses the lens: (0, 0) is
// the lens center (the pinhole ray itself).
struct LensPoint {
  double x = 0, y = 0;
};

// Shirley and Chiu's concentric map of [0,1)^2 onto the unit disk: strata of
// the square stay compact on the disk (the contract's lens sampling).
inline LensPoint concentric_disk(double a, double b) {
  const double x = 2.0 * a - 1.0, y = 2.0 * b - 1.0;
  if (x == 0.0 && y == 0.0) return {};
  double r, phi;
  if (std::abs(x) > std::abs(y)) {
    r = x;
    phi = (std::numbers::pi / 4) * (y / x);
  } else {
    r = y;
    phi = (std::numbers::pi / 2) - (std::numbers::pi / 4) * (x / y);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

// A ray that looks at nothing (a fisheye pixel outside its circle): the
// empty interval, so it misses everything and returns what a miss returns
// for its direction.
inline void make_ray_miss(Ray& ray) { ray.t_max = ray.t_min; }

inline Ray generate_camera_ray(const CameraFrame& f, double u, double v, LensPoint lens = {}) {
  Vec3 origin = f.origin;
  if (f.eye_offset != 0.0) {  // left eye on the image's left half
    const bool left = u < 0.5;
    u = left ? 2.0 * u : 2.0 * u - 1.0;
    origin += (left ? -f.eye_offset : f.eye_offset) * f.right;
  }
  const double sx = (2.0 * u - 1.0) * f.half_width;
  const double sy = (1.0 - 2.0 * v) * f.half_height;
  Ray ray;
  ray.origin = origin;
  switch (f.type) {
    case CameraType::perspective:
      ray.direction = normalize(f.forward + sx * f.right + sy * f.up);
      if (f.aperture > 0.0 && (lens.x != 0.0 || lens.y != 0.0)) {
        // Through the point where the pinhole ray meets the plane in focus.
        const Vec3 focus = origin + (f.focus_distance / dot(ray.direction, f.forward)) * ray.direction;
        ray.origin = origin + f.aperture * (lens.x * f.right + lens.y * f.up);
        ray.direction = normalize(focus - ray.origin);
      }
      break;
    case CameraType::orthographic:
      ray.origin = origin + sx * f.right + sy * f.up;
      ray.direction = f.forward;
      break;
    case CameraType::fisheye: {
      // Equidistant: the angle off the axis grows linearly with the distance
      // r from the image center (r = 1 at half the image height).
      const double r = std::sqrt(sx * sx + sy * sy);
      const double theta = r * f.fisheye_half_angle;
      if (r == 0.0) {
        ray.direction = f.forward;
      } else {
        const double s = std::sin(theta) / r;
        ray.direction = std::cos(theta) * f.forward + (s * sx) * f.right + (s * sy) * f.up;
      }
      if (r > 1.0 || theta > std::numbers::pi) make_ray_miss(ray);
      break;
    }
    case CameraType::equirectangular: {
      const double phi = (u - 0.5) * (2.0 * std::numbers::pi);  // longitude, to the right
      const double lat = (0.5 - v) * std::numbers::pi;          // latitude, up
      const double c = std::cos(lat);
      ray.direction = (c * std::sin(phi)) * f.right + (c * std::cos(phi)) * f.forward + std::sin(lat) * f.up;
      break;
    }
  }
  return ray;
}

}  // namespace glint
