// What a glint::api::Scene shares between its copies: the document (the
// truth, as JSON) and the Scene the loader made of it. Immutable once made;
// an edit makes a new one.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "glint/io/file_cache.h"
#include "glint/scene.h"
#include "glint/scene/scene.h"

namespace glint::api {

struct Scene::State {
  nlohmann::ordered_json document;
  std::filesystem::path base_dir;
  std::string name;  // the file or name messages give
  std::shared_ptr<const glint::Scene> scene;
  size_t geometry_key = 0;
  // Where the loader gets mesh and texture files; shared by every state
  // edited from this one. nullptr (Scene::load): read them each time.
  std::shared_ptr<FileCache> files;
};

// Scene::load with its mesh and texture files from `files` (glint serve:
// edits then re-read no file that has not changed).
Scene load_scene_with(const std::filesystem::path& path, std::shared_ptr<FileCache> files);

// The same document checked again, with its mesh and texture files as they
// are now (from its cache where they have not changed).
Scene reread_files(const Scene& scene);

}  // namespace glint::api
