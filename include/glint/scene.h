// glint::api::Scene: a scene as its document (the JSON of
// docs/scene-format.md) together with its checked, render-ready form.
// Loading, editing and writing back all go through the same loader, so an
// edit is checked exactly as the scene file would be, and to_json() loads
// back to an identical scene.
//
// Ownership: a Scene is a value. Copies are cheap (they share their state
// until one is edited) and nothing else ever refers into a Scene: a Renderer
// keeps its own snapshot, so a temporary Scene cannot dangle and editing a
// Scene never changes a render in flight.
//
// Threads: distinct Scene objects (copies included) may be used from
// different threads at once; one Scene object must not be edited while
// another thread uses it (as for standard containers).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "glint/error.h"

namespace glint::api {

// A triangle mesh as arrays in memory (what Python's glint.Scene.add_mesh
// hands over), flat, one row after another, in the types glint renders with.
struct MeshArrays {
  std::vector<float> positions;     // x, y, z per vertex
  std::vector<uint32_t> triangles;  // i, j, k per triangle: 0-based vertex indices
  std::vector<float> normals;       // empty, or x, y, z per vertex (zero: computed)
  std::vector<float> uvs;           // empty, or u, v per vertex
};

class Scene {
 public:
  // Any scene file glint reads, chosen by its extension (.json; .nff), or a
  // bare mesh file (.obj .ply .gltf .glb) framed by the rig of docs/cli.md.
  // Relative mesh and texture paths resolve against the file's folder.
  // Throws glint::Error with the file, line and column of the problem.
  static Scene load(const std::filesystem::path& path);
  // Scene JSON from text. Relative paths resolve against `base_dir`; `name`
  // is what error messages call the text.
  static Scene from_json(std::string_view json_text, const std::filesystem::path& base_dir = {},
                         std::string_view name = "<scene>");

  // The scene's JSON document: loads back (with base_dir()) to this scene.
  std::string to_json(int indent = 2) const;
  const std::filesystem::path& base_dir() const;
  // The file or name the scene came from, as messages give it.
  const std::string& name() const;

  // Values by their path in the document, as the loader names them in its
  // messages: "materials.floor.shininess", "lights[0].position",
  // "camera.look_at", "render.samples_per_pixel", "objects[2].radius".
  // get() returns the value as JSON text; a path that is not there throws.
  std::string get(std::string_view path) const;
  bool has(std::string_view path) const;

  // Sets the value at `path` (creating the last key of an object if it is
  // missing) and checks the whole scene as the loader does. A bad value
  // throws glint::Error carrying the loader's message, which names the path
  // ("materials.floor.shininess: must be > 0 (got -3)"), and leaves the
  // scene exactly as it was.
  void set_json(std::string_view path, std::string_view json_value);
  void set(std::string_view path, double value);
  void set(std::string_view path, int value);
  void set(std::string_view path, bool value);
  void set(std::string_view path, const std::array<double, 3>& value);
  void set_string(std::string_view path, std::string_view value);
  // Removes a key, a material, a light or an object (same checks; e.g. a
  // material still in use cannot go).
  void erase(std::string_view path);
  // Appends to an array ("lights", "objects"), creating it if missing.
  void append_json(std::string_view array_path, std::string_view json_value);
  // Sets the keys of `json_object` in the object at `path` (keeping the
  // others; a missing last key becomes an object), all in one checked edit.
  void update_json(std::string_view path, std::string_view json_object);

  // Appends a mesh object made of `arrays`, which are moved in: the scene
  // keeps them as they are (no copy, no JSON) and every check of the scene
  // builds the renderer's mesh from them by the rules of a mesh file. In the
  // document the object is an inline mesh (docs/scene-format.md): to_json()
  // and get() write the arrays out as "vertices", "triangles", "normals" and
  // "uvs". `object_json` holds the object's other keys ("material",
  // "transform", "smooth", "name"). Sizes, index ranges and finite values
  // are checked first: glint::Error naming "vertices[i]", "triangles[i]",
  // "normals[i]" or "uvs[i]"; the loader's problems name "objects[n]...".
  // An edit of the arrays themselves ("objects[n].vertices[0]") turns the
  // object into plain JSON first.
  void add_mesh(MeshArrays arrays, std::string_view object_json = "{}");

  // The loader's warnings (missing .mtl, dropped degenerate triangles...).
  std::vector<std::string> warnings() const;
  int width() const;
  int height() const;
  size_t object_count() const;
  size_t light_count() const;
  std::vector<std::string> material_names() const;

  // Identifies the scene's geometry: equal for two states whose objects,
  // mesh files and animation are the same, so a Renderer can keep its
  // acceleration structure across edits of materials, lights, camera and
  // render settings.
  size_t geometry_key() const;

  // Internal: the shared, immutable state behind a Scene (opaque here).
  struct State;
  explicit Scene(std::shared_ptr<const State> state) : state_(std::move(state)) {}
  const std::shared_ptr<const State>& state() const { return state_; }

 private:
  std::shared_ptr<const State> state_;
};

}  // namespace glint::api
