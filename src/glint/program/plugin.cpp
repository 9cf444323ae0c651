#include "glint/program/plugin.h"

#include <dlfcn.h>

#include <map>
#include <mutex>
#include <system_error>

namespace glint::plugin {

namespace {

std::filesystem::path program_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) return exe.parent_path();
  // Without /proc: the object this code is in, which is the program.
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&program_dir), &info) && info.dli_fname) {
    const std::filesystem::path self = std::filesystem::weakly_canonical(info.dli_fname, ec);
    if (!ec) return self.parent_path();
  }
  return {};
}

std::filesystem::path file_name(const std::string& name) { return "glint-" + name + ".so"; }

}  // namespace

std::filesystem::path find(const std::string& name) {
  const std::filesystem::path dir = program_dir();
  if (dir.empty()) return {};
  std::error_code ec;
  for (const std::filesystem::path& candidate : {dir / file_name(name), dir / GLINT_PLUGIN_SUBDIR / file_name(name)})
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate.lexically_normal();
  return {};
}

void* entry(const std::string& name, const char* symbol, bool global) {
  static std::mutex mutex;
  static std::map<std::string, void*> loaded;  // never unloaded: their code may be running until exit
  const std::lock_guard<std::mutex> lock(mutex);
  void*& handle = loaded[name];
  if (!handle) {
    const std::filesystem::path path = find(name);
    if (path.empty())
      throw Error("the plugin " + file_name(name).string() + " is missing: it belongs beside the glint program (" +
                  program_dir().string() + ") or in " +
                  (program_dir() / GLINT_PLUGIN_SUBDIR).lexically_normal().string() + "; reinstall glint");
    handle = dlopen(path.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL));
    if (!handle) {
      const char* why = dlerror();
      throw Error("cannot load the plugin " + path.string() + ": " + (why ? why : "unknown error"));
    }
  }
  void* f = dlsym(handle, symbol);
  if (!f) throw Error("the plugin " + find(name).string() + " has no " + symbol + ": reinstall glint");
  return f;
}

}  // namespace glint::plugin
