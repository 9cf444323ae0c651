// libFuzzer target: the scene loader must turn any input into a Scene or a
// glint::Error. Any other exception escaping (std::terminate), a sanitizer
// report, a timeout or an out-of-memory is a finding.
//
// It also runs `glint validate`'s reader (validate_scene, which collects every
// error and goes on reading after one) on the same text, from a scratch file:
// it must not throw at all, and it must find no error exactly when
// parse_scene loads the scene.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "glint/error.h"
#include "glint/io/scene_loader.h"
#include "scratch.h"

namespace {

std::filesystem::path scratch_file;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  scratch_file = glint_fuzz::make_scratch_dir("fuzz_scene_loader") / "fuzz.json";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  bool loaded = false;
  try {
    glint::Scene scene = glint::parse_scene(text, "fuzz.json", {});
    (void)scene;
    loaded = true;
  } catch (const glint::Error&) {
    // The one way bad input may fail.
  }

  // A full /tmp is not a finding.
  if (!glint_fuzz::write_file(scratch_file, std::string_view(reinterpret_cast<const char*>(data), size))) return 0;
  const std::vector<glint::Error> errors = glint::validate_scene(scratch_file);  // throws nothing
  if (errors.empty() != loaded) {
    // Relative file references (meshes) resolved against another folder:
    // compare with parse_scene reading from where validate_scene did.
    bool loaded_there = false;
    try {
      glint::Scene scene = glint::parse_scene(text, "fuzz.json", glint_fuzz::scratch_dir());
      (void)scene;
      loaded_there = true;
    } catch (const glint::Error&) {
    }
    if (errors.empty() != loaded_there) {
      std::fprintf(stderr, "fuzz_scene_loader: parse_scene %s but validate_scene found %zu error(s)%s%s\n",
                   loaded_there ? "loaded the scene" : "failed", errors.size(), errors.empty() ? "" : ": ",
                   errors.empty() ? "" : errors.front().what());
      std::abort();
    }
  }
  return 0;
}
