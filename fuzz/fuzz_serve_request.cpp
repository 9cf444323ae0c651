// libFuzzer target: what glint serve does with a request's own bytes. The
// input is a Host header, an Origin header and a body, one per line (the
// body is the rest): the Host and Origin checks must answer, and the body,
// parsed as the server parses it ({"edits": [...]}), must edit a scene or
// raise glint::Error, never anything else. An edit accepted must leave a
// scene whose document loads back whole (the API's fast path for camera,
// render and light edits reads those sections alone: it may not accept
// what the whole loader refuses).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "glint/error.h"
#include "glint/scene.h"
#include "glint/serve/rules.h"

namespace {

// Every section and most kinds of thing an edit can reach.
constexpr const char* kScene = R"({
  "render": {"width": 8, "height": 6, "background": [0.1, 0.1, 0.2], "fog": {"type": "exp", "density": 0.1}},
  "camera": {"position": [0, 1, 5], "look_at": [0, 0, 0], "fov_y": 40, "aperture": 0.1},
  "materials": {"red": {"diffuse": [0.8, 0.1, 0.1], "specular": 0.5}, "glass": {"transparency": 0.9, "ior": 1.5}},
  "lights": [{"type": "ambient", "ambient": 0.3, "occlusion": {"samples": 2}},
             {"type": "point", "position": [2, 4, 3]}, {"type": "spot", "position": [0, 3, 0],
              "direction": [0, -1, 0], "cutoff": 30}],
  "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]},
              {"type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "red", "name": "ball"},
              {"type": "torus", "center": [2, 1, 0], "axis": [0, 1, 0], "major_radius": 1, "minor_radius": 0.2},
              {"type": "csg", "operation": "difference", "material": "glass", "children": [
                {"type": "box", "min": [-1, 0, -1], "max": [1, 1, 1]},
                {"type": "sphere", "center": [0, 1, 0], "radius": 0.5}]}]})";

std::optional<glint::api::Scene> base;

std::string_view next_line(std::string_view& rest) {
  const size_t end = rest.find('\n');
  const std::string_view line = rest.substr(0, end);
  rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
  return line;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  base = glint::api::Scene::from_json(kScene);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  const std::string_view host = next_line(rest), origin = next_line(rest);
  (void)glint::serve::host_allowed(host, "localhost", 8080);
  (void)glint::serve::origin_allowed(origin, host);
  (void)glint::serve::is_ip_literal(host);

  const auto body = nlohmann::ordered_json::parse(rest, nullptr, /*allow_exceptions=*/false);
  if (body.is_discarded()) return 0;  // the server answers 400 before any edit
  const nlohmann::ordered_json edits = body.is_object() && body.contains("edits") ? body["edits"] : body;
  std::optional<glint::api::Scene> edited;
  try {
    edited = glint::serve::apply_edits(*base, edits);
  } catch (const glint::Error&) {
    return 0;  // the one way a bad edit may fail
  }
  try {
    (void)glint::api::Scene::from_json(edited->to_json(), edited->base_dir());
  } catch (const glint::Error& e) {
    std::fprintf(stderr, "fuzz_serve_request: an accepted edit left a scene that does not load: %s\n", e.what());
    std::abort();
  }
  return 0;
}
