#include "glint/io/scene_loader.h"

#include <new>
#include <vector>

#include "glint/io/json.h"
#include "glint/io/loader/scene_reader.h"
#include "glint/io/memory_limit.h"
#include "glint/io/mesh_scene.h"
#include "glint/io/nff_file.h"

namespace glint {

namespace {

using loader::SceneReader;

}  // namespace

void check_image_size(int width, int height, const SourceLocation& where) {
  // The film holds 3 floats per pixel; refuse what this machine cannot hold
  // rather than let the allocation fail (or the OOM killer strike) mid-render.
  const std::string excess = exceeds_budget(12.0 * width * height, default_memory_budget());
  if (!excess.empty())
    throw Error(where, "image of " + std::to_string(width) + "x" + std::to_string(height) + " pixels " + excess);
}

Scene parse_scene(std::string text, const std::string& filename, const std::filesystem::path& base_dir,
                  size_t memory_budget, const AttachedMeshes* attached, FileCache* files) {
  const json::Document doc = json::parse(std::move(text), filename);
  try {
    return SceneReader(doc, base_dir, memory_budget, attached, files).read();
  } catch (const std::bad_alloc&) {
    throw Error(SourceLocation{filename, 0, 0}, "out of memory while loading the scene");
  }
}

std::vector<Error> validate_scene(const std::filesystem::path& path) {
  if (is_nff_path(path)) return validate_nff_scene(path);
  std::vector<Error> errors;
  try {
    const json::Document doc = json::parse_file(path.string());
    SceneReader(doc, path.parent_path()).read(&errors);
  } catch (const Error& e) {
    errors.push_back(e);  // unreadable or not JSON: nothing more can be checked
  } catch (const std::bad_alloc&) {
    errors.push_back(Error(SourceLocation{path.string(), 0, 0}, "out of memory while loading the scene"));
  }
  return errors;
}

Scene load_scene(const std::filesystem::path& path, FileCache* files) {
  if (is_nff_path(path)) return load_nff_scene(path);  // an NFF names no other file
  // A bare mesh file is framed by a fixed rig (io/mesh_scene.h).
  if (is_mesh_file(path))
    return parse_scene(mesh_scene_json(path), path.string(), path.parent_path(), default_memory_budget(), nullptr,
                       files);
  const json::Document doc = json::parse_file(path.string());
  try {
    return SceneReader(doc, path.parent_path(), default_memory_budget(), nullptr, files).read();
  } catch (const std::bad_alloc&) {
    throw Error(SourceLocation{path.string(), 0, 0}, "out of memory while loading the scene");
  }
}

}  // namespace glint
