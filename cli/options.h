// What the commands of the glint CLI share: the one-line error printer, the
// option validators (CLI11's own let NaN and "abc" through or word them
// vaguely), and how a command is registered (cli/main.cpp runs the one that
// parsed). Each command lives in its own file: render.cpp, explain.cpp,
// validate.cpp, info.cpp, convert.cpp, serve.cpp.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace glint::cli {

// Prints `error: <what>` as exactly one line, whatever `what` holds (a file
// name from the command line may contain a line break).
void print_error(const std::string& what);

// A whole number in [lo, hi]; CLI11's Range alone calls "abc" out of range.
CLI::Validator whole_number_in(long long lo, long long hi);
// A finite number in [lo, hi] (CLI11's Range lets NaN through).
CLI::Validator number_in(double lo, double hi);
// One of `names`, with a did-you-mean hint for near misses.
CLI::Validator one_of(std::vector<std::string_view> names, std::string what);

// A subcommand: its parser, and what runs once it parsed (the exit status).
// `run` may throw glint::Error and std::exception: main prints them.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command add_render_command(CLI::App& app);
Command add_explain_command(CLI::App& app);
Command add_validate_command(CLI::App& app);
Command add_info_command(CLI::App& app);
Command add_convert_command(CLI::App& app);
// Defined only when glint serve is built (main.cpp asks for it under GLINT_HAVE_SERVE).
Command add_serve_command(CLI::App& app);

}  // namespace glint::cli
