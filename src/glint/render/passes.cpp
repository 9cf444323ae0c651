#include "glint/render/passes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "glint/error.h"
#include "glint/util/strings.h"

namespace glint {

namespace {
constexpr std::array<std::string_view, kPassCount> kNames = {"ambient",      "diffuse", "specular", "reflection",
                                                             "transmission", "normal",  "depth",    "albedo"};
}  // namespace

std::string_view pass_name(Pass pass) { return kNames[static_cast<size_t>(pass)]; }

std::optional<Pass> pass_from_name(std::string_view name) {
  for (int i = 0; i < kPassCount; ++i)
    if (kNames[static_cast<size_t>(i)] == name) return static_cast<Pass>(i);
  return std::nullopt;
}

std::vector<Pass> parse_pass_list(std::string_view list) {
  std::vector<Pass> out;
  auto add = [&out](Pass p) {
    if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
  };
  size_t start = 0;
  while (start <= list.size()) {
    size_t end = list.find(',', start);
    if (end == std::string_view::npos) end = list.size();
    const std::string_view word = list.substr(start, end - start);
    if (word == "all") {
      for (int i = 0; i < kPassCount; ++i) add(static_cast<Pass>(i));
    } else if (const auto pass = pass_from_name(word)) {
      add(*pass);
    } else {
      std::vector<std::string_view> names(kNames.begin(), kNames.end());
      names.push_back("all");
      std::string msg = "--passes: unknown pass \"" + std::string(word) + "\"";
      const std::string hint = closest_match(word, names);
      if (!hint.empty()) msg += " (did you mean \"" + hint + "\"?)";
      msg +=
          " (expected a comma-separated list of ambient, diffuse, specular, reflection, transmission, "
          "normal, depth, albedo, or all)";
      throw Error(msg);
    }
    start = end + 1;
  }
  return out;
}

PassImages::PassImages(std::vector<Pass> which, int width, int height) : passes(std::move(which)) {
  for (size_t i = 0; i < passes.size(); ++i) images.emplace_back(width, height);
}

std::string pass_file_name(const std::string& output, Pass pass) {
  const std::filesystem::path path(output);
  std::filesystem::path stem = path;
  stem.replace_extension();
  return stem.string() + "." + std::string(pass_name(pass)) + path.extension().string();
}

Image pass_image_for_8bit(Pass pass, const Image& image) {
  Image out = image;
  if (pass == Pass::normal) {
    for (size_t i = 0; i < out.rgb.size(); i += 3) {
      float* n = &out.rgb[i];
      if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f) continue;
      for (int c = 0; c < 3; ++c) n[c] = n[c] * 0.5f + 0.5f;
    }
  } else if (pass == Pass::depth) {
    float max_depth = 0.0f;
    for (float d : out.rgb)
      if (std::isfinite(d)) max_depth = std::max(max_depth, d);
    if (max_depth > 0.0f)
      for (float& d : out.rgb) d /= max_depth;
  }
  return out;
}

}  // namespace glint
