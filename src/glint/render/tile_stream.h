// Rendering tiles in the order a source hands them out, rather than from a
// list fixed in advance: the engine of distributed rendering, where another
// process decides which tile this one renders next. Pixels are the same as
// render_tiles' (each depends only on its coordinates).
#pragma once

#include <functional>

#include "glint/accel/accelerator.h"
#include "glint/image/image.h"
#include "glint/render/integrator.h"
#include "glint/render/tile_size.h"
#include "glint/scene/scene.h"

namespace glint {

struct TileStream {
  int tile_size = kTileSize;  // tiles numbered row-major, as in TileProgress
  // The next tile to render, or -1 when there are no more. Called from every
  // worker thread at once; may block until a tile is available.
  std::function<int()> next;
  // Called from the worker thread once the tile's pixels are in the image.
  std::function<void(int tile)> done;
};

// Renders tiles of `image` (scene.render's size) with `threads` workers until
// stream.next returns -1 to each of them. Returns the rays cast.
RayStats render_tile_stream(const Scene& scene, const Accelerator& accel, Image& image, const TileStream& stream,
                            int threads);

}  // namespace glint
