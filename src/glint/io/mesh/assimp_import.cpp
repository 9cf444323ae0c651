#include "glint/io/mesh/assimp_import.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>

#include <algorithm>
#include <mutex>
#include <string_view>
#include <system_error>
#include <utility>

#include "glint/io/memory_limit.h"
#include "glint/io/mesh/common.h"
#include "glint/io/mesh/gltf_checks.h"
#include "glint/io/mesh/mesh_builder.h"
#include "glint/io/mesh/ply_checks.h"

namespace glint::mesh_io {
namespace fs = std::filesystem;
namespace {

constexpr size_t kMaxTriangles = size_t(1) << 28;  // after glTF instancing: ~14 GiB of MeshFile

Material map_assimp_material(const aiMaterial& a) {
  Material m;
  aiString name;
  if (a.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
  aiColor4D c;
  if (aiGetMaterialColor(&a, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS) m.diffuse = Color(c.r, c.g, c.b);
  return m;
}

// Mesh instances with their node transforms (glTF scenes place and reuse meshes).
struct Instance {
  unsigned mesh;
  aiMatrix4x4 transform;
};

// Every mesh the node tree places (or every mesh, without a tree), with the
// memory they take checked against the budget and reserved in `raw`.
std::vector<Instance> collect_instances(const aiScene& scene, const std::string& file, size_t budget, RawMesh& raw) {
  std::vector<Instance> instances;
  size_t triangles = 0;
  double vertices = 0;
  if (scene.mRootNode) {
    std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{{scene.mRootNode, scene.mRootNode->mTransformation}};
    size_t visits = 0;
    while (!stack.empty()) {
      auto [node, m] = stack.back();
      stack.pop_back();
      if (++visits > 1'000'000) fail(file, "scene graph too large (more than a million nodes)");
      for (unsigned i = 0; i < node->mNumMeshes; ++i) {
        const unsigned mi = node->mMeshes[i];
        if (mi >= scene.mNumMeshes || !scene.mMeshes[mi]) continue;
        triangles += scene.mMeshes[mi]->mNumFaces;
        vertices += scene.mMeshes[mi]->mNumVertices;
        if (triangles > kMaxTriangles) fail(file, "too many triangles after instancing");
        instances.push_back({mi, m});
      }
      for (unsigned i = 0; i < node->mNumChildren; ++i)
        if (node->mChildren[i]) stack.push_back({node->mChildren[i], m * node->mChildren[i]->mTransformation});
    }
  }
  if (instances.empty())
    for (unsigned i = 0; i < scene.mNumMeshes; ++i)
      if (scene.mMeshes[i]) {
        instances.push_back({i, aiMatrix4x4()});
        triangles += scene.mMeshes[i]->mNumFaces;
        vertices += scene.mMeshes[i]->mNumVertices;
      }
  // Every instance gets its own copy of the mesh: a few nodes can multiply a
  // small mesh beyond memory.
  const std::string excess =
      exceeds_budget(kBytesPerTriangle * static_cast<double>(triangles) + kBytesPerVertex * vertices, budget);
  if (!excess.empty()) fail(file, plural(triangles, "triangle", "triangles") + " after instancing: that " + excess);
  raw.indices.reserve(3 * triangles);  // exact for triangle meshes
  raw.normals.reserve(3 * triangles);
  raw.triangle_material.reserve(triangles);
  return instances;
}

// The scene's materials (with their base color textures when those are files
// beside the mesh); texture files that are missing get one warning per material.
void add_assimp_materials(const aiScene& scene, const std::string& file, const fs::path& folder, RawMesh& raw) {
  for (unsigned i = 0; i < scene.mNumMaterials; ++i) {
    const aiMaterial* a = scene.mMaterials[i];
    raw.materials.push_back(a ? map_assimp_material(*a) : Material{});
    if (!a) continue;
    std::vector<std::string> missing;
    for (aiTextureType type : {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR, aiTextureType_SPECULAR,
                               aiTextureType_NORMALS, aiTextureType_EMISSIVE}) {
      for (unsigned k = 0; k < a->GetTextureCount(type); ++k) {
        aiString tex;
        if (a->GetTexture(type, k, &tex) != AI_SUCCESS) continue;
        const std::string t = tex.C_Str();
        if (t.empty() || t[0] == '*' || t.rfind("data:", 0) == 0) continue;  // embedded
        std::error_code ec;
        if (!fs::exists(folder / t, ec) && std::find(missing.begin(), missing.end(), t) == missing.end())
          missing.push_back(t);
      }
    }
    if (!missing.empty())
      raw.warnings.push_back(file + ": " + plural(missing.size(), "texture file", "texture files") +
                             " not found (defaults used): " + name_list(missing));
    // The base color texture, when it is a file beside the mesh, becomes the diffuse texture.
    for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
      aiString tex;
      aiTextureMapMode mode[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
      if (a->GetTextureCount(type) == 0 || a->GetTexture(type, 0, &tex) != AI_SUCCESS) continue;
      const std::string t = tex.C_Str();
      std::error_code ec;
      if (t.empty() || t[0] == '*' || t.rfind("data:", 0) == 0 || !fs::is_regular_file(folder / t, ec)) break;
      a->Get(AI_MATKEY_MAPPINGMODE_U(type, 0), mode[0]);
      MeshTexture mt;
      mt.file = folder / t;
      mt.name = t;
      mt.named_by = file;
      // One wrap mode for both directions: u's (glTF samplers rarely differ).
      mt.wrap = mode[0] == aiTextureMapMode_Clamp    ? TextureWrap::clamp
                : mode[0] == aiTextureMapMode_Mirror ? TextureWrap::mirror
                                                     : TextureWrap::repeat;
      raw.materials.back().diffuse_texture = static_cast<uint32_t>(raw.textures.size());
      raw.textures.push_back(std::move(mt));
      break;
    }
  }
}

// Where each instance's vertices start in `raw`, for messages.
struct Range {
  size_t first;
  unsigned mesh;
};

// Every instance's vertices (transformed) and faces (triangulated) into `raw`.
std::vector<Range> add_instances(const aiScene& scene, const std::vector<Instance>& instances, const std::string& file,
                                 bool use_materials, bool is_ply, RawMesh& raw) {
  std::vector<Range> ranges;
  for (const Instance& inst : instances) {
    const aiMesh& mesh = *scene.mMeshes[inst.mesh];
    const size_t base = raw.positions.size();
    if (base + mesh.mNumVertices > UINT32_MAX) fail(file, "too many vertices (more than 2^32)");
    if (!mesh.mVertices && mesh.mNumVertices > 0) continue;
    ranges.push_back({base, inst.mesh});
    const bool identity = inst.transform.IsIdentity();
    aiMatrix3x3 normal_matrix(inst.transform);
    normal_matrix.Inverse().Transpose();
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      aiVector3D p = mesh.mVertices[v];
      if (!identity) p = inst.transform * p;
      raw.positions.push_back({p.x, p.y, p.z});
    }
    const bool normals = mesh.mNormals != nullptr;
    const aiVector3D* uvs = mesh.HasTextureCoords(0) ? mesh.mTextureCoords[0] : nullptr;
    const int32_t material =
        use_materials && mesh.mMaterialIndex < raw.materials.size() ? static_cast<int32_t>(mesh.mMaterialIndex) : -1;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices < 3) {
        ++(is_ply ? raw.small_faces : raw.non_faces);
        continue;
      }
      for (unsigned k = 0; k < face.mNumIndices; ++k)
        if (face.mIndices[k] >= mesh.mNumVertices)
          fail(file, "mesh " + std::to_string(inst.mesh) + ", face " + std::to_string(f) + ": vertex index " +
                         std::to_string(face.mIndices[k]) + " out of range (" +
                         plural(mesh.mNumVertices, "vertex", "vertices") + ")");
      triangulate(
          face.mNumIndices, [&](size_t k) { return raw.positions[base + face.mIndices[k]]; },
          [&](size_t a, size_t b, size_t c) {
            for (size_t k : {a, b, c}) {
              const unsigned v = face.mIndices[k];
              raw.indices.push_back(static_cast<uint32_t>(base + v));
              if (normals) {
                aiVector3D n = mesh.mNormals[v];
                if (!identity) n = normal_matrix * n;
                raw.normals.push_back({n.x, n.y, n.z});
              } else {
                raw.normals.push_back({});
              }
              raw.uvs.push_back(uvs ? UVf{uvs[v].x, uvs[v].y} : UVf{});
            }
            raw.triangle_material.push_back(material);
          });
      if (normals) raw.has_normals = true;
      if (uvs) raw.has_uvs = true;
    }
  }
  return ranges;
}

// PLY faces with fewer than 3 vertices are skipped with a warning; glTF
// point and line primitives are simply not surfaces.
void from_assimp(const aiScene& scene, const std::string& file, const fs::path& folder, bool is_ply, size_t budget,
                 RawMesh& raw) {
  const bool use_materials = !is_ply;
  const std::vector<Instance> instances = collect_instances(scene, file, budget, raw);
  if (use_materials) add_assimp_materials(scene, file, folder, raw);
  const std::vector<Range> ranges = add_instances(scene, instances, file, use_materials, is_ply, raw);
  if (!raw.has_normals) raw.normals.clear();
  if (!raw.has_uvs) raw.uvs.clear();
  raw.nonfinite_vertex_error = [file, ranges, &scene](uint32_t v) {
    auto it =
        std::upper_bound(ranges.begin(), ranges.end(), size_t(v), [](size_t x, const Range& r) { return x < r.first; });
    std::string where = "vertex " + std::to_string(v);
    if (it != ranges.begin()) {
      --it;
      const aiMesh* mesh = scene.mMeshes[it->mesh];
      where = "vertex " + std::to_string(v - it->first);
      if (scene.mNumMeshes > 1)
        where = "mesh " + std::to_string(it->mesh) + " ('" + std::string(mesh->mName.C_Str()) + "'), " + where;
    }
    return Error(SourceLocation{file, 0, 0}, where + " has a non-finite coordinate");
  };
}

// assimp reports some repairs only in its log (e.g. glTF faces with
// out-of-range indices are dropped): capture its warnings while it reads.
// Its logger is global, so assimp reads are serialized.
class AssimpLogCapture {
 public:
  AssimpLogCapture() : lock_(mutex()) {
    Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(new Stream(messages), Assimp::Logger::Warn | Assimp::Logger::Err);
  }
  ~AssimpLogCapture() { Assimp::DefaultLogger::kill(); }
  AssimpLogCapture(const AssimpLogCapture&) = delete;
  AssimpLogCapture& operator=(const AssimpLogCapture&) = delete;

  bool contains(std::string_view text) const {
    for (const std::string& m : messages)
      if (m.find(text) != std::string::npos) return true;
    return false;
  }
  std::vector<std::string> messages;

 private:
  struct Stream : Assimp::LogStream {
    explicit Stream(std::vector<std::string>& out) : out_(out) {}
    void write(const char* message) override {
      std::string m = message ? message : "";
      while (!m.empty() && (m.back() == '\n' || m.back() == ' ')) m.pop_back();
      out_.push_back(std::move(m));
    }
    std::vector<std::string>& out_;
  };
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
};

std::string assimp_error(const Assimp::Importer& importer) {
  std::string e = importer.GetErrorString();
  while (!e.empty() && (e.back() == '\n' || e.back() == ' ')) e.pop_back();
  return e.empty() ? "unknown error" : e;
}

// Serves the glTF file itself from memory (reduced) and every file it names
// (external buffers, images) from disk, relative to it as assimp resolves
// them; only regular files, since opening a FIFO a buffer names would block.
class ReducedGltfIO final : public Assimp::DefaultIOSystem {
 public:
  ReducedGltfIO(std::string path, std::string bytes) : path_(std::move(path)), bytes_(std::move(bytes)) {}
  bool Exists(const char* file) const override { return path_ == file || is_regular(file); }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (path_ == file)
      return new Assimp::MemoryIOStream(reinterpret_cast<const uint8_t*>(bytes_.data()), bytes_.size());
    return is_regular(file) ? DefaultIOSystem::Open(file, mode) : nullptr;
  }

 private:
  static bool is_regular(const char* file) {
    std::error_code ec;
    return fs::is_regular_file(file, ec);
  }
  std::string path_, bytes_;
};

}  // namespace

MeshFile load_ply(const std::string& file, std::vector<unsigned char> bytes, size_t budget, bool vertex_normals) {
  const std::string_view data(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  const PlyHeader header = read_ply_header(data, file);
  const PlyLayout layout = ply_layout(header, file);
  check_ply_memory(header, layout, budget, file);
  check_ply_counts(header, data.size() - header.body, file);
  RawMesh raw;
  if (header.unknown_lines > 0)
    raw.warnings.push_back(file + ":" + std::to_string(header.unknown_line) + ": ignored " +
                           plural(header.unknown_lines, "unknown PLY header line", "unknown PLY header lines"));
  if (header.format == PlyFormat::ascii) walk_ascii_ply(header, layout, data, file, raw.bad_vertex_text);
  else walk_binary_ply(header, layout, data, file);
  if (layout.face < 0 || header.elements[layout.face].count == 0) fail(file, "no triangles (vertices only)");

  AssimpLogCapture log;
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, "ply");
  if (!scene) fail(file, "cannot read PLY: " + assimp_error(importer));
  from_assimp(*scene, file, {}, /*is_ply=*/true, budget, raw);
  // assimp keeps the file's vertex order, so PLY vertex numbers are the file's.
  if (raw.positions.size() != header.elements[layout.vertex].count)
    raw.bad_vertex_text.clear();  // numbering differs: report by position instead
  if (header.format != PlyFormat::ascii) {
    raw.nonfinite_vertex_error = [file](uint32_t v) {
      return Error(SourceLocation{file, 0, 0}, "vertex " + std::to_string(v) + " has a non-finite coordinate");
    };
  }
  return finish(std::move(raw), file, vertex_normals);
}

MeshFile load_gltf(const fs::path& path, const std::string& file, const std::vector<unsigned char>& bytes, bool binary,
                   size_t budget, bool vertex_normals) {
  const std::string json_text = gltf_json_text(bytes, binary, file);
  {
    const json::Document doc = parse_gltf_json(json_text, binary, file);
    // Memory first: a claim of billions is the news, not the buffer it overruns.
    check_gltf_memory(doc, binary, budget, file);
    check_gltf_structure(doc, binary, file);
  }
  AssimpLogCapture log;
  Assimp::Importer importer;
  importer.SetIOHandler(new ReducedGltfIO(path.string(), reduced_gltf_file(bytes, binary, json_text)));
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  // assimp drops faces with out-of-range indices (with a log line), and then
  // may fail for a mesh left without faces: the cause is the better message.
  if (log.contains("out-of-range indices")) fail(file, "face with a vertex index out of range");
  if (!scene) fail(file, "cannot read glTF: " + assimp_error(importer));
  RawMesh raw;
  from_assimp(*scene, file, path.parent_path(), /*is_ply=*/false, budget, raw);
  // assimp adds a default material for primitives without one: not the file's.
  for (int32_t& m : raw.triangle_material)
    if (m >= 0 && raw.materials[m].name == AI_DEFAULT_MATERIAL_NAME) m = -1;
  for (Material& m : raw.materials)
    if (m.name == AI_DEFAULT_MATERIAL_NAME) m.name.clear();  // dropped when unused
  return finish(std::move(raw), file, vertex_normals);
}

}  // namespace glint::mesh_io
