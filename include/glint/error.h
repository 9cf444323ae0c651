// glint::Error: the one exception type the library throws for bad input.
// It carries where the problem is (file, line, column) so the CLI can print
// `error: <file>:<line>:<col>: <what>`; the library itself never prints or exits.
#pragma once

#include <stdexcept>
#include <string>

namespace glint {

struct SourceLocation {
  std::string file;  // empty: no file applies (e.g. a command-line value)
  int line = 0;      // 1-based; 0: the whole file
  int column = 0;    // 1-based; 0: the whole line
};

class Error : public std::runtime_error {
 public:
  explicit Error(std::string message) : std::runtime_error(message), message_(std::move(message)) {}
  Error(SourceLocation location, std::string message)
      : std::runtime_error(format(location, message)), location_(std::move(location)), message_(std::move(message)) {}
  // A problem at a value of the scene document: message() is "path: what",
  // as the loader has always written it, and path() the path alone
  // ("materials.floor.shininess"), so a binding can name it without parsing.
  Error(SourceLocation location, std::string path, const std::string& what)
      : Error(std::move(location), path.empty() ? what : path + ": " + what) {
    path_ = std::move(path);
  }

  const SourceLocation& location() const { return location_; }
  // Where in the scene document the problem is; empty when none applies
  // (a file that is not JSON, a broken mesh file, an I/O error).
  const std::string& path() const { return path_; }
  // The problem alone, without the location prefix that what() carries.
  const std::string& message() const { return message_; }

  static std::string format(const SourceLocation& loc, const std::string& message) {
    std::string out;
    if (!loc.file.empty()) out += loc.file + ":";
    if (loc.line > 0) {
      out += std::to_string(loc.line) + ":";
      if (loc.column > 0) out += std::to_string(loc.column) + ":";
    }
    if (!out.empty()) out += " ";
    return out + message;
  }

 private:
  SourceLocation location_;
  std::string message_;
  std::string path_;
};

}  // namespace glint
