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
  // Each eye of a stereo pair sees half the image.
  const double eye_width = camera.eye_separation ? 0.5 * width : static_cast<double>(width);
  const double aspect = eye_width / height;
  switch (camera.type) {
    case CameraType::perspective:
      f.half_height = std::tan(0.5 * camera_fov_y(camera, height) * std::numbers::pi / 180.0);
      break;
    case CameraType::orthographic: f.half_height = 0.5 * camera.view_height; break;
    case CameraType::fisheye:
    case CameraType::equirectangular: f.half_height = 1.0; break;
  }
  f.half_width = f.half_height * aspect;
  f.fisheye_half_angle = 0.5 * camera.fisheye_fov * std::numbers::pi / 180.0;
  if (camera.type == CameraType::perspective && camera.aperture > 0.0) {
    f.aperture = camera.aperture;
    f.focus_distance = camera.focus_distance.value_or(length(camera.look_at - camera.position));
  }
  if (camera.eye_separation) f.eye_offset = 0.5 * *camera.eye_separation;
  return f;
}

}  // namespace glint
