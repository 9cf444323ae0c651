// glint serve: the live preview in the browser (docs/preview.md); the server
// itself is src/glint/serve/.
#ifdef GLINT_HAVE_SERVE
#include <cstdio>
#include <memory>
#include <string>

#include "glint/serve/serve.h"
#include "options.h"

namespace glint::cli {

Command add_serve_command(CLI::App& app) {
  auto options = std::make_shared<serve::ServeOptions>();
  CLI::App* serve =
      app.add_subcommand("serve", "live preview in the browser: edit, render and explain (docs/preview.md)");
  serve->add_option("scene", options->scene_path, "scene file (JSON)")->required();
  serve->add_option("--port", options->port, "TCP port (0: any free port; the address is printed)")
      ->check(whole_number_in(0, 65535));
  serve->add_option("--host", options->host, "address to listen on (default 127.0.0.1: this machine only)");
  serve->add_option("--threads", options->threads, "render threads (default: all cores)")
      ->check(whole_number_in(1, 1024));
  return {serve, [options] {
            // Once the scene loaded and the port is bound: tests wait for the address line.
            return serve::run(*options, [&host = options->host](const std::string& url) {
              if (host != "127.0.0.1" && host != "localhost" && host != "::1")
                std::fprintf(stderr,
                             "warning: listening on %s: anyone who can reach this address can see and edit the "
                             "scene (and save it)\n",
                             host.c_str());
              std::printf("glint serve: %s\n", url.c_str());
              std::fflush(stdout);
            });
          }};
}

}  // namespace glint::cli
#endif  // GLINT_HAVE_SERVE
