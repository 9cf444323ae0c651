#include "glint/render/camera.h"

#include <cmath>
#include <numbers>

namespace glint {

CameraFrame make_camera_frame(const Camera& camera, int width, int height) {
  CameraFrame f;
  f.type = camera.type;
  f.origin = camera.position;
  f.forward = normalize(camera.look_at - camera.position);
  f.right = normalize(cross(f.forward, camera.up));
  f.up = cross(f.right, f.forward);
  const double aspect = static_cast<double>(width) / height;
  f.half_height = camera.type == CameraType::perspective
                      ? std::tan(0.5 * camera_fov_y(camera, height) * std::numbers::pi / 180.0)
                      : 0.5 * camera.view_height;
  f.half_width = f.half_height * aspect;
  return f;
}

}  // namespace glint
