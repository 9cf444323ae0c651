// glTF files checked before assimp reads them: its glTF reader trusts the
// JSON, so glint's JSON reader checks it first (what it claims in memory,
// accessors within their views, sparse parts, data URIs), and assimp gets it
// reduced to what glint uses (no skins, animations, morph targets, cameras
// or embedded images).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "glint/io/json.h"

namespace glint::mesh_io {

// The glTF's JSON: all of a .gltf, or a .glb's first chunk, which must be JSON.
// Only glTF content goes to assimp: it would otherwise guess another format.
std::string gltf_json_text(const std::vector<unsigned char>& bytes, bool binary, const std::string& file);

// The JSON parsed (a .glb's JSON errors name the chunk, without a position).
json::Document parse_gltf_json(std::string text, bool binary, const std::string& file);

// What the glTF claims before assimp allocates for it: every accessor's data
// (assimp allocates count x element size even for an accessor without a
// buffer, e.g. a sparse one, so a 300-byte file can claim gigabytes), and the
// meshes' vertices and triangles times the nodes that instance each mesh.
void check_gltf_memory(const json::Document& doc, bool binary, size_t budget, const std::string& file);

// What the glTF specification requires and assimp 5.2 relies on without
// checking, for what reaches it (see reduce_gltf_json): it leaks on an
// accessor without a valid componentType or type (fuzz_mesh_glb) and on
// indices that are not scalar integers; for sparse accessors it dereferences
// null for a missing part and reads past the buffer for a count the buffer
// views cannot hold (fuzz_mesh_gltf).
void check_gltf_structure(const json::Document& doc, bool binary, const std::string& file);

// The file as assimp gets it: the reduced JSON, in a GLB with the file's
// other chunks (its binary buffer) when the file is one.
std::string reduced_gltf_file(const std::vector<unsigned char>& bytes, bool binary, const std::string& json_text);

}  // namespace glint::mesh_io
