// Builds a scene in code (no scene file) and renders it with glint's library:
// the same pipeline the glint command runs, one call per stage.
#include <cstdio>

#include <glint/accel/accelerator.h>
#include <glint/error.h>
#include <glint/image/image.h>
#include <glint/render/renderer.h>

int main(int argc, char** argv) {
  const char* output = argc > 1 ? argv[1] : "example.png";
  glint::Scene scene;
  scene.render.width = 320;
  scene.render.height = 240;
  scene.render.background = {0.1, 0.1, 0.15};
  scene.camera.position = {0, 1.5, 5};
  scene.camera.look_at = {0, 0.8, 0};

  glint::Material red;
  red.ambient = {0.1, 0.02, 0.02};
  red.diffuse = {0.8, 0.2, 0.15};
  red.specular = {0.7, 0.7, 0.7};
  red.shininess = 60;
  glint::Material floor;
  floor.diffuse = {0.6, 0.6, 0.6};
  floor.reflectivity = {0.3, 0.3, 0.3};

  glint::add_sphere(scene, {{0, 1, 0}, 1.0}, glint::add_material(scene, red));
  glint::add_plane(scene, {{0, 0, 0}, {0, 1, 0}}, glint::add_material(scene, floor));

  glint::Light light;  // a white point light, also giving ambient light
  light.type = glint::LightType::point;
  light.position = {-3, 5, 4};
  light.ambient = {1, 1, 1};
  scene.lights.push_back(light);

  try {
    const auto accel = glint::build_accelerator(scene);
    const glint::Image image = glint::render_image(scene, *accel);
    glint::write_image(image, output);
  } catch (const glint::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  std::printf("wrote %s\n", output);
  return 0;
}
