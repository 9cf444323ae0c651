// libFuzzer target for a texture image reader: the input is written to a
// scratch file named texture.GLINT_TEXTURE_EXT (load_texture_image picks its
// decoder by extension: stb_image for PNG, JPEG, BMP, TGA and Radiance HDR,
// glint's own PFM reader, tinyexr for OpenEXR) and read, which must give an
// image or throw glint::Error, and nothing else: no other exception, crash,
// sanitizer report, hang or absurd allocation. Built as fuzz_texture_png,
// _jpg, _bmp, _tga, _hdr, _pfm and _exr. The reader gets a memory budget of
// 512 MiB, well under the fuzzer's 2 GiB RSS limit: a header that claims
// more must be refused by glint's own check, not run out of memory.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

#include "glint/error.h"
#include "glint/io/texture_file.h"
#include "scratch.h"

namespace {

constexpr size_t kMemoryBudget = size_t(512) << 20;
std::filesystem::path scratch_file;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  scratch_file = glint_fuzz::make_scratch_dir("fuzz_texture") / ("texture." GLINT_TEXTURE_EXT);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // A full /tmp is not a finding.
  if (!glint_fuzz::write_file(scratch_file, std::string_view(reinterpret_cast<const char*>(data), size))) return 0;
  try {
    const glint::TextureImage image = glint::load_texture_image(scratch_file, kMemoryBudget);
    (void)image;
  } catch (const glint::Error&) {
  }
  return 0;
}
