// Passes (AOVs): images of the parts of the main image, filled by the same
// samples with the same weights. The five color passes sum to the main image;
// normal, depth and albedo describe the camera ray's first hit.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "glint/image/image.h"
#include "glint/io/image_file.h"

namespace glint {

enum class Pass { ambient, diffuse, specular, reflection, transmission, normal, depth, albedo };
inline constexpr int kPassCount = 8;
inline constexpr int kColorPassCount = 5;  // ambient .. transmission: they sum to the image

std::string_view pass_name(Pass pass);
std::optional<Pass> pass_from_name(std::string_view name);
// True for the five passes whose sum is the image.
inline bool is_color_pass(Pass pass) { return static_cast<int>(pass) < kColorPassCount; }

// "diffuse,normal" -> {diffuse, normal}; "all" gives all eight. Duplicates
// are kept once, in the order given. Throws glint::Error naming an unknown
// pass (with a did-you-mean hint).
std::vector<Pass> parse_pass_list(std::string_view list);

// The extra images of a render, one per requested pass, each as large as the
// main image. Depth is stored in all three channels.
struct PassImages {
  std::vector<Pass> passes;
  std::vector<Image> images;  // images[i] holds passes[i]

  PassImages() = default;
  PassImages(std::vector<Pass> which, int width, int height);
  bool empty() const { return passes.empty(); }
};

// `out.png` + diffuse -> `out.diffuse.png`: the pass's file beside the output.
std::string pass_file_name(const std::string& output, Pass pass);

// What an 8-bit file of a data pass shows (written with WriteOptions::data):
// normal n -> n*0.5+0.5 (a pixel that saw nothing stays 0), depth d ->
// d / (the image's largest depth), so near is dark and misses are 0.
// Color passes and albedo are returned unchanged (they are light-like).
Image pass_image_for_8bit(Pass pass, const Image& image);

}  // namespace glint
