// glint serve: a live preview of a scene in the browser (docs/preview.md).
// An HTTP server on one address serves the page (built into the binary),
// takes edits checked by the loader, renders progressively (a coarse frame,
// then the full one) and streams the frames to every tab by server-sent
// events; the scene file and the files it names are watched.
#pragma once

#include <string>

namespace glint::serve {

struct ServeOptions {
  std::string scene_path;
  std::string host = "127.0.0.1";
  int port = 8000;  // 0: any free port (the address printed says which)
  int threads = 0;  // render threads; 0: all cores
};

// Runs until SIGINT or SIGTERM. Prints "glint serve: http://HOST:PORT/" on
// stdout once the port is bound (tests wait for that line). Returns the
// exit code; a scene that does not load or a port that cannot be bound
// throws glint::Error.
int run(const ServeOptions& options);

}  // namespace glint::serve
