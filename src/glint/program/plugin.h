// The command-line program's optional parts that need big shared libraries
// -- Embree (--accel embree), assimp (PLY and glTF meshes), Open MPI (under
// mpirun) and cpp-httplib with OpenSSL (glint serve) -- are plugins, loaded
// when used: mapping and relocating those libraries (and OpenSSL's set-up)
// cost every start of the program about 20 ms, more than loading and
// rendering a small scene takes (docs/performance.md, "SPD scenes").
//
// The library, libglint, still links them as it always has. Only the
// program is built from *_proxy.cpp here, which define the same functions as
// the real ones (so the archive's objects that would pull the libraries in
// are never linked, and --as-needed drops the libraries) and forward each
// call to the plugin, glint-NAME.so, built from *_plugin.cpp and the real
// code (cmake/GlintProgram.cmake).
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>

#include "glint/error.h"

namespace glint::plugin {

// glint-NAME.so beside the program (the build tree), or in the install
// tree's lib/glint relative to the program's bin; empty when neither exists.
std::filesystem::path find(const std::string& name);

// The plugin's entry point `symbol`, the plugin loaded on first use; with
// `global`, its symbols (and its libraries') are visible to libraries loaded
// later (Open MPI loads its components that way and they look for its
// symbols there). Throws glint::Error naming the plugin when it is missing
// or cannot be loaded.
void* entry(const std::string& name, const char* symbol, bool global = false);

// Every plugin's entry point returns a table of functions that starts with
// this header: a plugin from another build of glint is refused.
struct Header {
  uint32_t size;        // of the whole table
  const char* version;  // GLINT_VERSION_STRING
};

// The table `symbol` of plugin `name`, checked against the program's.
template <class Api>
const Api& api(const std::string& name, const char* symbol, const char* version, bool global = false) {
  using Entry = const Api* (*)();
  const Api* table = reinterpret_cast<Entry>(entry(name, symbol, global))();
  if (!table || table->header.size != sizeof(Api) || std::strcmp(table->header.version, version) != 0)
    throw Error("the plugin " + find(name).string() + " is from another build of glint: reinstall glint");
  return *table;
}

}  // namespace glint::plugin
