#include "glint/serve/rules.h"

#include <arpa/inet.h>

#include <string>

#include "glint/error.h"

namespace glint::serve {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

bool is_ip_literal(std::string_view host) {
  unsigned char address[16];
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') {
    const std::string inside(host.substr(1, host.size() - 2));
    return inet_pton(AF_INET6, inside.c_str(), address) == 1;
  }
  return inet_pton(AF_INET, std::string(host).c_str(), address) == 1;
}

bool host_allowed(std::string_view host_header, std::string_view bind_host, int port) {
  const size_t colon = host_header.rfind(':');
  // No port ("[::1]" ends in ']'): not how a browser names us on our port.
  if (colon == std::string_view::npos || host_header.back() == ']') return false;
  if (host_header.substr(colon + 1) != std::to_string(port)) return false;
  const std::string_view name = host_header.substr(0, colon);
  return name == "localhost" || (!bind_host.empty() && name == bind_host) || is_ip_literal(name);
}

bool origin_allowed(std::string_view origin, std::string_view host_header) {
  return origin.size() == 7 + host_header.size() && origin.substr(0, 7) == "http://" && origin.substr(7) == host_header;
}

fs::path new_file_beside(const fs::path& original) {
  const fs::path folder = original.parent_path();
  const std::string stem = original.stem().string();
  for (int i = 1;; ++i) {
    std::string name = stem + "-edited";
    if (i > 1) {
      name += '-';
      name += std::to_string(i);
    }
    name += ".json";
    const fs::path candidate = folder / name;
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(candidate, ec))) return candidate;
  }
}

api::Scene apply_edits(api::Scene scene, const Json& edits) {
  if (!edits.is_array() || edits.empty()) throw Error("edits: expected a non-empty array");
  for (size_t i = 0; i < edits.size(); ++i) {
    const Json& e = edits[i];
    const std::string where = "edits[" + std::to_string(i) + "]";
    if (!e.is_object()) throw Error(where + ": expected an object");
    const auto op = e.find("op"), path = e.find("path"), value = e.find("value");
    if (op == e.end() || !op->is_string()) throw Error(where + ".op: expected \"set\", \"erase\" or \"append\"");
    if (path == e.end() || !path->is_string()) throw Error(where + ".path: expected a path in the scene");
    const std::string& p = path->get_ref<const std::string&>();
    if (*op == "set") {
      if (value == e.end()) throw Error(p + ": no value");
      scene.set_json(p, value->dump());
    } else if (*op == "erase") {
      scene.erase(p);
    } else if (*op == "append") {
      if (value == e.end()) throw Error(p + ": no value");
      scene.append_json(p, value->dump());
    } else {
      throw Error(where + ".op: unknown edit \"" + op->get<std::string>() + "\"");
    }
  }
  return scene;
}

}  // namespace glint::serve
