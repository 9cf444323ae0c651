// A program using an installed glint through its public API only
// (include/glint/): a scene from JSON text, an edit checked by the loader's
// rules, a render, a second render after a material edit that reuses the
// acceleration structure, and the images written.
#include <glint/glint.h>
#include <cstdio>

int main(int argc, char** argv) {
  const char* output = argc > 1 ? argv[1] : "example.png";
  try {
    glint::api::Scene scene = glint::api::Scene::from_json(R"({
      "render": { "width": 320, "height": 240, "background": [0.1, 0.1, 0.15] },
      "camera": { "position": [0, 1.5, 5], "look_at": [0, 0.8, 0] },
      "materials": {
        "red":   { "ambient": [0.1, 0.02, 0.02], "diffuse": [0.8, 0.2, 0.15], "specular": 0.7, "shininess": 60 },
        "floor": { "diffuse": 0.6, "reflectivity": 0.3 }
      },
      "lights": [ { "type": "point", "position": [-3, 5, 4], "ambient": 1 } ],
      "objects": [
        { "type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "red" },
        { "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor" }
      ]
    })");
    try {
      scene.set("materials.red.shininess", -3.0);  // refused: the scene stays as it was
    } catch (const glint::Error& e) {
      std::printf("refused: %s\n", e.message().c_str());
    }
    glint::api::Renderer renderer(scene);
    glint::api::write_image(renderer.render().image, output);

    scene.set("materials.red.shininess", 8.0);  // a wider highlight; same geometry
    renderer.update(scene);
    const glint::api::RenderResult result = renderer.render();
    std::printf("glint %s: wrote %s; %llu camera rays, %d acceleration build(s)\n", glint::version(), output,
                static_cast<unsigned long long>(result.stats.camera_rays), result.stats.builds);
  } catch (const glint::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
