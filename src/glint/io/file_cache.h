// Mesh and texture files as last read, so that a scene parsed again after an
// edit of its materials, lights, camera or render settings does not read its
// files again (glint serve parses the whole document on every edit). An
// entry holds while its file and every file read with it (an OBJ's .mtl)
// keep their size, modification time and inode; forget() drops one at once
// (a file watcher saw it change: a rewrite within the clock's granularity
// keeps the time). Errors are not kept: a broken file is read again next time.
//
// Thread-safe. The scene loader copies what it gets, so a cached file costs
// its memory once more while it is in the cache; keep_only() lets go of the
// files a scene no longer names.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "glint/io/mesh_file.h"
#include "glint/scene/scene.h"

namespace glint {

class FileCache {
 public:
  // As load_mesh_file / load_texture_image, from the cache when still valid.
  std::shared_ptr<const MeshFile> mesh(const std::filesystem::path& file, size_t memory_budget, bool vertex_normals);
  std::shared_ptr<const TextureImage> texture(const std::filesystem::path& file);

  // Drops the entries that read `file` (as their own file or beside it).
  void forget(const std::filesystem::path& file);
  // Drops the entries whose own file is not in `files`.
  void keep_only(const std::vector<std::filesystem::path>& files);
  // Every file the entries read (to watch them): meshes, their .mtl, textures.
  std::vector<std::filesystem::path> files() const;
  // How many files were read from disk (not from the cache): tests and stats.
  uint64_t reads() const;

 private:
  // A file as it was when read: it is unchanged while these are.
  struct Stamp {
    std::filesystem::path file;
    uintmax_t size = 0;
    int64_t mtime_ns = 0;
    uint64_t inode = 0;
    bool operator==(const Stamp&) const = default;
  };
  struct Entry {
    std::filesystem::path file;
    std::vector<Stamp> stamps;  // the file itself first, then what was read with it
    std::shared_ptr<const MeshFile> mesh;
    std::shared_ptr<const TextureImage> texture;
  };
  static Stamp stamp(const std::filesystem::path& file);
  bool valid(const Entry& entry) const;

  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;  // by kind, options and canonical path
  uint64_t reads_ = 0;
};

}  // namespace glint
