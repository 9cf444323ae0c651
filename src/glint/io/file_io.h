// Files as wholes: read one into memory, or replace one atomically so that a
// failed or interrupted write never leaves a broken or clobbered file.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace glint {

// Whether write_file_atomically waits until the bytes are on the disk before
// the rename (fsync), so that not even a power cut can leave the target
// empty: yes for files that cannot be made again by running glint again (a
// scene saved by glint serve, a resume file); not for a render's outputs,
// which the rename alone keeps whole or absent to every program -- on a busy
// disk that wait took 2 to 30 ms, more than a small scene's whole render
// (docs/performance.md, "SPD scenes").
enum class Flush { to_disk, no };

// Writes `bytes` to a temporary file in the target's folder, flushes it (as
// `flush` says) and renames it over `target`. Throws glint::Error("<target>:
// cannot write: ...").
void write_file_atomically(const std::filesystem::path& target, std::span<const unsigned char> bytes,
                           Flush flush = Flush::to_disk);

// Throws glint::Error("<path>: cannot read: ...").
std::vector<unsigned char> read_file(const std::filesystem::path& path);

// The two errors above, for the readers and writers of file formats:
// glint::Error("<path>: cannot write: <reason>") and "...: cannot read: ...".
[[noreturn]] void fail_write(const std::filesystem::path& path, const std::string& reason);
[[noreturn]] void fail_read(const std::filesystem::path& path, const std::string& reason);

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
