// glint convert: an NFF scene as glint JSON (docs/cli.md#convert, docs/nff.md).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "glint/error.h"
#include "glint/io/file_io.h"
#include "glint/io/nff_file.h"
#include "glint/io/scene_loader.h"
#include "options.h"

namespace glint::cli {

namespace {

struct ConvertArgs {
  std::string input, output;
};

// Checked by loading it first, so a file written is one that loads; written
// atomically like every output.
int run_convert(const ConvertArgs& args) {
  const std::string& input = args.input;
  const std::string& output = args.output;
  if (!is_nff_path(input)) throw Error(input + ": convert reads NFF scenes (.nff)");
  std::string ext = std::filesystem::path(output).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".json") throw Error(output + ": convert writes glint JSON: the output must end in .json");
  const std::filesystem::path out(output);
  const std::filesystem::path out_dir = out.has_parent_path() ? out.parent_path() : ".";
  if (!std::filesystem::is_directory(out_dir))
    throw Error(output + ": output folder " + out_dir.string() + " does not exist");
  load_scene(input);  // every error the loader finds, at its NFF line
  const std::string text = nff_json_text(read_nff_file(input)).text;
  write_file_atomically(out, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
  return 0;
}

}  // namespace

Command add_convert_command(CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* convert = app.add_subcommand("convert", "convert an NFF scene to glint JSON");
  convert->add_option("scene", args->input, "scene file (.nff)")->required();
  convert->add_option("-o,--output", args->output, "output scene: .json")->required();
  return {convert, [args] { return run_convert(*args); }};
}

}  // namespace glint::cli
