// A guard in front of stb_image's Radiance HDR decoder (Debian 12's stb).
// Internal to io/.
#pragma once

#include <cstddef>

namespace glint {

// Whether stb_image's Radiance HDR decoder comes to an end on these bytes:
// it loops for ever on a run-length encoded scanline with a run of length 0
// (or that ends early), which a corrupt file can hold. Read before decoding
// (read_image, load_texture_image); kHdrEndless is the reason given.
bool hdr_decoding_ends(const unsigned char* data, std::size_t size);
extern const char* const kHdrEndless;

}  // namespace glint
