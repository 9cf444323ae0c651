// A read-only JSON document that remembers where every value and key came from
// (file, line, column), so scene errors can point at the offending text.
// nlohmann::json does the parsing (SAX); we only keep a compact flat tree.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "glint/error.h"

namespace glint::json {

enum class Kind : uint8_t { null, boolean, number, string, array, object };

// "null", "boolean", "number", "string", "array" or "object", for messages.
const char* kind_name(Kind kind);

// Documents nested deeper than this are rejected (a clean Error, not a stack
// overflow in whoever walks the tree recursively).
inline constexpr size_t kMaxDepth = 10000;

namespace detail {
struct DocumentData;
}

// A cheap, copyable handle to one value of a Document. It stays valid as long
// as the Document it came from (or the Document that one was moved into) lives.
// Accessors marked "precondition" must only be called on the right kind /
// with an index below size(); they assert in debug builds.
class Value {
 public:
  Kind kind() const;
  const char* kind_name() const { return json::kind_name(kind()); }
  bool is_null() const { return kind() == Kind::null; }
  bool is_bool() const { return kind() == Kind::boolean; }
  bool is_number() const { return kind() == Kind::number; }
  bool is_string() const { return kind() == Kind::string; }
  bool is_array() const { return kind() == Kind::array; }
  bool is_object() const { return kind() == Kind::object; }

  bool as_bool() const;                // precondition: is_bool()
  double as_number() const;            // precondition: is_number()
  std::string_view as_string() const;  // precondition: is_string(); unescaped UTF-8

  // A number whose value is integral with |value| < 2^53, so as_number() holds
  // it exactly and it converts to int64_t without loss: 640, 640.0 and 6.4e2
  // all qualify; 0.5 and 1e300 do not. (Like every number, decimal text is
  // first rounded to the nearest double.)
  bool is_integer() const;

  // Array items or object members; 0 for every other kind.
  size_t size() const;
  Value operator[](size_t i) const;             // precondition: is_array(), i < size()
  std::string_view key(size_t i) const;         // precondition: is_object(), i < size()
  Value member(size_t i) const;                 // precondition: is_object(), i < size()
  SourceLocation key_location(size_t i) const;  // where member i's key (its '"') is
  // The member named `key` (keys are unique: duplicates are a parse error), or
  // nullopt; also nullopt when this is not an object. Linear: objects are small.
  std::optional<Value> find(std::string_view key) const;

  // Where the value's first character is (the '"' of a string, the '-' of a
  // negative number). Lines and columns are 1-based; a column counts bytes
  // (not code points) from the start of the line; only '\n' ends a line, so
  // CRLF files count like LF files. A leading UTF-8 byte-order mark is not
  // counted: the first character after it is line 1, column 1.
  SourceLocation location() const;
  // Byte offset of the value's first character in the file (BOM included).
  size_t offset() const;

 private:
  friend class Document;
  Value(const detail::DocumentData* doc, uint32_t node) : doc_(doc), node_(node) {}

  const detail::DocumentData* doc_;
  uint32_t node_;
};

// A parsed file: owns every node and string. Move-only.
class Document {
 public:
  Document(Document&&) noexcept;
  Document& operator=(Document&&) noexcept;
  Document(const Document&) = delete;
  Document& operator=(const Document&) = delete;
  ~Document();

  Value root() const;
  const std::string& filename() const;
  // The location of a byte offset in the file, by the same rules as
  // Value::location() (offsets past the end clamp to the end of the file).
  SourceLocation location_at(size_t offset) const;
  // Number of nodes (values and keys) held: for tests and statistics.
  size_t node_count() const;

 private:
  friend Document parse(std::string text, std::string filename);
  explicit Document(std::unique_ptr<detail::DocumentData> data);

  std::unique_ptr<detail::DocumentData> data_;
};

// Parses `text` (strict RFC 8259 JSON, optionally behind a UTF-8 BOM) whose
// positions are reported against `filename`. Throws glint::Error, with the
// position of the problem, for: syntax errors (including NaN/Infinity,
// comments, trailing commas, trailing content, invalid UTF-8 in strings),
// numbers that overflow a double, duplicate keys, an empty file, nesting
// deeper than kMaxDepth, files of 4 GiB or more, and running out of memory.
Document parse(std::string text, std::string filename);

// Reads and parses the file at `path` (reported as `path`). Throws
// glint::Error("<path>: cannot open: <reason>") and the errors of parse().
Document parse_file(const std::string& path);

}  // namespace glint::json
