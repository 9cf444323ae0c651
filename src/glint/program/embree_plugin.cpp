// The plugin glint-embree.so (plugin.h): the Embree backend.
#include "glint/program/api.h"
#include "glint/version.h"

GLINT_PLUGIN_ENTRY const glint::plugin::EmbreeApi* glint_embree_api() {
  static const glint::plugin::EmbreeApi api{{sizeof api, GLINT_VERSION_STRING}, &glint::build_embree_accelerator};
  return &api;
}
