// What a glint::api::Scene shares between its copies: the document (the
// truth, as JSON) and the Scene the loader made of it. Immutable once made;
// an edit makes a new one.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "glint/scene.h"
#include "glint/scene/scene.h"

namespace glint::api {

struct Scene::State {
  nlohmann::ordered_json document;
  std::filesystem::path base_dir;
  std::string name;  // the file or name messages give
  std::shared_ptr<const glint::Scene> scene;
  size_t geometry_key = 0;
};

}  // namespace glint::api
