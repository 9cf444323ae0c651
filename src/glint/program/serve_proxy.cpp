// glint serve through the plugin glint-serve.so (plugin.h).
#include "glint/program/api.h"
#include "glint/version.h"

namespace glint::serve {

int run(const ServeOptions& options, const std::function<void(const std::string& url)>& on_listening) {
  return plugin::api<plugin::ServeApi>("serve", "glint_serve_api", GLINT_VERSION_STRING).run(options, on_listening);
}

}  // namespace glint::serve
