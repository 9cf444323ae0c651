// A scratch folder of the fuzz targets whose readers take a path: made once
// per process (under $TMPDIR or /tmp), removed at exit.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

namespace glint_fuzz {

inline std::filesystem::path& scratch_dir() {
  static std::filesystem::path dir;
  return dir;
}

// Makes the folder (aborting, named `who`, if it cannot) and returns it.
inline const std::filesystem::path& make_scratch_dir(const char* who) {
  const char* tmp = std::getenv("TMPDIR");
  std::string dir = std::string(tmp && *tmp ? tmp : "/tmp") + "/glint-fuzz-XXXXXX";
  if (!mkdtemp(dir.data())) {
    std::perror((std::string(who) + ": mkdtemp").c_str());
    std::abort();
  }
  scratch_dir() = dir;
  std::atexit([] {
    std::error_code ec;
    std::filesystem::remove_all(scratch_dir(), ec);
  });
  return scratch_dir();
}

// False when the bytes could not all be written (a full /tmp is not a finding).
inline bool write_file(const std::filesystem::path& path, std::string_view bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  return std::fclose(f) == 0 && written;
}

}  // namespace glint_fuzz
