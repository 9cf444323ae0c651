// PLY files checked against their own header before assimp reads them: its
// PLY reader crashes, aborts or hangs on truncated or inconsistent files, so
// counts are checked against the file size and the memory budget, and every
// record is walked (present, list lengths sane, indices in range) without
// storing anything.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "glint/io/mesh/mesh_builder.h"

namespace glint::mesh_io {

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

struct PlyProperty {
  std::string name;
  bool list = false;
  PlyType type = PlyType::f32;       // scalar, or list items
  PlyType count_type = PlyType::u8;  // list
};
struct PlyElement {
  std::string name;
  uint64_t count = 0;
  int line = 0;
  std::vector<PlyProperty> properties;
};
enum class PlyFormat { ascii, binary_le, binary_be };
struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  size_t body = 0;    // byte offset of the data
  int body_line = 0;  // line number of the data's first line
  size_t unknown_lines = 0;
  int unknown_line = 0;  // the first
};

// The header, or glint::Error at the line that breaks it.
PlyHeader read_ply_header(std::string_view data, const std::string& file);

// Which element is the vertex list and which list property holds face indices.
struct PlyLayout {
  int vertex = -1, face = -1, face_list = -1;
  int xyz[3] = {-1, -1, -1};  // property numbers in the vertex element
};

// The layout, or glint::Error when there is no vertex element with x, y, z.
PlyLayout ply_layout(const PlyHeader& h, const std::string& file);

// Absurd counts: every record takes at least some bytes, so a count larger
// than the data allows is refused before anything is allocated for it.
void check_ply_counts(const PlyHeader& h, size_t data_bytes, const std::string& file);

// What the header's counts would take in memory once read (at least one
// triangle per face), refused before assimp allocates anything for them.
void check_ply_memory(const PlyHeader& h, const PlyLayout& l, size_t budget, const std::string& file);

// Walks the binary data record by record: every record present, list counts
// sane, face indices in range. Nothing is stored.
void walk_binary_ply(const PlyHeader& h, const PlyLayout& l, std::string_view data, const std::string& file);

// Walks the ASCII data: one record per line (blank lines skipped, as assimp
// does), every value a number of its type, face indices in range. Records
// non-finite x/y/z text with its line for the back end.
void walk_ascii_ply(const PlyHeader& h, const PlyLayout& l, std::string_view data, const std::string& file,
                    std::vector<BadVertexText>& bad);

}  // namespace glint::mesh_io
