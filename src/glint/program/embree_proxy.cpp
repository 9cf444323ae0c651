// --accel embree through the plugin glint-embree.so (plugin.h).
#include "glint/program/api.h"
#include "glint/version.h"

namespace glint {

bool embree_available() { return !plugin::find("embree").empty(); }

std::unique_ptr<Accelerator> build_embree_accelerator(const Scene& scene, const AcceleratorOptions& options) {
  return plugin::api<plugin::EmbreeApi>("embree", "glint_embree_api", GLINT_VERSION_STRING).build(scene, options);
}

}  // namespace glint
