// The function tables the plugins export (plugin.h): one per plugin, filled
// by *_plugin.cpp with the real functions and called by *_proxy.cpp.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/io/mesh/assimp_import.h"
#include "glint/program/plugin.h"
#include "glint/render/distributed_job.h"
#include "glint/serve/serve.h"

namespace glint::plugin {

struct EmbreeApi {
  Header header;
  decltype(&build_embree_accelerator) build;
};

struct AssimpApi {
  Header header;
  decltype(&mesh_io::load_ply) load_ply;
  decltype(&mesh_io::load_gltf) load_gltf;
};

struct MpiApi {
  Header header;
  void (*open_session)(int& rank, int& size);  // a mpi::Session for the process
  void (*close_session)();
  decltype(&mpi::abort_job) abort_job;
  decltype(&mpi::render_distributed) render_distributed;
};

struct ServeApi {
  Header header;
  decltype(&serve::run) run;
};

}  // namespace glint::plugin

// Each plugin's one exported symbol.
#define GLINT_PLUGIN_ENTRY extern "C" __attribute__((visibility("default")))
