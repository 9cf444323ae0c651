// Scene: plain data describing what to render, as the scene file says it
// (see docs/scene-format.md). No I/O and no rendering here: io/ fills a Scene,
// accel/ and render/ read it. Everything refers to everything else by index.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "glint/geometry/shape_types.h"
#include "glint/math/bounds.h"
#include "glint/math/transform.h"
#include "glint/scene/animation.h"

namespace glint {

enum class ShadingModel { phong, blinn_phong };

enum class FilterType { box, gaussian, mitchell };

// How camera samples are weighted into a pixel (a glint addition; box is the
// contract's). Separable: f(x, y) = f1(x) f1(y), offsets in pixels from the
// pixel center, f1 zero beyond `radius`, normalized so that f integrates to 1.
struct PixelFilter {
  FilterType type = FilterType::box;
  double radius = 0.5;                  // box: the pixel itself (fixed); gaussian default 1.5, mitchell default 2
  double sigma = 0.5;                   // gaussian: standard deviation in pixels
  double b = 1.0 / 3.0, c = 1.0 / 3.0;  // Mitchell-Netravali B and C
};
inline constexpr double kGaussianRadius = 1.5, kMitchellRadius = 2.0, kMaxFilterRadius = 16.0;

// Adaptive sampling (a glint addition): after the whole image is rendered at
// samples_per_pixel, pixels that differ from a neighbour by more than
// `threshold` are rendered again at max_samples_per_pixel.
struct AdaptiveSampling {
  int max_samples_per_pixel = 64;
  double threshold = 0.05;
};

// Fog (render.fog): a ray that hits at distance t returns f*C + (1 - f)*color.
enum class FogType : uint8_t { linear, exp, exp2 };
struct Fog {
  Color color{0.5};
  FogType type = FogType::linear;
  double start = 0, end = 1;  // linear: f = clamp((end - t) / (end - start), 0, 1)
  double density = 1;         // exp: f = exp(-density t); exp2: f = exp(-(density t)^2)
};

// The environment (render.environment): an image around the scene that rays
// which hit nothing see instead of the background (latitude-longitude map).
struct Environment {
  uint32_t image = 0;   // into Scene::texture_images
  double rotate = 0;    // degrees, added to the longitude
  Color scale{1.0};
};

struct RenderSettings {
  int width = 640;
  int height = 480;
  int samples_per_pixel = 1;
  int max_depth = 5;  // the camera ray is depth 1
  ShadingModel shading_model = ShadingModel::phong;
  Color background{0.0};
  std::optional<double> epsilon;  // nullopt: scale-aware automatic value
  PixelFilter pixel_filter;
  std::optional<AdaptiveSampling> adaptive;  // nullopt: every pixel gets samples_per_pixel
  std::optional<Fog> fog;
  std::optional<Environment> environment;  // replaces background for rays that miss
};

// New types go at the end (tools name them by these values).
enum class CameraType { perspective, orthographic, fisheye, equirectangular };

struct Camera {
  CameraType type = CameraType::perspective;
  Vec3 position{0, 0, 0};
  Vec3 look_at{0, 0, -1};
  Vec3 up{0, 1, 0};
  double fov_y = 45.0;       // degrees, perspective
  double view_height = 2.0;  // world units, orthographic
  double fisheye_fov = 180;  // degrees across the image height, fisheye
  // Thin lens (perspective): the lens radius (0: a pinhole) and the distance
  // along the view direction to the plane in focus (nullopt: to look_at).
  double aperture = 0;
  std::optional<double> focus_distance;
  // Parallel stereo: a left and a right image side by side, each half of
  // render.width (the loader doubles the file's width), eyes this far apart.
  std::optional<double> eye_separation;
  // Degrees between the centers of the first and last pixel rows (an NFF
  // view's `angle`). When set, the perspective fov_y is derived from it for
  // the height actually rendered (camera_fov_y below), so a
  // --height override keeps the file's view; fov_y then holds the value for
  // the file's own resolution. Not a JSON key: only NFF scenes set it.
  std::optional<double> row_center_angle;
};

// The image's width for a render.width (or --width) of `width`: each eye's
// width, doubled, for a stereo pair.
inline int image_width(const Camera& camera, int width) { return camera.eye_separation ? 2 * width : width; }

// The vertical field of view, degrees, of an image `height` rows high:
// camera.fov_y, or for a camera with a row_center_angle a (the NFF view) the
// fov_y with tan(fov_y/2) = tan(a/2) * H/(H - 1), which puts the centers of
// the first and last rows a apart. One row has no such span: a is then
// taken edge to edge.
double camera_fov_y(const Camera& camera, int height);
double fov_y_for_row_center_angle(double row_center_angle, int height);

// Surface coordinates for textures (docs/scene-format.md: "Textures").
struct UV {
  double u = 0, v = 0;
};
struct UVf {  // compact per-corner storage in meshes
  float u = 0, v = 0;
};

enum class TextureWrap : uint8_t { repeat, clamp, mirror };

// An image file's pixels as linear RGB, row 0 at the top; loaded once per
// file however many textures use it.
struct TextureImage {
  std::string file;
  int width = 0, height = 0;
  std::vector<Vec3f> texels;  // width * height, row-major from the top row
};

// A reflectance that varies over a surface: an image or a checkerboard.
// The lookup point is (u * scale_u + offset_u, v * scale_v + offset_v).
enum class TextureKind : uint8_t { image, checker };
struct Texture {
  TextureKind kind = TextureKind::image;
  TextureWrap wrap = TextureWrap::repeat;  // image
  uint32_t image = 0;                      // image: into Scene::texture_images
  Color even{1.0}, odd{0.0};               // checker: cells with floor(u') + floor(v') even / odd
  double scale_u = 1, scale_v = 1, offset_u = 0, offset_v = 0;
};

inline constexpr uint32_t kNoTexture = UINT32_MAX;

// The reflectances of the Phong model plus the recursive-ray weights.
struct Material {
  std::string name;
  Color ambient{0.0};       // R_a
  Color diffuse{0.8};       // R_d
  Color specular{0.0};      // R_s
  double shininess = 32.0;  // alpha
  Color reflectivity{0.0};  // k
  double transparency = 0.0;
  double ior = 1.5;
  bool fresnel = false;
  bool unlit = false;  // MTL illum 0: the color is `diffuse`, no lights, no shadows
  // Textures that replace R_a, R_d, R_s at the hit point: into Scene::textures.
  uint32_t ambient_texture = kNoTexture, diffuse_texture = kNoTexture, specular_texture = kNoTexture;

  // One test on the integrator's hot path: plain colors skip all texture work.
  bool textured() const { return (ambient_texture & diffuse_texture & specular_texture) != kNoTexture; }
};

enum class LightType { ambient, point, directional, spot, area };

struct Light {
  LightType type = LightType::point;
  Color ambient{0.0};           // L_a
  Color diffuse{1.0};           // L_d
  Color specular{1.0};          // L_s
  Vec3 position;                // point, spot
  Vec3 direction{0, -1, 0};     // directional, spot: unit, the way light travels
  double cutoff = 180.0;        // spot half-angle, degrees
  double falloff = 0.0;         // spot exponent
  Vec3 attenuation{1, 0, 0};    // 1 / (c + l d + q d^2)
  Vec3 corner, edge_u, edge_v;  // area: the parallelogram corner + s edge_u + t edge_v
  int samples = 16;             // area: shadow samples per shading point
  // Ambient occlusion (ambient lights): R_a L_a is scaled by the fraction of
  // occlusion_samples cosine-weighted rays that hit nothing within
  // occlusion_distance; 0 samples: never occluded (the contract's default).
  int occlusion_samples = 0;
  double occlusion_distance = kInfinity;
  std::string name;
};

// New types go at the end: tools count objects by these values.
enum class ShapeType : uint8_t { sphere, plane, triangle, box, mesh, cylinder, cone, disk, polygon, torus, csg };
inline constexpr int kShapeTypeCount = 11;
// The scene file's name of each type ("sphere", ..., "csg").
inline const char* shape_type_name(ShapeType t) {
  static constexpr const char* kNames[kShapeTypeCount] = {"sphere", "plane", "triangle", "box",   "mesh", "cylinder",
                                                          "cone",   "disk",  "polygon",  "torus", "csg"};
  return kNames[static_cast<int>(t)];
}

// Sphere, Plane, Triangle, Box, Cone, Disk and Polygon: geometry/shape_types.h.

// A triangle mesh in its own space, loaded once per file and shared by every
// object that uses it (each object an instance with its own transform).
struct Mesh {
  std::string file;
  std::vector<Vec3f> positions;
  std::vector<uint32_t> indices;            // 3 per triangle
  std::vector<Vec3f> corner_normals;        // 3 per triangle, unit
  std::vector<uint32_t> triangle_material;  // per triangle, into Scene::materials
  std::vector<UVf> corner_uvs;              // 3 per triangle, or empty: the file has no UVs
  Bounds3 bounds;                           // of the positions, set by add_mesh

  size_t triangle_count() const { return indices.size() / 3; }
};

inline constexpr uint32_t kNoTransform = UINT32_MAX;
// A mesh object's `material` when it names none: each triangle uses its own.
inline constexpr uint32_t kMeshMaterials = UINT32_MAX;

// One object of the scene file. `shape` indexes the vector of its type;
// `transform` indexes Scene::transforms (spheres, boxes, cylinders, cones,
// disks, polygons and meshes keep theirs and are intersected in object space;
// planes and triangles are baked into world space). Cylinders and cones both
// index Scene::cones.
struct Object {
  ShapeType type = ShapeType::sphere;
  bool smooth = true;  // meshes: interpolate vertex normals
  uint32_t shape = 0;
  uint32_t material = 0;
  uint32_t transform = kNoTransform;
};

struct Scene {
  RenderSettings render;
  Camera camera;
  std::vector<Material> materials;  // materials[0] is the default material
  std::vector<Light> lights;
  std::vector<Object> objects;
  std::vector<Sphere> spheres;
  std::vector<Plane> planes;
  std::vector<Triangle> triangles;
  std::vector<Box> boxes;
  std::vector<Cone> cones;  // cylinders and cones
  std::vector<Disk> disks;
  std::vector<Polygon> polygons;
  std::vector<Torus> tori;
  std::vector<Csg> csgs;
  std::vector<Mesh> meshes;
  std::vector<Transform> transforms;
  std::vector<Texture> textures;
  std::vector<TextureImage> texture_images;
  // Per-vertex UVs of triangle objects that give them, by Scene::triangles
  // index (the rest use (0,0), (1,0), (0,1)); apart, so Triangle stays small.
  std::unordered_map<uint32_t, std::array<UV, 3>> triangle_uvs;
  std::vector<std::string> warnings;  // recoverable problems met while loading
  // Names the scene file gave objects (most have none; kept apart so Object
  // stays 16 bytes for scenes of millions of objects).
  std::unordered_map<uint32_t, std::string> object_names;
  // Keyframes of the scene file's "animation" (frames == 0: none); see
  // scene/animation.h for the scene at a given frame.
  Animation animation;

  Scene();  // with the default material in place
};

// Building a scene in code (what the loader uses too). Each returns the new index.
uint32_t add_material(Scene& scene, Material material);
uint32_t add_sphere(Scene& scene, const Sphere& sphere, uint32_t material = 0,
                    const std::optional<Transform>& transform = std::nullopt);
uint32_t add_plane(Scene& scene, const Plane& plane, uint32_t material = 0,
                   const std::optional<Transform>& transform = std::nullopt);
uint32_t add_triangle(Scene& scene, const Triangle& triangle, uint32_t material = 0,
                      const std::optional<Transform>& transform = std::nullopt);
uint32_t add_box(Scene& scene, const Box& box, uint32_t material = 0,
                 const std::optional<Transform>& transform = std::nullopt);

// A cylinder is a cone whose radii are equal (make_cone); `cylinder` only
// decides which type the object reports (glint info).
uint32_t add_cone(Scene& scene, const Cone& cone, uint32_t material = 0,
                  const std::optional<Transform>& transform = std::nullopt, bool cylinder = false);
uint32_t add_disk(Scene& scene, const Disk& disk, uint32_t material = 0,
                  const std::optional<Transform>& transform = std::nullopt);
// The polygon as make_polygon (geometry/polygon.h) returns it: triangulated.
uint32_t add_polygon(Scene& scene, Polygon polygon, uint32_t material = 0,
                     const std::optional<Transform>& transform = std::nullopt);

uint32_t add_torus(Scene& scene, const Torus& torus, uint32_t material = 0,
                   const std::optional<Transform>& transform = std::nullopt);
// The CSG tree as the loader builds it; computes csg.bounds.
uint32_t add_csg(Scene& scene, Csg csg, uint32_t material = 0, const std::optional<Transform>& transform = std::nullopt);

uint32_t add_mesh(Scene& scene, Mesh mesh);  // computes mesh.bounds
uint32_t add_mesh_object(Scene& scene, uint32_t mesh, uint32_t material = kMeshMaterials, bool smooth = true,
                         const std::optional<Transform>& transform = std::nullopt);

// World-space bounds of a finite object (empty for planes).
Bounds3 object_bounds(const Scene& scene, uint32_t object);

// The automatic secondary-ray offset: a small fraction of the scene's size,
// so it stays above double rounding error at any scale (see render/integrator.cpp).
double auto_epsilon(const Scene& scene);

}  // namespace glint
