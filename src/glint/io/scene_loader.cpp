#include "glint/io/scene_loader.h"

// GCC 12 warns falsely about std::string concatenation at -O3 (GCC bug 105329).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ == 12
#pragma GCC diagnostic ignored "-Wrestrict"
#endif

#include <algorithm>
#include <cctype>
#include <new>
#include <vector>

#include "glint/io/json.h"
#include "glint/io/loader/scene_reader.h"
#include "glint/io/memory_limit.h"
#include "glint/io/mesh_scene.h"
#include "glint/io/nff_file.h"

namespace glint {

namespace {

using loader::SceneReader;

// Edits (insert, delete, substitute, swap two neighbours) between a and b,
// ignoring case: "widht" is one edit from "width".
size_t edit_distance(std::string_view a, std::string_view b) {
  if (a.size() > 256 || b.size() > 256) return std::max(a.size(), b.size());  // no hint for huge keys
  auto lower = [](char c) { return std::tolower(static_cast<unsigned char>(c)); };
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) && lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

}  // namespace

std::string closest_match(std::string_view word, const std::vector<std::string_view>& candidates) {
  std::string best;
  // A plausible typo: at most one edit per three letters (two for short
  // words), and fewer edits than the word has letters ("zz" is no "a").
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (std::string_view c : candidates) {
    const size_t d = edit_distance(word, c);
    if (d < best_distance && d < word.size()) {
      best_distance = d;
      best = std::string(c);
    }
  }
  return best;
}

void check_image_size(int width, int height, const SourceLocation& where) {
  // The film holds 3 floats per pixel; refuse what this machine cannot hold
  // rather than let the allocation fail (or the OOM killer strike) mid-render.
  const std::string excess = exceeds_budget(12.0 * width * height, default_memory_budget());
  if (!excess.empty())
    throw Error(where, "image of " + std::to_string(width) + "x" + std::to_string(height) + " pixels " + excess);
}

Scene parse_scene(std::string text, const std::string& filename, const std::filesystem::path& base_dir,
                  size_t memory_budget) {
  const json::Document doc = json::parse(std::move(text), filename);
  try {
    return SceneReader(doc, base_dir, memory_budget).read();
  } catch (const std::bad_alloc&) {
    throw Error(SourceLocation{filename, 0, 0}, "out of memory while loading the scene");
  }
}

namespace {

// An NFF file (docs/scene-format.md, "NFF scenes") goes through the JSON
// loader as the document nff_file.h makes of it, so both formats get the same
// checks; whatever the loader finds is reported at the NFF entity behind it.
Scene load_nff_scene(const std::filesystem::path& path) {
  const NffScene nff = read_nff_file(path);
  NffJsonText json = nff_json_text(nff);
  Scene scene;
  try {
    scene = parse_scene(std::move(json.text), path.string(), path.parent_path());
  } catch (const Error& e) {
    throw nff_error(nff, json, e);
  }
  // The view's angle spans the rows' centers: fov_y follows the rendered height.
  scene.camera.row_center_angle = nff.angle;
  return scene;
}

std::vector<Error> validate_nff_scene(const std::filesystem::path& path) {
  std::vector<Error> errors;
  try {
    const NffScene nff = read_nff_file(path);
    const NffJsonText json = nff_json_text(nff);
    std::vector<Error> found;
    try {
      const json::Document doc = json::parse(json.text, path.string());
      SceneReader(doc, path.parent_path()).read(&found);
    } catch (const Error& e) {
      found.push_back(e);
    }
    for (const Error& e : found) errors.push_back(nff_error(nff, json, e));
  } catch (const Error& e) {
    errors.push_back(e);  // the NFF itself is malformed: nothing more can be checked
  } catch (const std::bad_alloc&) {
    errors.push_back(Error(SourceLocation{path.string(), 0, 0}, "out of memory while loading the scene"));
  }
  return errors;
}

}  // namespace

std::vector<Error> validate_scene(const std::filesystem::path& path) {
  if (is_nff_path(path)) return validate_nff_scene(path);
  std::vector<Error> errors;
  try {
    const json::Document doc = json::parse_file(path.string());
    SceneReader(doc, path.parent_path()).read(&errors);
  } catch (const Error& e) {
    errors.push_back(e);  // unreadable or not JSON: nothing more can be checked
  } catch (const std::bad_alloc&) {
    errors.push_back(Error(SourceLocation{path.string(), 0, 0}, "out of memory while loading the scene"));
  }
  return errors;
}

Scene load_scene(const std::filesystem::path& path) {
  if (is_nff_path(path)) return load_nff_scene(path);
  // A bare mesh file is framed by a fixed rig (io/mesh_scene.h).
  if (is_mesh_file(path)) return parse_scene(mesh_scene_json(path), path.string(), path.parent_path());
  const json::Document doc = json::parse_file(path.string());
  try {
    return SceneReader(doc, path.parent_path()).read();
  } catch (const std::bad_alloc&) {
    throw Error(SourceLocation{path.string(), 0, 0}, "out of memory while loading the scene");
  }
}

}  // namespace glint
