#include "glint/render/resume.h"

#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "glint/error.h"
#include "glint/io/file_io.h"

namespace glint {

namespace {

// Version 2 adds the passes after the image; version 1 files (no passes) are still read.
constexpr char kMagic[] = "GLINT-RESUME-2\n";  // 15 bytes + NUL, the NUL not stored
constexpr char kMagicV1[] = "GLINT-RESUME-1\n";
constexpr size_t kMagicSize = sizeof(kMagic) - 1;

// A 64-bit digest of bytes, 8 at a time (the loaded arrays run to hundreds
// of megabytes): each word xor-ed in, multiplied and folded, so a change in
// any bit reaches every bit of the state. Not cryptographic: it guards
// against accidents (an edited file), not against forgery.
class Digest {
 public:
  void add(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    size_t i = 0;
    for (; i + 8 <= size; i += 8) {
      uint64_t word;
      std::memcpy(&word, p + i, 8);
      mix(word);
    }
    uint64_t tail = 0;
    if (size > i) std::memcpy(&tail, p + i, size - i);
    mix(tail ^ (static_cast<uint64_t>(size) << 56));  // the length, so "ab" + "" differs from "a" + "b"
  }
  template <class T>
  void add_array(const std::vector<T>& v) {
    static_assert(std::has_unique_object_representations_v<T> || std::is_floating_point_v<T> ||
                  std::is_same_v<T, Vec3f> || std::is_same_v<T, UVf>);
    add(v.data(), v.size() * sizeof(T));
  }
  void add_value(double v) { add(&v, sizeof v); }
  void add_value(uint64_t v) { add(&v, sizeof v); }
  void add_value(const Color& c) {
    const double xyz[] = {c.x, c.y, c.z};
    add(xyz, sizeof xyz);
  }
  uint64_t value() const { return h_; }

 private:
  void mix(uint64_t word) {
    h_ = (h_ ^ word) * 0x9e3779b97f4a7c15ULL;
    h_ ^= h_ >> 32;
  }
  uint64_t h_ = 0xcbf29ce484222325ULL;
};

// Field by field: the structs have padding, whose bytes are not values.
void add_material(Digest& d, const Material& m) {
  d.add(m.name.data(), m.name.size());
  for (const Color& c : {m.ambient, m.diffuse, m.specular, m.reflectivity}) d.add_value(c);
  for (double v : {m.shininess, m.transparency, m.ior}) d.add_value(v);
  for (uint64_t v : {uint64_t{m.fresnel}, uint64_t{m.unlit}, uint64_t{m.ambient_texture}, uint64_t{m.diffuse_texture},
                     uint64_t{m.specular_texture}})
    d.add_value(v);
}

void add_texture(Digest& d, const Texture& t) {
  for (uint64_t v : {uint64_t(t.kind), uint64_t(t.wrap), uint64_t{t.image}}) d.add_value(v);
  for (const Color& c : {t.even, t.odd}) d.add_value(c);
  for (double v : {t.scale_u, t.scale_v, t.offset_u, t.offset_v}) d.add_value(v);
}

template <class T>
void put(std::vector<unsigned char>& out, const T& value) {
  const auto* p = reinterpret_cast<const unsigned char*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}

class Reader {
 public:
  Reader(const std::vector<unsigned char>& bytes, const std::filesystem::path& path) : bytes_(bytes), path_(path) {}
  template <class T>
  T get() {
    T value;
    need(sizeof(T));
    std::memcpy(&value, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }
  void read(void* out, size_t size) {
    need(size);
    std::memcpy(out, bytes_.data() + pos_, size);
    pos_ += size;
  }
  bool at_end() const { return pos_ == bytes_.size(); }
  [[noreturn]] void fail(const std::string& why) const {
    throw Error(SourceLocation{path_.string(), 0, 0}, "not a valid resume file: " + why);
  }

 private:
  void need(size_t size) const {
    if (bytes_.size() - pos_ < size) fail("truncated");
  }
  const std::vector<unsigned char>& bytes_;
  const std::filesystem::path& path_;
  size_t pos_ = 0;
};

}  // namespace

uint64_t scene_inputs_digest(std::span<const unsigned char> description, const Scene& scene) {
  Digest d;
  d.add(description.data(), description.size());
  d.add_value(uint64_t{scene.meshes.size()});
  for (const Mesh& m : scene.meshes) {
    d.add_array(m.positions);
    d.add_array(m.indices);
    d.add_array(m.corner_normals);
    d.add_array(m.triangle_material);
    d.add_array(m.corner_uvs);
  }
  d.add_value(uint64_t{scene.texture_images.size()});
  for (const TextureImage& image : scene.texture_images) {
    d.add_value(uint64_t(image.width) << 32 | uint64_t(image.height));
    d.add_array(image.texels);
  }
  d.add_value(uint64_t{scene.materials.size()});
  for (const Material& m : scene.materials) add_material(d, m);
  d.add_value(uint64_t{scene.textures.size()});
  for (const Texture& t : scene.textures) add_texture(d, t);
  return d.value();
}

uint64_t resume_key(uint64_t inputs_digest, const RenderSettings& s, int frame) {
  Digest d;
  d.add_value(inputs_digest);
  const int32_t fields[] = {
      s.width, s.height, s.samples_per_pixel, s.max_depth, s.shading_model == ShadingModel::phong ? 0 : 1, frame};
  d.add(fields, sizeof fields);
  // The filter and adaptive sampling can come from the command line.
  const PixelFilter& f = s.pixel_filter;
  const double filter[] = {static_cast<double>(f.type), f.radius, f.sigma, f.b, f.c};
  d.add(filter, sizeof filter);
  const double adaptive[] = {s.adaptive ? static_cast<double>(s.adaptive->max_samples_per_pixel) : -1.0,
                             s.adaptive ? s.adaptive->threshold : -1.0};
  d.add(adaptive, sizeof adaptive);
  return d.value();
}

std::filesystem::path resume_path_for(const std::filesystem::path& output) {
  return std::filesystem::path(output.string() + ".glint-resume");
}

void write_resume_file(const std::filesystem::path& path, const ResumeState& state) {
  std::vector<unsigned char> out(kMagic, kMagic + kMagicSize);
  put(out, state.key);
  const int32_t header[] = {state.image.width, state.image.height, state.progress.tile_size, state.progress.tiles_x,
                            state.progress.tiles_y};
  for (int32_t v : header) put(out, v);
  out.insert(out.end(), state.progress.done.begin(), state.progress.done.end());
  auto put_pixels = [&out](const Image& image) {
    const auto* pixels = reinterpret_cast<const unsigned char*>(image.rgb.data());
    out.insert(out.end(), pixels, pixels + image.rgb.size() * sizeof(float));
  };
  put_pixels(state.image);
  put(out, static_cast<int32_t>(state.passes.passes.size()));
  for (Pass p : state.passes.passes) put(out, static_cast<int32_t>(p));
  for (const Image& image : state.passes.images) put_pixels(image);
  // Adaptive sampling's choice of pixels, once made (empty before).
  put(out, static_cast<int32_t>(state.progress.refine.empty() ? 0 : 1));
  out.insert(out.end(), state.progress.refine.begin(), state.progress.refine.end());
  write_file_atomically(path, out);
}

std::optional<ResumeState> read_resume_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  const std::vector<unsigned char> bytes = read_file(path);
  Reader in(bytes, path);
  char magic[kMagicSize];
  in.read(magic, kMagicSize);
  const bool v1 = std::memcmp(magic, kMagicV1, kMagicSize) == 0;
  if (!v1 && std::memcmp(magic, kMagic, kMagicSize) != 0) in.fail("wrong signature");
  ResumeState state;
  state.key = in.get<uint64_t>();
  const int32_t width = in.get<int32_t>(), height = in.get<int32_t>(), tile = in.get<int32_t>();
  const int32_t tiles_x = in.get<int32_t>(), tiles_y = in.get<int32_t>();
  if (width <= 0 || height <= 0 || width > (1 << 20) || height > (1 << 20) || tile <= 0 || tile > 4096)
    in.fail("bad image or tile size");
  state.progress = TileProgress(width, height, tile);
  if (state.progress.tiles_x != tiles_x || state.progress.tiles_y != tiles_y) in.fail("tile counts do not match");
  const size_t pixel_bytes = 3 * sizeof(float) * static_cast<size_t>(width) * static_cast<size_t>(height);
  const size_t head_bytes = kMagicSize + 8 + 20 + state.progress.done.size();
  if (v1 && bytes.size() != head_bytes + pixel_bytes) in.fail("wrong size");
  in.read(state.progress.done.data(), state.progress.done.size());
  for (uint8_t d : state.progress.done)
    if (d > (v1 ? 1 : 2)) in.fail("bad tile flag");
  state.image = Image(width, height);
  in.read(state.image.rgb.data(), pixel_bytes);
  if (!v1) {
    const int32_t pass_count = in.get<int32_t>();
    if (pass_count < 0 || pass_count > kPassCount) in.fail("bad pass count");
    std::vector<Pass> passes;
    for (int32_t i = 0; i < pass_count; ++i) {
      const int32_t p = in.get<int32_t>();
      if (p < 0 || p >= kPassCount) in.fail("bad pass");
      passes.push_back(static_cast<Pass>(p));
    }
    // Checked before allocating, so a corrupt count cannot ask for too much.
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    const size_t with_passes = head_bytes + pixel_bytes + 4 + 4 * passes.size() + pixel_bytes * passes.size() + 4;
    if (bytes.size() != with_passes && bytes.size() != with_passes + pixels) in.fail("wrong size");
    state.passes = PassImages(std::move(passes), width, height);
    for (Image& image : state.passes.images) in.read(image.rgb.data(), pixel_bytes);
    const int32_t has_refine = in.get<int32_t>();
    if (has_refine != 0 && has_refine != 1) in.fail("bad refinement flag");
    if (has_refine) {
      state.progress.refine.resize(pixels);
      in.read(state.progress.refine.data(), pixels);
      for (uint8_t r : state.progress.refine)
        if (r > 1) in.fail("bad refinement flag");
    }
  }
  if (!in.at_end()) in.fail("trailing bytes");
  return state;
}

}  // namespace glint
