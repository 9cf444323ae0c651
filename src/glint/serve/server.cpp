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
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
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
#include "glint/serve/session.h"
#include "glint/serve/watch.h"
#include "glint/serve/worker.h"

namespace glint::serve {

namespace {

// Request bodies are edits and small commands: anything larger is refused.
constexpr size_t kMaxRequestBytes = 1 << 20;
// Each open event stream holds one HTTP thread; more tabs than this are refused.
constexpr int kMaxStreams = 12;

const std::vector<std::string> kPasses = {"image",        "ambient", "diffuse", "specular", "reflection",
                                          "transmission", "normal",  "depth",   "albedo"};

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
  return {{"seq", f.seq},
          {"version", f.version},
          {"scene_version", f.scene_version},
          {"coarse", f.coarse},
          {"width", f.width},
          {"height", f.height},
          {"pass", f.pass.empty() ? "image" : f.pass},
          {"exposure", f.exposure},
          {"tonemap", f.tonemap},
          {"render_ms", f.render_ms}};
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
  write_file_atomically(
      path, std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

Json parse_body(const httplib::Request& req) {
  Json body = Json::parse(req.body, nullptr, false);
  if (body.is_discarded() || !body.is_object()) throw Error("request: expected a JSON object");
  return body;
}

// A command's handler: `run` takes the request's JSON object and gives the
// answer; its glint::Error (the loader's message) is the answer otherwise.
httplib::Server::Handler command(std::function<Json(const Json&)> run) {
  return [run = std::move(run)](const httplib::Request& req, httplib::Response& res) {
    try {
      send_json(res, run(parse_body(req)));
    } catch (const std::exception& e) {
      send_error(res, e.what());
    }
  };
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
    if (req.local_port > 0 && (!socket_end(fd, false, local_address, local_port) || local_port != req.local_port))
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
  void guard_routes();
  void edit_routes();
  void view_and_file_routes();
  void frame_routes();
  void event_route();
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
  port = options.port == 0 ? http.bind_to_any_port(host) : (http.bind_to_port(host, options.port) ? options.port : -1);
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
    ++session.reloads_;
    const std::string document = fresh.to_json();
    // Only the scene file changed, and it says what is on screen (our own
    // Save, or an editor writing the same text): nothing to render again.
    const bool only_scene_file =
        std::all_of(changed.begin(), changed.end(), [&](const fs::path& f) { return f == path; });
    if (only_scene_file && !session.dirty_ && document == session.scene_.to_json()) {
      session.file_scene_ = fresh;
      session.conflict_.reset();
      if (!session.error_.empty()) {
        session.error_.clear();
        session.bump(false);
      } else {
        session.changed.notify_all();  // for wait_until: the reload is done
      }
      return;
    }
    session.error_.clear();
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
    ++session.reloads_;
    session.error_ = std::string("error: ") + e.what();
    session.bump(false);
  }
}

void Server::Impl::routes() {
  guard_routes();
  // The page: only the assets built into the binary.
  for (const Asset& asset : assets()) {
    std::string route = "/";
    if (asset.name != "index.html") route.append(asset.name);
    http.Get(route, [asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(std::string(asset.data, asset.size), std::string(asset.type));
    });
  }
  // The page names its icon (favicon.svg); a client that asks for the
  // conventional one anyway gets "no content" rather than an error.
  http.Get("/favicon.ico", [](const httplib::Request&, httplib::Response& res) { res.status = 204; });
  edit_routes();
  view_and_file_routes();
  frame_routes();
  event_route();
}

// Who may talk to us, and how: before any route.
void Server::Impl::guard_routes() {
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
}

// The scene's edits: edit, undo and redo, reset, resolve a conflict.
void Server::Impl::edit_routes() {
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
}

// The view (exposure, tone map, pass), a pixel's ray tree, saving, the state.
void Server::Impl::view_and_file_routes() {
  http.Get("/api/state", [this](const httplib::Request&, httplib::Response& res) {
    std::lock_guard lock(session.mutex);
    send_json(res, session.state_json(stats_locked()));
  });

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
                if (path.extension() != ".json")
                  throw Error(path.filename().string() + " is not a scene file: save as new");
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
}

// Frames by number: only the last few that were rendered.
void Server::Impl::frame_routes() {
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
}

// Server-sent events: the state and each new frame, to every tab. A stream
// sleeps in poll() on its eventfd (the session's changes) and its socket
// (the tab going away): no timer, so nothing runs while nothing changes, and
// a closed tab is let go of at once.
void Server::Impl::event_route() {
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

int run(const ServeOptions& options, const std::function<void(const std::string& url)>& on_listening) {
  // Signals go to this thread, which waits for them (no polling anywhere);
  // every thread started from here on has them blocked.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  Server server(options);
  if (on_listening) on_listening(server.url());
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
