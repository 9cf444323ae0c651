// Pixel filters: each filter integrates to 1 (numerically, against the closed
// forms the code uses); importance-sampled offsets follow |f| and their signed
// weights reproduce f; box stays the contract's average; filtered renders are
// deterministic across threads and resumes, and their passes still sum.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/io/scene_loader.h"
#include "glint/math/rng.h"
#include "glint/render/filter.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

std::vector<PixelFilter> test_filters() {
  PixelFilter gauss{FilterType::gaussian, kGaussianRadius};
  PixelFilter wide_gauss{FilterType::gaussian, 2.5};
  wide_gauss.sigma = 0.9;
  PixelFilter mitchell{FilterType::mitchell, kMitchellRadius};
  PixelFilter sharp{FilterType::mitchell, 1.3};
  sharp.b = 0;
  sharp.c = 0.5;  // Catmull-Rom
  return {PixelFilter{}, gauss, wide_gauss, mitchell, sharp};
}

// Midpoint rule over [-r, r]^2 on an n x n grid.
double integrate_2d(const PixelFilter& f, int n) {
  const double h = 2.0 * f.radius / n;
  double sum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) sum += filter_value(f, -f.radius + (i + 0.5) * h, -f.radius + (j + 0.5) * h);
  return sum * h * h;
}

TEST(PixelFilter, WeightsIntegrateToOne) {
  for (const PixelFilter& f : test_filters()) {
    SCOPED_TRACE(static_cast<int>(f.type));
    EXPECT_NEAR(integrate_2d(f, 1000), 1.0, 1e-5);
  }
  // Mitchell really has negative lobes, and the Gaussian reaches 0 at its radius.
  const PixelFilter m{FilterType::mitchell, 2.0};
  EXPECT_LT(filter_profile(m, 1.5), 0.0);
  const PixelFilter g{FilterType::gaussian, 1.5};
  EXPECT_NEAR(filter_profile(g, 1.4999999), 0.0, 1e-6);
  EXPECT_EQ(filter_profile(g, 1.6), 0.0);
}

TEST(PixelFilter, SampledOffsetsFollowTheFilter) {
  // Histograms of many sampled offsets: the share of samples in a bin is the
  // bin's share of |f1|, and the mean signed weight in a bin is f1's integral
  // over it (so the estimator of any pixel integral is unbiased).
  constexpr int kSamples = 400000, kBins = 16;
  for (const PixelFilter& f : test_filters()) {
    SCOPED_TRACE(static_cast<int>(f.type));
    const FilterSampler sampler(f);
    Rng rng(7);
    std::vector<double> count(kBins, 0.0), weighted(kBins, 0.0);
    double weight_sum = 0;
    for (int s = 0; s < kSamples; ++s) {
      const FilterSample fs = sampler.sample(rng.next_double(), rng.next_double());
      ASSERT_LE(std::abs(fs.dx), f.radius);
      ASSERT_LE(std::abs(fs.dy), f.radius);
      // The weight carries the filter's sign.
      const double value = filter_value(f, fs.dx, fs.dy);
      if (value != 0.0) {
        ASSERT_EQ(fs.weight > 0, value > 0);
      }
      const int bin = std::min(kBins - 1, static_cast<int>((fs.dx + f.radius) / (2 * f.radius) * kBins));
      count[bin] += 1;
      weighted[bin] += fs.weight;
      weight_sum += fs.weight;
    }
    EXPECT_NEAR(weight_sum / kSamples, 1.0, 0.01);  // E[f/pdf] = integral of f = 1
    double abs_total = 0;
    std::vector<double> abs_mass(kBins), mass(kBins);
    for (int b = 0; b < kBins; ++b) {
      // The bin's integrals of f1 and |f1|, by a fine midpoint rule.
      const double lo = -f.radius + 2 * f.radius * b / kBins, h = 2 * f.radius / kBins / 1000;
      for (int k = 0; k < 1000; ++k) {
        const double v = filter_profile(f, lo + (k + 0.5) * h) * h;
        mass[b] += v;
        abs_mass[b] += std::abs(v);
      }
      abs_total += abs_mass[b];
    }
    for (int b = 0; b < kBins; ++b) {
      SCOPED_TRACE(b);
      const double p = abs_mass[b] / abs_total;
      const double sd = std::sqrt(p * (1 - p) / kSamples);
      EXPECT_NEAR(count[b] / kSamples, p, 5 * sd + 1e-4);
      // Marginal in x: the y factor integrates to 1, so the mean weight per bin is f1's mass.
      EXPECT_NEAR(weighted[b] / kSamples, mass[b], 0.01);
    }
  }
}

Scene test_scene(int spp, FilterType type) {
  Scene scene = load_scene(std::string(GLINT_SOURCE_DIR) + "/scenes/showcase.json");
  scene.render.width = 64;
  scene.render.height = 40;
  scene.render.samples_per_pixel = spp;
  scene.render.pixel_filter.type = type;
  scene.render.pixel_filter.radius = type == FilterType::gaussian   ? kGaussianRadius
                                     : type == FilterType::mitchell ? kMitchellRadius
                                                                    : 0.5;
  return scene;
}

TEST(PixelFilter, OneSampleIsThePixelCenterWhateverTheFilter) {
  const Scene box = test_scene(1, FilterType::box);
  const auto accel = build_accelerator(box);
  const Image want = render_image(box, *accel);
  for (FilterType t : {FilterType::gaussian, FilterType::mitchell})
    EXPECT_EQ(render_image(test_scene(1, t), *accel).rgb, want.rgb);
}

TEST(PixelFilter, FiltersChangeTheImageButKeepItsLevel) {
  const Scene box = test_scene(16, FilterType::box);
  const auto accel = build_accelerator(box);
  const Image b = render_image(box, *accel);
  for (FilterType t : {FilterType::gaussian, FilterType::mitchell}) {
    const Image f = render_image(test_scene(16, t), *accel);
    EXPECT_NE(f.rgb, b.rgb);
    double mean_b = 0, mean_f = 0;
    for (size_t i = 0; i < b.rgb.size(); ++i) mean_b += b.rgb[i], mean_f += f.rgb[i];
    EXPECT_NEAR(mean_f / mean_b, 1.0, 0.02);  // a normalized filter moves light around, not up or down
  }
}

TEST(PixelFilter, DeterministicAcrossThreadsAndResumes) {
  for (FilterType t : {FilterType::gaussian, FilterType::mitchell}) {
    const Scene scene = test_scene(6, t);
    const auto accel = build_accelerator(scene);
    RenderOptions one, seven;
    one.threads = 1;
    seven.threads = 7;
    const Image a = render_image(scene, *accel, one);
    EXPECT_EQ(a.rgb, render_image(scene, *accel, seven).rgb);
    // Every other tile first, then the rest: the same image.
    Image image(scene.render.width, scene.render.height);
    TileProgress first(scene.render.width, scene.render.height, 16), rest = first;
    for (size_t i = 0; i < first.done.size(); ++i) first.done[i] = i % 2, rest.done[i] = 1 - i % 2;
    render_tiles(scene, *accel, image, first);
    render_tiles(scene, *accel, image, rest);
    EXPECT_EQ(image.rgb, a.rgb);
  }
}

TEST(PixelFilter, PassesStillSumToTheImage) {
  for (FilterType t : {FilterType::gaussian, FilterType::mitchell}) {
    const Scene scene = test_scene(9, t);
    const auto accel = build_accelerator(scene);
    Image image(scene.render.width, scene.render.height);
    PassImages passes(parse_pass_list("all"), scene.render.width, scene.render.height);
    TileProgress tiles(scene.render.width, scene.render.height, 16);
    render_tiles(scene, *accel, image, tiles, {}, nullptr, &passes);
    EXPECT_EQ(image.rgb, render_image(scene, *accel).rgb);
    for (size_t i = 0; i < image.rgb.size(); ++i) {
      double sum = 0;
      for (int p = 0; p < kColorPassCount; ++p) sum += passes.images[static_cast<size_t>(p)].rgb[i];
      ASSERT_NEAR(sum, image.rgb[i], 1e-6 * std::max(1.0f, std::abs(image.rgb[i]))) << i;
    }
  }
}

}  // namespace
}  // namespace glint
