// The reader's paths and messages (how a value of the document is named and
// quoted), the order in which it reads the sections, and where the files a
// scene names are found.
#include "glint/io/loader/scene_reader.h"

#include <cstdio>
#include <sstream>
#include <system_error>

namespace glint::loader {

// Text from the scene file as it appears in a message: control characters
// escaped (a message is one line) and long text cut short.
std::string printable(std::string_view s) {
  constexpr size_t kMaxShown = 64;
  std::string out;
  size_t shown = s.size() > kMaxShown ? kMaxShown : s.size();
  while (shown < s.size() && shown > 0 && (static_cast<unsigned char>(s[shown]) & 0xC0) == 0x80)
    --shown;  // do not cut a UTF-8 sequence in two
  for (size_t i = 0; i < shown; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04X", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  if (shown < s.size()) out += "...";
  return out;
}

std::string quote_text(std::string_view s) { return "\"" + printable(s) + "\""; }

std::string quoted_list(const Keys& keys) {
  std::string out;
  for (size_t i = 0; i < keys.size(); ++i) {
    if (i) out += ", ";
    out += "\"" + std::string(keys[i]) + "\"";
  }
  return out;
}

std::string format_number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

std::string Path::str() const {
  std::string out = parent_ ? parent_->str() : std::string();
  if (is_index_) return out + "[" + std::to_string(index_) + "]";
  if (!out.empty()) out += ".";
  return out + (parent_ ? printable(name_) : std::string(name_));
}

// With `errors`, problems are collected (one per material, light, object
// or section) and reading goes on; without, the first one is thrown.
Scene SceneReader::read(std::vector<Error>* errors) {
  errors_ = errors;
  const Value root = doc_.root();
  expect_object(root, "scene");
  collect([&] {
    check_keys(root, "", {"render", "camera", "materials", "lights", "objects", "animation", "$schema"});
  });
  if (auto r = root.find("render")) collect([&] { read_render(*r); });
  collect([&] { read_camera(require(root, "", "camera")); });
  if (auto m = root.find("materials")) collect([&] { read_materials(*m); });
  if (auto l = root.find("lights")) collect([&] { read_lights(*l); });
  collect([&] { read_objects(require(root, "", "objects")); });
  if (auto a = root.find("animation")) collect([&] { read_animation(*a, root.find("objects")); });
  return std::move(scene_);
}

// A file named in the scene: relative names are relative to the scene file's folder.
std::filesystem::path SceneReader::beside_scene(std::string_view name) const {
  const std::filesystem::path file(name);
  return file.is_relative() ? base_dir_ / file : file;
}

// The key that identifies a file however it is written (textures and meshes are read once).
std::string SceneReader::file_key(const std::filesystem::path& file) {
  std::error_code ec;
  const std::filesystem::path key = std::filesystem::weakly_canonical(file, ec);
  return ec ? file.string() : key.string();
}

}  // namespace glint::loader
