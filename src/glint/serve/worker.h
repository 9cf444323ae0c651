// glint serve's render worker: a thread that renders the session's newest
// scene and view whenever a tab is open (a coarse frame at about 40,000
// pixels and 1 sample, then the full one), cancelled within a row by the next
// change, and sleeps without a timeout otherwise. Internal to src/glint/serve/.
#pragma once

#include <cstdint>
#include <memory>
#include <shared_mutex>
#include <string>
#include <thread>

#include "glint/glint.h"
#include "glint/serve/session.h"

namespace glint::serve {

class Worker {
 public:
  Worker(Session& session, int threads);
  ~Worker();
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  // The ray tree of a pixel of the image on screen.
  std::string explain(int x, int y);

 private:
  void publish(Frame frame);
  void set_rendering(bool on);
  void loop();
  bool render_version(const Scene& scene, uint64_t version, uint64_t scene_version, const std::string& pass,
                      const api::WriteOptions& wo, std::shared_ptr<const api::Image>& last_full);
  void publish_full(const api::Image& img, uint64_t version, uint64_t scene_version, const std::string& pass,
                    const api::WriteOptions& wo, double ms, std::shared_ptr<const api::Image> linear);

  Session& session_;
  int threads_;
  View view_;  // of the job in hand
  std::shared_mutex renderer_mutex_;
  std::unique_ptr<api::Renderer> renderer_;
  std::thread thread_;
};

}  // namespace glint::serve
