// explain_pixel: the ray tree behind one pixel, traced exactly as the render
// traces it (one ray through the pixel center, the pixel's own random numbers),
// so its color is the pixel's value in a render at samples_per_pixel 1.
#pragma once

#include <string>

#include "glint/accel/accelerator.h"
#include "glint/render/integrator.h"

namespace glint {

struct PixelExplanation {
  int x = 0, y = 0;
  Color color;  // as stored in the image (float precision)
  RayTrace ray;
};

// Throws glint::Error when (x, y) is outside the image.
PixelExplanation explain_pixel(const Scene& scene, const Accelerator& accel, int x, int y);

// The contract's `glint explain --json` object (docs/scene-format.md).
std::string explanation_json(const Scene& scene, const PixelExplanation& e);
// The same, for people: an indented tree with one line per fact.
std::string explanation_text(const Scene& scene, const PixelExplanation& e);

}  // namespace glint
