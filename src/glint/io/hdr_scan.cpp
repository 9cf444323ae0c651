#include "glint/io/hdr_scan.h"

#include <stb_image.h>

#include <limits>

namespace glint {

const char* const kHdrEndless =
    "a run-length encoded scanline of the Radiance file holds a run of length 0 or ends early";

bool hdr_decoding_ends(const unsigned char* data, std::size_t size) {
  if (size > static_cast<std::size_t>(std::numeric_limits<int>::max())) return true;  // refused as too large anyway
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(data, static_cast<int>(size), &w, &h, &channels)) return true;  // stb refuses it
  if (w < 8 || w >= 32768) return true;  // flat scanlines: stb reads w * h pixels and stops
  // The pixels start after the header as stb reads it: lines (its tokens,
  // up to '\n'; a character read at the end of the bytes is not kept), the
  // magic, then lines up to an empty one (or one whose first byte is 0),
  // then the resolution line.
  std::size_t at = 0;
  auto next = [&] { return at < size ? data[at++] : 0; };
  auto line_is_empty = [&] {
    int c = next(), length = 0, first = 0;
    while (at < size && c != '\n') {
      if (length++ == 0) first = c;
      if (length == 1023) {  // stb's buffer: the rest of the line is skipped
        while (at < size && next() != '\n') {
        }
        break;
      }
      c = next();
    }
    return length == 0 || first == 0;
  };
  line_is_empty();  // the magic
  while (!line_is_empty()) {
  }
  line_is_empty();  // the resolution
  // stb's loop over each scanline's four run-length encoded components,
  // without storing anything: it never advances on a count of 0 (a dump of
  // none, a run of none, or a byte read past the end, which stb reads as 0).
  for (int y = 0; y < h; ++y) {
    const int c1 = next(), c2 = next(), len_high = next();
    if (c1 != 2 || c2 != 2 || (len_high & 0x80)) return true;  // not RLE: stb reads the rest flat
    if (((len_high << 8) | next()) != w) return true;          // stb refuses the scanline
    for (int k = 0; k < 4; ++k) {
      for (int i = 0; i < w;) {
        int count = next();
        if (count == 0 || count == 128) return false;
        if (count > 128) {
          count -= 128;
          next();  // the run's value
        } else {
          at += static_cast<std::size_t>(count);
        }
        if (count > w - i) return true;  // stb refuses it
        i += count;
      }
    }
  }
  return true;
}

}  // namespace glint
