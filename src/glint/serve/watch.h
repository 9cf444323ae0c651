// Watches files for changes with inotify, by their folders: an editor that
// writes in place (IN_CLOSE_WRITE) and one that renames a temporary file over
// the original (IN_MOVED_TO) both count, and so does a file created or
// deleted under a watched name.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace glint::serve {

class FileWatcher {
 public:
  // `on_change` runs on the watcher's thread once a burst of changes has
  // settled (no event for `settle_ms`), so one save is one call; it gets
  // the watched files that changed (absolute paths).
  using OnChange = std::function<void(const std::vector<std::filesystem::path>& changed)>;
  explicit FileWatcher(OnChange on_change, int settle_ms = 40);
  ~FileWatcher();
  FileWatcher(const FileWatcher&) = delete;
  FileWatcher& operator=(const FileWatcher&) = delete;

  // The files to watch from now on (replaces the previous set).
  void set_files(const std::vector<std::filesystem::path>& files);

 private:
  void loop();

  OnChange on_change_;
  int settle_ms_;
  int inotify_fd_ = -1, wake_fd_ = -1;
  std::mutex mutex_;
  std::map<int, std::filesystem::path> folders_;  // watch descriptor -> folder
  std::set<std::filesystem::path> files_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace glint::serve
