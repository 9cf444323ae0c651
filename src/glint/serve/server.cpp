// glint serve: the session (one scene state for every tab, undo/redo, the
// file as the truth), the render worker (coarse then full frames, cancelled
// by the next edit) and the HTTP front (the page, edits, frames, events).
#include <pthread.h>
#include <signal.h>

#include <httplib.h>

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
#include <shared_mutex>
#include <string>
#include <thread>
#include <vector>

#include "glint/api/scene_state.h"
#include "glint/glint.h"
#include "glint/io/file_io.h"
#include "glint/serve/assets.h"
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
// An event stream sends a comment this often so a closed tab is noticed.
constexpr auto kKeepAlive = std::chrono::seconds(10);

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

// Everything a tab sees, guarded by one mutex; every change bumps `version`
// and is announced to every stream.
class Session {
 public:
  Session(fs::path path, Scene scene) : path_(std::move(path)), scene_(scene), file_scene_(std::move(scene)) {}

  std::mutex mutex;
  std::condition_variable changed;  // state, frames or stop: streams and the worker wait on it

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
  bool rendering_ = false;
  int streams_ = 0;              // open event streams (visible tabs)
  bool stop_ = false;
  std::string notice_;           // one-off message for the page (saved as ...)
  uint64_t notice_seq_ = 0;

  std::atomic<bool> cancel{false};

  // Call with the mutex held after any change.
  void bump(bool scene_changed) {
    ++version_;
    if (scene_changed) {
      ++scene_version_;
      cancel = true;  // the render in flight is of an old state
    }
    changed.notify_all();
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

  Json state_json() const {
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
    return s;
  }
};

// --- edits ------------------------------------------------------------------

// Applies a list of edits to a copy: all of them or none.
Scene apply_edits(Scene scene, const Json& edits) {
  if (!edits.is_array() || edits.empty()) throw Error("edits: expected a non-empty array");
  for (const Json& e : edits) {
    const std::string op = e.value("op", "");
    const std::string path = e.value("path", "");
    if (op == "set") {
      if (!e.contains("value")) throw Error(path + ": no value");
      scene.set_json(path, e["value"].dump());
    } else if (op == "erase") {
      scene.erase(path);
    } else if (op == "append") {
      scene.append_json(path, e.value("value", Json()).dump());
    } else {
      throw Error("unknown edit \"" + op + "\"");
    }
  }
  return scene;
}

std::vector<fs::path> watched_files(const fs::path& scene_path, const Scene& scene) {
  std::vector<fs::path> files{scene_path};
  const glint::Scene& internal = *scene.state()->scene;
  for (const auto& mesh : internal.meshes) files.emplace_back(mesh.file);
  for (const auto& image : internal.texture_images) files.emplace_back(image.file);
  return files;
}

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
      session_.changed.notify_all();
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
    session_.frames_.push_back(std::move(frame));
    while (session_.frames_.size() > 4) session_.frames_.pop_front();
    session_.changed.notify_all();
  }
  void set_rendering(bool on) {
    std::lock_guard lock(session_.mutex);
    session_.rendering_ = on;
    ++session_.version_;
    session_.changed.notify_all();
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
          continue;  // cancelled by a newer state
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

// --- security: who may talk to us -----------------------------------------

bool is_ip_literal(const std::string& host) {
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') return true;  // IPv6
  int dots = 0;
  for (char c : host) {
    if (c == '.') ++dots;
    else if (c < '0' || c > '9') return false;
  }
  return dots == 3;
}

// A Host header names us when its port is ours and its name is an address
// or localhost (or the --host given): a DNS name that happens to resolve to
// us (DNS rebinding) is refused.
bool host_allowed(const std::string& host_header, const std::string& bind_host, int port) {
  const size_t colon = host_header.rfind(':');
  if (colon == std::string::npos || host_header.back() == ']') return false;
  if (host_header.substr(colon + 1) != std::to_string(port)) return false;
  const std::string name = host_header.substr(0, colon);
  return name == "localhost" || name == bind_host || is_ip_literal(name);
}

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

// A name beside `original` that does not exist yet: scene-edited.json,
// scene-edited-2.json, ... (glint chooses it, never the request).
fs::path new_file_beside(const fs::path& original) {
  const fs::path folder = original.parent_path();
  const std::string stem = original.stem().string();
  for (int i = 1;; ++i) {
    std::string name = stem + "-edited";
    if (i > 1) {
      name += '-';
      name += std::to_string(i);
    }
    name += ".json";
    const fs::path candidate = folder / name;
    std::error_code ec;
    if (!fs::exists(candidate, ec)) return candidate;
  }
}

void write_text_atomically(const fs::path& path, const std::string& text) {
  write_file_atomically(path, std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(text.data()),
                                                             text.size()));
}

}  // namespace

int run(const ServeOptions& options) {
  // Signals go to one thread that waits for them (no polling anywhere).
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  const fs::path path = fs::absolute(options.scene_path).lexically_normal();
  Session session(path, Scene::load(path));
  Worker worker(session, options.threads);

  // The file is the truth: reload on change; keep unsaved edits on conflict.
  std::unique_ptr<FileWatcher> watcher;
  auto reload = [&] {
    try {
      Scene fresh = Scene::load(path);
      std::lock_guard lock(session.mutex);
      session.error_.clear();
      if (!session.dirty_ || fresh.to_json() == session.scene_.to_json()) {
        session.scene_ = fresh;
        session.dirty_ = false;
        session.conflict_.reset();
      } else {
        session.conflict_ = fresh;
      }
      session.file_scene_ = fresh;
      watcher->set_files(watched_files(path, fresh));
      session.bump(true);
    } catch (const std::exception& e) {
      std::lock_guard lock(session.mutex);
      session.error_ = std::string("error: ") + e.what();
      session.bump(false);
    }
  };
  watcher = std::make_unique<FileWatcher>(reload);
  watcher->set_files(watched_files(path, session.scene_));

  httplib::Server server;
  // Enough HTTP threads for a stream per tab plus requests.
  server.new_task_queue = [] { return new httplib::ThreadPool(kMaxStreams + 8); };
  server.set_payload_max_length(kMaxRequestBytes);
  server.set_read_timeout(10, 0);
  server.set_write_timeout(10, 0);
  int port = 0;
  const std::string host = options.host;

  server.set_pre_routing_handler([&](const httplib::Request& req, httplib::Response& res) {
    add_common_headers(res);
    const std::string host_header = req.get_header_value("Host");
    if (!host_allowed(host_header, host, port)) {
      send_error(res, "refused: Host \"" + host_header + "\" is not this server", 403);
      return httplib::Server::HandlerResponse::Handled;
    }
    // Cross-origin requests: a page elsewhere must not drive the preview.
    const std::string origin = req.get_header_value("Origin");
    if (!origin.empty() && origin != "http://" + host_header) {
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
    server.Get(route, [asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(std::string(asset.data, asset.size), std::string(asset.type));
    });
  }

  auto parse_body = [](const httplib::Request& req) {
    Json body = Json::parse(req.body, nullptr, false);
    if (body.is_discarded() || !body.is_object()) throw Error("request: expected a JSON object");
    return body;
  };
  // Runs a command; its glint::Error (the loader's message) is the answer.
  auto command = [&](auto&& body_fn) {
    return [&, body_fn](const httplib::Request& req, httplib::Response& res) {
      try {
        send_json(res, body_fn(parse_body(req)));
      } catch (const std::exception& e) {
        send_error(res, e.what());
      }
    };
  };

  server.Get("/api/state", [&](const httplib::Request&, httplib::Response& res) {
    std::lock_guard lock(session.mutex);
    send_json(res, session.state_json());
  });

  server.Post("/api/edit", command([&](const Json& body) {
    Scene base = [&] {
      std::lock_guard lock(session.mutex);
      return session.scene_;
    }();
    // The loader runs outside the lock (it may read mesh files).
    Scene edited = apply_edits(base, body.value("edits", Json()));
    std::lock_guard lock(session.mutex);
    if (session.scene_.state() != base.state())  // another tab edited meanwhile: apply to the newest
      edited = apply_edits(session.scene_, body.value("edits", Json()));
    session.push_undo(body.value("coalesce", ""));
    session.scene_ = edited;
    session.dirty_ = true;
    session.bump(true);
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  server.Post("/api/undo", command([&](const Json& body) {
    std::lock_guard lock(session.mutex);
    const bool redo = body.value("redo", false);
    auto& from = redo ? session.redo_ : session.undo_;
    auto& to = redo ? session.undo_ : session.redo_;
    if (from.empty()) throw Error(redo ? "nothing to redo" : "nothing to undo");
    to.push_back(session.scene_);
    session.scene_ = from.back();
    from.pop_back();
    session.coalesce_key_.clear();
    session.dirty_ = session.scene_.to_json() != session.file_scene_.to_json();
    session.bump(true);
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  server.Post("/api/reset", command([&](const Json&) {
    std::lock_guard lock(session.mutex);
    session.push_undo("");
    session.scene_ = session.file_scene_;
    session.dirty_ = false;
    session.conflict_.reset();
    session.bump(true);
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  server.Post("/api/resolve", command([&](const Json& body) {
    std::lock_guard lock(session.mutex);
    if (!session.conflict_) throw Error("no conflict to resolve");
    if (body.value("keep", "") == "file") {
      session.push_undo("");
      session.scene_ = *session.conflict_;
      session.dirty_ = false;
    } else if (body.value("keep", "") != "mine") {
      throw Error("keep: \"file\" or \"mine\"");
    }
    session.conflict_.reset();
    session.bump(true);
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  server.Post("/api/view", command([&](const Json& body) {
    std::lock_guard lock(session.mutex);
    View v = session.view_;
    if (body.contains("exposure")) {
      const double e = body["exposure"].get<double>();
      if (!(e >= -64 && e <= 64)) throw Error("exposure: from -64 to 64");
      v.exposure = e;
    }
    if (body.contains("tonemap")) {
      v.tonemap = body["tonemap"].get<std::string>();
      if (v.tonemap != "clamp" && v.tonemap != "reinhard" && v.tonemap != "aces")
        throw Error("tonemap: clamp, reinhard or aces");
    }
    if (body.contains("pass")) {
      v.pass = body["pass"].get<std::string>();
      if (std::find(kPasses.begin(), kPasses.end(), v.pass) == kPasses.end()) throw Error("unknown pass " + v.pass);
    }
    session.view_ = v;
    session.bump(false);
    return Json{{"ok", true}, {"version", session.version_}};
  }));

  server.Post("/api/explain", command([&](const Json& body) {
    const int x = body.at("x").get<int>(), y = body.at("y").get<int>();
    return Json::parse(worker.explain(x, y));
  }));

  server.Post("/api/save", command([&](const Json& body) {
    std::lock_guard lock(session.mutex);
    const std::string text = session.scene_.to_json(2) + "\n";
    const std::string mode = body.value("mode", "");
    if (mode == "overwrite") {
      if (path.extension() != ".json") throw Error(path.filename().string() + " is not a scene file: save as new");
      write_text_atomically(path, text);
      session.file_scene_ = session.scene_;
      session.dirty_ = false;
      session.conflict_.reset();
      session.notice_ = "saved " + path.filename().string();
    } else if (mode == "new") {
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
  auto find_frame = [&](uint64_t seq) -> std::optional<Frame> {
    std::lock_guard lock(session.mutex);
    for (const Frame& f : session.frames_)
      if (f.seq == seq) return f;
    return std::nullopt;
  };
  server.Get(R"(/frame/(\d{1,18})\.png)", [&](const httplib::Request& req, httplib::Response& res) {
    const auto f = find_frame(std::stoull(req.matches[1].str()));
    if (!f) return send_error(res, "no such frame", 404);
    if (req.has_param("download")) res.set_header("Content-Disposition", "attachment; filename=\"glint.png\"");
    res.set_content(std::string(f->png.begin(), f->png.end()), "image/png");
  });
  server.Get(R"(/frame/(\d{1,18})\.pfm)", [&](const httplib::Request& req, httplib::Response& res) {
    const auto f = find_frame(std::stoull(req.matches[1].str()));
    if (!f || !f->linear) return send_error(res, "no such full frame", 404);
    const auto bytes = api::encode_image(*f->linear, "pfm");
    res.set_header("Content-Disposition", "attachment; filename=\"glint.pfm\"");
    res.set_content(std::string(bytes.begin(), bytes.end()), "application/octet-stream");
  });

  // Server-sent events: the state and each new frame, to every tab.
  server.Get("/events", [&](const httplib::Request&, httplib::Response& res) {
    {
      std::lock_guard lock(session.mutex);
      if (session.streams_ >= kMaxStreams) return send_error(res, "too many tabs", 503);
      ++session.streams_;
      session.changed.notify_all();
    }
    auto seen_version = std::make_shared<uint64_t>(0);
    auto seen_frame = std::make_shared<uint64_t>(0);
    res.set_header("X-Accel-Buffering", "no");
    res.set_chunked_content_provider(
        "text/event-stream",
        [&, seen_version, seen_frame](size_t, httplib::DataSink& sink) {
          std::string out;
          {
            std::unique_lock lock(session.mutex);
            const bool woke = session.changed.wait_for(lock, kKeepAlive, [&] {
              return session.stop_ || session.version_ != *seen_version ||
                     (!session.frames_.empty() && session.frames_.back().seq != *seen_frame);
            });
            if (session.stop_) return false;
            if (woke && session.version_ != *seen_version) {
              *seen_version = session.version_;
              out += sse("state", session.state_json().dump());
            }
            if (woke && !session.frames_.empty() && session.frames_.back().seq != *seen_frame) {
              // The newest frame only: a slow tab skips frames rather than queue them.
              *seen_frame = session.frames_.back().seq;
              out += sse("frame", frame_json(session.frames_.back()).dump());
            }
          }
          if (out.empty()) out = ": keep-alive\n\n";
          return sink.write(out.data(), out.size());
        },
        [&](bool) {
          std::lock_guard lock(session.mutex);
          --session.streams_;
        });
  });

  port = options.port == 0 ? server.bind_to_any_port(host) : (server.bind_to_port(host, options.port) ? options.port : -1);
  if (port <= 0) throw Error("cannot listen on " + host + ":" + std::to_string(options.port));
  const std::string shown_host = host.find(':') != std::string::npos ? "[" + host + "]" : host;
  if (host != "127.0.0.1" && host != "localhost" && host != "::1")
    std::fprintf(stderr,
                 "warning: listening on %s: anyone who can reach this address can see and edit the scene "
                 "(and save it)\n",
                 host.c_str());
  std::printf("glint serve: http://%s:%d/\n", shown_host.c_str(), port);
  std::fflush(stdout);

  std::thread signal_thread([&] {
    int signal = 0;
    sigset_t wait_for;
    sigemptyset(&wait_for);
    sigaddset(&wait_for, SIGINT);
    sigaddset(&wait_for, SIGTERM);
    sigwait(&wait_for, &signal);
    {
      std::lock_guard lock(session.mutex);
      session.stop_ = true;
      session.cancel = true;
      session.changed.notify_all();
    }
    server.stop();
  });
  server.listen_after_bind();
  {
    std::lock_guard lock(session.mutex);
    session.stop_ = true;
    session.cancel = true;
    session.changed.notify_all();
  }
  if (signal_thread.joinable()) {
    pthread_kill(signal_thread.native_handle(), SIGTERM);
    signal_thread.join();
  }
  return 0;
}

}  // namespace glint::serve
