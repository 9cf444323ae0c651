// Scene loading: scene JSON text -> validated Scene, or a glint::Error that
// names the file, line, column, the key's path and the problem. Everything the
// contract calls out of domain (NaN/Inf, zero directions, non-positive sizes,
// unknown keys, names and enum values) is rejected here, so later stages can
// trust the Scene.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "glint/error.h"
#include "glint/io/memory_limit.h"
#include "glint/scene/scene.h"

namespace glint {

class FileCache;

namespace api {
struct MeshArrays;
}

// Mesh arrays held in memory beside a scene document, by id (what
// glint::api::Scene::add_mesh keeps): the document's mesh object
// {"type": "mesh", "$arrays": id} takes its vertices, triangles, normals and
// uvs from here, with the rules of an inline mesh. Only the API passes them;
// in a scene file "$arrays" is an unknown key.
inline constexpr const char* kAttachedMeshKey = "$arrays";
using AttachedMeshes = std::map<uint64_t, std::shared_ptr<const api::MeshArrays>>;

// A path ending in .nff (any case) is read as an NFF file (docs/nff.md).
// With `files`, mesh and texture files come from that cache (file_cache.h).
Scene load_scene(const std::filesystem::path& path, FileCache* files = nullptr);

// Every problem load_scene would find, in file order, without stopping at the
// first (one per material, light, object or section; a JSON syntax error ends
// the list). Empty when the scene is valid.
std::vector<Error> validate_scene(const std::filesystem::path& path);
// `filename` is what messages name; relative paths inside resolve against
// base_dir. Mesh files, each alone and all together, must fit memory_budget.
Scene parse_scene(std::string text, const std::string& filename, const std::filesystem::path& base_dir = {},
                  size_t memory_budget = default_memory_budget(), const AttachedMeshes* attached = nullptr,
                  FileCache* files = nullptr);

// Limits the loader enforces beyond the contract, so no input can exhaust
// memory or the stack; documented in docs/scene-format.md.
inline constexpr int kMaxDepthLimit = 1000;
inline constexpr int kMaxSamplesPerPixel = 1 << 16;
inline constexpr int kMaxAreaLightSamples = 1 << 16;
inline constexpr int kMaxFrames = 1000000;  // animation.frames

// Throws when a width x height float image would not fit in this machine's memory.
void check_image_size(int width, int height, const SourceLocation& where);

}  // namespace glint
