#include "glint/io/mesh/gltf_checks.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string_view>
#include <system_error>

#include "glint/io/memory_limit.h"
#include "glint/io/mesh/common.h"

namespace glint::mesh_io {
namespace fs = std::filesystem;
namespace {

// Bytes of one element of a glTF accessor (0 for types assimp will refuse).
double gltf_element_bytes(const json::Value& accessor) {
  const auto type = accessor.find("type");
  const auto component = accessor.find("componentType");
  if (!type || !type->is_string() || !component || !component->is_number()) return 0;
  static const std::pair<std::string_view, int> kComponents[] = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
                                                                 {"MAT2", 4},   {"MAT3", 9}, {"MAT4", 16}};
  int components = 0;
  for (const auto& [name, n] : kComponents)
    if (type->as_string() == name) components = n;
  const double c = component->as_number();
  const int size = c == 5120 || c == 5121 ? 1 : c == 5122 || c == 5123 ? 2 : c == 5125 || c == 5126 ? 4 : 0;
  return double(components) * size;
}

// An accessor's count as the file claims it (0 when it is no count at all,
// which assimp reports itself).
double gltf_count(const json::Value& accessor) {
  const auto count = accessor.find("count");
  return count && count->is_number() && count->as_number() > 0 ? count->as_number() : 0;
}

// A non-negative integer member, or nullopt.
std::optional<double> gltf_index(const json::Value& object, std::string_view key) {
  const auto v = object.find(key);
  if (!v || !v->is_integer() || v->as_number() < 0) return std::nullopt;
  return v->as_number();
}

// False for a "data:...;base64,..." URI whose payload is not base64 (the
// alphabet, a length of whole 4-character groups, '=' only as padding);
// true for anything else (other URIs are assimp's to judge).
bool is_valid_data_uri(std::string_view uri) {
  if (uri.substr(0, 5) != "data:") return true;
  const size_t comma = uri.find(',');
  if (comma == std::string_view::npos) return true;
  const std::string_view header = uri.substr(0, comma);
  if (header.size() < 7 || header.substr(header.size() - 7) != ";base64") return true;
  std::string_view payload = uri.substr(comma + 1);
  if (payload.size() % 4 != 0) return false;
  for (int pad = 0; pad < 2 && !payload.empty() && payload.back() == '='; ++pad) payload.remove_suffix(1);
  for (char c : payload)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '+' && c != '/') return false;
  return true;
}

// assimp 5.2's data URI parser (glTFCommon ParseDataURI) keeps the offsets of
// the parts it found in the string's first bytes, each as a char: a header
// (the part before the first ',') of 127 bytes or more wraps an offset
// negative, and the payload is then read from before the string (a leak);
// a string starting with byte 0x10 counts as already parsed, its next four
// bytes as those offsets (a length near 2^64). Both found by hand next to a
// fuzz_mesh_gltf finding; buffers are checked for both, and images never
// reach the parser (see reduce_gltf_json).
constexpr size_t kMaxDataUriHeader = 126;
bool assimp_reads_as_data_uri(std::string_view uri) {
  return uri.substr(0, 5) == "data:" || (!uri.empty() && uri[0] == '\x10');
}

// One primitive's indices: unsigned integer scalars (assimp leaked on a VEC3
// index accessor), and at least as many corners (indices, or positions
// without them) as its mode needs for one point, line or triangle: with fewer,
// assimp leaked (lines, fans) or wrapped a count to 2^64 (strips, fans).
template <class Where>
void check_gltf_primitive(const json::Value& primitive, const std::optional<json::Value>& accessors, Where where,
                          const std::string& name) {
  auto accessor = [&](const std::optional<double>& index) -> std::optional<json::Value> {
    if (!index || !accessors || !accessors->is_array() || *index >= double(accessors->size())) return std::nullopt;
    return (*accessors)[static_cast<size_t>(*index)];  // else assimp reports it
  };
  const auto indices = accessor(gltf_index(primitive, "indices"));
  if (indices) {
    const auto type = indices->find("type");
    const auto component = indices->find("componentType");
    const double c = component && component->is_number() ? component->as_number() : 0;
    if (!type || !type->is_string() || type->as_string() != "SCALAR" || (c != 5121 && c != 5123 && c != 5125))
      throw Error(where(*primitive.find("indices")),
                  name + ".indices: must be a SCALAR accessor of 5121, 5123 or 5125 (unsigned integers)");
  }
  const auto attributes = primitive.find("attributes");
  const auto positions = attributes ? accessor(gltf_index(*attributes, "POSITION")) : std::nullopt;
  // No positions at all count as none (a strip of none wrapped too).
  const double corners = indices ? gltf_count(*indices) : positions ? gltf_count(*positions) : 0;
  const double mode = gltf_index(primitive, "mode").value_or(4);
  const double needed = mode == 0 ? 1 : mode <= 3 ? 2 : 3;
  if (corners < needed)
    throw Error(where(primitive), name + ": " + format_count(corners) + (indices ? " indices" : " vertices") +
                                      " are too few for mode " + format_count(mode) + " (at least " +
                                      format_count(needed) + ")");
}

// What glint reads from a glTF is the node tree, the meshes' positions,
// normals, first UV set and indices, and the materials (with their base color
// textures). Skins, animations, morph targets, cameras and other vertex
// attributes are dropped before assimp sees the file: glint would ignore
// them, and assimp 5.2 crashes or leaks on many
// malformed ones (a skin without inverseBindMatrices, an animation channel
// without a target, float joints: fuzz_mesh_gltf). LINE_LOOPs become
// LINE_STRIPs (see below). `text` is valid JSON.
std::string reduce_gltf_json(const std::string& text) {
  using NJson = nlohmann::json;
  NJson j = NJson::parse(text);
  if (!j.is_object()) return text;
  for (const char* key : {"animations", "skins", "cameras"}) j.erase(key);
  // Embedded images (data URIs, or bytes in a buffer view) are never read by
  // glint, and assimp 5.2 fails on their details: it leaked decoding bad
  // base64, called strcmp on strchr(type, '/') + 1 (address 1) for a media
  // type without '/' ("data:png;...", a fuzz_mesh_gltf finding, or
  // "mimeType": "png"), misread a long data URI header. Each reaches it as
  // the same 3 zero bytes of PNG. Image files keep their uri.
  if (auto images = j.find("images"); images != j.end() && images->is_array())
    for (NJson& image : *images) {
      if (!image.is_object()) continue;
      // assimp reads a bufferView when there is no string uri.
      const auto uri = image.find("uri");
      const bool embedded = uri != image.end() && uri->is_string() ? assimp_reads_as_data_uri(uri->get<std::string>())
                                                                   : image.contains("bufferView");
      if (!embedded) continue;
      image.erase("bufferView");
      image.erase("mimeType");
      image["uri"] = "data:image/png;base64,AAAA";
    }
  if (auto nodes = j.find("nodes"); nodes != j.end() && nodes->is_array())
    for (NJson& node : *nodes)
      if (node.is_object())
        for (const char* key : {"skin", "camera", "weights"}) node.erase(key);
  if (auto meshes = j.find("meshes"); meshes != j.end() && meshes->is_array())
    for (NJson& mesh : *meshes) {
      if (!mesh.is_object()) continue;
      mesh.erase("weights");
      auto primitives = mesh.find("primitives");
      if (primitives == mesh.end() || !primitives->is_array()) continue;
      for (NJson& primitive : *primitives) {
        if (!primitive.is_object()) continue;
        primitive.erase("targets");
        // Lines are no surfaces to glint, but assimp 5.2 dereferences null
        // closing a LINE_LOOP whose indices are out of range (fuzz_mesh_glb):
        // a LINE_STRIP is read the same way, without the closing segment.
        if (auto mode = primitive.find("mode"); mode != primitive.end() && *mode == 2) *mode = 3;
        auto attributes = primitive.find("attributes");
        if (attributes == primitive.end() || !attributes->is_object()) continue;
        for (auto it = attributes->begin(); it != attributes->end();)
          it = it.key() == "POSITION" || it.key() == "NORMAL" || it.key() == "TEXCOORD_0" ? std::next(it)
                                                                                          : attributes->erase(it);
      }
    }
  return j.dump(-1, ' ', false, NJson::error_handler_t::replace);
}

}  // namespace

std::string gltf_json_text(const std::vector<unsigned char>& bytes, bool binary, const std::string& file) {
  if (!binary) {
    size_t i = 0;
    if (bytes.size() >= 3 && std::memcmp(bytes.data(), "\xEF\xBB\xBF", 3) == 0) i = 3;
    while (i < bytes.size() && std::isspace(bytes[i])) ++i;
    if (i >= bytes.size() || bytes[i] != '{') fail(file, "not a glTF file (no JSON object)");
    return std::string(bytes.begin(), bytes.end());
  }
  if (bytes.size() < 12 || std::memcmp(bytes.data(), "glTF", 4) != 0)
    fail(file, "not a binary glTF file (no 'glTF' magic)");
  const uint64_t declared = read_binary_uint(bytes.data() + 8, 4, false);
  if (declared > bytes.size())
    fail(file, "truncated: the header declares " + std::to_string(declared) + " bytes, the file has " +
                   std::to_string(bytes.size()));
  if (bytes.size() < 20) fail(file, "truncated: no JSON chunk after the header");
  const uint64_t length = read_binary_uint(bytes.data() + 12, 4, false);
  if (std::memcmp(bytes.data() + 16, "JSON", 4) != 0) fail(file, "the first chunk is not the JSON chunk");
  if (length > bytes.size() - 20)
    fail(file, "truncated: the JSON chunk claims " + std::to_string(length) + " bytes, " +
                   std::to_string(bytes.size() - 20) + " follow");
  std::string text(bytes.begin() + 20, bytes.begin() + 20 + static_cast<ptrdiff_t>(length));
  while (!text.empty() && text.back() == '\0') text.pop_back();  // padding some exporters write
  return text;
}

json::Document parse_gltf_json(std::string text, bool binary, const std::string& file) {
  try {
    return json::parse(std::move(text), file);
  } catch (const Error& e) {
    if (!binary) throw;
    fail(file, "JSON chunk: " + e.message());
  }
}

void check_gltf_memory(const json::Document& doc, bool binary, size_t budget, const std::string& file) {
  const json::Value root = doc.root();
  // A .glb's JSON positions mean little to people: name the file only.
  auto where = [&](const json::Value& v) { return binary ? SourceLocation{file, 0, 0} : v.location(); };
  const auto accessors = root.find("accessors");
  std::vector<double> counts;
  double accessor_bytes = 0;
  if (accessors && accessors->is_array()) {
    for (size_t i = 0; i < accessors->size(); ++i) {
      const json::Value a = (*accessors)[i];
      counts.push_back(gltf_count(a));
      const double bytes = counts.back() * gltf_element_bytes(a);
      const std::string excess = exceeds_budget(bytes, budget);
      if (!excess.empty())
        throw Error(where(*a.find("count")), "accessors[" + std::to_string(i) + "].count: " +
                                                 format_count(counts.back()) + " elements: that " + excess);
      accessor_bytes += bytes;
    }
  }
  // assimp holds every buffer whole (an external .bin may be any size).
  const auto buffers = root.find("buffers");
  for (size_t i = 0; buffers && buffers->is_array() && i < buffers->size(); ++i) {
    const auto length = (*buffers)[i].find("byteLength");
    if (!length || !length->is_number() || length->as_number() <= 0) continue;
    const std::string excess = exceeds_budget(length->as_number(), budget);
    if (!excess.empty())
      throw Error(where(*length), "buffers[" + std::to_string(i) +
                                      "].byteLength: " + format_count(length->as_number()) + " bytes: that " + excess);
    accessor_bytes += length->as_number();
  }
  auto count_of = [&](const std::optional<json::Value>& index) {
    if (!index || !index->is_integer() || index->as_number() < 0 || index->as_number() >= double(counts.size()))
      return 0.0;
    return counts[static_cast<size_t>(index->as_number())];
  };
  const auto meshes = root.find("meshes");
  const auto nodes = root.find("nodes");
  double vertices = 0, triangles = 0;
  for (size_t m = 0; meshes && meshes->is_array() && m < meshes->size(); ++m) {
    double instances = 0;
    for (size_t n = 0; nodes && nodes->is_array() && n < nodes->size(); ++n) {
      const auto mesh = (*nodes)[n].find("mesh");
      instances += mesh && mesh->is_number() && mesh->as_number() == double(m);
    }
    const auto primitives = (*meshes)[m].find("primitives");
    for (size_t p = 0; primitives && primitives->is_array() && p < primitives->size(); ++p) {
      const json::Value primitive = (*primitives)[p];
      const auto attributes = primitive.find("attributes");
      const double positions = attributes ? count_of(attributes->find("POSITION")) : 0;
      const auto indices = primitive.find("indices");
      const double corners = indices ? count_of(indices) : positions;
      const auto mode = primitive.find("mode");
      const bool strip_or_fan = mode && mode->is_number() && (mode->as_number() == 5 || mode->as_number() == 6);
      vertices += std::max(instances, 1.0) * positions;
      triangles += std::max(instances, 1.0) * (strip_or_fan ? corners : corners / 3);
    }
  }
  const std::string excess =
      exceeds_budget(accessor_bytes + kBytesPerVertex * vertices + kBytesPerTriangle * triangles, budget);
  if (!excess.empty())
    fail(file, "the accessors claim " + format_count(vertices) + " vertices and " + format_count(triangles) +
                   " triangles (instances counted): that " + excess);
}

void check_gltf_structure(const json::Document& doc, bool binary, const std::string& file) {
  const json::Value root = doc.root();
  auto where = [&](const json::Value& v) { return binary ? SourceLocation{file, 0, 0} : v.location(); };
  // glTF 1.0 (objects where 2.0 has arrays) would go to assimp's glTF 1
  // reader, unchecked by anything here.
  const auto asset = root.find("asset");
  const auto version = asset ? asset->find("version") : std::nullopt;
  if (!version || !version->is_string()) throw Error(where(root), "no asset.version: not a glTF 2.0 file");
  if (version->as_string().substr(0, 2) != "2.")
    throw Error(where(*version),
                "asset.version: glTF " + std::string(version->as_string()) + " is not supported (only glTF 2.0)");
  const auto accessors = root.find("accessors");
  const auto views = root.find("bufferViews");
  const size_t view_count = views && views->is_array() ? views->size() : 0;
  // byteLength of a buffer view by index; nullopt when there is no such view.
  auto view_length = [&](const std::optional<double>& index) -> std::optional<double> {
    if (!index || *index >= double(view_count)) return std::nullopt;
    const auto length = gltf_index((*views)[static_cast<size_t>(*index)], "byteLength");
    return length ? length : std::optional<double>(0.0);
  };
  for (size_t i = 0; accessors && accessors->is_array() && i < accessors->size(); ++i) {
    const json::Value a = (*accessors)[i];
    const std::string name = "accessors[" + std::to_string(i) + "]";
    if (!a.is_object()) continue;  // assimp reports that one
    const double element = gltf_element_bytes(a);
    if (element == 0)
      throw Error(where(a), name +
                                ": needs a componentType of 5120, 5121, 5122, 5123, 5125 or 5126 and a type of "
                                "SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4");
    // The specification's bound on an accessor within its view, stride
    // included: assimp checks count x element size only, then reads strided
    // elements past the view, throws half-way and leaks (fuzz_mesh_glb).
    const auto view_index = gltf_index(a, "bufferView");
    if (const auto length = view_length(view_index); length && gltf_count(a) > 0) {
      const json::Value view = (*views)[static_cast<size_t>(*view_index)];
      const double stride = gltf_index(view, "byteStride").value_or(0) > 0 ? *gltf_index(view, "byteStride") : element;
      const double end = gltf_index(a, "byteOffset").value_or(0) + stride * (gltf_count(a) - 1) + element;
      if (end > *length)
        throw Error(where(a), name + ": " + format_count(gltf_count(a)) + " elements need " + format_count(end) +
                                  " bytes of buffer view " + format_count(*view_index) + ", which has " +
                                  format_count(*length));
    }
    const auto sparse = a.find("sparse");
    if (!sparse) continue;
    auto bad_sparse = [&](const std::string& what) { throw Error(where(*sparse), name + ".sparse: " + what); };
    const auto count = sparse->is_object() ? gltf_index(*sparse, "count") : std::nullopt;
    if (!count || *count < 1 || *count > gltf_count(a)) bad_sparse("needs a count from 1 to the accessor's count");
    const auto indices = sparse->find("indices"), values = sparse->find("values");
    if (!indices || !indices->is_object() || !values || !values->is_object())
      bad_sparse("needs 'indices' and 'values' objects");
    const auto index_type = indices->find("componentType");
    const double t = index_type && index_type->is_number() ? index_type->as_number() : 0;
    const double index_bytes = t == 5121 ? 1 : t == 5123 ? 2 : t == 5125 ? 4 : 0;
    if (index_bytes == 0) bad_sparse("indices need a componentType of 5121, 5123 or 5125");
    const auto index_view = view_length(gltf_index(*indices, "bufferView"));
    const auto value_view = view_length(gltf_index(*values, "bufferView"));
    if (!index_view || !value_view) bad_sparse("indices and values each need a bufferView that exists");
    if (gltf_index(*indices, "byteOffset").value_or(0) + *count * index_bytes > *index_view ||
        gltf_index(*values, "byteOffset").value_or(0) + *count * element > *value_view)
      bad_sparse(format_count(*count) + " entries do not fit in their buffer views");
  }
  // assimp 5.2's base64 decoder leaks its buffer when it throws on a bad
  // character (fuzz_mesh_gltf). Images are not read at all (see
  // reduce_gltf_json); buffers must decode.
  const auto buffers = root.find("buffers");
  for (size_t i = 0; buffers && buffers->is_array() && i < buffers->size(); ++i) {
    const auto uri = (*buffers)[i].find("uri");
    if (!uri || !uri->is_string()) continue;
    const std::string_view u = uri->as_string();
    const std::string name = "buffers[" + std::to_string(i) + "].uri: ";
    if (!u.empty() && static_cast<unsigned char>(u[0]) < 0x20)
      throw Error(where(*uri), name + "starts with a control character (not a URI)");
    if (assimp_reads_as_data_uri(u) && std::min(u.find(','), u.size()) > kMaxDataUriHeader)
      throw Error(where(*uri), name + "a data URI whose header (before the first ',') is longer than " +
                                   std::to_string(kMaxDataUriHeader) + " bytes");
    if (!is_valid_data_uri(u)) throw Error(where(*uri), name + "a data URI whose base64 does not decode");
    // assimp 5.2 leaks the stream of an external buffer file shorter than
    // its byteLength when it throws (adversarial review): checked here.
    const auto length = (*buffers)[i].find("byteLength");
    if (u.substr(0, 5) != "data:" && length && length->is_number()) {
      const fs::path bin = fs::path(file).parent_path() / std::string(u);
      std::error_code ec;
      if (fs::is_regular_file(bin, ec)) {
        const auto size = fs::file_size(bin, ec);
        if (!ec && double(size) < length->as_number())
          throw Error(where(*length), "buffers[" + std::to_string(i) +
                                          "].byteLength: " + format_count(length->as_number()) + " bytes, but '" +
                                          std::string(u) + "' holds " + std::to_string(size));
      }
    }
  }
  const auto meshes = root.find("meshes");
  for (size_t m = 0; meshes && meshes->is_array() && m < meshes->size(); ++m) {
    const auto primitives = (*meshes)[m].find("primitives");
    for (size_t p = 0; primitives && primitives->is_array() && p < primitives->size(); ++p)
      check_gltf_primitive((*primitives)[p], accessors, where,
                           "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]");
  }
}

std::string reduced_gltf_file(const std::vector<unsigned char>& bytes, bool binary, const std::string& json_text) {
  std::string json = reduce_gltf_json(json_text);
  if (!binary) return json;
  while (json.size() % 4) json += ' ';  // chunks stay 4-byte aligned
  const uint64_t declared = read_binary_uint(bytes.data() + 8, 4, false);
  const uint64_t rest = 20 + read_binary_uint(bytes.data() + 12, 4, false);
  const std::string tail = rest < declared ? std::string(bytes.begin() + static_cast<ptrdiff_t>(rest),
                                                         bytes.begin() + static_cast<ptrdiff_t>(declared))
                                           : std::string();
  auto u32 = [](uint64_t v) {
    const char b[4] = {char(v & 0xff), char((v >> 8) & 0xff), char((v >> 16) & 0xff), char((v >> 24) & 0xff)};
    return std::string(b, 4);
  };
  return std::string(reinterpret_cast<const char*>(bytes.data()), 8) + u32(20 + json.size() + tail.size()) +
         u32(json.size()) + "JSON" + json + tail;
}

}  // namespace glint::mesh_io
