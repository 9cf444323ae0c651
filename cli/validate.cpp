// glint validate: every error of a scene, one line each (docs/cli.md#validate).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "glint/error.h"
#include "glint/io/scene_loader.h"
#include "options.h"

namespace glint::cli {

namespace {

struct ValidateArgs {
  std::string scene_path;
  bool quiet = false;
};

// Exit 1 if there was any error.
int run_validate(const ValidateArgs& args) {
  const std::vector<Error> errors = validate_scene(args.scene_path);
  for (const Error& e : errors) print_error(e.what());
  if (errors.empty() && !args.quiet) std::printf("%s: valid\n", args.scene_path.c_str());
  return errors.empty() ? 0 : 1;
}

}  // namespace

Command add_validate_command(CLI::App& app) {
  auto args = std::make_shared<ValidateArgs>();
  CLI::App* validate = app.add_subcommand("validate", "check a scene file without rendering; list every error");
  validate->add_option("scene", args->scene_path, "scene file (JSON or NFF)")->required();
  validate->add_flag("-q,--quiet", args->quiet, "print nothing when the scene is valid");
  return {validate, [args] { return run_validate(*args); }};
}

}  // namespace glint::cli
