#include "glint/io/file_cache.h"

#include <sys/stat.h>

#include <algorithm>

#include "glint/io/file_io.h"
#include "glint/io/texture_file.h"

namespace glint {

namespace fs = std::filesystem;

namespace {
// One name for a file however the scene spells it (relative, "..", links).
fs::path canonical_name(const fs::path& file) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(file, ec);
  return ec ? file.lexically_normal() : c;
}
}  // namespace

FileCache::Stamp FileCache::stamp(const fs::path& file) {
  Stamp s;
  s.file = file;
  struct stat info {};
  if (::stat(file.c_str(), &info) != 0) return s;  // missing: never equal to a file that was read
  s.size = static_cast<uintmax_t>(info.st_size);
  s.mtime_ns = static_cast<int64_t>(info.st_mtim.tv_sec) * 1000000000 + info.st_mtim.tv_nsec;
  s.inode = static_cast<uint64_t>(info.st_ino);
  return s;
}

bool FileCache::valid(const Entry& entry) const {
  return std::all_of(entry.stamps.begin(), entry.stamps.end(), [](const Stamp& s) { return stamp(s.file) == s; });
}

std::shared_ptr<const MeshFile> FileCache::mesh(const fs::path& file, size_t memory_budget, bool vertex_normals) {
  const fs::path name = canonical_name(file);
  const std::string key =
      "mesh " + std::to_string(memory_budget) + (vertex_normals ? " normals " : " flat ") + name.string();
  std::lock_guard lock(mutex_);
  if (auto it = entries_.find(key); it != entries_.end() && valid(it->second)) return it->second.mesh;
  // Stamped before reading: a change while it is read makes the entry stale, not wrong.
  Entry entry{name, {stamp(name)}, nullptr, nullptr};
  FileReadLog log;
  ++reads_;
  entry.mesh = std::make_shared<const MeshFile>(load_mesh_file(file, memory_budget, vertex_normals));
  for (const fs::path& read : log.files()) {
    const fs::path other = canonical_name(read);
    if (other != name) entry.stamps.push_back(stamp(other));
  }
  auto mesh = entry.mesh;
  entries_[key] = std::move(entry);
  return mesh;
}

std::shared_ptr<const TextureImage> FileCache::texture(const fs::path& file) {
  const fs::path name = canonical_name(file);
  const std::string key = "texture " + name.string();
  std::lock_guard lock(mutex_);
  if (auto it = entries_.find(key); it != entries_.end() && valid(it->second)) return it->second.texture;
  Entry entry{name, {stamp(name)}, nullptr, nullptr};
  ++reads_;
  entry.texture = std::make_shared<const TextureImage>(load_texture_image(file));
  auto texture = entry.texture;
  entries_[key] = std::move(entry);
  return texture;
}

void FileCache::forget(const fs::path& file) {
  const fs::path name = canonical_name(file);
  std::lock_guard lock(mutex_);
  std::erase_if(entries_, [&](const auto& item) {
    const auto& stamps = item.second.stamps;
    return std::any_of(stamps.begin(), stamps.end(), [&](const Stamp& s) { return s.file == name; });
  });
}

void FileCache::keep_only(const std::vector<fs::path>& files) {
  std::set<fs::path> keep;
  for (const fs::path& f : files) keep.insert(canonical_name(f));
  std::lock_guard lock(mutex_);
  std::erase_if(entries_, [&](const auto& item) { return !keep.count(item.second.file); });
}

std::vector<fs::path> FileCache::files() const {
  std::set<fs::path> all;
  std::lock_guard lock(mutex_);
  for (const auto& [key, entry] : entries_)
    for (const Stamp& s : entry.stamps) all.insert(s.file);
  return {all.begin(), all.end()};
}

uint64_t FileCache::reads() const {
  std::lock_guard lock(mutex_);
  return reads_;
}

}  // namespace glint
