// glint serve's session: one scene state for every tab (the scene shown and
// the file's, undo and redo, the view, the last frames), guarded by one
// mutex; every change is announced to the render worker and to the event
// streams. Internal to src/glint/serve/.
#pragma once

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "glint/api/scene_state.h"
#include "glint/glint.h"
#include "glint/scene/memory.h"
#include "glint/serve/serve.h"

namespace glint::serve {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using api::Scene;

// Undo steps kept: at most kUndoLimit, and no more than fit kUndoBytes of
// mesh and texture data (each step holds the scene it shows, its meshes
// included: 200 steps of a 1M-triangle model would hold 20 GB).
inline constexpr size_t kUndoLimit = 200;
inline constexpr size_t kUndoBytes = size_t{1} << 30;

// The bytes of a scene's meshes and texture images (what dominates it), as
// `glint info` counts them: by capacity, what is allocated. The bound is on
// memory held, so what is allocated is the right measure for it too; a
// loader's spare room is small beside the arrays.
inline size_t scene_bytes(const Scene& scene) {
  const SceneMemory memory = scene_memory(*scene.state()->scene);
  return memory.meshes + memory.textures;
}

// Drops the oldest steps until at most max_steps are left and they hold at
// most max_bytes (the newest step always stays).
inline void trim_undo(std::vector<Scene>& steps, size_t max_steps, size_t max_bytes) {
  size_t bytes = 0, keep = 0;
  for (auto it = steps.rbegin(); it != steps.rend() && keep < max_steps; ++it, ++keep) {
    bytes += scene_bytes(*it);
    if (keep > 0 && bytes > max_bytes) break;
  }
  steps.erase(steps.begin(), steps.end() - static_cast<std::ptrdiff_t>(keep));
}

struct View {
  double exposure = 0;
  std::string tonemap = "clamp";
  std::string pass = "image";
};

inline api::ToneMap tonemap_named(const std::string& name) {
  return name == "reinhard" ? api::ToneMap::reinhard : name == "aces" ? api::ToneMap::aces : api::ToneMap::clamp;
}

struct Frame {
  uint64_t seq = 0;
  uint64_t version = 0;        // the session version it shows
  uint64_t scene_version = 0;  // and the scene version
  bool coarse = false;
  int width = 0, height = 0;
  std::vector<unsigned char> png;
  std::shared_ptr<const api::Image> linear;  // full frames: the exact values (PFM download)
  std::string pass;
  double exposure = 0;  // the view it was encoded with
  std::string tonemap;
  double render_ms = 0;
};

// The files a scene reads: meshes and textures (its own file aside).
inline std::vector<fs::path> files_named(const Scene& scene) {
  std::vector<fs::path> files;
  const glint::Scene& internal = *scene.state()->scene;
  for (const auto& mesh : internal.meshes) files.emplace_back(mesh.file);
  for (const auto& image : internal.texture_images) files.emplace_back(image.file);
  return files;
}

// Everything a tab sees, guarded by one mutex; every change bumps `version`
// and is announced to the worker and to every stream.
class Session {
 public:
  Session(fs::path path, Scene scene) : path_(std::move(path)), scene_(scene), file_scene_(std::move(scene)) {}

  std::mutex mutex;
  std::condition_variable changed;  // the worker and wait_until() wait on it

  // --- guarded by mutex ---
  fs::path path_;
  Scene scene_;       // what is shown and edited
  Scene file_scene_;  // the file as last loaded (reset, dirty)
  bool dirty_ = false;
  std::string error_;              // the file's last load error ("error: file:line:col: ...")
  std::optional<Scene> conflict_;  // the file changed under unsaved edits
  std::vector<Scene> undo_, redo_;
  std::string coalesce_key_;  // a slider drag is one undo step
  std::chrono::steady_clock::time_point coalesce_time_;
  View view_;
  uint64_t version_ = 1;        // any change of scene or view
  uint64_t scene_version_ = 1;  // changes of the scene
  std::deque<Frame> frames_;    // the last few frames
  uint64_t frame_seq_ = 0;
  uint64_t full_frames_ = 0;
  uint64_t full_frame_scene_version_ = 0;
  uint64_t renders_ = 0;
  int builds_ = 0;        // acceleration structures built (the worker's Renderer)
  uint64_t reloads_ = 0;  // times the watcher read the scene file again
  bool rendering_ = false;
  int streams_ = 0;              // open event streams (visible tabs)
  std::set<int> stream_wakers_;  // their eventfds: a stream sleeps in poll() on its own and its socket
  bool stop_ = false;
  std::string notice_;  // one-off message for the page (saved as ...)
  uint64_t notice_seq_ = 0;

  std::atomic<bool> cancel{false};

  // Wakes everyone who waits for a change. Call with the mutex held.
  void notify() {
    changed.notify_all();
    const uint64_t one = 1;
    for (int fd : stream_wakers_) (void)!write(fd, &one, sizeof one);
  }

  // Call with the mutex held after any change.
  void bump(bool scene_changed) {
    ++version_;
    if (scene_changed) {
      ++scene_version_;
      cancel = true;  // the render in flight is of an old state
    }
    notify();
  }

  void push_undo(const std::string& coalesce_key) {
    const auto now = std::chrono::steady_clock::now();
    const bool same_drag = !coalesce_key.empty() && coalesce_key == coalesce_key_ &&
                           now - coalesce_time_ < std::chrono::seconds(2) && !undo_.empty();
    if (!same_drag) {
      undo_.push_back(scene_);
      trim_undo(undo_, kUndoLimit, kUndoBytes);
    }
    coalesce_key_ = coalesce_key;
    coalesce_time_ = now;
    redo_.clear();
  }

  // The files the cache should keep: those of the scenes the page can reach
  // without touching the disk's other files (shown, file, conflict).
  std::vector<fs::path> files_in_use() const {
    std::vector<fs::path> files = files_named(scene_);
    for (const fs::path& f : files_named(file_scene_)) files.push_back(f);
    if (conflict_)
      for (const fs::path& f : files_named(*conflict_)) files.push_back(f);
    return files;
  }

  ServerStats stats(uint64_t file_reads) const {
    ServerStats s;
    s.version = version_;
    s.scene_version = scene_version_;
    s.tabs = streams_;
    s.rendering = rendering_;
    s.renders = renders_;
    s.frames = frame_seq_;
    s.full_frames = full_frames_;
    s.full_frame_scene_version = full_frame_scene_version_;
    s.file_reads = file_reads;
    s.builds = builds_;
    s.reloads = reloads_;
    return s;
  }

  Json state_json(const ServerStats& stats) const {
    Json s;
    s["version"] = version_;
    s["scene_version"] = scene_version_;
    s["file"] = path_.filename().string();
    s["scene"] = Json::parse(scene_.to_json(-1));
    s["dirty"] = dirty_;
    s["error"] = error_;
    s["conflict"] = conflict_.has_value();
    s["can_undo"] = !undo_.empty();
    s["can_redo"] = !redo_.empty();
    s["rendering"] = rendering_;
    s["width"] = scene_.width();
    s["height"] = scene_.height();
    s["view"] = {{"exposure", view_.exposure}, {"tonemap", view_.tonemap}, {"pass", view_.pass}};
    s["warnings"] = scene_.warnings();
    s["notice"] = notice_;
    s["notice_seq"] = notice_seq_;
    s["can_overwrite"] = path_.extension() == ".json";
    s["stats"] = {{"tabs", stats.tabs},
                  {"renders", stats.renders},
                  {"frames", stats.frames},
                  {"full_frames", stats.full_frames},
                  {"file_reads", stats.file_reads},
                  {"builds", stats.builds},
                  {"reloads", stats.reloads}};
    return s;
  }
};

}  // namespace glint::serve
