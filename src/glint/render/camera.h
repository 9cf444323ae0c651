// Camera rays: the camera's orthonormal frame and image-plane extent, computed
// once, and the ray through image-plane coordinates (u, v) in [0,1]^2, with
// (0,0) the top-left corner. Pixel (i,j)'s center is ((i+0.5)/W, (j+0.5)/H).
#pragma once

#include "glint/math/ray.h"
#include "glint/scene/scene.h"

namespace glint {

struct CameraFrame {
  CameraType type = CameraType::perspective;
  Vec3 origin, forward, right, up;         // unit, right-handed: right = forward x up
  double half_width = 1, half_height = 1;  // tan(fov/2) or view_height/2, times aspect for width
};

// camera_fov_y (the vertical field of view at a given height) is in scene/scene.h.
CameraFrame make_camera_frame(const Camera& camera, int width, int height);

inline Ray generate_camera_ray(const CameraFrame& f, double u, double v) {
  const double sx = (2.0 * u - 1.0) * f.half_width;
  const double sy = (1.0 - 2.0 * v) * f.half_height;
  Ray ray;
  if (f.type == CameraType::perspective) {
    ray.origin = f.origin;
    ray.direction = normalize(f.forward + sx * f.right + sy * f.up);
  } else {
    ray.origin = f.origin + sx * f.right + sy * f.up;
    ray.direction = f.forward;
  }
  return ray;
}

}  // namespace glint
