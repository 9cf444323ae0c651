// The plugin glint-serve.so (plugin.h): the live preview's HTTP server.
#include "glint/program/api.h"
#include "glint/version.h"

GLINT_PLUGIN_ENTRY const glint::plugin::ServeApi* glint_serve_api() {
  static const glint::plugin::ServeApi api{{sizeof api, GLINT_VERSION_STRING}, &glint::serve::run};
  return &api;
}
