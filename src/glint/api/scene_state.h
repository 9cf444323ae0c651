// What a glint::api::Scene shares between its copies: the document (the
// truth, as JSON), the mesh arrays held beside it, and the Scene the loader
// made of both. Immutable once made; an edit makes a new one.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "glint/io/file_cache.h"
#include "glint/io/scene_loader.h"
#include "glint/scene.h"
#include "glint/scene/scene.h"

namespace glint::api {

// An NFF file's view (docs/nff.md): its `angle` spans the centers of the
// first and last pixel rows, so fov_y follows the rendered height. The
// scene keeps that meaning while its camera and render.height are still
// the ones the NFF reader wrote (`camera`, `height`); after an edit of
// either it is its JSON document, as a converted file is.
struct NffView {
  double angle = 0;
  nlohmann::ordered_json camera, height;
};

struct Scene::State {
  nlohmann::ordered_json document;
  // The arrays of add_mesh's objects, which the document names by id
  // ({"type": "mesh", "$arrays": id}); shared by the states that use them.
  AttachedMeshes meshes;
  std::optional<NffView> nff;
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
