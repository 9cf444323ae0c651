// glint's own Wavefront OBJ text reader: the text -> arrays part of loading
// an OBJ (obj.cpp builds the RawMesh from them). It reads what tinyobjloader
// read before it (tests/test_obj_reader.cpp compares the two on every OBJ at
// hand) with the same checks and messages (obj_checks.h), but in parallel:
// the text is cut into chunks at line ends; a first pass counts each
// chunk's statements, a second parses each chunk on its own thread straight
// into the arrays at its place in file order, so the result does not depend
// on the number of threads, and an index that counts back ("f -3 -2 -1")
// is resolved against the vertices before it as it is read. usemtl and
// mtllib are replayed in file order afterwards.
#pragma once

#include <tiny_obj_loader.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "glint/io/mesh/common.h"  // run_parallel
#include "glint/io/mesh/mesh_builder.h"

namespace glint::mesh_io {

struct ObjData {
  std::vector<Vec3f> positions;  // v (x y z; w and vertex colors are not kept)
  std::vector<Vec3f> normals;    // vn
  std::vector<UVf> texcoords;    // vt (u v; w is not kept, a missing v is 0)
  // Faces with at least 3 corners, in file order: face f has the corners
  // face_start[f] .. face_start[f + 1] - 1.
  std::vector<uint32_t> face_start{0};
  // Per corner, 0-based: the vertex, and the texture coordinate and normal
  // (-1: none). corner_texcoord / corner_normal are empty when the file has
  // no vt / vn statement. The vertices are unsigned, as a mesh's indices are:
  // a file of triangles hands them over as they stand (obj.cpp).
  std::vector<uint32_t> corner_vertex;
  std::vector<int32_t> corner_texcoord, corner_normal;
  std::vector<int32_t> face_material;          // per face: index into materials, or -1
  std::vector<tinyobj::material_t> materials;  // from the mtllib libraries, as tinyobj::LoadMtl reads them
  std::vector<std::string> unknown_materials;  // usemtl names no library loaded before it has, in file order
  std::vector<BadVertexText> bad_vertex_text;  // "nan"/"inf" coordinates of v statements (read as 0)
  size_t small_faces = 0;                      // f statements with fewer than 3 corners (skipped)
  size_t non_faces = 0;  // lines and point indices of the shapes tinyobjloader kept (only "> 0" matters)

  size_t face_count() const { return face_start.size() - 1; }
};

struct ObjReadOptions {
  size_t chunks = 0;   // 0: about one per MiB of text, at most 8 per hardware thread
  size_t threads = 0;  // 0: std::thread::hardware_concurrency()
};

// Parses an OBJ's text (UTF-8, without a byte-order mark). `mtl` reads each
// mtllib library as tinyobj::LoadObj would call it (null: none read). Throws
// glint::Error at file:line:col on the first bad number or index, with the
// messages of find_obj_bad_statement.
ObjData read_obj(std::string_view text, const std::string& file, tinyobj::MaterialReader* mtl,
                 const ObjReadOptions& options = {});

// The chunk boundaries read_obj uses: `chunks` + 1 offsets from 0 to
// text.size(), each (but the ends) just after a '\n', so a "\r\n" is never
// split; empty chunks are possible.
std::vector<size_t> split_obj_chunks(std::string_view text, size_t chunks);

}  // namespace glint::mesh_io
