// Tests for glint::json: the tree, the source positions of values and keys,
// and every error class with its message and position.
#include "glint/io/json.h"

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace glint::json {
namespace {

// Line and column of a location, for compact expectations.
std::pair<int, int> lc(const SourceLocation& loc) { return {loc.line, loc.column}; }
using LC = std::pair<int, int>;

// Parses `text` expecting an Error; returns it (fails the test otherwise).
Error parse_error(const std::string& text) {
  try {
    parse(text, "t.json");
  } catch (const Error& e) {
    return e;
  } catch (...) {
    ADD_FAILURE() << "non-glint exception for: " << text;
    return Error("wrong exception");
  }
  ADD_FAILURE() << "no error for: " << text;
  return Error("no error");
}

#define EXPECT_JSON_ERROR(text, line, column, msg)                                                \
  do {                                                                                            \
    Error e_ = parse_error(text);                                                                 \
    EXPECT_EQ(e_.message(), msg) << "input: " << (text);                                          \
    EXPECT_EQ(lc(e_.location()), LC(line, column)) << "input: " << (text) << " -> " << e_.what(); \
    EXPECT_EQ(e_.location().file, "t.json");                                                      \
  } while (0)

// --- tree and lookups ----------------------------------------------------------

TEST(JsonTree, ScalarsAndKinds) {
  Document doc = parse(R"([null, true, false, 1.5, -2, "hi", [], {}])", "t.json");
  Value r = doc.root();
  ASSERT_TRUE(r.is_array());
  ASSERT_EQ(r.size(), 8u);
  EXPECT_TRUE(r[0].is_null());
  EXPECT_TRUE(r[1].is_bool());
  EXPECT_TRUE(r[1].as_bool());
  EXPECT_FALSE(r[2].as_bool());
  EXPECT_EQ(r[3].as_number(), 1.5);
  EXPECT_EQ(r[4].as_number(), -2.0);
  EXPECT_EQ(r[5].as_string(), "hi");
  EXPECT_TRUE(r[6].is_array());
  EXPECT_EQ(r[6].size(), 0u);
  EXPECT_TRUE(r[7].is_object());
  EXPECT_EQ(r[7].size(), 0u);
  EXPECT_EQ(r[5].size(), 0u);  // not a container
  const char* names[] = {"null", "boolean", "boolean", "number", "number", "string", "array", "object"};
  for (size_t i = 0; i < 8; ++i) EXPECT_STREQ(r[i].kind_name(), names[i]);
  EXPECT_STREQ(kind_name(Kind::object), "object");
  EXPECT_EQ(doc.filename(), "t.json");
}

TEST(JsonTree, ScalarRoot) {
  EXPECT_EQ(parse("42", "t.json").root().as_number(), 42.0);
  EXPECT_EQ(parse(" \"s\" ", "t.json").root().as_string(), "s");
  EXPECT_TRUE(parse("null", "t.json").root().is_null());
  EXPECT_TRUE(parse("true\n", "t.json").root().as_bool());
}

TEST(JsonTree, ObjectsKeepFileOrderAndFind) {
  Document doc = parse(R"({"b": 1, "a": {"x": [1, 2, {"deep": "yes"}]}, "c": null})", "t.json");
  Value r = doc.root();
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r.key(0), "b");
  EXPECT_EQ(r.key(1), "a");
  EXPECT_EQ(r.key(2), "c");
  EXPECT_EQ(r.member(0).as_number(), 1.0);
  EXPECT_TRUE(r.member(2).is_null());
  auto a = r.find("a");
  ASSERT_TRUE(a);
  auto x = a->find("x");
  ASSERT_TRUE(x && x->is_array());
  ASSERT_EQ(x->size(), 3u);
  EXPECT_EQ((*x)[1].as_number(), 2.0);
  EXPECT_EQ((*x)[2].find("deep")->as_string(), "yes");
  EXPECT_FALSE(r.find("missing"));
  EXPECT_FALSE(r.find("B"));
  EXPECT_FALSE(r.find(""));
  EXPECT_FALSE((*x)[0].find("b"));  // not an object
  EXPECT_FALSE(x->find("b"));
}

TEST(JsonTree, StringsAreUnescaped) {
  Document doc = parse(R"(["a\"b", "c\\", "\u00e9\n\t", "\ud83d\ude00", "", "caf\u00E9 ☕"])", "t.json");
  Value r = doc.root();
  EXPECT_EQ(r[0].as_string(), "a\"b");
  EXPECT_EQ(r[1].as_string(), "c\\");
  EXPECT_EQ(r[2].as_string(), "\xC3\xA9\n\t");
  EXPECT_EQ(r[3].as_string(), "\xF0\x9F\x98\x80");
  EXPECT_EQ(r[4].as_string(), "");
  EXPECT_EQ(r[5].as_string(), "caf\xC3\xA9 \xE2\x98\x95");
}

TEST(JsonTree, EmbeddedNulInStringViaEscape) {
  Document doc = parse(R"({"k\u0000": "a\u0000b"})", "t.json");
  EXPECT_EQ(doc.root().key(0), std::string_view("k\0", 2));
  EXPECT_EQ(doc.root().member(0).as_string(), std::string_view("a\0b", 3));
  EXPECT_TRUE(doc.root().find(std::string_view("k\0", 2)));
  EXPECT_FALSE(doc.root().find("k"));
}

TEST(JsonTree, Numbers) {
  Document doc = parse(
      "[640, 640.0, 6.4e2, 0.5, -3, 1e300, 18446744073709551615, -9223372036854775808,"
      " 9007199254740991, 9007199254740993, 1e-400, -0.0, 0, 1E+2]",
      "t.json");
  Value r = doc.root();
  EXPECT_TRUE(r[0].is_integer());
  EXPECT_TRUE(r[1].is_integer());
  EXPECT_TRUE(r[2].is_integer());
  EXPECT_EQ(r[2].as_number(), 640.0);
  EXPECT_FALSE(r[3].is_integer());
  EXPECT_TRUE(r[4].is_integer());
  EXPECT_EQ(r[4].as_number(), -3.0);
  EXPECT_FALSE(r[5].is_integer());  // integral but not exactly an int64
  EXPECT_EQ(r[6].as_number(), 18446744073709551615.0);
  EXPECT_FALSE(r[6].is_integer());
  EXPECT_EQ(r[7].as_number(), -9223372036854775808.0);
  EXPECT_TRUE(r[8].is_integer());     // 2^53 - 1
  EXPECT_FALSE(r[9].is_integer());    // 2^53 + 1 is not representable
  EXPECT_EQ(r[10].as_number(), 0.0);  // underflow is not an error
  EXPECT_TRUE(r[11].is_integer());
  EXPECT_TRUE(std::signbit(r[11].as_number()));
  EXPECT_TRUE(r[12].is_integer());
  EXPECT_EQ(r[13].as_number(), 100.0);
  EXPECT_FALSE(r[0].is_string());
  EXPECT_FALSE(parse("\"1\"", "t.json").root().is_integer());
}

TEST(JsonTree, ValuesSurviveDocumentMove) {
  Document doc = parse(R"({"a": [1, 2]})", "t.json");
  Value a = *doc.root().find("a");
  Document moved = std::move(doc);
  EXPECT_EQ(a[1].as_number(), 2.0);
  EXPECT_EQ(moved.root().member(0).size(), 2u);
}

TEST(JsonTree, LargeObjectDuplicateDetectionAndLookup) {
  std::string text = "{";
  for (int i = 0; i < 200; ++i) {
    if (i > 0) text += ',';
    text += "\"k" + std::to_string(i);
    text += "\":" + std::to_string(i);
  }
  Document doc = parse(text + "}", "t.json");
  EXPECT_EQ(doc.root().size(), 200u);
  EXPECT_EQ(doc.root().find("k137")->as_number(), 137.0);
  // The duplicate is found past the linear-scan limit too, at its position.
  Error e = parse_error(text + ",\n  \"k150\": 1}");
  EXPECT_EQ(e.message(), "duplicate key \"k150\"");
  EXPECT_EQ(lc(e.location()), LC(2, 3));
}

// --- positions -------------------------------------------------------------------

TEST(JsonPosition, ValuesAndKeysOnOneLine) {
  //                     1234567890123456789012345678901234567890
  Document doc = parse(R"({"a": 1, "bb": [true, null], "c": "x"})", "t.json");
  Value r = doc.root();
  EXPECT_EQ(lc(r.location()), LC(1, 1));
  EXPECT_EQ(r.location().file, "t.json");
  EXPECT_EQ(lc(r.key_location(0)), LC(1, 2));
  EXPECT_EQ(lc(r.member(0).location()), LC(1, 7));
  EXPECT_EQ(lc(r.key_location(1)), LC(1, 10));
  EXPECT_EQ(lc(r.member(1).location()), LC(1, 16));
  EXPECT_EQ(lc(r.member(1)[0].location()), LC(1, 17));
  EXPECT_EQ(lc(r.member(1)[1].location()), LC(1, 23));
  EXPECT_EQ(lc(r.key_location(2)), LC(1, 30));
  EXPECT_EQ(lc(r.member(2).location()), LC(1, 35));
  EXPECT_EQ(r.member(2).offset(), 34u);
}

TEST(JsonPosition, MultiLineWhitespace) {
  std::string text =
      "{\n"
      "  \"camera\":\n"
      "\n"
      "\t\t{ \"fov_y\"  :   45 ,\n"
      "      \"up\": [\n"
      "        0,\n"
      "           1,\n"
      "  0\n"
      "]}}";
  Document doc = parse(text, "t.json");
  Value cam = *doc.root().find("camera");
  EXPECT_EQ(lc(doc.root().key_location(0)), LC(2, 3));
  EXPECT_EQ(lc(cam.location()), LC(4, 3));
  EXPECT_EQ(lc(cam.key_location(0)), LC(4, 5));
  EXPECT_EQ(lc(cam.member(0).location()), LC(4, 18));
  EXPECT_EQ(lc(cam.key_location(1)), LC(5, 7));
  Value up = cam.member(1);
  EXPECT_EQ(lc(up.location()), LC(5, 13));
  EXPECT_EQ(lc(up[0].location()), LC(6, 9));
  EXPECT_EQ(lc(up[1].location()), LC(7, 12));
  EXPECT_EQ(lc(up[2].location()), LC(8, 3));
}

TEST(JsonPosition, StringsWithEscapedQuotesAndBackslashes) {
  // Each string ends somewhere tricky; the value after it must still be exact.
  std::string text = R"(["a\"b", 1, "\\", 2, "\\\"", 3, "x\\\\", 4, "\"", {"k\"\\": "\\\\\"", "z": 5}])";
  Document doc = parse(text, "t.json");
  Value r = doc.root();
  auto col = [&](Value v) { return v.location().column; };
  EXPECT_EQ(col(r[0]), static_cast<int>(text.find(R"("a\"b")") + 1));
  EXPECT_EQ(col(r[1]), static_cast<int>(text.find("1") + 1));
  EXPECT_EQ(col(r[2]), static_cast<int>(text.find(R"("\\")") + 1));
  EXPECT_EQ(col(r[3]), static_cast<int>(text.find("2") + 1));
  EXPECT_EQ(col(r[4]), static_cast<int>(text.find(R"("\\\"")") + 1));
  EXPECT_EQ(col(r[5]), static_cast<int>(text.find("3") + 1));
  EXPECT_EQ(col(r[6]), static_cast<int>(text.find(R"("x\\\\")") + 1));
  EXPECT_EQ(col(r[7]), static_cast<int>(text.find("4") + 1));
  EXPECT_EQ(col(r[8]), static_cast<int>(text.find(R"(, "\"")") + 3));
  Value obj = r[9];
  EXPECT_EQ(obj.key(0), "k\"\\");
  EXPECT_EQ(obj.key_location(0).column, static_cast<int>(text.find(R"("k\"\\")") + 1));
  EXPECT_EQ(obj.member(0).as_string(), "\\\\\"");
  EXPECT_EQ(col(obj.member(0)), static_cast<int>(text.find(R"("\\\\\"")") + 1));
  EXPECT_EQ(obj.key_location(1).column, static_cast<int>(text.find(R"("z")") + 1));
  EXPECT_EQ(col(obj.member(1)), static_cast<int>(text.find("5") + 1));
}

TEST(JsonPosition, NumbersFollowedByEveryKindOfDelimiter) {
  std::string text = "[1,22 ,-3.5e+2\n,4]";
  Document doc = parse(text, "t.json");
  Value r = doc.root();
  EXPECT_EQ(lc(r[0].location()), LC(1, 2));
  EXPECT_EQ(lc(r[1].location()), LC(1, 4));
  EXPECT_EQ(lc(r[2].location()), LC(1, 8));
  EXPECT_EQ(lc(r[3].location()), LC(2, 2));
  EXPECT_EQ(r[2].as_number(), -350.0);
  Document obj = parse(R"({"a":-1,"b":2})", "t.json");
  EXPECT_EQ(lc(obj.root().member(0).location()), LC(1, 6));
  EXPECT_EQ(lc(obj.root().key_location(1)), LC(1, 9));
  EXPECT_EQ(lc(obj.root().member(1).location()), LC(1, 13));
}

TEST(JsonPosition, NumberAtEndOfFile) {
  Document doc = parse("\n\n   -12.5e-1", "t.json");
  EXPECT_EQ(lc(doc.root().location()), LC(3, 4));
  EXPECT_EQ(doc.root().as_number(), -1.25);
  Document doc2 = parse("7", "t.json");
  EXPECT_EQ(lc(doc2.root().location()), LC(1, 1));
}

TEST(JsonPosition, CrLfLineEndings) {
  std::string text = "{\r\n  \"a\": 1,\r\n  \"b\": [\r\n    true\r\n  ]\r\n}\r\n";
  Document doc = parse(text, "t.json");
  Value r = doc.root();
  EXPECT_EQ(lc(r.key_location(0)), LC(2, 3));
  EXPECT_EQ(lc(r.member(0).location()), LC(2, 8));
  EXPECT_EQ(lc(r.key_location(1)), LC(3, 3));
  EXPECT_EQ(lc(r.member(1).location()), LC(3, 8));
  EXPECT_EQ(lc(r.member(1)[0].location()), LC(4, 5));
}

// Writes random JSON with hostile whitespace and strings, remembering the
// true offset of every value and key in the order a pre-order walk visits them.
class RandomJson {
 public:
  explicit RandomJson(unsigned seed) : rng_(seed) {}

  std::string text;
  std::vector<size_t> offsets;  // value, then for objects: key, value, key...

  void document() {
    space();
    value(0);
    space();
  }

 private:
  unsigned next(unsigned n) { return std::uniform_int_distribution<unsigned>(0, n - 1)(rng_); }
  void space() {
    static const char* pieces[] = {"", " ", "\n", "\r\n", "\t", "  \n\n ", "\r\n\t"};
    for (unsigned i = next(3); i > 0; --i) text += pieces[next(7)];
  }
  void string() {
    static const char* pieces[] = {"a",        "\\\"", "\\\\", "\\n",      "\\u00e9", "\\ud83d\\ude00",
                                   "\xC3\xA9", " ",    "\\/",  "x\\\\\\\""};
    text += '"';
    for (unsigned i = next(5); i > 0; --i) text += pieces[next(10)];
    text += '"';
  }
  void value(int depth) {
    offsets.push_back(text.size());
    unsigned kind = depth == 0 ? 4 + next(2) : depth > 4 ? next(4) : next(6);
    switch (kind) {
      case 0: {
        static const char* numbers[] = {
            "0", "-0", "12", "-3.25", "1e5", "2.5E-3", "-7e+2", "640.0", "123456789012345678901"};
        text += numbers[next(9)];
        break;
      }
      case 1: string(); break;
      case 2: text += next(2) ? "true" : "false"; break;
      case 3: text += "null"; break;
      case 4: {
        text += '[';
        unsigned n = next(6);
        for (unsigned i = 0; i < n; ++i) {
          space();
          value(depth + 1);
          space();
          if (i + 1 < n) text += ',';
        }
        space();
        text += ']';
        break;
      }
      default: {
        text += '{';
        unsigned n = next(6);
        for (unsigned i = 0; i < n; ++i) {
          space();
          offsets.push_back(text.size());
          text += "\"k" + std::to_string(i);  // unique keys, some with escapes
          if (next(2)) text += "\\\"\\\\";
          text += '"';
          space();
          text += ':';
          space();
          value(depth + 1);
          space();
          if (i + 1 < n) text += ',';
        }
        space();
        text += '}';
      }
    }
  }
  std::mt19937 rng_;
};

// The byte offset that a line/column names in `text` (columns count bytes).
size_t offset_of(const std::string& text, const SourceLocation& loc) {
  size_t line_start = 0;
  for (int l = 1; l < loc.line; ++l) line_start = text.find('\n', line_start) + 1;
  return line_start + static_cast<size_t>(loc.column) - 1;
}

TEST(JsonPosition, RandomDocumentsMatchGeneratorOffsets) {
  constexpr size_t kValue = std::string::npos;
  size_t checked = 0;
  for (unsigned seed = 1; seed <= 1000; ++seed) {
    RandomJson gen(seed);
    gen.document();
    Document doc = parse(gen.text, "r.json");
    // Walk in the generator's order: a value, then each member's key and value.
    std::vector<size_t> got;
    std::vector<std::pair<Value, size_t>> work{{doc.root(), kValue}};  // (object, member i) or (value, kValue)
    while (!work.empty()) {
      auto [v, member] = work.back();
      work.pop_back();
      if (member != kValue) {
        got.push_back(offset_of(gen.text, v.key_location(member)));
        work.push_back({v.member(member), kValue});
        continue;
      }
      got.push_back(v.offset());
      ASSERT_EQ(offset_of(gen.text, v.location()), v.offset()) << "seed " << seed;
      if (v.is_array()) {
        for (size_t i = v.size(); i-- > 0;) work.push_back({v[i], kValue});
      } else if (v.is_object()) {
        for (size_t i = v.size(); i-- > 0;) work.push_back({v, i});
      }
    }
    ASSERT_EQ(got, gen.offsets) << "seed " << seed << "\n" << gen.text;
    checked += got.size();
  }
  EXPECT_GT(checked, 10000u);  // the generator really produces non-trivial documents
}

TEST(JsonPosition, ColumnsCountBytes) {
  // "é" is two bytes, so the value after it is one column further right
  // than a character count would say.
  Document doc = parse("{\"\xC3\xA9\": 1}", "t.json");
  EXPECT_EQ(lc(doc.root().member(0).location()), LC(1, 8));
}

TEST(JsonPosition, ByteOrderMarkIsSkippedAndNotCounted) {
  Document doc = parse("\xEF\xBB\xBF{\"a\": [1]}", "t.json");
  Value r = doc.root();
  EXPECT_EQ(lc(r.location()), LC(1, 1));
  EXPECT_EQ(lc(r.key_location(0)), LC(1, 2));
  EXPECT_EQ(lc(r.member(0)[0].location()), LC(1, 8));
  EXPECT_EQ(r.offset(), 3u);  // offsets do count it
  EXPECT_EQ(lc(doc.location_at(0)), LC(1, 1));
  Document doc2 = parse("\xEF\xBB\xBF\n 5", "t.json");
  EXPECT_EQ(lc(doc2.root().location()), LC(2, 2));
}

TEST(JsonPosition, LocationAt) {
  Document doc = parse("[1,\n 2]\n", "t.json");
  EXPECT_EQ(lc(doc.location_at(0)), LC(1, 1));
  EXPECT_EQ(lc(doc.location_at(3)), LC(1, 4));  // the '\n' ends line 1
  EXPECT_EQ(lc(doc.location_at(4)), LC(2, 1));
  EXPECT_EQ(lc(doc.location_at(8)), LC(3, 1));     // end of file
  EXPECT_EQ(lc(doc.location_at(1000)), LC(3, 1));  // clamped
}

// --- errors ----------------------------------------------------------------------

TEST(JsonErrors, EmptyFile) {
  EXPECT_JSON_ERROR("", 1, 1, "empty file: expected a JSON value");
  EXPECT_JSON_ERROR(" \n\t\r\n  ", 1, 1, "empty file: expected a JSON value");
  EXPECT_JSON_ERROR("\xEF\xBB\xBF", 1, 1, "empty file: expected a JSON value");
  EXPECT_JSON_ERROR("\xEF\xBB\xBF\n ", 1, 1, "empty file: expected a JSON value");
}

TEST(JsonErrors, UnexpectedTokens) {
  EXPECT_JSON_ERROR(R"({"a": })", 1, 7, "syntax error: unexpected '}'; expected value");
  EXPECT_JSON_ERROR("[1,,2]", 1, 4, "syntax error: unexpected ','; expected value");
  EXPECT_JSON_ERROR("[1,]", 1, 4, "syntax error: unexpected ']'; expected value");
  EXPECT_JSON_ERROR(R"({"a":1,})", 1, 8, "syntax error: unexpected '}'; expected string key");
  EXPECT_JSON_ERROR("{1:2}", 1, 2, "syntax error: unexpected number; expected string key");
  EXPECT_JSON_ERROR(R"({"a" "b"})", 1, 6, "syntax error: unexpected string; expected ':'");
  EXPECT_JSON_ERROR("{\"a\":1\n  \"b\":2}", 2, 3, "syntax error: unexpected string; expected ',' or '}'");
  EXPECT_JSON_ERROR("[1 true]", 1, 4, "syntax error: unexpected 'true'; expected ',' or ']'");
  EXPECT_JSON_ERROR("[1 false]", 1, 4, "syntax error: unexpected 'false'; expected ',' or ']'");
  EXPECT_JSON_ERROR("[1 null]", 1, 4, "syntax error: unexpected 'null'; expected ',' or ']'");
  EXPECT_JSON_ERROR("[1 -25]", 1, 4, "syntax error: unexpected number; expected ',' or ']'");
  EXPECT_JSON_ERROR(R"([1 "a\"b"])", 1, 4, "syntax error: unexpected string; expected ',' or ']'");
  EXPECT_JSON_ERROR("{\"a\":[1 \"s\"]}", 1, 9, "syntax error: unexpected string; expected ',' or ']'");
  EXPECT_JSON_ERROR("]", 1, 1, "syntax error: unexpected ']'; expected value");
}

TEST(JsonErrors, UnexpectedEndOfInput) {
  EXPECT_JSON_ERROR("[1,", 1, 4, "syntax error: unexpected end of input; expected value");
  EXPECT_JSON_ERROR("{\"a\": [1, 2]\n", 2, 1, "syntax error: unexpected end of input; expected ',' or '}'");
  EXPECT_JSON_ERROR("{", 1, 2, "syntax error: unexpected end of input; expected string key");
  EXPECT_JSON_ERROR("[\"abc", 1, 6, "syntax error: invalid string: missing closing quote");
}

TEST(JsonErrors, TrailingContent) {
  EXPECT_JSON_ERROR("[1] [2]", 1, 5, "syntax error: unexpected '['; expected end of input");
  EXPECT_JSON_ERROR("{}\n}", 2, 1, "syntax error: unexpected '}'; expected end of input");
  EXPECT_JSON_ERROR("01", 1, 2, "syntax error: unexpected number; expected end of input");
  EXPECT_JSON_ERROR("[1]x", 1, 4, "syntax error: invalid literal 'x'");
  EXPECT_JSON_ERROR("1 2", 1, 3, "syntax error: unexpected number; expected end of input");
  EXPECT_JSON_ERROR("\"a\" \"b\"", 1, 5, "syntax error: unexpected string; expected end of input");
}

TEST(JsonErrors, NulBytes) {
  // nlohmann's lexer reads NUL as end of input; we must not stop there.
  EXPECT_JSON_ERROR(std::string("[1]\0[", 5), 1, 4, "syntax error: unexpected NUL byte; expected end of input");
  EXPECT_JSON_ERROR(std::string("[1]\n \0", 6), 2, 2, "syntax error: unexpected NUL byte; expected end of input");
  EXPECT_JSON_ERROR(std::string("[1,\0]", 5), 1, 4, "syntax error: unexpected NUL byte; expected value");
  EXPECT_JSON_ERROR(std::string("\0", 1), 1, 1, "syntax error: unexpected NUL byte; expected value");
  EXPECT_JSON_ERROR(std::string("[\"a\0\"]", 6), 1, 4,
                    "syntax error: invalid string: control character U+0000 (NUL) must be escaped to \\u0000");
}

TEST(JsonErrors, InvalidLiterals) {
  EXPECT_JSON_ERROR("NaN", 1, 1, "syntax error: invalid literal 'NaN'");
  EXPECT_JSON_ERROR("[1, Infinity]", 1, 5, "syntax error: invalid literal 'Infinity'");
  EXPECT_JSON_ERROR("[-Infinity]", 1, 3, "syntax error: invalid number; expected digit after '-'");
  EXPECT_JSON_ERROR("{\"a\": tru}", 1, 7, "syntax error: invalid literal 'tru'");
  EXPECT_JSON_ERROR("{\"a\": True}", 1, 7, "syntax error: invalid literal 'True'");
  EXPECT_JSON_ERROR("[nul", 1, 2, "syntax error: invalid literal 'nul'");
  EXPECT_JSON_ERROR("[1x]", 1, 2, "syntax error: invalid literal '1x'");
  EXPECT_JSON_ERROR("{'a': 1}", 1, 2, "syntax error: unexpected character '''");
  EXPECT_JSON_ERROR("[1, @]", 1, 5, "syntax error: unexpected character '@'");
  EXPECT_JSON_ERROR(
      "[\xE2\x80\x9C"
      "a\xE2\x80\x9D]",
      1, 2, "syntax error: unexpected byte 0xE2");
  EXPECT_JSON_ERROR("[1] // comment", 1, 5, "syntax error: unexpected character '/'");
}

TEST(JsonErrors, InvalidNumbers) {
  EXPECT_JSON_ERROR("[1.e5]", 1, 4, "syntax error: invalid number; expected digit after '.'");
  EXPECT_JSON_ERROR("[+1]", 1, 2, "syntax error: unexpected character '+'");
  EXPECT_JSON_ERROR("[.5]", 1, 2, "syntax error: unexpected character '.'");
  EXPECT_JSON_ERROR("\n[1e]", 2, 4, "syntax error: invalid number; expected '+', '-', or digit after exponent");
}

TEST(JsonErrors, InvalidStrings) {
  EXPECT_JSON_ERROR("\"ab\ncd\"", 1, 4,
                    "syntax error: invalid string: control character U+000A (LF) must be escaped to \\u000A or \\n");
  EXPECT_JSON_ERROR(R"(["a\qb"])", 1, 5, "syntax error: invalid string: forbidden character after backslash");
  EXPECT_JSON_ERROR(R"(["\u12G4"])", 1, 7,  // at the bad hex digit
                    "syntax error: invalid string: '\\u' must be followed by 4 hex digits");
  EXPECT_JSON_ERROR(R"(["\udc00"])", 1, 8,
                    "syntax error: invalid string: surrogate U+DC00..U+DFFF must follow U+D800..U+DBFF");
}

TEST(JsonErrors, InvalidUtf8) {
  EXPECT_JSON_ERROR("[\"\xFF\"]", 1, 3, "syntax error: invalid string: ill-formed UTF-8 byte");
  EXPECT_JSON_ERROR("{\"ok\": \"caf\xC3\"}", 1, 13, "syntax error: invalid string: ill-formed UTF-8 byte");
  EXPECT_JSON_ERROR("[\"\xC0\xAF\"]", 1, 3, "syntax error: invalid string: ill-formed UTF-8 byte");      // overlong
  EXPECT_JSON_ERROR("[\"\xED\xA0\x80\"]", 1, 4, "syntax error: invalid string: ill-formed UTF-8 byte");  // surrogate
}

TEST(JsonErrors, BrokenByteOrderMark) {
  EXPECT_JSON_ERROR("\xEF\xBB{}", 1, 1, "syntax error: invalid byte-order mark");
}

TEST(JsonErrors, NumberOutOfRange) {
  EXPECT_JSON_ERROR("1e999", 1, 1, "number out of range: 1e999");
  EXPECT_JSON_ERROR("[0, -1e999]", 1, 5, "number out of range: -1e999");
  EXPECT_JSON_ERROR("{\"r\":\n  -1.5E+400 }", 2, 3, "number out of range: -1.5E+400");
  std::string big = "1" + std::string(400, '0');
  // Quoted up to 40 bytes: a million digits made a one-megabyte error line.
  EXPECT_JSON_ERROR("[" + big + "]", 1, 2, "number out of range: " + big.substr(0, 40) + "...");
  const std::string huge = "8" + std::string(1000000, '0');
  EXPECT_JSON_ERROR("{\"width\": " + huge + "}", 1, 11, "number out of range: " + huge.substr(0, 40) + "...");
  EXPECT_JSON_ERROR("[" + big.substr(0, 40) + "e999]", 1, 2, "number out of range: " + big.substr(0, 40) + "...");
}

TEST(JsonErrors, DuplicateKeys) {
  EXPECT_JSON_ERROR("{\"radius\": 1,\n \"radius\": 2}", 2, 2, "duplicate key \"radius\"");
  EXPECT_JSON_ERROR(R"({"a": {"x": 1, "y": 2, "x": 3}})", 1, 24, "duplicate key \"x\"");
  // Equal after unescaping is equal.
  EXPECT_JSON_ERROR(R"({"ab": 1, "a\u0062": 2})", 1, 11, "duplicate key \"ab\"");
  EXPECT_JSON_ERROR(R"({"q\"": 1, "q\"": 2})", 1, 12, "duplicate key \"q\\\"\"");
  // Same key in different objects is fine.
  EXPECT_NO_THROW(parse(R"([{"a": 1}, {"a": 2, "b": {"a": 3}}])", "t.json"));
}

TEST(JsonErrors, DeepNesting) {
  // Within the limit: parses, without recursion.
  std::string ok = std::string(kMaxDepth, '[') + std::string(kMaxDepth, ']');
  Document doc = parse(ok, "t.json");
  Value v = doc.root();
  for (size_t i = 1; i < kMaxDepth; ++i) v = v[0];
  EXPECT_EQ(v.size(), 0u);
  // Past it, and far past it: a clean error at the first bracket too deep.
  std::string deep = std::string(100000, '[');
  Error e = parse_error(deep);
  EXPECT_EQ(e.message(), "nesting too deep: more than 10000 levels of arrays and objects");
  EXPECT_EQ(lc(e.location()), LC(1, 10001));
  Error e2 = parse_error(std::string(50000, '[') + std::string(50000, ']'));
  EXPECT_EQ(lc(e2.location()), LC(1, 10001));
  std::string objects;
  for (int i = 0; i < 20000; ++i) objects += "{\"a\":";
  EXPECT_EQ(lc(parse_error(objects).location()), LC(1, 5 * 10000 + 1));
}

TEST(JsonErrors, MessageIsOneLine) {
  const char* inputs[] = {"{\"a\": }", "[1,", "NaN", "\"ab\ncd\"", "[\"\xFF\"]", "{\"\\u0001\":1,\"\\u0001\":2}"};
  for (const char* text : inputs) {
    Error e = parse_error(text);
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("json.exception"), std::string::npos) << e.what();
  }
  EXPECT_EQ(parse_error("{\"\\u0001\":1,\"\\u0001\":2}").message(), "duplicate key \"\\u0001\"");
}

TEST(JsonErrors, WhatCarriesFileLineColumn) {
  Error e = parse_error("{\n  \"a\": ]\n}");
  EXPECT_STREQ(e.what(), "t.json:2:8: syntax error: unexpected ']'; expected value");
}

// --- files -------------------------------------------------------------------------

TEST(JsonFile, ParsesFileAndReportsItsPath) {
  std::string path = ::testing::TempDir() + "glint_test_json_file.json";
  {
    std::ofstream out(path, std::ios::binary);
    out << "{\n  \"materials\": {\"gold\": {\"shininess\": -1}}\n}\n";
  }
  Document doc = parse_file(path);
  EXPECT_EQ(doc.filename(), path);
  Value s = *doc.root().find("materials")->find("gold")->find("shininess");
  SourceLocation loc = s.location();
  EXPECT_EQ(loc.file, path);
  EXPECT_EQ(lc(loc), LC(2, 39));
  std::remove(path.c_str());
}

TEST(JsonFile, MissingFile) {
  try {
    parse_file("/nonexistent/dir/scene.json");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/dir/scene.json: cannot open: No such file or directory");
    EXPECT_EQ(e.location().line, 0);
  }
}

TEST(JsonFile, DirectoryIsAnError) {
  try {
    parse_file(::testing::TempDir());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "cannot read: Is a directory");
  }
}

// /dev/zero was read until memory ran out (seconds, gigabytes); a FIFO
// nobody writes to blocked glint forever in open().
TEST(JsonFile, DevicesAreRefusedAndAFifoWithoutWriterDoesNotBlock) {
  try {
    parse_file("/dev/zero");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "not a regular file (nor a pipe)");
  }
  const std::string fifo = ::testing::TempDir() + "glint_test_json_fifo_" + std::to_string(::getpid());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    parse_file(fifo);  // read as empty: nobody writes
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.location().file, fifo);
  }
  std::remove(fifo.c_str());
}

}  // namespace
}  // namespace glint::json
