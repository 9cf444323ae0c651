// Texture images: a file a texture names -> linear RGB texels. 8- and 16-bit
// images (PNG, JPEG, BMP, TGA) are sRGB-encoded and decoded to linear here;
// Radiance .hdr, OpenEXR and PFM hold linear values already. Alpha is ignored.
#pragma once

#include <cstddef>
#include <filesystem>

#include "glint/io/memory_limit.h"

#include "glint/scene/scene.h"

namespace glint {

// Throws glint::Error("<path>: cannot read texture: <reason>") for a missing,
// unreadable, unsupported or corrupt file, and for one whose header claims
// more pixels than `memory_budget` holds (io/memory_limit.h), before decoding.
TextureImage load_texture_image(const std::filesystem::path& path, size_t memory_budget = default_memory_budget());

// ".png, .jpg, .jpeg, .bmp, .tga, .hdr, .exr, .pfm", for messages.
const char* supported_texture_extensions();

}  // namespace glint
