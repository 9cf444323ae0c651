// NFF (Eric Haines's Neutral File Format, the SPD's scenes) -> a glint JSON
// scene document, by the mapping of docs/scene-format.md ("NFF scenes").
// The reader checks the NFF itself (syntax, numbers, counts, the view); what
// the JSON loader checks (a degenerate polygon, a negative color) it leaves to
// the loader, and nff_error() reports those at the NFF entity that made them.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "glint/error.h"
#include "glint/scene/scene.h"

namespace glint {

// Where one part of the generated document came from.
struct NffOrigin {
  std::string entity;    // the NFF keyword, for messages: "s", "p", "v", ...
  SourceLocation where;  // its keyword (for the view's parts: "from", "at", ... lines)
};

struct NffScene {
  std::string filename;             // as messages name it
  nlohmann::ordered_json document;  // a glint scene: render, camera, materials, lights, objects
  // Keyed by the document path of each render/camera member, material,
  // light and object: "render.width", "camera.up", "materials.f1",
  // "lights[0]", "objects[7]".
  std::unordered_map<std::string, NffOrigin> origins;
  double angle = 45;  // the view's angle: degrees between the first and last pixel rows' centers
};

// True for a path whose extension is .nff, in any case.
bool is_nff_path(const std::filesystem::path& path);

// The scene of an NFF file (load_scene and validate_scene call these for
// .nff files): built from the file's parts straight away, no JSON document
// in between, with the JSON loader's checks on what the mapping makes; each
// problem is reported at the NFF entity behind it, as nff_error() words it.
Scene load_nff_scene(const std::filesystem::path& path);
std::vector<Error> validate_nff_scene(const std::filesystem::path& path);
// load_nff_scene of text read elsewhere, named `filename` in messages.
Scene parse_nff_scene(std::string_view text, const std::string& filename);

// Throws glint::Error("FILE:line:col: what") for every malformed input.
NffScene read_nff(std::string_view text, const std::string& filename);
// Reads the file first; an unreadable file is an Error naming it.
NffScene read_nff_file(const std::filesystem::path& path);

// The document as JSON text laid out one render/camera member, material,
// light and object per line, so that a position in the text names the part
// it falls in. line_paths[i] is line i+1's document path ("" for braces).
struct NffJsonText {
  std::string text;
  std::vector<std::string> line_paths;
};
NffJsonText nff_json_text(const NffScene& scene);

// `e`, an error of the JSON loader at a position in `json` (read as the
// file named json_filename), as the same problem at the NFF entity that
// made that part of the document; errors without such a position name the
// NFF file alone.
Error nff_error(const NffScene& scene, const NffJsonText& json, const Error& e);

}  // namespace glint
