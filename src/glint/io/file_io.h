// Files as wholes: read one into memory, or replace one atomically so that a
// failed or interrupted write never leaves a broken or clobbered file.
#pragma once

#include <filesystem>
#include <span>
#include <vector>

namespace glint {

// Writes `bytes` to a temporary file in the target's folder, flushes it and
// renames it over `target`. Throws glint::Error("<target>: cannot write: ...").
void write_file_atomically(const std::filesystem::path& target, std::span<const unsigned char> bytes);

// Throws glint::Error("<path>: cannot read: ...").
std::vector<unsigned char> read_file(const std::filesystem::path& path);

}  // namespace glint
