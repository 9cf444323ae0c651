// Scene loading: scene JSON text -> validated Scene, or a glint::Error that
// names the file, line, column, the key's path and the problem. Everything the
// contract calls out of domain (NaN/Inf, zero directions, non-positive sizes,
// unknown keys, names and enum values) is rejected here, so later stages can
// trust the Scene.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "glint/error.h"
#include "glint/io/memory_limit.h"
#include "glint/scene/scene.h"

namespace glint {

// A path ending in .nff (any case) is read as an NFF file (docs/nff.md).
Scene load_scene(const std::filesystem::path& path);

// Every problem load_scene would find, in file order, without stopping at the
// first (one per material, light, object or section; a JSON syntax error ends
// the list). Empty when the scene is valid.
std::vector<Error> validate_scene(const std::filesystem::path& path);
// `filename` is what messages name; relative paths inside resolve against
// base_dir. Mesh files, each alone and all together, must fit memory_budget.
Scene parse_scene(std::string text, const std::string& filename, const std::filesystem::path& base_dir = {},
                  size_t memory_budget = default_memory_budget());

// Limits the loader enforces beyond the contract, so no input can exhaust
// memory or the stack; documented in docs/scene-format.md.
inline constexpr int kMaxDepthLimit = 1000;
inline constexpr int kMaxSamplesPerPixel = 1 << 16;
inline constexpr int kMaxAreaLightSamples = 1 << 16;
inline constexpr int kMaxFrames = 1000000;  // animation.frames

// Throws when a width x height float image would not fit in this machine's memory.
void check_image_size(int width, int height, const SourceLocation& where);

}  // namespace glint
