// "materials" and the textures they use (checkers, image files read once each).
#include "glint/io/loader/scene_reader.h"

#include <array>
#include <filesystem>
#include <string>
#include <system_error>

#include "glint/io/file_cache.h"
#include "glint/io/texture_file.h"

namespace glint::loader {

void SceneReader::read_materials(const Value& m) {
  const Path materials_path("materials");
  expect_object(m, materials_path);
  for (size_t i = 0; i < m.size(); ++i) {
    const std::string name(m.key(i));
    const Path path(materials_path, name);
    const Value v = m.member(i);
    // A broken material still exists, so objects naming it report nothing more.
    if (!collect([&] { read_material(v, path); })) material_index_[name] = 0;
  }
}

void SceneReader::read_material(const Value& v, const Path& path) {
  const std::string name(path.last_key());
  expect_object(v, path);
  check_keys(v, path,
             {"ambient", "diffuse", "specular", "shininess", "reflectivity", "transparency", "ior", "fresnel"});
  Material mat;
  mat.name = name;
  if (auto x = v.find("ambient")) reflectance(*x, join(path, "ambient"), mat.ambient, mat.ambient_texture);
  if (auto x = v.find("diffuse")) reflectance(*x, join(path, "diffuse"), mat.diffuse, mat.diffuse_texture);
  if (auto x = v.find("specular")) reflectance(*x, join(path, "specular"), mat.specular, mat.specular_texture);
  if (auto x = v.find("shininess")) mat.shininess = positive(*x, join(path, "shininess"));
  if (auto x = v.find("reflectivity")) mat.reflectivity = color(*x, join(path, "reflectivity"));
  if (auto x = v.find("transparency")) mat.transparency = non_negative(*x, join(path, "transparency"));
  if (auto x = v.find("ior")) mat.ior = positive(*x, join(path, "ior"));
  if (auto x = v.find("fresnel")) mat.fresnel = boolean(*x, join(path, "fresnel"));
  material_index_[name] = add_material(scene_, std::move(mat));
}

// A reflectance is a color or a texture object (docs/scene-format.md, "Textures").
void SceneReader::reflectance(const Value& v, const Path& path, Color& c, uint32_t& texture) {
  if (v.is_object()) {
    texture = read_texture(v, path);
    return;
  }
  if (v.is_string())
    fail(v, path,
         "expected a color ([r, g, b] or a number) or a texture object, got a string (an image is "
         "written {\"texture\": " +
             quote_text(v.as_string()) + "})");
  c = color(v, path);
}

// [a, b] of finite numbers.
std::array<double, 2> SceneReader::pair(const Value& v, const Path& path) const {
  if (!v.is_array() || v.size() != 2)
    fail(v, path,
         std::string("expected [u, v], got ") +
             (v.is_array() ? "an array of " + std::to_string(v.size()) : std::string(v.kind_name())));
  return {number(v[0], index(path, 0)), number(v[1], index(path, 1))};
}

// `scale` (a number or [su, sv], non-zero) and `offset` ([ou, ov]) of a texture's uv.
void SceneReader::read_uv_transform(const Value& v, const Path& path, Texture& t) const {
  if (auto x = v.find("scale")) {
    const Path p = join(path, "scale");
    const std::array<double, 2> s = x->is_number() ? std::array<double, 2>{number(*x, p), number(*x, p)} : pair(*x, p);
    if (s[0] == 0 || s[1] == 0) fail(*x, p, "must not be zero");
    t.scale_u = s[0];
    t.scale_v = s[1];
  }
  if (auto x = v.find("offset")) {
    const std::array<double, 2> o = pair(*x, join(path, "offset"));
    t.offset_u = o[0];
    t.offset_v = o[1];
  }
}

uint32_t SceneReader::read_texture(const Value& v, const Path& path) {
  const auto image = v.find("texture");
  const auto checker = v.find("checker");
  // An error at `key` of this object (the key, not its value, is what is misplaced).
  auto fail_at_key = [&](std::string_view key, const std::string& what) {
    for (size_t k = 0; k < v.size(); ++k)
      if (v.key(k) == key) throw Error(v.key_location(k), join(path, key).str(), what);
  };
  Texture t;
  if (image && checker) fail_at_key("checker", "give either \"texture\" or \"checker\", not both");
  if (checker) {
    // The checker's options live in its own object; say so for the usual slip.
    for (const char* key : {"scale", "offset"})
      if (v.find(key)) fail_at_key(key, std::string("put \"") + key + "\" inside \"checker\"");
    check_keys(v, path, {"checker"});
    const Path p = join(path, "checker");
    expect_object(*checker, p);
    check_keys(*checker, p, {"even", "odd", "scale", "offset"});
    t.kind = TextureKind::checker;
    t.even = color(require(*checker, p, "even"), join(p, "even"));
    t.odd = color(require(*checker, p, "odd"), join(p, "odd"));
    read_uv_transform(*checker, p, t);
  } else {
    check_keys(v, path, {"texture", "wrap", "scale", "offset", "checker"});
    if (!image) fail(v, path, "a texture object needs \"texture\" (an image file) or \"checker\"");
    if (auto x = v.find("wrap")) {
      static constexpr TextureWrap kWraps[] = {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror};
      t.wrap = kWraps[choice(*x, join(path, "wrap"), {"repeat", "clamp", "mirror"}, "wrap mode")];
    }
    read_uv_transform(v, path, t);
    t.image = load_texture(*image, join(path, "texture"));
  }
  scene_.textures.push_back(t);
  return static_cast<uint32_t>(scene_.textures.size() - 1);
}

// Each image file is read once, however many textures use it. Throws
// glint::Error naming the file for a missing or unreadable one.
uint32_t SceneReader::texture_image(const std::filesystem::path& file) {
  const std::string key = file_key(file);
  if (auto it = texture_image_index_.find(key); it != texture_image_index_.end()) return it->second;
  scene_.texture_images.push_back(files_ ? *files_->texture(file) : load_texture_image(file, memory_budget_));
  const auto index = static_cast<uint32_t>(scene_.texture_images.size() - 1);
  texture_image_index_[key] = index;
  return index;
}

uint32_t SceneReader::load_texture(const Value& v, const Path& path) {
  const std::string name = string(v, path);
  if (name.empty()) fail(v, path, "must name a texture file");
  const std::filesystem::path file = beside_scene(name);
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) fail(v, path, "texture file " + quote_text(file.string()) + " not found");
  try {
    return texture_image(file);
  } catch (const Error& e) {
    fail(v, path, "texture file " + quote_text(file.string()) + ": " + e.message());
  }
}

}  // namespace glint::loader
