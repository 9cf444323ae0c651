#include "glint/serve/watch.h"

#include <poll.h>
#include <sys/eventfd.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "glint/error.h"

namespace glint::serve {

namespace fs = std::filesystem;

namespace {
fs::path absolute_path(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  return (ec ? p : a).lexically_normal();
}
}  // namespace

FileWatcher::FileWatcher(OnChange on_change, int settle_ms) : on_change_(std::move(on_change)), settle_ms_(settle_ms) {
  inotify_fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (inotify_fd_ < 0 || wake_fd_ < 0) throw Error(std::string("cannot watch files: ") + std::strerror(errno));
  thread_ = std::thread([this] { loop(); });
}

FileWatcher::~FileWatcher() {
  stop_ = true;
  const uint64_t one = 1;
  (void)!write(wake_fd_, &one, sizeof one);
  thread_.join();
  close(inotify_fd_);
  close(wake_fd_);
}

void FileWatcher::set_files(const std::vector<fs::path>& files) {
  std::lock_guard lock(mutex_);
  files_.clear();
  for (const fs::path& f : files) {
    const fs::path file = absolute_path(f);
    files_.insert(file);
    const fs::path folder = file.parent_path();
    bool known = false;
    for (const auto& [wd, dir] : folders_) known = known || dir == folder;
    if (known) continue;
    // The folder, not the file: a rename over the file replaces its inode.
    const int wd = inotify_add_watch(inotify_fd_, folder.c_str(),
                                     IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_DELETE | IN_MOVED_FROM);
    if (wd >= 0) folders_[wd] = folder;
  }
}

void FileWatcher::loop() {
  alignas(inotify_event) char buffer[16384];
  std::set<fs::path> changed;  // since the burst began
  while (!stop_) {
    const bool pending = !changed.empty();
    pollfd fds[2] = {{inotify_fd_, POLLIN, 0}, {wake_fd_, POLLIN, 0}};
    // Blocks with no timeout (no CPU) until something happens; a pending
    // change waits for the burst to settle.
    const int ready = poll(fds, 2, pending ? settle_ms_ : -1);
    if (stop_) break;
    if (ready == 0) {
      const std::vector<fs::path> files(changed.begin(), changed.end());
      changed.clear();
      on_change_(files);
      continue;
    }
    if (ready < 0) continue;  // EINTR
    if (!(fds[0].revents & POLLIN)) continue;
    for (;;) {
      const ssize_t n = read(inotify_fd_, buffer, sizeof buffer);
      if (n <= 0) break;
      std::lock_guard lock(mutex_);
      for (ssize_t at = 0; at < n;) {
        const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
        at += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
        if (event->mask & IN_Q_OVERFLOW) {  // events were lost: any file may have changed
          changed.insert(files_.begin(), files_.end());
          continue;
        }
        auto folder = folders_.find(event->wd);
        if (folder == folders_.end() || event->len == 0) continue;
        const fs::path file = folder->second / event->name;
        if (files_.count(file)) changed.insert(file);
      }
    }
  }
}

}  // namespace glint::serve
