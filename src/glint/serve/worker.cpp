#include "glint/serve/worker.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace glint::serve {

namespace {
// The coarse frame has about this many pixels (1 spp).
constexpr double kCoarsePixels = 40000;
}  // namespace

Worker::Worker(Session& session, int threads) : session_(session), threads_(threads) {
  thread_ = std::thread([this] { loop(); });
}

Worker::~Worker() {
  {
    // Also on an early exit (a port that cannot be bound): the thread must not wait forever.
    std::lock_guard lock(session_.mutex);
    session_.stop_ = true;
    session_.cancel = true;
    session_.notify();
  }
  thread_.join();
}

std::string Worker::explain(int x, int y) {
  std::shared_lock lock(renderer_mutex_);
  if (!renderer_) throw Error("nothing rendered yet");
  const Scene& s = renderer_->scene();
  if (x < 0 || y < 0 || x >= s.width() || y >= s.height())
    throw Error("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the image");
  return renderer_->explain_json(x, y);
}

void Worker::publish(Frame frame) {
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

void Worker::set_rendering(bool on) {
  std::lock_guard lock(session_.mutex);
  session_.rendering_ = on;
  if (on) ++session_.renders_;
  ++session_.version_;
  session_.notify();
}

void Worker::loop() {
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
bool Worker::render_version(const Scene& scene, uint64_t version, uint64_t scene_version, const std::string& pass,
                            const api::WriteOptions& wo, std::shared_ptr<const api::Image>& last_full) {
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
    std::lock_guard session_lock(session_.mutex);
    session_.builds_ = r.stats.builds;
  }
  auto linear = std::make_shared<const api::Image>(pass.empty() ? std::move(r.image) : std::move(r.passes.at(pass)));
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  publish_full(*linear, version, scene_version, pass, wo, ms, linear);
  last_full = linear;
  return true;
}

void Worker::publish_full(const api::Image& img, uint64_t version, uint64_t scene_version, const std::string& pass,
                          const api::WriteOptions& wo, double ms, std::shared_ptr<const api::Image> linear) {
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

}  // namespace glint::serve
