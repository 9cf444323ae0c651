// Checks of an OBJ's text that tinyobjloader does not make: it reads what is
// not a number as 0 and indices with atoi, and keeps a face's vertex count
// in 8 bits. Each is one pass over the text; find_obj_statement and
// scan_obj_face_sizes run only when something needs explaining.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "glint/io/mesh/mesh_builder.h"
#include "glint/io/mesh/text_scan.h"

namespace glint::mesh_io {

// [+-]digits[.digits][(e|E)[+-]digits] with a digit before or after the
// point: what parse_number reads, without converting (most of the cost).
bool is_decimal_number(std::string_view s);

// The 1-based line of the n-th (0-based) statement with this keyword.
int find_obj_statement(std::string_view text, std::string_view keyword, size_t ordinal);

// Literal "nan"/"inf" coordinates on 'v' lines (tinyobjloader reads them as 0).
std::vector<BadVertexText> scan_obj_nonfinite_text(std::string_view text);

// The first statement whose numbers tinyobjloader would read wrongly or not
// at all: line, column and message. tinyobjloader reads a coordinate that is
// not a number ("v a b c", "v 1" without y and z) as 0, and an index with
// atoi, so "1.5" is 1 and "99999999999999999999" wraps to -1, a valid index
// counted back from the end. Checked here, in one pass over the text, before
// it parses: every v/vn has 3 numbers and every vt 1 (the rest of a line is
// not read); every index of a face, line or point is a whole number that
// names an existing vertex, texture coordinate or normal (negative ones count
// back from the current end). "nan" and "inf" are numbers here: a vertex
// holding one is an error only if a triangle uses it.
TextProblem find_obj_bad_statement(std::string_view text);

// The vertex count of every face with at least 3, in file order (what
// tinyobjloader keeps, before its 8-bit count wraps above 255).
std::vector<size_t> scan_obj_face_sizes(std::string_view text);

}  // namespace glint::mesh_io
