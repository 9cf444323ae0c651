// Pixel filters by importance sampling (as pbrt-v4 does): a pixel's sample
// offsets are drawn with density proportional to |f|, each sample weighted
// f/pdf (negative in Mitchell's lobes), and the pixel is the weighted sum over
// the sum of the weights. Each pixel needs only its own samples, so images
// stay independent of tiles, threads and resumes.
#pragma once

#include <vector>

#include "glint/scene/scene.h"

namespace glint {

// f1(x): the filter's 1D profile, zero for |x| >= radius, integrating to 1
// (normalized in closed form, not numerically).
double filter_profile(const PixelFilter& filter, double x);
// f(x, y) = f1(x) f1(y): integrates to 1 over the plane.
inline double filter_value(const PixelFilter& filter, double x, double y) {
  return filter_profile(filter, x) * filter_profile(filter, y);
}

struct FilterSample {
  double dx = 0, dy = 0;  // offset from the pixel center, in pixels
  double weight = 1;      // f(dx, dy) / pdf(dx, dy)
};

// Tabulates |f1| on a fine grid (piecewise-constant pdf) and inverts its CDF.
// Stratified inputs stay stratified: u is mapped monotonically.
class FilterSampler {
 public:
  explicit FilterSampler(const PixelFilter& filter);
  // (ux, uy) in [0, 1)^2 -> an offset and its weight.
  FilterSample sample(double ux, double uy) const;

 private:
  // u in [0, 1) -> x in [-radius, radius] and f1(x) / pdf(x).
  void sample_1d(double u, double& x, double& weight) const;

  PixelFilter filter_;
  double bin_width_ = 0;
  std::vector<double> cdf_;  // bins + 1 entries, 0 .. 1
  std::vector<double> pdf_;  // per bin, density of x
};

}  // namespace glint
