#include "glint/render/camera.h"

#include <cmath>
#include <numbers>

namespace glint {

double fov_y_for_row_center_angle(double row_center_angle, int height) {
  if (height < 2) return row_center_angle;
  const double half = 0.5 * row_center_angle * std::numbers::pi / 180.0;
  return 2.0 * std::atan(std::tan(half) * height / (height - 1.0)) * 180.0 / std::numbers::pi;
}

double camera_fov_y(const Camera& camera, int height) {
  return camera.row_center_angle ? fov_y_for_row_center_angle(*camera.row_center_angle, height) : camera.fov_y;
}

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
