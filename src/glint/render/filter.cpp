#include "glint/render/filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace glint {

namespace {

double gaussian(double x, double sigma) { return std::exp(-x * x / (2.0 * sigma * sigma)); }

// Mitchell-Netravali on [-2, 2] (Mitchell & Netravali 1988); integrates to 1
// for every B and C.
double mitchell(double x, double b, double c) {
  x = std::abs(x);
  if (x < 1.0) return ((12 - 9 * b - 6 * c) * x * x * x + (-18 + 12 * b + 6 * c) * x * x + (6 - 2 * b)) / 6.0;
  if (x < 2.0)
    return ((-b - 6 * c) * x * x * x + (6 * b + 30 * c) * x * x + (-12 * b - 48 * c) * x + (8 * b + 24 * c)) / 6.0;
  return 0.0;
}

// Bins per pixel of radius for the sampling table: fine enough that f/pdf
// stays within a fraction of a percent of its mean inside each bin.
constexpr int kBinsPerPixel = 256;

}  // namespace

double filter_profile(const PixelFilter& f, double x) {
  if (!(std::abs(x) < f.radius)) return 0.0;
  switch (f.type) {
    case FilterType::box: return 1.0 / (2.0 * f.radius);
    case FilterType::gaussian: {
      // pbrt's Gaussian: shifted down to reach 0 at the radius. Its integral
      // over [-r, r]: sigma sqrt(2 pi) erf(r / (sigma sqrt 2)) - 2 r g(r).
      const double edge = gaussian(f.radius, f.sigma);
      const double integral =
          f.sigma * std::sqrt(2.0 * std::numbers::pi) * std::erf(f.radius / (f.sigma * std::sqrt(2.0))) -
          2.0 * f.radius * edge;
      return (gaussian(x, f.sigma) - edge) / integral;
    }
    case FilterType::mitchell:
      // Stretched from [-2, 2] to [-r, r]; the factor 2/r keeps the integral 1.
      return mitchell(2.0 * x / f.radius, f.b, f.c) * (2.0 / f.radius);
  }
  return 0.0;
}

FilterSampler::FilterSampler(const PixelFilter& filter) : filter_(filter) {
  const int bins = std::max(1, static_cast<int>(std::ceil(kBinsPerPixel * filter.radius)));
  bin_width_ = 2.0 * filter.radius / bins;
  std::vector<double> mass(static_cast<size_t>(bins));
  double total = 0;
  for (int i = 0; i < bins; ++i) {
    // |f1| at the bin's center: the density is piecewise constant over bins.
    const double x = -filter.radius + (i + 0.5) * bin_width_;
    mass[static_cast<size_t>(i)] = std::abs(filter_profile(filter, x)) * bin_width_;
    total += mass[static_cast<size_t>(i)];
  }
  cdf_.assign(static_cast<size_t>(bins) + 1, 0.0);
  pdf_.assign(static_cast<size_t>(bins), 0.0);
  for (size_t i = 0; i < mass.size(); ++i) {
    cdf_[i + 1] = cdf_[i] + mass[i] / total;
    pdf_[i] = mass[i] / total / bin_width_;
  }
  cdf_.back() = 1.0;
}

void FilterSampler::sample_1d(double u, double& x, double& weight) const {
  // The bin whose CDF interval holds u (bins of zero mass are never chosen).
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const size_t bin = std::min(pdf_.size() - 1, static_cast<size_t>(std::max<std::ptrdiff_t>(0, it - cdf_.begin() - 1)));
  const double width = cdf_[bin + 1] - cdf_[bin];
  const double t = width > 0 ? std::clamp((u - cdf_[bin]) / width, 0.0, 1.0) : 0.5;
  x = -filter_.radius + (static_cast<double>(bin) + t) * bin_width_;
  weight = pdf_[bin] > 0 ? filter_profile(filter_, x) / pdf_[bin] : 0.0;
}

FilterSample FilterSampler::sample(double ux, double uy) const {
  FilterSample s;
  double wx = 0, wy = 0;
  sample_1d(ux, s.dx, wx);
  sample_1d(uy, s.dy, wy);
  s.weight = wx * wy;
  return s;
}

}  // namespace glint
