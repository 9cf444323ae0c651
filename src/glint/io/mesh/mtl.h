// Wavefront MTL material libraries: tinyobjloader parses them; a scan of the
// text beside it finds what its material_t cannot say (which keys a block
// gave, one-number colors) and numbers it would misread, and map_mtl applies
// the contract's MTL table (Ka/Kd/Ks/Ns, illum 0..10) to glint::Material.
#pragma once

#include <tiny_obj_loader.h>

#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "glint/error.h"
#include "glint/scene/scene.h"

namespace glint::mesh_io {

// What tinyobjloader's material_t cannot tell: which keys a newmtl block gave,
// whether a color had one value (the MTL spec: g = b = r), and where.
struct MtlBlock {
  std::string name;
  int line = 0;
  std::set<std::string> keys;    // "Ka", "Kd", "Ks", "Tf", "Ns", "Ni", "d", "Tr", "illum"
  std::set<std::string> single;  // colors given as one number
  int illum_line = 0, ns_line = 0;
};

// Per-file findings while mapping materials, reported once each.
struct MtlReport {
  size_t ns_below_one = 0;
  int ns_line = 0;
  size_t illum_8_to_10 = 0;
  int illum_line = 0;
  size_t illum_unknown = 0;
  int illum_unknown_line = 0;
  std::vector<std::string> missing_textures;
};

// The contract's MTL table: Ka/Kd/Ks/Ns and illum 0..10 onto glint::Material.
Material map_mtl(const tinyobj::material_t& t, const MtlBlock& b, MtlReport& report);

// Reads each mtllib file next to the OBJ, remembers which were missing, and
// scans each one's text alongside tinyobj::LoadMtl.
class MtlReader : public tinyobj::MaterialReader {
 public:
  explicit MtlReader(std::filesystem::path folder) : folder_(std::move(folder)) {}
  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials, std::map<std::string, int>* map,
                  std::string* warn, std::string* err) override;

  struct Origin {
    std::filesystem::path mtl;
    MtlBlock block;
  };
  std::vector<Origin> origin;  // per material, as tinyobjloader numbers them
  std::vector<std::string> missing;
  std::optional<Error> error;  // the first bad number in a material library (thrown once LoadObj returns)

 private:
  std::filesystem::path folder_;
};

}  // namespace glint::mesh_io
