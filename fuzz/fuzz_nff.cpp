// libFuzzer target: the NFF reader must turn any input into a document or a
// glint::Error; the document's JSON text must always parse; and whatever the
// scene loader then finds in it must be reported at a line of the NFF input
// (the translation of io/nff_file.h). Anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "glint/error.h"
#include "glint/io/json.h"
#include "glint/io/nff_file.h"
#include "glint/io/scene_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  glint::NffScene nff;
  try {
    nff = glint::read_nff(text, "fuzz.nff");
  } catch (const glint::Error& e) {
    if (e.location().line < 1 || e.location().column < 1) {
      std::fprintf(stderr, "fuzz_nff: an NFF error without a line and column: %s\n", e.what());
      std::abort();
    }
    return 0;
  }
  // The document load_scene builds in memory comes from the same reading.
  try {
    (void)glint::nff_loader_document(text, "fuzz.nff");
  } catch (const glint::Error& e) {
    std::fprintf(stderr, "fuzz_nff: read_nff took what nff_loader_document refused: %s\n", e.what());
    std::abort();
  }
  const glint::NffJsonText json = glint::nff_json_text(nff);
  try {
    glint::json::parse(json.text, "fuzz.nff");
  } catch (const glint::Error& e) {
    std::fprintf(stderr, "fuzz_nff: the generated JSON does not parse: %s\n", e.what());
    std::abort();
  }
  try {
    glint::parse_scene(json.text, "fuzz.nff", {});
  } catch (const glint::Error& e) {
    const glint::Error translated = glint::nff_error(nff, json, e);
    if (e.location().line > 0 && translated.location().line == 0) {
      std::fprintf(stderr, "fuzz_nff: a loader error found no NFF line: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
