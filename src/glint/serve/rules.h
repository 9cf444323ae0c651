// The rules glint serve applies to what a request may do, as plain functions
// (the server calls them; tests/test_serve.cpp tests them directly).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string_view>

#include "glint/scene.h"

namespace glint::serve {

// An IPv4 address in dotted decimal, or an IPv6 address in brackets
// ("[::1]"): what a browser sends as Host for an address typed as one.
bool is_ip_literal(std::string_view host);

// A Host header names this server when its port is ours and its name is an
// IP literal, "localhost" or the --host name: a DNS name that happens to
// resolve to us (DNS rebinding) is refused, and so is a missing port.
bool host_allowed(std::string_view host_header, std::string_view bind_host, int port);

// An Origin header (when a browser sends one) must be our own page's:
// "http://" and the Host the request was sent to. "null" is never ours.
bool origin_allowed(std::string_view origin, std::string_view host_header);

// The file "Save as new" writes: beside `original`, named after it and not
// existing yet (scene-edited.json, scene-edited-2.json, ...). Nothing of the
// request takes part in the name.
std::filesystem::path new_file_beside(const std::filesystem::path& original);

// Applies `edits` ([{"op": "set" | "erase" | "append", "path", "value"}]) to
// a copy of `scene`, each checked by the loader: all of them, or a
// glint::Error and none.
api::Scene apply_edits(api::Scene scene, const nlohmann::ordered_json& edits);

}  // namespace glint::serve
