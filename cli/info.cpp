// glint info: what a scene holds and what rendering it takes in memory
// (docs/cli.md#info).
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "glint/accel/accelerator.h"
#include "glint/io/memory_limit.h"
#include "glint/io/scene_loader.h"
#include "glint/scene/memory.h"
#include "options.h"

namespace glint::cli {

namespace {

// What the scene holds and what rendering it will take in memory.
int run_info(const std::string& scene_path) {
  const Scene scene = load_scene(scene_path);
  const auto accel = build_accelerator(scene);
  const RenderSettings& r = scene.render;
  size_t by_type[kShapeTypeCount] = {};
  Bounds3 bounds;
  for (uint32_t i = 0; i < scene.objects.size(); ++i) {
    by_type[static_cast<int>(scene.objects[i].type)]++;
    if (scene.objects[i].type != ShapeType::plane) bounds.extend(object_bounds(scene, i));
  }
  size_t lights_by_type[5] = {0, 0, 0, 0, 0};
  for (const Light& l : scene.lights) lights_by_type[static_cast<int>(l.type)]++;
  const double scene_bytes = static_cast<double>(scene_memory(scene).total());
  size_t mesh_triangles = 0;  // of the mesh objects (an instance counts its mesh again)
  for (const Object& o : scene.objects)
    if (o.type == ShapeType::mesh) mesh_triangles += scene.meshes[o.shape].triangle_count();
  const double image_bytes = 12.0 * r.width * r.height;
  std::printf("scene      %s\n", scene_path.c_str());
  const char* filters[] = {"box", "gaussian", "mitchell"};
  std::string sampling = std::to_string(r.samples_per_pixel) + " spp";
  if (r.adaptive) sampling += " (adaptive up to " + std::to_string(r.adaptive->max_samples_per_pixel) + ")";
  std::printf("image      %dx%d, %s, %s filter, max depth %d, %s\n", r.width, r.height, sampling.c_str(),
              filters[static_cast<int>(r.pixel_filter.type)], r.max_depth,
              r.shading_model == ShadingModel::phong ? "phong" : "blinn-phong");
  const auto count = [&](ShapeType t) { return by_type[static_cast<int>(t)]; };
  std::printf(
      "objects    %zu: %zu spheres, %zu planes, %zu triangles, %zu boxes, %zu meshes (%zu triangles), "
      "%zu cylinders, %zu cones, %zu disks, %zu polygons\n",
      scene.objects.size(), count(ShapeType::sphere), count(ShapeType::plane), count(ShapeType::triangle),
      count(ShapeType::box), count(ShapeType::mesh), mesh_triangles, count(ShapeType::cylinder), count(ShapeType::cone),
      count(ShapeType::disk), count(ShapeType::polygon));
  std::printf("lights     %zu: %zu ambient, %zu point, %zu directional, %zu spot, %zu area\n", scene.lights.size(),
              lights_by_type[0], lights_by_type[1], lights_by_type[2], lights_by_type[3], lights_by_type[4]);
  std::printf("materials  %zu (and the default)\n", scene.materials.size() - 1);
  if (!scene.textures.empty())
    std::printf("textures   %zu, %zu image files\n", scene.textures.size(), scene.texture_images.size());
  if (scene.animation.frames > 0)
    std::printf("animation  %d frames at %g fps, %zu animated object%s%s\n", scene.animation.frames,
                scene.animation.fps, scene.animation.objects.size(), scene.animation.objects.size() == 1 ? "" : "s",
                scene.animation.camera.position.empty() && scene.animation.camera.look_at.empty() &&
                        scene.animation.camera.up.empty() && scene.animation.camera.fov_y.empty()
                    ? ""
                    : ", animated camera");
  if (!bounds.empty())
    std::printf("bounds     (%g, %g, %g) to (%g, %g, %g), planes excluded\n", bounds.lo.x, bounds.lo.y, bounds.lo.z,
                bounds.hi.x, bounds.hi.y, bounds.hi.z);
  const double accel_bytes = static_cast<double>(accel->memory_bytes());
  std::printf("memory     scene %s + BVH %s + image %s = %s\n", format_bytes(scene_bytes).c_str(),
              format_bytes(accel_bytes).c_str(), format_bytes(image_bytes).c_str(),
              format_bytes(scene_bytes + accel_bytes + image_bytes).c_str());
  return 0;
}

}  // namespace

Command add_info_command(CLI::App& app) {
  auto scene_path = std::make_shared<std::string>();
  CLI::App* info = app.add_subcommand("info", "what a scene holds: counts, bounds, memory");
  info->add_option("scene", *scene_path, "scene file (JSON or NFF)")->required();
  return {info, [scene_path] { return run_info(*scene_path); }};
}

}  // namespace glint::cli
