// libFuzzer target: the NFF reader must turn any input into its parts or a
// glint::Error at a line and column; the JSON text `glint convert` writes
// from them must always parse; and the two roads to a scene must agree:
// load_scene's, which builds the Scene from the parts (io/nff/nff_scene.cpp),
// and the JSON loader's on that text, whose errors nff_error translates to
// the NFF entity. Both load or both fail at the same place, and what loads
// has the same objects, materials and lights. Anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>

#include "glint/error.h"
#include "glint/io/json.h"
#include "glint/io/nff_file.h"
#include "glint/io/scene_loader.h"

namespace {

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_nff: %s: %s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string path = "fuzz.nff";
  glint::NffScene nff;
  try {
    nff = glint::read_nff(text, path);
  } catch (const glint::Error& e) {
    if (e.location().line < 1 || e.location().column < 1) finding("an NFF error without a line and column", e.what());
    return 0;
  }
  const glint::NffJsonText json = glint::nff_json_text(nff);
  try {
    glint::json::parse(json.text, path);
  } catch (const glint::Error& e) {
    finding("the generated JSON does not parse", e.what());
  }
  std::optional<glint::Scene> converted;
  std::optional<glint::Error> converted_error;
  try {
    converted = glint::parse_scene(json.text, path, {});
  } catch (const glint::Error& e) {
    converted_error = glint::nff_error(nff, json, e);
    if (e.location().line > 0 && converted_error->location().line == 0)
      finding("a loader error found no NFF line", e.what());
  }
  try {
    const glint::Scene direct = glint::parse_nff_scene(text, path);
    if (converted_error) finding("the converted JSON fails, the NFF loads", converted_error->what());
    if (direct.objects.size() != converted->objects.size() || direct.materials.size() != converted->materials.size() ||
        direct.lights.size() != converted->lights.size())
      finding("the NFF's scene and the converted JSON's differ", std::string(text.substr(0, 200)));
  } catch (const glint::Error& e) {
    if (!converted_error) finding("the NFF fails, the converted JSON loads", e.what());
    // Messages may differ in one case only (a product beyond a double, which
    // the JSON text writes as null); the place may not.
    if (e.location().line != converted_error->location().line ||
        e.location().column != converted_error->location().column)
      finding("the two roads fail at different places", std::string(e.what()) + " | " + converted_error->what());
  }
  return 0;
}
