// The page's files (web/), built into the binary by cmake/embed_assets.cmake:
// the server serves these and nothing else from its routes.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

namespace glint::serve {

struct Asset {
  std::string_view name;  // "index.html", "app.js", ...
  std::string_view type;  // its Content-Type
  const char* data;
  size_t size;
};

const std::vector<Asset>& assets();

}  // namespace glint::serve
