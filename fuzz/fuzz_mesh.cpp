// libFuzzer target for a mesh file reader: the input is written to a scratch
// file named mesh.GLINT_MESH_EXT (the loader picks its reader by extension)
// and read with glint::load_mesh_file, which must return a mesh or throw
// glint::Error, and nothing else: no other exception, crash, sanitizer
// report, hang or absurd allocation. Built as fuzz_mesh_obj, fuzz_mesh_ply,
// fuzz_mesh_gltf and fuzz_mesh_glb. The loader gets a memory budget of
// 512 MiB, well under the fuzzer's 2 GiB RSS limit: a file that claims more
// must be refused by glint's own checks, not run out of memory.
// For OBJ, whatever follows a line "#MTL" is written beside it as m.mtl, so
// the fuzzer mutates an OBJ and the MTL it names ("mtllib m.mtl") together.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

#include "glint/error.h"
#include "glint/io/mesh_file.h"
#include "scratch.h"

namespace {

constexpr size_t kMemoryBudget = size_t(512) << 20;
std::filesystem::path scratch_dir;
std::filesystem::path scratch_file;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  scratch_dir = glint_fuzz::make_scratch_dir("fuzz_mesh");
  scratch_file = scratch_dir / ("mesh." GLINT_MESH_EXT);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view mesh(reinterpret_cast<const char*>(data), size), mtl;
  if (std::string_view(GLINT_MESH_EXT) == "obj") {
    const size_t split = mesh.find("\n#MTL\n");
    if (split != std::string_view::npos) {
      mtl = mesh.substr(split + 6);
      mesh = mesh.substr(0, split + 1);
    }
  }
  // A full /tmp is not a finding.
  if (!glint_fuzz::write_file(scratch_file, mesh) || !glint_fuzz::write_file(scratch_dir / "m.mtl", mtl)) return 0;
  try {
    const glint::MeshFile loaded = glint::load_mesh_file(scratch_file, kMemoryBudget);
    (void)loaded;
  } catch (const glint::Error&) {
  }
  return 0;
}
