#include "glint/io/mesh_scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "glint/io/mesh_file.h"
#include "glint/math/bounds.h"

namespace glint {

namespace {
// The rig's fixed choices (docs/cli.md).
constexpr double kFovY = 40.0;    // degrees
constexpr double kMargin = 1.15;  // the sphere's radius is this much inside the frame's height
constexpr int kWidth = 800, kHeight = 450, kSamples = 4;
}  // namespace

bool is_mesh_file(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".obj" || ext == ".ply" || ext == ".gltf" || ext == ".glb";
}

std::string mesh_scene_json(const std::filesystem::path& mesh) {
  const MeshFile file = load_mesh_file(mesh, default_memory_budget(), /*vertex_normals=*/false);
  Bounds3 bounds;
  for (const Vec3f& p : file.positions) bounds.extend(Vec3(p.x, p.y, p.z));
  const Vec3 c = bounds.center();
  // The bounding sphere: the box's center and half its diagonal.
  const double r = std::max(0.5 * length(bounds.diagonal()), 1e-6);
  // Far enough that the sphere fills the frame's height with a margin.
  const double d = kMargin * r / std::sin(0.5 * kFovY * std::numbers::pi / 180.0);
  // From above and in front (+y up, +z toward the viewer, as glTF and most OBJ exporters have it).
  const Vec3 eye = c + d * normalize(Vec3(0, 0.5, 1));
  const Vec3 key = c + d * Vec3(-0.8, 1.2, 0.9);  // above the camera, to its left
  const Vec3 fill = c + d * Vec3(1.0, 0.3, 0.7);  // low on the right, dimmer
  auto v = [](const Vec3& p) { return nlohmann::ordered_json::array({p.x, p.y, p.z}); };
  nlohmann::ordered_json scene = {
      {"render",
       {{"width", kWidth},
        {"height", kHeight},
        {"samples_per_pixel", kSamples},
        {"max_depth", 5},
        {"background", {0.05, 0.06, 0.08}}}},
      {"camera", {{"position", v(eye)}, {"look_at", v(c)}, {"up", {0, 1, 0}}, {"fov_y", kFovY}}},
      {"lights",
       {{{"type", "ambient"}, {"ambient", 0.2}, {"name", "ambient"}},
        {{"type", "point"}, {"position", v(key)}, {"diffuse", 0.9}, {"specular", 0.9}, {"name", "key"}},
        {{"type", "point"}, {"position", v(fill)}, {"diffuse", 0.35}, {"specular", 0.1}, {"name", "fill"}}}},
      {"objects", {{{"type", "mesh"}, {"file", mesh.filename().string()}, {"name", mesh.stem().string()}}}},
  };
  return scene.dump(2);
}

}  // namespace glint
