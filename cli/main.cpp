// glint: the command line. main() registers the commands (one file each in
// cli/: render, explain, validate, info, convert, serve), parses, and runs the
// one given; the work itself is the library's. All errors end as one
// `error:` line.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "glint/error.h"
#include "glint/util/strings.h"
#include "glint/version.h"
#include "options.h"

namespace {

using glint::cli::print_error;

// CLI11 words a missing or unknown command as "A subcommand is required":
// the message names the word and the closest command. Empty when argv[1]
// is an option or a known command.
std::string unknown_command(CLI::App& app, int argc, char** argv) {
  if (argc <= 1) return "no command given (usage: glint render SCENE.json -o OUT.png; see glint --help)";
  if (argv[1][0] == '-') return {};
  std::vector<std::string_view> commands;
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) commands.push_back(sub->get_name());
  const std::string_view word = argv[1];
  if (std::find(commands.begin(), commands.end(), word) != commands.end()) return {};
  std::string msg = "unknown command \"" + std::string(word) + "\"";
  const std::string hint = glint::closest_match(word, commands);
  if (!hint.empty()) return msg + " (did you mean \"" + hint + "\"?)";
  msg += " (expected";
  for (size_t i = 0; i < commands.size(); ++i) msg += (i ? ", \"" : " \"") + std::string(commands[i]) + "\"";
  return msg + ")";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"glint: a Whitted-style ray tracer for the Phong and Blinn-Phong reflection models"};
  app.require_subcommand(1);
  // The library's version (include/glint/version.h), which is the command's:
  // the command is linked with the library it was built with.
  app.set_version_flag("--version", std::string("glint ") + glint::version(), "print the version and exit");
  const std::vector<glint::cli::Command> commands = {
      glint::cli::add_render_command(app), glint::cli::add_convert_command(app), glint::cli::add_validate_command(app),
      glint::cli::add_info_command(app),   glint::cli::add_explain_command(app),
#ifdef GLINT_HAVE_SERVE
      glint::cli::add_serve_command(app),
#endif
  };

  if (const std::string problem = unknown_command(app, argc, argv); !problem.empty()) {
    print_error(problem);
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --help-all, --version: printed, exit 0
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string what = e.what();
    if (what.empty()) what = e.get_name();
    print_error(what);
    return 2;
  }

  try {
    for (const glint::cli::Command& command : commands)
      if (command.app->parsed()) return command.run();
  } catch (const glint::Error& e) {
    print_error(e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    print_error("out of memory");
    return 1;
  } catch (const std::exception& e) {
    print_error(e.what());
    return 1;
  }
  return 0;
}
