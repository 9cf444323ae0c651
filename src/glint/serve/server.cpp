// glint serve: the session (one scene state for every tab, undo/redo, the
// file as the truth), the render worker (coarse then full frames, cancelled
// by the next edit) and the HTTP front (the page, edits, frames, events).
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <httplib.h>
#include <netdb.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <shared_mutex>
#include <string>
#include <thread>
#include <vector>

#include "glint/api/scene_state.h"
#include "glint/glint.h"
#include "glint/io/file_cache.h"
#include "glint/io/file_io.h"
#include "glint/serve/assets.h"
#include "glint/serve/rules.h"
#include "glint/serve/serve.h"
#include "glint/serve/watch.h"

namespace glint::serve {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using api::Scene;

// Request bodies are edits and small commands: anything larger is refused.
constexpr size_t kMaxRequestBytes = 1 << 20;
// Each open event stream holds one HTTP thread; more tabs than this are refused.
constexpr int kMaxStreams = 12;
// The coarse frame has about this many pixels (1 spp).
constexpr double kCoarsePixels = 40000;
// Undo steps kept.
constexpr size_t kUndoLimit = 200;

const std::vector<std::string> kPasses = {"image",      "ambient",      "diffuse", "specular", "reflection",
                                          "transmission", "normal", "depth",   "albedo"};

struct View {
  double exposure = 0;
  std::string tonemap = "clamp";
  std::string pass = "image";
};

api::ToneMap tonemap_named(const std::string& name) {
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
std::vector<fs::path> files_named(const Scene& scene) {
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
  std::string error_;                 // the file's last load error ("error: file:line:col: ...")
  std::optional<Scene> conflict_;     // the file changed under unsaved edits
  std::vector<Scene> undo_, redo_;
  std::string coalesce_key_;          // a slider drag is one undo step
  std::chrono::steady_clock::time_point coalesce_time_;
  View view_;
  uint64_t version_ = 1;         // any change of scene or view
  uint64_t scene_version_ = 1;   // changes of the scene
  std::deque<Frame> frames_;     // the last few frames
  uint64_t frame_seq_ = 0;
  uint64_t full_frames_ = 0;
  uint64_t full_frame_scene_version_ = 0;
  uint64_t renders_ = 0;
  int builds_ = 0;               // acceleration structures built (the worker's Renderer)
  bool rendering_ = false;
  int streams_ = 0;              // open event streams (visible tabs)
  std::set<int> stream_wakers_;  // their eventfds: a stream sleeps in poll() on its own and its socket
  bool stop_ = false;
  std::string notice_;           // one-off message for the page (saved as ...)
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
      if (undo_.size() > kUndoLimit) undo_.erase(undo_.begin());
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
    s["stats"] = {{"tabs", stats.tabs},     {"renders", stats.renders},         {"frames", stats.frames},
                  {"full_frames", stats.full_frames}, {"file_reads", stats.file_reads},
                  {"builds", stats.builds}};
    return s;
  }
};

// --- the render worker ----------------------------------------------------

class Worker {
 public:
  Worker(Session& session, int threads) : session_(session), threads_(threads) {
    thread_ = std::thread([this] { loop(); });
  }
  ~Worker() {
    {
      // Also on an early exit (a port that cannot be bound): the thread must not wait forever.
      std::lock_guard lock(session_.mutex);
      session_.stop_ = true;
      session_.cancel = true;
      session_.notify();
    }
    thread_.join();
  }

  // The ray tree of a pixel of the image on screen.
  std::string explain(int x, int y) {
    std::shared_lock lock(renderer_mutex_);
    if (!renderer_) throw Error("nothing rendered yet");
    const Scene& s = renderer_->scene();
    if (x < 0 || y < 0 || x >= s.width() || y >= s.height())
      throw Error("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the image");
    return renderer_->explain_json(x, y);
  }

 private:
  void publish(Frame frame) {
    frame.exposure = view_.exposure;
    frame.tonemap = view_.tonemap;
    std::lock_guard lock(session_.mutex);
    frame.seq = ++session_.frame_seq_;
    if (!frame.coarse) {
      ++session_.full_frames_;
      session_.full_frame_scene_version_ = frame.scene_version;
    }
    session_.frames_.push_back(std::move(frame));
    while (session_.frames_.size() > 4) session_.frames_.pop_front();
    session_.notify();
  }
  void set_rendering(bool on) {
    std::lock_guard lock(session_.mutex);
    session_.rendering_ = on;
    if (on) ++session_.renders_;
    ++session_.version_;
    session_.notify();
  }

  void loop() {
    // What the last frame shows; a change of any of it is work to do.
    uint64_t done_scene_version = 0;
    View done;
    std::shared_ptr<const api::Image> last_full;  // the last full frame's linear values
    for (;;) {
      std::optional<Scene> scene;
      View view;
      uint64_t version = 0, scene_version = 0;
      {
        std::unique_lock lock(session_.mutex);
        // Nothing to do, or nobody watching: sleep without a timeout.
        session_.changed.wait(lock, [&] {
          const View& v = session_.view_;
          return session_.stop_ ||
                 (session_.streams_ > 0 && (session_.scene_version_ != done_scene_version || v.pass != done.pass ||
                                            v.exposure != done.exposure || v.tonemap != done.tonemap));
        });
        if (session_.stop_) return;
        scene = session_.scene_;
        view = session_.view_;
        version = session_.version_;
        scene_version = session_.scene_version_;
        session_.cancel = false;
      }
      view_ = view;
      api::WriteOptions wo;
      wo.exposure = view.exposure;
      wo.tonemap = tonemap_named(view.tonemap);
      const std::string pass = view.pass == "image" ? std::string() : view.pass;
      if (scene_version == done_scene_version && view.pass == done.pass && last_full) {
        // Only the exposure or tone map changed: encode the last values again.
        publish_full(*last_full, version, scene_version, pass, wo, 0, last_full);
        done = view;
        continue;
      }
      set_rendering(true);
      try {
        if (!render_version(*scene, version, scene_version, pass, wo, last_full)) {
          set_rendering(false);
          continue;  // cancelled by a newer state, or the last tab went away
        }
      } catch (const std::exception& e) {
        std::lock_guard lock(session_.mutex);
        session_.error_ = std::string("error: ") + e.what();
        last_full.reset();
      }
      done_scene_version = scene_version;
      done = view;
      set_rendering(false);
    }
  }

  // Coarse, then full; false when cancelled.
  bool render_version(const Scene& scene, uint64_t version, uint64_t scene_version, const std::string& pass, const api::WriteOptions& wo,
                       std::shared_ptr<const api::Image>& last_full) {
    {
      std::unique_lock lock(renderer_mutex_);
      if (!renderer_) renderer_ = std::make_unique<api::Renderer>(scene, api::PrepareOptions{threads_});
      else renderer_->update(scene);  // keeps the BVH unless the geometry changed
    }
    std::shared_lock lock(renderer_mutex_);
    const int w = scene.width(), h = scene.height();
    const double scale = std::sqrt(static_cast<double>(w) * h / kCoarsePixels);
    api::RenderOptions options;
    options.threads = threads_;
    options.cancel = &session_.cancel;
    if (pass.empty()) options.passes.clear();
    else options.passes = {pass};
    if (scale > 1.5) {
      api::RenderOptions coarse = options;
      coarse.width = std::max(1, static_cast<int>(std::lround(w / scale)));
      coarse.height = std::max(1, static_cast<int>(std::lround(h / scale)));
      coarse.samples_per_pixel = 1;
      const auto start = std::chrono::steady_clock::now();
      api::RenderResult r = renderer_->render(coarse);
      if (!r.complete) return false;
      const api::Image& img = pass.empty() ? r.image : r.passes.at(pass);
      Frame f;
      f.version = version;
      f.scene_version = scene_version;
      f.coarse = true;
      f.width = img.width;
      f.height = img.height;
      f.png = api::encode_image(img, "png", wo, pass);
      f.pass = pass;
      f.render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      publish(std::move(f));
    }
    const auto start = std::chrono::steady_clock::now();
    api::RenderResult r = renderer_->render(options);
    if (!r.complete) return false;
    {
      std::lock_guard lock(session_.mutex);
      session_.builds_ = r.stats.builds;
    }
    auto linear = std::make_shared<const api::Image>(pass.empty() ? std::move(r.image) : std::move(r.passes.at(pass)));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    publish_full(*linear, version, scene_version, pass, wo, ms, linear);
    last_full = linear;
    return true;
  }

  void publish_full(const api::Image& img, uint64_t version, uint64_t scene_version, const std::string& pass, const api::WriteOptions& wo,
                    double ms, std::shared_ptr<const api::Image> linear) {
    Frame f;
    f.version = version;
    f.scene_version = scene_version;
    f.width = img.width;
    f.height = img.height;
    f.png = api::encode_image(img, "png", wo, pass);
    f.linear = std::move(linear);
    f.pass = pass;
    f.render_ms = ms;
    publish(std::move(f));
  }

  Session& session_;
  int threads_;
  View view_;  // of the job in hand
  std::shared_mutex renderer_mutex_;
  std::unique_ptr<api::Renderer> renderer_;
  std::thread thread_;
};

// --- HTTP helpers ------------------------------------------------------------

void add_common_headers(httplib::Response& res) {
  res.set_header("Cache-Control", "no-store");
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_header("X-Frame-Options", "DENY");
  res.set_header("Referrer-Policy", "no-referrer");
  res.set_header("Content-Security-Policy",
                 "default-src 'self'; img-src 'self' blob: data:; connect-src 'self'; style-src 'self'; "
                 "script-src 'self'; frame-ancestors 'none'");
}

void send_json(httplib::Response& res, const Json& body, int status = 200) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

void send_error(httplib::Response& res, const std::string& message, int status = 400) {
  send_json(res, Json{{"error", message}}, status);
}

std::string sse(const std::string& event, const std::string& data) {
  return "event: " + event + "\ndata: " + data + "\n\n";
}

Json frame_json(const Frame& f) {
  return {{"seq", f.seq},     {"version", f.version}, {"scene_version", f.scene_version}, {"coarse", f.coarse}, {"width", f.width},
          {"height", f.height}, {"pass", f.pass.empty() ? "image" : f.pass}, {"exposure", f.exposure},
          {"tonemap", f.tonemap},   {"render_ms", f.render_ms}};
}

// A command's field, or "" / false when it is missing or of another type
// (the command then says what it expected).
std::string string_field(const Json& body, const char* key) {
  const auto it = body.find(key);
  return it != body.end() && it->is_string() ? it->get<std::string>() : std::string();
}
bool true_field(const Json& body, const char* key) {
  const auto it = body.find(key);
  return it != body.end() && *it == true;
}

void write_text_atomically(const fs::path& path, const std::string& text) {
  write_file_atomically(path, std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(text.data()),
                                                             text.size()));
}

// "address port" of a socket's end, as httplib writes Request::remote_addr.
bool socket_end(int fd, bool peer, std::string& address, int& port) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  if ((peer ? getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &len)
            : getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len)) != 0)
    return false;
  char host[NI_MAXHOST], service[NI_MAXSERV];
  if (getnameinfo(reinterpret_cast<sockaddr*>(&addr), len, host, sizeof host, service, sizeof service,
                  NI_NUMERICHOST | NI_NUMERICSERV) != 0)
    return false;
  address = host;
  port = std::atoi(service);
  return true;
}

// The socket of a request's connection, or -1. httplib 0.11 does not hand
// it to handlers, so it is found among our descriptors by its two ends (the
// pair is unique while the connection is open). An event stream polls it to
// learn at once that its tab went away, rather than at a later write.
int connection_socket(const httplib::Request& req) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/proc/self/fd", ec)) {
    const std::string name = entry.path().filename().string();
    const int fd = std::atoi(name.c_str());
    std::string peer_address, local_address;
    int peer_port = 0, local_port = 0;
    if (!socket_end(fd, true, peer_address, peer_port) || peer_port != req.remote_port ||
        peer_address != req.remote_addr)
      continue;
    if (req.local_port > 0 &&
        (!socket_end(fd, false, local_address, local_port) || local_port != req.local_port))
      continue;
    return fd;
  }
  return -1;
}

// Threads started while one lives have SIGPIPE blocked: a write to a tab
// that went away fails with EPIPE rather than killing the process.
class SigpipeBlocked {
 public:
  SigpipeBlocked() {
    sigset_t pipe;
    sigemptyset(&pipe);
    sigaddset(&pipe, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe, &saved_);
  }
  ~SigpipeBlocked() { pthread_sigmask(SIG_SETMASK, &saved_, nullptr); }

 private:
  sigset_t saved_;
};

}  // namespace

// --- the server ----------------------------------------------------------------

struct Server::Impl {
  explicit Impl(const ServeOptions& options);
  ~Impl();

  void routes();
  void reload(const std::vector<fs::path>& changed);
  // After the scene shown or the file's scene changed (mutex held): the
  // cache and the watcher follow, the worker and the tabs hear of it.
  void scene_changed();
  ServerStats stats_locked() const { return session.stats(files->reads()); }

  ServeOptions options;
  fs::path path;
  std::shared_ptr<FileCache> files = std::make_shared<FileCache>();
  Session session;
  std::unique_ptr<Worker> worker;
  std::unique_ptr<FileWatcher> watcher;
  httplib::Server http;
  int port = 0;
  std::thread thread;  // serves (start())
  std::atomic<bool> listening_done{false};
};

Server::Impl::Impl(const ServeOptions& opts)
    : options(opts),
      path(fs::absolute(opts.scene_path).lexically_normal()),
      session(path, api::load_scene_with(path, files)) {
  {
    SigpipeBlocked no_sigpipe;  // for the threads made here
    worker = std::make_unique<Worker>(session, opts.threads);
    // The file is the truth: reload on change; keep unsaved edits on conflict.
    watcher = std::make_unique<FileWatcher>([this](const std::vector<fs::path>& changed) { reload(changed); });
  }
  {
    std::lock_guard lock(session.mutex);
    watcher->set_files(std::vector<fs::path>{path});
    scene_changed();
  }
  routes();
  // Enough HTTP threads for a stream per tab plus requests.
  http.new_task_queue = [] { return new httplib::ThreadPool(kMaxStreams + 8); };
  http.set_payload_max_length(kMaxRequestBytes);
  http.set_read_timeout(10, 0);
  http.set_write_timeout(10, 0);
  // One request per connection: httplib waits for a connection's next request
  // by polling every few milliseconds (for up to its keep-alive timeout), CPU
  // spent while nothing changes. A new connection to this machine costs less.
  http.set_keep_alive_max_count(1);
  const std::string& host = options.host;
  port = options.port == 0 ? http.bind_to_any_port(host)
                           : (http.bind_to_port(host, options.port) ? options.port : -1);
  if (port <= 0) throw Error("cannot listen on " + host + ":" + std::to_string(options.port));
}

Server::Impl::~Impl() {
  // The watcher goes first (its callback uses the session), then the worker.
  watcher.reset();
  worker.reset();
}

void Server::Impl::scene_changed() {
  files->keep_only(session.files_in_use());
  std::vector<fs::path> watched = files->files();
  for (const fs::path& f : files_named(session.scene_)) watched.push_back(f);
  for (const fs::path& f : files_named(session.file_scene_)) watched.push_back(f);
  watched.push_back(path);
  watcher->set_files(watched);
  session.bump(true);
}

void Server::Impl::reload(const std::vector<fs::path>& changed) {
  // A file rewritten within the clock's granularity keeps its size and time:
  // what the watcher saw change is read again whatever its stamp says.
  for (const fs::path& f : changed) files->forget(f);
  try {
    Scene fresh = api::load_scene_with(path, files);
    std::lock_guard lock(session.mutex);
    session.error_.clear();
    const std::string document = fresh.to_json();
    if (!session.dirty_ || document == session.scene_.to_json()) {
      session.scene_ = fresh;
      session.dirty_ = false;
      session.conflict_.reset();
    } else if (document == session.file_scene_.to_json()) {
      // The scene file is as it was: a mesh or a texture changed. The edits
      // stay, over the files as they are now.
      session.scene_ = api::reread_files(session.scene_);
      if (session.conflict_) session.conflict_ = fresh;
    } else {
      session.conflict_ = fresh;
    }
    session.file_scene_ = fresh;
    scene_changed();
  } catch (const std::exception& e) {
    std::lock_guard lock(session.mutex);
    session.error_ = std::string("error: ") + e.what();
    session.bump(false);
  }
}

void Server::Impl::routes() {
  http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    add_common_headers(res);
    const std::string host_header = req.get_header_value("Host");
    if (!host_allowed(host_header, options.host, port)) {
      send_error(res, "refused: Host \"" + host_header + "\" is not this server", 403);
      return httplib::Server::HandlerResponse::Handled;
    }
    // Cross-origin requests: a page elsewhere must not drive the preview.
    const std::string origin = req.get_header_value("Origin");
    if (req.has_header("Origin") && !origin_allowed(origin, host_header)) {
      send_error(res, "refused: cross-origin request from " + origin, 403);
      return httplib::Server::HandlerResponse::Handled;
    }
    const std::string site = req.get_header_value("Sec-Fetch-Site");
    if (!site.empty() && site != "same-origin" && site != "none") {
      send_error(res, "refused: cross-site request", 403);
      return httplib::Server::HandlerResponse::Handled;
    }
    if (req.method == "POST" && req.get_header_value("Content-Type").rfind("application/json", 0) != 0) {
      send_error(res, "refused: commands are JSON", 415);
      return httplib::Server::HandlerResponse::Handled;
    }
    if (req.method != "GET" && req.method != "POST") {
      send_error(res, "method not allowed", 405);
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });

  // The page: only the assets built into the binary.
  for (const Asset& asset : assets()) {
    std::string route = "/";
    if (asset.name != "index.html") route.append(asset.name);
    http.Get(route, [asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(std::string(asset.data, asset.size), std::string(asset.type));
    });
  }

  auto parse_body = [](const httplib::Request& req) {
    Json body = Json::parse(req.body, nullptr, false);
    if (body.is_discarded() || !body.is_object()) throw Error("request: expected a JSON object");
    return body;
  };
  // Runs a command; its glint::Error (the loader's message) is the answer.
  auto command = [parse_body](auto&& body_fn) {
    return [parse_body, body_fn](const httplib::Request& req, httplib::Response& res) {
      try {
        send_json(res, body_fn(parse_body(req)));
      } catch (const std::exception& e) {
        send_error(res, e.what());
      }
    };
  };

  http.Get("/api/state", [this](const httplib::Request&, httplib::Response& res) {
    std::lock_guard lock(session.mutex);
    send_json(res, session.state_json(stats_locked()));
  });

  http.Post("/api/edit", command([this](const Json& body) {
    const Json edits = body.contains("edits") ? body["edits"] : Json();
    const std::string coalesce = string_field(body, "coalesce");
    Scene base = [&] {
      std::lock_guard lock(session.mutex);
      return session.scene_;
    }();
    // The loader runs outside the lock (it may read mesh files).
    Scene edited = apply_edits(base, edits);
    std::lock_guard lock(session.mutex);
    if (session.scene_.state() != base.state())  // another tab edited meanwhile: apply to the newest
      edited = apply_edits(session.scene_, edits);
    session.push_undo(coalesce);
    session.scene_ = edited;
    session.dirty_ = true;
    scene_changed();
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  http.Post("/api/undo", command([this](const Json& body) {
    std::lock_guard lock(session.mutex);
    const bool redo = true_field(body, "redo");
    auto& from = redo ? session.redo_ : session.undo_;
    auto& to = redo ? session.undo_ : session.redo_;
    if (from.empty()) throw Error(redo ? "nothing to redo" : "nothing to undo");
    // Its mesh and texture files as they are now, not as they were then.
    Scene target = api::reread_files(from.back());
    to.push_back(session.scene_);
    session.scene_ = std::move(target);
    from.pop_back();
    session.coalesce_key_.clear();
    session.dirty_ = session.scene_.to_json() != session.file_scene_.to_json();
    scene_changed();
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  http.Post("/api/reset", command([this](const Json&) {
    std::lock_guard lock(session.mutex);
    session.push_undo("");
    session.scene_ = session.file_scene_;
    session.dirty_ = false;
    session.conflict_.reset();
    scene_changed();
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  http.Post("/api/resolve", command([this](const Json& body) {
    std::lock_guard lock(session.mutex);
    if (!session.conflict_) throw Error("no conflict to resolve");
    const std::string keep = string_field(body, "keep");
    if (keep == "file") {
      session.push_undo("");
      session.scene_ = *session.conflict_;
      session.dirty_ = false;
    } else if (keep != "mine") {
      throw Error("keep: \"file\" or \"mine\"");
    }
    session.conflict_.reset();
    scene_changed();
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  http.Post("/api/view", command([this](const Json& body) {
    std::lock_guard lock(session.mutex);
    View v = session.view_;
    if (body.contains("exposure")) {
      const Json& e = body["exposure"];
      if (!e.is_number() || !(e.get<double>() >= -64 && e.get<double>() <= 64))
        throw Error("exposure: a number from -64 to 64");
      v.exposure = e.get<double>();
    }
    if (body.contains("tonemap")) {
      const Json& t = body["tonemap"];
      if (t != "clamp" && t != "reinhard" && t != "aces") throw Error("tonemap: clamp, reinhard or aces");
      v.tonemap = t.get<std::string>();
    }
    if (body.contains("pass")) {
      const Json& p = body["pass"];
      if (!p.is_string() || std::find(kPasses.begin(), kPasses.end(), p.get<std::string>()) == kPasses.end())
        throw Error("unknown pass " + p.dump());
      v.pass = p.get<std::string>();
    }
    session.view_ = v;
    session.bump(false);
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  http.Post("/api/explain", command([this](const Json& body) {
    const auto x = body.find("x"), y = body.find("y");
    if (x == body.end() || y == body.end() || !x->is_number_integer() || !y->is_number_integer())
      throw Error("explain: \"x\" and \"y\", a pixel's column and row");
    return Json::parse(worker->explain(x->get<int>(), y->get<int>()));
  }));

  http.Post("/api/save", command([this](const Json& body) {
    std::lock_guard lock(session.mutex);
    const std::string text = session.scene_.to_json(2) + "\n";
    const std::string mode = string_field(body, "mode");
    if (mode == "overwrite") {
      if (path.extension() != ".json") throw Error(path.filename().string() + " is not a scene file: save as new");
      write_text_atomically(path, text);
      session.file_scene_ = session.scene_;
      session.dirty_ = false;
      session.conflict_.reset();
      session.notice_ = "saved " + path.filename().string();
    } else if (mode == "new") {
      // The name is glint's: nothing in the request takes part in it.
      const fs::path target = new_file_beside(path);
      write_text_atomically(target, text);
      session.notice_ = "saved as " + target.filename().string();
    } else {
      throw Error("mode: \"overwrite\" or \"new\"");
    }
    ++session.notice_seq_;
    session.bump(false);
    return Json{{"ok", true}, {"notice", session.notice_}};
  }));

  // Frames by number: only the last few that were rendered.
  auto find_frame = [this](uint64_t seq) -> std::optional<Frame> {
    std::lock_guard lock(session.mutex);
    for (const Frame& f : session.frames_)
      if (f.seq == seq) return f;
    return std::nullopt;
  };
  http.Get(R"(/frame/(\d{1,18})\.png)", [find_frame](const httplib::Request& req, httplib::Response& res) {
    const auto f = find_frame(std::stoull(req.matches[1].str()));
    if (!f) return send_error(res, "no such frame", 404);
    if (req.has_param("download")) res.set_header("Content-Disposition", "attachment; filename=\"glint.png\"");
    res.set_content(std::string(f->png.begin(), f->png.end()), "image/png");
  });
  http.Get(R"(/frame/(\d{1,18})\.pfm)", [find_frame](const httplib::Request& req, httplib::Response& res) {
    const auto f = find_frame(std::stoull(req.matches[1].str()));
    if (!f || !f->linear) return send_error(res, "no such full frame", 404);
    const auto bytes = api::encode_image(*f->linear, "pfm");
    res.set_header("Content-Disposition", "attachment; filename=\"glint.pfm\"");
    res.set_content(std::string(bytes.begin(), bytes.end()), "application/octet-stream");
  });

  // Server-sent events: the state and each new frame, to every tab. A
  // stream sleeps in poll() on its eventfd (the session's changes) and its
  // socket (the tab going away): no timer, so nothing runs while nothing
  // changes, and a closed tab is let go of at once.
  http.Get("/events", [this](const httplib::Request& req, httplib::Response& res) {
    struct Stream {
      int wake = -1, socket = -1;
      uint64_t seen_version = 0, seen_frame = 0;
    };
    auto stream = std::make_shared<Stream>();
    {
      std::lock_guard lock(session.mutex);
      if (session.streams_ >= kMaxStreams) return send_error(res, "too many tabs", 503);
      stream->wake = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
      if (stream->wake < 0) return send_error(res, "cannot open an event stream", 503);
      ++session.streams_;
      session.stream_wakers_.insert(stream->wake);
      session.notify();
    }
    stream->socket = connection_socket(req);
    res.set_header("X-Accel-Buffering", "no");
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, stream](size_t, httplib::DataSink& sink) {
          for (;;) {
            uint64_t count = 0;
            while (read(stream->wake, &count, sizeof count) > 0) {
            }
            std::string out;
            {
              std::lock_guard lock(session.mutex);
              if (session.stop_) return false;
              if (session.version_ != stream->seen_version) {
                stream->seen_version = session.version_;
                out += sse("state", session.state_json(stats_locked()).dump());
              }
              if (!session.frames_.empty() && session.frames_.back().seq != stream->seen_frame) {
                // The newest frame only: a slow tab skips frames rather than queue them.
                stream->seen_frame = session.frames_.back().seq;
                out += sse("frame", frame_json(session.frames_.back()).dump());
              }
            }
            if (!out.empty()) return sink.write(out.data(), out.size());
            pollfd fds[2] = {{stream->wake, POLLIN, 0}, {stream->socket, POLLRDHUP, 0}};
            if (poll(fds, 2, -1) < 0 && errno != EINTR) return false;
            if (fds[1].revents & (POLLRDHUP | POLLHUP | POLLERR)) return false;  // the tab went away
          }
        },
        [this, stream](bool) {
          std::lock_guard lock(session.mutex);
          session.stream_wakers_.erase(stream->wake);
          close(stream->wake);
          // Nobody watches any more: the render in flight is for no one.
          if (--session.streams_ == 0) session.cancel = true;
          session.notify();
        });
  });
}

Server::Server(const ServeOptions& options) : impl_(std::make_unique<Impl>(options)) {}

Server::~Server() { stop(); }

int Server::port() const { return impl_->port; }

std::string Server::url() const {
  const std::string& host = impl_->options.host;
  const std::string shown = host.find(':') != std::string::npos ? "[" + host + "]" : host;
  return "http://" + shown + ":" + std::to_string(impl_->port) + "/";
}

void Server::start() {
  if (impl_->thread.joinable()) return;
  SigpipeBlocked no_sigpipe;  // for the HTTP threads, made by this one
  impl_->thread = std::thread([impl = impl_.get()] {
    impl->http.listen_after_bind();
    impl->listening_done = true;
  });
}

void Server::stop() {
  {
    std::lock_guard lock(impl_->session.mutex);
    impl_->session.stop_ = true;
    impl_->session.cancel = true;
    impl_->session.notify();
  }
  if (!impl_->thread.joinable()) return;
  // httplib's stop() does nothing before listen_after_bind() has begun:
  // a stop right after start() waits for that (start-up only).
  while (!impl_->http.is_running() && !impl_->listening_done) std::this_thread::yield();
  impl_->http.stop();
  impl_->thread.join();
}

ServerStats Server::stats() const {
  std::lock_guard lock(impl_->session.mutex);
  return impl_->stats_locked();
}

bool Server::wait_until(const std::function<bool(const ServerStats&)>& condition, std::chrono::milliseconds timeout) {
  std::unique_lock lock(impl_->session.mutex);
  return impl_->session.changed.wait_for(lock, timeout, [&] { return condition(impl_->stats_locked()); });
}

int run(const ServeOptions& options) {
  // Signals go to this thread, which waits for them (no polling anywhere);
  // every thread started from here on has them blocked.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  Server server(options);
  const std::string& host = options.host;
  if (host != "127.0.0.1" && host != "localhost" && host != "::1")
    std::fprintf(stderr,
                 "warning: listening on %s: anyone who can reach this address can see and edit the scene "
                 "(and save it)\n",
                 host.c_str());
  std::printf("glint serve: %s\n", server.url().c_str());
  std::fflush(stdout);
  server.start();

  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  int signal = 0;
  sigwait(&stop_signals, &signal);
  server.stop();
  return 0;
}

}  // namespace glint::serve
