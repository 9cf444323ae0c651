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

// While one lives, read_file notes each file it reads on this thread (and
// for every enclosing log too): a cache of mesh files learns which other
// files a mesh depended on (an OBJ's .mtl) without the readers telling it.
class FileReadLog {
 public:
  FileReadLog();
  ~FileReadLog();
  FileReadLog(const FileReadLog&) = delete;
  FileReadLog& operator=(const FileReadLog&) = delete;
  const std::vector<std::filesystem::path>& files() const { return files_; }

 private:
  friend std::vector<unsigned char> read_file(const std::filesystem::path& path);
  std::vector<std::filesystem::path> files_;
  FileReadLog* outer_;
};

}  // namespace glint
