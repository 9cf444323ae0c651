// glint serve: a live preview of a scene in the browser (docs/preview.md).
// An HTTP server on one address serves the page (built into the binary),
// takes edits checked by the loader, renders progressively (a coarse frame,
// then the full one) and streams the frames to every tab by server-sent
// events; the scene file and the files it names are watched.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace glint::serve {

struct ServeOptions {
  std::string scene_path;
  std::string host = "127.0.0.1";
  int port = 8000;  // 0: any free port (the address printed says which)
  int threads = 0;  // render threads; 0: all cores
};

// What the server has done so far (GET /api/state has it as "stats").
struct ServerStats {
  uint64_t version = 0;        // changes of the scene or the view
  uint64_t scene_version = 0;  // changes of the scene
  int tabs = 0;                // open event streams
  bool rendering = false;
  uint64_t renders = 0;  // renders begun (a coarse and a full frame, or a re-encoding)
  uint64_t frames = 0;   // frames published, coarse and full
  uint64_t full_frames = 0;
  uint64_t full_frame_scene_version = 0;  // the scene version the newest full frame shows
  uint64_t file_reads = 0;                // mesh and texture files read from disk (not from the cache)
  int builds = 0;                         // acceleration structures built: only when the geometry changed
  uint64_t reloads = 0;                   // times the watcher read the scene file again (after a change on disk)
};

// One preview server. The constructor loads the scene and binds the port
// (throwing glint::Error when either fails); start() serves on a thread of
// its own until stop() or the destructor. run() is the command line's.
class Server {
 public:
  explicit Server(const ServeOptions& options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  int port() const;
  std::string url() const;  // "http://127.0.0.1:PORT/"
  void start();
  void stop();

  ServerStats stats() const;
  // Waits until `condition` holds, checking it at each change of the
  // server's state (no polling); false if `timeout` passed first.
  bool wait_until(const std::function<bool(const ServerStats&)>& condition, std::chrono::milliseconds timeout);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// Runs until SIGINT or SIGTERM. Calls on_listening with the server's address
// ("http://HOST:PORT/") once the scene is loaded and the port bound, before
// it serves (the command line prints it there: tests wait for that line).
// Returns the exit code; a scene that does not load or a port that cannot be
// bound throws glint::Error. Prints nothing.
int run(const ServeOptions& options, const std::function<void(const std::string& url)>& on_listening = {});

}  // namespace glint::serve
