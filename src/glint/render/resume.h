// Resume files: what an interrupted render keeps so `--resume` can finish
// only the missing tiles. It holds the finished tiles' exact float pixels
// (the output image may be 8-bit) and a key of the scene and settings, so a
// resume never mixes two different renders.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>

#include "glint/image/image.h"
#include "glint/render/passes.h"
#include "glint/render/renderer.h"
#include "glint/scene/scene.h"

namespace glint {

struct ResumeState {
  uint64_t key = 0;
  TileProgress progress;
  Image image;
  PassImages passes;  // the passes' finished tiles, when the render has passes
};

// FNV-1a over the scene file's bytes and the settings that shape the pixels.
uint64_t resume_key(std::span<const unsigned char> scene_bytes, const RenderSettings& settings);

// `<output>.glint-resume`, beside the output image.
std::filesystem::path resume_path_for(const std::filesystem::path& output);

void write_resume_file(const std::filesystem::path& path, const ResumeState& state);  // atomic
// nullopt when there is no such file; glint::Error when it is not a valid one.
std::optional<ResumeState> read_resume_file(const std::filesystem::path& path);

}  // namespace glint
