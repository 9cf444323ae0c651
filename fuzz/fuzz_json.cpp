// libFuzzer target for the JSON reader alone (glint::json::parse). Besides
// "only glint::Error escapes", it checks what the rest of glint relies on:
// every value's position points at its first character, keys are unique and
// found by find(), error positions lie inside the file, and a document is only
// accepted when nlohmann::json also accepts the text.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/error.h"
#include "glint/io/json.h"

namespace {

[[noreturn]] void finding(const char* what, size_t offset) {
  std::fprintf(stderr, "fuzz_json: %s (offset %zu)\n", what, offset);
  std::abort();
}

void check(bool ok, const char* what, size_t offset = 0) {
  if (!ok) finding(what, offset);
}

// The line and column of `offset` counted the slow way (see json.h).
std::pair<int, int> expected_location(std::string_view text, size_t base, size_t offset) {
  int line = 1;
  size_t line_start = base;
  for (size_t i = base; i < offset && i < text.size(); ++i)
    if (text[i] == '\n') ++line, line_start = i + 1;
  return {line, static_cast<int>(offset - line_start) + 1};
}

void check_value(std::string_view text, size_t base, const glint::json::Document& doc, const glint::json::Value& v) {
  using glint::json::Kind;
  const size_t at = v.offset();
  check(at >= base && at < text.size(), "value offset outside the text", at);
  const char c = text[at];
  switch (v.kind()) {
    case Kind::null: check(text.substr(at, 4) == "null", "null not at 'null'", at); break;
    case Kind::boolean:
      check(text.substr(at, v.as_bool() ? 4 : 5) == (v.as_bool() ? "true" : "false"), "boolean misplaced", at);
      break;
    case Kind::number: check(c == '-' || (c >= '0' && c <= '9'), "number not at a digit or '-'", at); break;
    case Kind::string: check(c == '"', "string not at '\"'", at); break;
    case Kind::array: check(c == '[', "array not at '['", at); break;
    case Kind::object: check(c == '{', "object not at '{'", at); break;
  }
  const glint::SourceLocation loc = v.location();
  const auto [line, column] = expected_location(text, base, at);
  check(loc.line == line && loc.column == column, "wrong line/column", at);
  check(loc.file == doc.filename(), "wrong file name", at);
  if (v.is_string()) {
    // The stored value is no longer than its raw text (escapes only shrink).
    check(v.as_string().size() + 2 <= text.size() - at, "string longer than its text", at);
  }
}

void walk(std::string_view text, size_t base, const glint::json::Document& doc) {
  std::vector<glint::json::Value> stack{doc.root()};
  size_t visited = 0;
  while (!stack.empty()) {
    const glint::json::Value v = stack.back();
    stack.pop_back();
    ++visited;
    check_value(text, base, doc, v);
    if (v.is_array()) {
      for (size_t i = 0; i < v.size(); ++i) {
        check(v[i].offset() > v.offset(), "item before its array", v.offset());
        stack.push_back(v[i]);
      }
    } else if (v.is_object()) {
      for (size_t i = 0; i < v.size(); ++i) {
        const auto found = v.find(v.key(i));
        check(found && found->offset() == v.member(i).offset(), "find(key) is not the member (duplicate key?)",
              v.offset());
        const glint::SourceLocation kl = v.key_location(i);
        check(kl.line >= 1 && kl.column >= 1, "bad key location", v.offset());
        check(v.member(i).offset() > v.offset(), "member before its object", v.offset());
        stack.push_back(v.member(i));
      }
    } else {
      check(v.size() == 0, "scalar with a size", v.offset());
    }
  }
  check(visited <= doc.node_count(), "more values than nodes");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const size_t base = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  try {
    const glint::json::Document doc = glint::json::parse(text, "fuzz.json");
    // Accepted: it must be JSON by nlohmann's own (SAX-free) reading too.
    check(nlohmann::json::accept(text.begin() + static_cast<std::ptrdiff_t>(base), text.end()),
          "accepted text that nlohmann::json::accept rejects");
    walk(text, base, doc);
  } catch (const glint::Error& e) {
    const glint::SourceLocation& loc = e.location();
    check(loc.file == "fuzz.json", "error names the wrong file");
    if (loc.line > 0) {
      // An error position is a byte of the file or just past its end.
      const auto [last_line, last_column] = expected_location(text, base, text.size());
      check(loc.line < last_line || (loc.line == last_line && loc.column >= 1 && loc.column <= last_column),
            "error position outside the file");
      check(loc.column >= 1, "error column < 1");
    }
    check(!e.message().empty(), "empty error message");
  }
  return 0;
}
