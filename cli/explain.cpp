// glint explain: one pixel's ray tree, term by term (docs/cli.md#explain).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/error.h"
#include "glint/io/scene_loader.h"
#include "glint/render/explain.h"
#include "glint/scene/animation.h"
#include "options.h"

namespace glint::cli {

namespace {

struct ExplainArgs {
  std::string scene_path;
  std::vector<int> pixel;
  bool json = false;
  std::optional<int> width, height, max_depth;
  std::optional<std::string> shading_model;
  int frame = 0;  // of an animation
};

int run_explain(const ExplainArgs& args) {
  const Scene loaded = load_scene(args.scene_path);
  if (args.frame >= frame_count(loaded))
    throw Error("--frame " + std::to_string(args.frame) + ": the scene has frames 0-" +
                std::to_string(frame_count(loaded) - 1));
  Scene scene = scene_at_frame(loaded, args.frame);
  RenderSettings& r = scene.render;
  if (args.width) r.width = image_width(scene.camera, *args.width);
  if (args.height) r.height = *args.height;
  if (args.max_depth) r.max_depth = *args.max_depth;
  if (args.shading_model)
    r.shading_model = *args.shading_model == "phong" ? ShadingModel::phong : ShadingModel::blinn_phong;
  r.samples_per_pixel = 1;                      // explain follows the pixel's center ray
  r.adaptive.reset();                           // (of a render at one sample per pixel, so never refined)
  const auto accel = build_accelerator(scene);  // render's default kernel: the numbers match its pixels
  const PixelExplanation e = explain_pixel(scene, *accel, args.pixel.at(0), args.pixel.at(1));
  const std::string text = args.json ? explanation_json(scene, e) : explanation_text(scene, e);
  std::fwrite(text.data(), 1, text.size(), stdout);
  return 0;
}

}  // namespace

Command add_explain_command(CLI::App& app) {
  auto args = std::make_shared<ExplainArgs>();
  CLI::App* explain = app.add_subcommand("explain", "explain one pixel: its whole ray tree, term by term");
  explain->add_option("scene", args->scene_path, "scene file (JSON or NFF)")->required();
  explain->add_option("--pixel", args->pixel, "pixel X Y (0 0 is the top-left)")->required()->expected(2);
  explain->add_flag("--json", args->json, "print one JSON object (the format of docs/scene-format.md)");
  explain->add_option("--frame", args->frame, "frame of an animated scene (default 0)")
      ->check(whole_number_in(0, kMaxFrames - 1));
  explain->add_option("--width", args->width, "image width in pixels")->check(whole_number_in(1, 1 << 20));
  explain->add_option("--height", args->height, "image height in pixels")->check(whole_number_in(1, 1 << 20));
  explain->add_option("--max-depth", args->max_depth, "longest ray path (camera ray = 1)")
      ->check(whole_number_in(1, kMaxDepthLimit));
  explain->add_option("--shading-model", args->shading_model, "phong or blinn-phong")
      ->check(one_of({"phong", "blinn-phong"}, "shading model"));
  return {explain, [args] { return run_explain(*args); }};
}

}  // namespace glint::cli
