// The side of a square tile in pixels: the unit threads, MPI ranks, progress,
// resume files and tile streams all work in (edge tiles are smaller). One
// value everywhere, so a resume file or a distributed render tiles an image
// the way a local render does.
#pragma once

namespace glint {

inline constexpr int kTileSize = 16;

}  // namespace glint
