// Builds a glint::json::Document from nlohmann::json's SAX events and turns
// nlohmann's errors into one-line glint::Errors with the right position.
// nlohmann does all validation; this file only locates tokens and stores them.
#include "glint/io/json.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <new>
#include <stdexcept>
#include <unordered_set>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/io/memory_limit.h"

using NJson = nlohmann::json;

namespace glint::json {

namespace detail {

// One value or object key. 16 bytes: a million-sphere scene has 12 million.
struct Node {
  union {
    double number;
    bool boolean;
    uint32_t span[2];  // string: pool offset, length; array/object: first
                       // index in DocumentData::children, item/member count
  };
  uint32_t offset;  // byte offset of the first character in the file
  Kind kind;
};
static_assert(sizeof(Node) == 16);

struct DocumentData {
  std::string filename;
  std::vector<Node> nodes;  // nodes[0] is the root
  // An array's items are children[first, first + n); an object's members are
  // the pairs (key node, value node) in children[first, first + 2n).
  std::vector<uint32_t> children;
  std::string pool;  // every string and key, back to back
  // Offset of each line's first byte, ascending; line 1 starts after the BOM.
  std::vector<uint32_t> line_starts;
  size_t size = 0;  // of the file, in bytes

  std::string_view string(const Node& n) const { return {pool.data() + n.span[0], n.span[1]}; }

  SourceLocation location(size_t offset) const {
    offset = std::clamp<size_t>(offset, line_starts.front(), size);
    auto next = std::upper_bound(line_starts.begin(), line_starts.end(), offset);
    size_t line = static_cast<size_t>(next - line_starts.begin());  // >= 1
    size_t column = offset - line_starts[line - 1] + 1;
    return SourceLocation{filename, static_cast<int>(line), static_cast<int>(column)};
  }
};

}  // namespace detail

namespace {

using detail::DocumentData;
using detail::Node;

// Objects with more members than this check duplicate keys with a hash set,
// so a hostile file with one huge object stays linear.
constexpr size_t kLinearKeyLimit = 16;

// Character classes by table: these run once per byte between tokens.
enum : uint8_t { kSpace = 1, kGap = 2, kNumber = 4 };
constexpr std::array<uint8_t, 256> kCharClass = [] {
  std::array<uint8_t, 256> t{};
  for (unsigned char c : {' ', '\t', '\n', '\r'}) t[c] = kSpace | kGap;
  // Between two tokens that produce SAX events there can only be whitespace
  // and the separators, which produce no events.
  t[','] = t[':'] = kGap;
  for (unsigned char c : {'-', '+', '.', 'e', 'E'}) t[c] = kNumber;
  for (unsigned char c = '0'; c <= '9'; ++c) t[c] = kNumber;
  return t;
}();
bool is_whitespace(char c) { return kCharClass[static_cast<unsigned char>(c)] & kSpace; }
bool is_gap(char c) { return kCharClass[static_cast<unsigned char>(c)] & kGap; }
bool is_number_char(char c) { return kCharClass[static_cast<unsigned char>(c)] & kNumber; }
bool is_alnum(char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }

// A key for a message: quoted, with quotes, backslashes and control
// characters escaped so the message stays one readable line.
std::string quote_key(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    unsigned char u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04X", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string describe_byte(unsigned char c) {
  char buf[32];
  if (c == 0) return "NUL byte";
  if (c > 0x20 && c < 0x7F) {
    std::snprintf(buf, sizeof buf, "character '%c'", c);
  } else {
    std::snprintf(buf, sizeof buf, "byte 0x%02X", c);
  }
  return buf;
}

bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

// nlohmann's token names, shortened for our messages.
std::string token_name(std::string_view name) {
  if (name == "string literal") return "string";
  if (name == "number literal") return "number";
  if (name == "true literal") return "'true'";
  if (name == "false literal") return "'false'";
  if (name == "null literal") return "'null'";
  return std::string(name);
}

struct KeyHash {
  const DocumentData* doc;
  size_t operator()(uint32_t node) const { return std::hash<std::string_view>{}(doc->string(doc->nodes[node])); }
};
struct KeyEqual {
  const DocumentData* doc;
  bool operator()(uint32_t a, uint32_t b) const { return doc->string(doc->nodes[a]) == doc->string(doc->nodes[b]); }
};
using KeySet = std::unordered_set<uint32_t, KeyHash, KeyEqual>;

// The SAX handler. nlohmann reports no positions with its events, so each
// token is located in the text: its first byte is the first one after the
// previous event's token that is not whitespace, ',' or ':' (the only tokens
// without events), and its end is found from its kind. This only relies on
// the text read so far being valid JSON, which it is whenever an event fires,
// and it is immune to the lexer's one-byte lookahead after numbers.
// Everything here is iterative: nesting depth costs heap, never stack.
class Builder {
 public:
  Builder(std::string_view text, size_t base, DocumentData& doc) : text_(text), base_(base), cursor_(base), doc_(doc) {}

  bool null() { return scalar(Kind::null, 4); }
  bool boolean(bool value) {
    uint32_t n = scalar_node(Kind::boolean, value ? 4 : 5);
    doc_.nodes[n].boolean = value;
    return true;
  }
  bool number_integer(NJson::number_integer_t value) { return number(static_cast<double>(value), 0); }
  bool number_unsigned(NJson::number_unsigned_t value) { return number(static_cast<double>(value), 0); }
  // `token` is the lexer's copy of the number's text (byte for byte), which
  // gives its length for free.
  bool number_float(NJson::number_float_t value, const NJson::string_t& token) { return number(value, token.size()); }
  bool binary(NJson::binary_t&) { return true; }  // never produced by the JSON text format

  bool string(NJson::string_t& value) {
    add_child(string_node(value));
    return true;
  }

  bool key(NJson::string_t& value) {
    size_t start = token_start();
    uint32_t k = string_node(value);
    Frame& frame = frames_.back();
    size_t count = (pending_.size() - frame.base) / 2;
    bool duplicate = false;
    if (count < kLinearKeyLimit) {
      for (size_t i = 0; i < count && !duplicate; ++i) {
        std::string_view other = doc_.string(doc_.nodes[pending_[frame.base + 2 * i]]);
        // Scene keys often share a length ("center", "radius"): test the
        // first byte before paying for a memcmp call.
        duplicate = other.size() == value.size() && (other.empty() || other[0] == value[0]) && other == value;
      }
    } else {
      if (!frame.keys) {
        frame.keys = std::make_unique<KeySet>(64, KeyHash{&doc_}, KeyEqual{&doc_});
        for (size_t i = 0; i < count; ++i) frame.keys->insert(pending_[frame.base + 2 * i]);
      }
      duplicate = !frame.keys->insert(k).second;
    }
    if (duplicate) fail(start, "duplicate key " + quote_key(value));
    pending_.push_back(k);
    return true;
  }

  bool start_object(std::size_t) { return open(Kind::object); }
  bool start_array(std::size_t) { return open(Kind::array); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool parse_error(std::size_t position, const std::string& last_token, const nlohmann::detail::exception& ex);

  // After a successful parse: nlohmann treats a NUL byte as the end of the
  // input, so make sure nothing but whitespace follows the root value.
  void finish() {
    while (cursor_ < text_.size() && is_whitespace(text_[cursor_])) ++cursor_;
    if (cursor_ < text_.size()) {
      fail(cursor_, "syntax error: unexpected " + describe_byte(static_cast<unsigned char>(text_[cursor_])) +
                        "; expected end of input");
    }
  }

 private:
  struct Frame {
    uint32_t node;                 // the open array or object
    size_t base;                   // its children start at pending_[base]
    std::unique_ptr<KeySet> keys;  // only for objects past kLinearKeyLimit
  };

  [[noreturn]] void fail(size_t offset, std::string message) const {
    throw Error(doc_.location(offset), std::move(message));
  }

  size_t token_start() {
    while (cursor_ < text_.size() && is_gap(text_[cursor_])) ++cursor_;
    return cursor_;
  }

  uint32_t new_node(Kind kind, size_t offset, uint32_t span0 = 0, uint32_t span1 = 0) {
    Node node;
    node.span[0] = span0;
    node.span[1] = span1;
    node.offset = static_cast<uint32_t>(offset);
    node.kind = kind;
    doc_.nodes.push_back(node);
    return static_cast<uint32_t>(doc_.nodes.size() - 1);
  }

  // The root is nodes[0] and nobody's child; everything else waits in
  // pending_ until its container closes.
  void add_child(uint32_t node) {
    if (!frames_.empty()) pending_.push_back(node);
  }

  uint32_t scalar_node(Kind kind, size_t length) {
    size_t start = token_start();
    cursor_ = start + length;
    uint32_t n = new_node(kind, start);
    add_child(n);
    return n;
  }
  bool scalar(Kind kind, size_t length) {
    scalar_node(kind, length);
    return true;
  }

  // `length`: the token's length if known, else 0 (then it is measured).
  bool number(double value, size_t length) {
    size_t start = token_start();
    size_t end = start + length;
    if (length == 0 || end > text_.size() || (end < text_.size() && is_number_char(text_[end]))) {
      end = start;
      while (end < text_.size() && is_number_char(text_[end])) ++end;
    }
    cursor_ = end;
    uint32_t n = new_node(Kind::number, start);
    doc_.nodes[n].number = value;
    add_child(n);
    return true;
  }

  // A string or key token: stores the unescaped value and moves past the
  // closing quote. nlohmann has validated the string, so the first '"' not
  // escaped by a backslash ends it. Escapes only shrink, so the raw text is
  // at least as long as `value`: the byte right after that length is inside
  // the string or its closing quote, and a '"' inside the string is always
  // written \", so a '"' there not preceded by '\\' must be the end. That
  // is every string without escapes, found without walking its bytes.
  uint32_t string_node(const std::string& value) {
    size_t start = token_start();
    size_t quote = start + 1 + value.size();
    if (!(quote < text_.size() && text_[quote] == '"' && text_[quote - 1] != '\\')) {
      quote = start + 1;
      while (quote < text_.size() && text_[quote] != '"') quote += text_[quote] == '\\' ? 2 : 1;
    }
    cursor_ = std::min(quote + 1, text_.size());
    uint32_t n =
        new_node(Kind::string, start, static_cast<uint32_t>(doc_.pool.size()), static_cast<uint32_t>(value.size()));
    doc_.pool += value;
    return n;
  }

  bool open(Kind kind) {
    size_t start = token_start();
    cursor_ = start + 1;
    if (frames_.size() >= kMaxDepth) {
      fail(start, "nesting too deep: more than " + std::to_string(kMaxDepth) + " levels of arrays and objects");
    }
    uint32_t n = new_node(kind, start);
    add_child(n);
    frames_.push_back(Frame{n, pending_.size(), nullptr});
    return true;
  }

  bool close() {
    cursor_ = token_start() + 1;
    Frame& frame = frames_.back();
    Node& node = doc_.nodes[frame.node];
    size_t count = pending_.size() - frame.base;
    node.span[0] = static_cast<uint32_t>(doc_.children.size());
    node.span[1] = static_cast<uint32_t>(node.kind == Kind::object ? count / 2 : count);
    doc_.children.insert(doc_.children.end(), pending_.begin() + static_cast<std::ptrdiff_t>(frame.base),
                         pending_.end());
    pending_.resize(frame.base);
    frames_.pop_back();
    return true;
  }

  std::string_view text_;
  size_t base_;    // where nlohmann's input starts (after a BOM)
  size_t cursor_;  // just past the last token that produced an event
  DocumentData& doc_;
  std::vector<uint32_t> pending_;
  std::vector<Frame> frames_;
};

// nlohmann's `position` counts the bytes its lexer has read (of the text after
// the BOM): exact for a complete token, since the lexer un-reads its
// lookahead, and one past the end at end of input. Its message looks like
// "[json.exception.parse_error.101] parse error at line 1, column 7: syntax
// error while parsing value - unexpected '}'; expected '[', '{', or a literal";
// we keep the gist and point at the token or the offending byte.
bool Builder::parse_error(std::size_t position, const std::string& last_token, const nlohmann::detail::exception& ex) {
  const size_t size = text_.size();
  const size_t end = std::min(base_ + position, size + 1);       // one past the last byte read
  const size_t last = std::clamp(end, base_ + 1, size + 1) - 1;  // the last byte read (or EOF)
  auto back = [&](size_t length) { return end >= base_ + length ? end - length : base_; };

  if (ex.id == 406) {  // out_of_range: a number that overflows a double
    // Quoted as far as 40 bytes: a million-digit literal makes no message.
    const std::string shown = last_token.size() > 40 ? last_token.substr(0, 40) + "..." : last_token;
    fail(back(last_token.size()), "number out of range: " + shown);
  }

  std::string_view what = ex.what();
  size_t at = what.find("syntax error ");
  if (at == std::string_view::npos) {
    size_t colon = what.find("] ");
    fail(last, std::string(colon == std::string_view::npos ? what : what.substr(colon + 2)));
  }
  std::string_view rest = what.substr(at + 13);
  std::string_view context;
  if (starts_with(rest, "while parsing ")) {
    size_t dash = rest.find(" - ");
    if (dash != std::string_view::npos) {
      context = rest.substr(14, dash - 14);
      rest = rest.substr(dash + 1);
    }
  }
  if (starts_with(rest, "- ")) rest.remove_prefix(2);

  if (starts_with(rest, "unexpected ")) {
    // The parser got a well-formed token it did not expect.
    rest.remove_prefix(11);
    size_t semi = rest.find("; expected ");
    std::string_view token = rest.substr(0, semi);
    std::string_view expected = semi == std::string_view::npos ? std::string_view() : rest.substr(semi + 11);
    size_t start = last;
    std::string name = token_name(token);
    if (token == "string literal" || token == "number literal") {
      start = back(last_token.size());  // the lexer's token text is exactly the token
    } else if (token == "true literal" || token == "null literal") {
      start = back(4);
    } else if (token == "false literal") {
      start = back(5);
    } else if (token == "end of input" && last < size) {
      name = "NUL byte";  // nlohmann's lexer stops at a NUL as at the end
    }
    std::string message = "syntax error: unexpected " + name;
    if (!expected.empty()) {
      std::string exp(expected);
      if (expected == "'[', '{', or a literal") {
        exp = "value";
      } else if (expected == "string literal") {
        exp = "string key";
      } else if (context == "array" && expected == "']'") {
        exp = "',' or ']'";
      } else if (context == "object" && expected == "'}'") {
        exp = "',' or '}'";
      }
      message += "; expected " + exp;
    }
    fail(start, std::move(message));
  }

  // The lexer rejected the input at its last byte read. Its "last read"
  // quote may span earlier tokens, so we drop it and quote what we mean.
  std::string_view lexer_message = rest.substr(0, rest.find("; last read: '"));
  if (starts_with(lexer_message, "invalid BOM")) fail(base_, "syntax error: invalid byte-order mark");
  if (lexer_message == "invalid literal") {
    // Quote the bad word (NaN, Infinity, tru, yes...) at its start, or the
    // single byte that cannot start any value.
    size_t a = last, b = last;
    while (a > base_ && is_alnum(text_[a - 1])) --a;
    while (b < size && is_alnum(text_[b])) ++b;
    if (b > a) {
      fail(a, "syntax error: invalid literal '" + std::string(text_.substr(a, std::min<size_t>(b - a, 40))) + "'");
    }
    if (last < size) {
      fail(last, "syntax error: unexpected " + describe_byte(static_cast<unsigned char>(text_[last])));
    }
  }
  fail(last, "syntax error: " + std::string(lexer_message));
}

std::vector<uint32_t> find_line_starts(std::string_view text, size_t base) {
  std::vector<uint32_t> starts{static_cast<uint32_t>(base)};
  const char* begin = text.data();
  const char* p = begin + base;
  const char* end = begin + text.size();
  while (const void* nl = std::memchr(p, '\n', static_cast<size_t>(end - p))) {
    p = static_cast<const char*>(nl) + 1;
    starts.push_back(static_cast<uint32_t>(p - begin));
  }
  return starts;
}

}  // namespace

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::null: return "null";
    case Kind::boolean: return "boolean";
    case Kind::number: return "number";
    case Kind::string: return "string";
    case Kind::array: return "array";
    case Kind::object: return "object";
  }
  return "unknown";
}

// --- Value -------------------------------------------------------------------

Kind Value::kind() const { return doc_->nodes[node_].kind; }

bool Value::as_bool() const {
  assert(is_bool());
  return doc_->nodes[node_].boolean;
}

double Value::as_number() const {
  assert(is_number());
  return doc_->nodes[node_].number;
}

std::string_view Value::as_string() const {
  assert(is_string());
  return doc_->string(doc_->nodes[node_]);
}

bool Value::is_integer() const {
  if (!is_number()) return false;
  double v = doc_->nodes[node_].number;
  return std::fabs(v) < 9007199254740992.0 && std::trunc(v) == v;  // 2^53
}

size_t Value::size() const {
  const Node& n = doc_->nodes[node_];
  return n.kind == Kind::array || n.kind == Kind::object ? n.span[1] : 0;
}

Value Value::operator[](size_t i) const {
  assert(is_array() && i < size());
  return Value(doc_, doc_->children[doc_->nodes[node_].span[0] + i]);
}

std::string_view Value::key(size_t i) const {
  assert(is_object() && i < size());
  return doc_->string(doc_->nodes[doc_->children[doc_->nodes[node_].span[0] + 2 * i]]);
}

Value Value::member(size_t i) const {
  assert(is_object() && i < size());
  return Value(doc_, doc_->children[doc_->nodes[node_].span[0] + 2 * i + 1]);
}

SourceLocation Value::key_location(size_t i) const {
  assert(is_object() && i < size());
  return doc_->location(doc_->nodes[doc_->children[doc_->nodes[node_].span[0] + 2 * i]].offset);
}

std::optional<Value> Value::find(std::string_view key) const {
  if (!is_object()) return std::nullopt;
  const uint32_t* members = doc_->children.data() + doc_->nodes[node_].span[0];
  for (size_t i = 0, n = size(); i < n; ++i) {
    if (doc_->string(doc_->nodes[members[2 * i]]) == key) return Value(doc_, members[2 * i + 1]);
  }
  return std::nullopt;
}

SourceLocation Value::location() const { return doc_->location(doc_->nodes[node_].offset); }

size_t Value::offset() const { return doc_->nodes[node_].offset; }

// --- Document ------------------------------------------------------------------

Document::Document(std::unique_ptr<detail::DocumentData> data) : data_(std::move(data)) {}
Document::Document(Document&&) noexcept = default;
Document& Document::operator=(Document&&) noexcept = default;
Document::~Document() = default;

Value Document::root() const { return Value(data_.get(), 0); }
const std::string& Document::filename() const { return data_->filename; }
SourceLocation Document::location_at(size_t offset) const { return data_->location(offset); }
size_t Document::node_count() const { return data_->nodes.size(); }

// --- parsing -------------------------------------------------------------------

Document parse(std::string text, std::string filename) {
  const std::string name = filename;  // for errors after `filename` has moved
  try {
    // Offsets are stored in 32 bits to keep nodes at 16 bytes.
    if (text.size() >= UINT32_MAX) {
      throw Error(SourceLocation{name, 0, 0}, "file too large for the JSON reader (4 GiB or more)");
    }
    auto data = std::make_unique<DocumentData>();
    data->filename = std::move(filename);
    data->size = text.size();
    const size_t base = starts_with(text, "\xEF\xBB\xBF") ? 3 : 0;
    data->line_starts = find_line_starts(text, base);

    size_t first = base;
    while (first < text.size() && is_whitespace(text[first])) ++first;
    if (first == text.size()) throw Error(data->location(base), "empty file: expected a JSON value");
    // nlohmann would silently skip a second BOM too, shifting every position.
    if (base != 0 && starts_with(std::string_view(text).substr(base), "\xEF\xBB\xBF")) {
      throw Error(data->location(base), "syntax error: unexpected byte-order mark (only one may start the file)");
    }

    // Capacity for scene-like files (a node and a child index per ~7 bytes,
    // strings ~1/3 of the bytes) with headroom, so the big arrays are rarely
    // copied while growing. Pages never touched cost no resident memory;
    // exact upper bounds (a node per 2 bytes) would reserve ~11x the file.
    data->nodes.reserve(text.size() / 5 + 16);
    data->children.reserve(text.size() / 5 + 16);
    data->pool.reserve(text.size() / 2 + 16);

    Builder builder(text, base, *data);
    const char* begin = text.data() + base;
    const char* end = text.data() + text.size();
    if (!NJson::sax_parse(begin, end, &builder)) {
      // parse_error() throws, so this is only reached if nlohmann stops early
      // for a reason it did not report.
      throw Error(data->location(base), "syntax error");
    }
    builder.finish();
    return Document(std::move(data));
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(SourceLocation{name, 0, 0}, "out of memory while reading JSON");
  } catch (const std::length_error&) {
    throw Error(SourceLocation{name, 0, 0}, "out of memory while reading JSON");
  } catch (const std::exception& e) {
    throw Error(SourceLocation{name, 0, 0}, std::string("cannot read JSON: ") + e.what());
  }
}

Document parse_file(const std::string& path) {
  std::string text;
  try {
    auto fail = [&](const std::string& what) -> void { throw Error(SourceLocation{path, 0, 0}, what); };
    if (path.empty()) fail("the scene file name is empty");  // else a nameless "cannot open"
    // O_NONBLOCK: opening a pipe (FIFO) that nobody writes to returns at once
    // (and reads as an empty file) instead of waiting forever. Cleared below.
    struct Fd {
      int fd;
      ~Fd() {
        if (fd >= 0) ::close(fd);
      }
    } file{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)};
    if (file.fd < 0) {
      int err = errno;  // before anything else can overwrite it
      fail(std::string("cannot open: ") + std::strerror(err));
    }
    struct stat info {};
    if (::fstat(file.fd, &info) != 0) fail(std::string("cannot read: ") + std::strerror(errno));
    if (S_ISDIR(info.st_mode)) fail(std::string("cannot read: ") + std::strerror(EISDIR));
    // A device (/dev/zero, /dev/urandom) can be endless: only files and pipes.
    if (!S_ISREG(info.st_mode) && !S_ISFIFO(info.st_mode)) fail("not a regular file (nor a pipe)");
    const int flags = ::fcntl(file.fd, F_GETFL);
    if (flags == -1 || ::fcntl(file.fd, F_SETFL, flags & ~O_NONBLOCK) == -1)
      fail(std::string("cannot read: ") + std::strerror(errno));
    // A pipe can be endless too: it may hold at most the memory budget.
    const size_t budget = default_memory_budget();
    if (S_ISREG(info.st_mode)) {
      const std::string excess = exceeds_budget(static_cast<double>(info.st_size), budget);
      if (!excess.empty()) fail("the file is " + format_bytes(static_cast<double>(info.st_size)) + ": that " + excess);
      // Read straight into a buffer of the file's size, then keep going in case it grew.
      text.reserve(static_cast<size_t>(info.st_size) + 1);
    }
    char chunk[1 << 16];
    for (;;) {
      const ssize_t n = ::read(file.fd, chunk, sizeof chunk);
      if (n < 0) {
        if (errno == EINTR) continue;
        fail(std::string("cannot read: ") + std::strerror(errno));
      }
      if (n == 0) break;
      text.append(chunk, static_cast<size_t>(n));
      if (text.size() > budget)
        fail("more than " + format_bytes(static_cast<double>(budget)) + " read: that " +
             exceeds_budget(static_cast<double>(text.size()), budget));
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception&) {  // bad_alloc, length_error
    throw Error(SourceLocation{path, 0, 0}, "out of memory while reading the file");
  }
  return parse(std::move(text), path);
}

}  // namespace glint::json
