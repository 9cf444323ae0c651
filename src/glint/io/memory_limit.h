// How much memory one input may make glint allocate, checked before the
// allocation: a header that claims billions of pixels, vertices or triangles
// gets a clear error instead of a failed allocation mid-load or the OOM killer.
#pragma once

#include <cstddef>
#include <string>

namespace glint {

// Half of this machine's physical memory (4 GiB if the system cannot say):
// the most an image, one mesh file, or all of a scene's meshes may need.
size_t default_memory_budget();

// Rough bytes per mesh vertex and per triangle once loaded, as estimates for
// the checks (not exact accounting). A vertex: its position, and its normal
// while the readers hold it. A triangle: 3 indices, 3 corner normals and a
// material (52 B) plus its share of the BVH nodes and references.
inline constexpr double kBytesPerVertex = 24;
inline constexpr double kBytesPerTriangle = 100;

// "44.7 GiB", "1.5 MiB", "800 B".
std::string format_bytes(double bytes);

// "" when `bytes` fit in `budget`; else why not, for an error message:
// "needs 44.7 GiB, more than half of this machine's 23.4 GiB of memory"
// (or "... more than the memory budget of 512 MiB" for another budget).
std::string exceeds_budget(double bytes, size_t budget);

}  // namespace glint
