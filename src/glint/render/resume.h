// Resume files: what an interrupted render keeps so `--resume` can finish
// only the missing tiles. It holds the finished tiles' exact float pixels
// (the output image may be 8-bit) and a key of every input and setting the
// pixels depend on, so a resume never mixes two different renders.
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

// What a scene's pixels depend on besides its render settings, as one digest:
// `description` (the scene file's bytes, or the scene's canonical JSON when it
// was made from text or in code) and what the scene read from every other
// file, as loaded: each mesh's arrays, each texture image's texels, and the
// materials and textures (MTL and glTF files bring their own). Hashing what
// was loaded rather than the files again covers the files a mesh file names
// (its .mtl, a glTF's buffers and images), cannot see a file edited after it
// was read, and costs no I/O. A key computed before a render thus refuses a
// resume after any edit that changes a pixel's inputs. (Edits that load to
// the same data, such as a comment in an OBJ file, resume: the image is the
// same.) Cost: one pass over the loaded arrays, a few GB/s.
uint64_t scene_inputs_digest(std::span<const unsigned char> description, const Scene& scene);

// The key of one frame's resume file: the inputs' digest, the settings that
// shape the pixels, and the frame.
uint64_t resume_key(uint64_t inputs_digest, const RenderSettings& settings, int frame = 0);

// `<output>.glint-resume`, beside the output image.
std::filesystem::path resume_path_for(const std::filesystem::path& output);

void write_resume_file(const std::filesystem::path& path, const ResumeState& state);  // atomic
// nullopt when there is no such file; glint::Error when it is not a valid one.
std::optional<ResumeState> read_resume_file(const std::filesystem::path& path);

}  // namespace glint
