// The stratified grid behind a pixel's samples and an area light's shadow
// samples: N jittered points, one per cell of an nx x ny grid with
// nx * ny == N, as square as N's factors allow (nx the largest factor not
// above sqrt(N)). One function, so pixels and area lights factor alike.
#pragma once

#include <cmath>

namespace glint {

struct StratifiedGrid {
  int nx = 1, ny = 1;
};

inline StratifiedGrid stratified_grid(int samples) {
  int nx = static_cast<int>(std::sqrt(static_cast<double>(samples)));
  while (samples % nx != 0) --nx;
  return {nx, samples / nx};
}

}  // namespace glint
