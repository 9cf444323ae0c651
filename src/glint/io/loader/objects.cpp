// The "objects" array: transforms, material references and every shape but meshes.
#include "glint/io/loader/scene_reader.h"

#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "glint/geometry/polygon.h"

namespace glint::loader {

std::optional<Transform> SceneReader::read_transform(const Value& v, const Path& path) const {
  expect_object(v, path);
  check_keys(v, path, {"scale", "rotate", "translate", "matrix"});
  Transform t;
  if (auto m = v.find("matrix")) {
    if (v.size() != 1) fail(v, path, "\"matrix\" cannot be combined with \"scale\", \"rotate\" or \"translate\"");
    const Path p = join(path, "matrix");
    if (!m->is_array() || m->size() != 16) fail(*m, p, "expected 16 numbers (a 4x4 matrix, row by row)");
    double e[16];
    for (size_t i = 0; i < 16; ++i) e[i] = number((*m)[i], index(p, i));
    if (e[12] != 0 || e[13] != 0 || e[14] != 0 || e[15] != 1) fail(*m, p, "the last row must be 0 0 0 1");
    Affine a;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) a[r][c] = e[4 * r + c];
    auto xf = Transform::from_affine(a);
    if (!xf) fail(*m, p, "the matrix is singular (or too badly scaled to invert)");
    return xf;
  }
  if (auto s = v.find("scale")) {
    const Path p = join(path, "scale");
    const Vec3 f = s->is_number() ? Vec3(number(*s, p)) : vec3(*s, p);
    if (f.x == 0 || f.y == 0 || f.z == 0) fail(*s, p, "a zero scale makes the transform singular");
    t = Transform::scale(f);
  }
  if (auto r = v.find("rotate")) {
    const Path p = join(path, "rotate");
    expect_object(*r, p);
    check_keys(*r, p, {"axis", "angle"});
    const Vec3 axis = direction(require(*r, p, "axis"), join(p, "axis"));
    const double angle = number(require(*r, p, "angle"), join(p, "angle"));
    t = compose(Transform::rotate(axis, angle), t);
  }
  if (auto tr = v.find("translate")) t = compose(Transform::translate(vec3(*tr, join(path, "translate"))), t);
  // Recheck: extreme scales can still make the composition numerically singular.
  if (!Transform::from_affine(t.m)) fail(v, path, "the transform is singular (or too badly scaled to invert)");
  return t;
}

void SceneReader::read_objects(const Value& list) {
  expect_array(list, "objects");
  // Vertex normals are computed only for mesh files some object shades
  // smoothly (the default); a malformed entry is reported by read_object.
  for (size_t i = 0; i < list.size(); ++i) {
    const Value o = list[i];
    if (!o.is_object()) continue;
    const auto type = o.find("type"), file = o.find("file"), smooth = o.find("smooth");
    if (!type || !type->is_string() || type->as_string() != "mesh" || !file || !file->is_string()) continue;
    if (smooth && smooth->is_bool() && !smooth->as_bool()) continue;
    smooth_mesh_files_.insert(file_key(beside_scene(file->as_string())));
  }
  scene_.objects.reserve(list.size());
  for (size_t i = 0; i < list.size(); ++i) {
    collect([&] { read_object(list[i], index("objects", i)); });
    object_json_index_.resize(scene_.objects.size(), i);  // for the animation's names
  }
}

uint32_t SceneReader::material_ref(const Value& v, const Path& path) const {
  const std::string name = string(v, path);
  auto it = material_index_.find(name);
  if (it != material_index_.end()) return it->second;
  Keys names;
  for (const auto& [n, _] : material_index_) names.push_back(n);
  std::string msg = "unknown material " + quote_text(name);
  const std::string hint = closest_match(name, names);
  if (!hint.empty()) msg += " (did you mean \"" + hint + "\"?)";
  else if (names.empty()) msg += " (the scene defines no materials)";
  fail(v, path, msg);
}

void SceneReader::read_object(const Value& v, const Path& path) {
  expect_object(v, path);
  static const Keys types = {"sphere", "plane", "triangle", "box",     "mesh", "cylinder",
                             "cone",   "disk",  "polygon",  "torus", "csg"};
  const Value type_value = require(v, path, "type");
  const size_t type = choice(type_value, join(path, "type"), types, "object type");
  Keys allowed = {"type", "material", "transform", "name"};
  switch (type) {
    case 0: allowed.insert(allowed.end(), {"center", "radius"}); break;
    case 1: allowed.insert(allowed.end(), {"point", "normal"}); break;
    case 2: allowed.insert(allowed.end(), {"vertices", "uv"}); break;
    case 3: allowed.insert(allowed.end(), {"min", "max"}); break;
    case 4:
      allowed.insert(allowed.end(), {"file", "smooth", "vertices", "triangles", "normals", "uvs"});
      if (attached_) allowed.push_back(kAttachedMeshKey);
      break;
    case 5: allowed.insert(allowed.end(), {"base", "apex", "radius", "caps"}); break;
    case 6: allowed.insert(allowed.end(), {"base", "apex", "base_radius", "apex_radius", "caps"}); break;
    case 7: allowed.insert(allowed.end(), {"center", "normal", "radius", "inner_radius"}); break;
    case 8: allowed.insert(allowed.end(), {"vertices", "normals"}); break;
    case 9: allowed.insert(allowed.end(), {"center", "axis", "major_radius", "minor_radius"}); break;
    case 10: allowed.insert(allowed.end(), {"operation", "children"}); break;
  }
  check_keys(v, path, allowed);
  uint32_t material = 0;
  if (auto m = v.find("material")) material = material_ref(*m, join(path, "material"));
  std::optional<Transform> transform;
  if (auto t = v.find("transform")) transform = read_transform(*t, join(path, "transform"));

  uint32_t object = 0;
  switch (type) {
    case 0: object = add_sphere(scene_, read_sphere(v, path), material, transform); break;
    case 1: {
      Plane p;
      p.point = vec3(require(v, path, "point"), join(path, "point"));
      p.normal = direction(require(v, path, "normal"), join(path, "normal"));
      object = add_plane(scene_, p, material, transform);
      break;
    }
    case 2: {
      const Value verts = require(v, path, "vertices");
      const Path p = join(path, "vertices");
      if (!verts.is_array() || verts.size() != 3) fail(verts, p, "expected three vertices [[x,y,z], [x,y,z], [x,y,z]]");
      Triangle t{vec3(verts[0], index(p, 0)), vec3(verts[1], index(p, 1)), vec3(verts[2], index(p, 2))};
      if (!(length(cross(t.v1 - t.v0, t.v2 - t.v0)) > 0)) fail(verts, p, "degenerate triangle (zero area)");
      object = add_triangle(scene_, t, material, transform);
      const Triangle& w = scene_.triangles.back();
      if (!(length(cross(w.v1 - w.v0, w.v2 - w.v0)) > 0)) fail(verts, p, "degenerate triangle after its transform");
      if (auto uv = v.find("uv")) {
        const Path up = join(path, "uv");
        if (!uv->is_array() || uv->size() != 3) fail(*uv, up, "expected three [u, v] pairs, one per vertex");
        std::array<UV, 3> uvs;
        for (size_t k = 0; k < 3; ++k) {
          const std::array<double, 2> c = pair((*uv)[k], index(up, k));
          uvs[k] = {c[0], c[1]};
        }
        scene_.triangle_uvs[scene_.objects[object].shape] = uvs;
      }
      break;
    }
    case 3: object = add_box(scene_, read_box(v, path), material, transform); break;
    case 4: {
      bool smooth = true;
      if (auto x = v.find("smooth")) smooth = boolean(*x, join(path, "smooth"));
      uint32_t mesh = 0;
      if (attached_ && v.find(kAttachedMeshKey)) {
        mesh = attached_mesh(v, path, smooth);
      } else if (v.find("vertices") || v.find("triangles")) {
        mesh = inline_mesh(v, path, smooth);
      } else {
        const Value file = require(v, path, "file");
        mesh = load_mesh(file, join(path, "file"));
      }
      object = add_mesh_object(scene_, mesh, v.find("material") ? material : kMeshMaterials, smooth, transform);
      break;
    }
    case 5:
    case 6: object = add_cone(scene_, read_cone(v, path, type == 5), material, transform, type == 5); break;
    case 7: {
      Disk d;
      d.center = vec3(require(v, path, "center"), join(path, "center"));
      d.normal = direction(require(v, path, "normal"), join(path, "normal"));
      d.radius = positive(require(v, path, "radius"), join(path, "radius"));
      if (auto x = v.find("inner_radius")) {
        d.inner_radius = non_negative(*x, join(path, "inner_radius"));
        if (!(d.inner_radius < d.radius))
          fail(*x, join(path, "inner_radius"),
               "must be less than \"radius\" (" + format_number(d.radius) + "; got " + format_number(d.inner_radius) +
                   ")");
      }
      object = add_disk(scene_, d, material, transform);
      break;
    }
    case 8: object = read_polygon(v, path, material, transform); break;
    case 9: object = add_torus(scene_, read_torus(v, path), material, transform); break;
    case 10: {
      Csg csg;
      csg.nodes.emplace_back();
      read_csg_operation(v, path, material, std::nullopt, csg, 0, 1);
      object = add_csg(scene_, std::move(csg), material, transform);
      break;
    }
  }
  if (auto n = v.find("name")) scene_.object_names[object] = string(*n, join(path, "name"));
}

Sphere SceneReader::read_sphere(const Value& v, const Path& path) const {
  Sphere s;
  s.center = vec3(require(v, path, "center"), join(path, "center"));
  s.radius = positive(require(v, path, "radius"), join(path, "radius"));
  return s;
}

Box SceneReader::read_box(const Value& v, const Path& path) const {
  Box b;
  b.lo = vec3(require(v, path, "min"), join(path, "min"));
  const Value max_value = require(v, path, "max");
  b.hi = vec3(max_value, join(path, "max"));
  if (!(b.hi.x > b.lo.x && b.hi.y > b.lo.y && b.hi.z > b.lo.z))
    fail(max_value, join(path, "max"), "must be greater than \"min\" on every axis (a box needs a positive size)");
  return b;
}

Torus SceneReader::read_torus(const Value& v, const Path& path) const {
  Torus t;
  t.center = vec3(require(v, path, "center"), join(path, "center"));
  t.axis = direction(require(v, path, "axis"), join(path, "axis"));
  t.major_radius = positive(require(v, path, "major_radius"), join(path, "major_radius"));
  const Value minor = require(v, path, "minor_radius");
  t.minor_radius = positive(minor, join(path, "minor_radius"));
  if (!(t.minor_radius < t.major_radius))
    fail(minor, join(path, "minor_radius"),
         "must be less than \"major_radius\" (" + format_number(t.major_radius) + "; got " +
             format_number(t.minor_radius) + ")");
  return t;
}

// {"operation": ..., "children": [...]} into node `node` of `csg`. `to_csg`
// maps this level's space into the CSG object's (the transforms of the
// levels above, composed); children without a material take `material`.
void SceneReader::read_csg_operation(const Value& v, const Path& path, uint32_t material,
                                     const std::optional<Transform>& to_csg, Csg& csg, uint32_t node, int depth) {
  static const Keys operations = {"union", "intersection", "difference"};
  CsgNode op;
  op.op = static_cast<CsgOp>(choice(require(v, path, "operation"), join(path, "operation"), operations,
                                    "CSG operation"));
  const Value children = require(v, path, "children");
  const Path cp = join(path, "children");
  expect_array(children, cp);
  if (children.size() < 2)
    fail(children, cp, "a csg needs two or more children (got " + std::to_string(children.size()) + ")");
  op.first = static_cast<uint32_t>(csg.child_nodes.size());
  op.count = static_cast<uint32_t>(children.size());
  csg.child_nodes.resize(csg.child_nodes.size() + children.size());
  for (size_t i = 0; i < children.size(); ++i) {
    const auto child = static_cast<uint32_t>(csg.nodes.size());
    csg.nodes.emplace_back();
    csg.child_nodes[op.first + i] = child;
    read_csg_child(children[i], index(cp, i), material, to_csg, csg, child, depth);
  }
  csg.nodes[node] = op;
}

void SceneReader::read_csg_child(const Value& v, const Path& path, uint32_t material,
                                 const std::optional<Transform>& to_csg, Csg& csg, uint32_t node, int depth) {
  // Nesting deeper than any model needs is a malformed (or hostile) file.
  if (depth > 64) fail(v, path, "csg nested more than 64 levels deep");
  expect_object(v, path);
  static const Keys solids = {"sphere", "box", "cylinder", "cone", "torus", "csg"};
  const Value type_value = require(v, path, "type");
  const Path tp = join(path, "type");
  const std::string type_name = string(type_value, tp);
  for (const char* open : {"plane", "triangle", "mesh", "disk", "polygon"})
    if (type_name == open)
      fail(type_value, tp,
           "a csg child must be a closed solid (sphere, box, cylinder, cone, torus or csg), not a " + type_name);
  const size_t type = choice(type_value, tp, solids, "csg child type");
  Keys allowed = {"type", "material", "transform", "name"};
  switch (type) {
    case 0: allowed.insert(allowed.end(), {"center", "radius"}); break;
    case 1: allowed.insert(allowed.end(), {"min", "max"}); break;
    case 2: allowed.insert(allowed.end(), {"base", "apex", "radius", "caps"}); break;
    case 3: allowed.insert(allowed.end(), {"base", "apex", "base_radius", "apex_radius", "caps"}); break;
    case 4: allowed.insert(allowed.end(), {"center", "axis", "major_radius", "minor_radius"}); break;
    case 5: allowed.insert(allowed.end(), {"operation", "children"}); break;
  }
  check_keys(v, path, allowed);
  if (auto m = v.find("material")) material = material_ref(*m, join(path, "material"));
  std::optional<Transform> xf = to_csg;
  if (auto t = v.find("transform")) {
    const std::optional<Transform> own = read_transform(*t, join(path, "transform"));
    xf = xf ? compose(*xf, *own) : own;
  }
  if (type == 5) {
    read_csg_operation(v, path, material, xf, csg, node, depth + 1);
    return;
  }
  CsgLeaf leaf;
  leaf.material = material;
  leaf.transform = xf;
  if (auto n = v.find("name")) leaf.name = string(*n, join(path, "name"));
  switch (type) {
    case 0: leaf.sphere = read_sphere(v, path); break;
    case 1:
      leaf.type = CsgLeafType::box;
      leaf.box = read_box(v, path);
      break;
    case 2:
    case 3:
      leaf.type = CsgLeafType::cone;
      leaf.cylinder = type == 2;
      leaf.cone = read_cone(v, path, type == 2);
      if (!leaf.cone.caps)
        fail(*v.find("caps"), join(path, "caps"), "a csg child must be a closed solid: \"caps\" cannot be false");
      break;
    case 4:
      leaf.type = CsgLeafType::torus;
      leaf.torus = read_torus(v, path);
      break;
  }
  csg.nodes[node].leaf = true;
  csg.nodes[node].index = static_cast<uint32_t>(csg.leaves.size());
  csg.leaves.push_back(std::move(leaf));
}

// A cylinder (base, apex, radius) or a cone (base, apex, base_radius, apex_radius).
Cone SceneReader::read_cone(const Value& v, const Path& path, bool cylinder) const {
  const Vec3 base = vec3(require(v, path, "base"), join(path, "base"));
  const Value apex_value = require(v, path, "apex");
  const Vec3 apex = vec3(apex_value, join(path, "apex"));
  if (apex == base) fail(apex_value, join(path, "apex"), "must differ from \"base\" (the axis needs a length)");
  if (!std::isfinite(length(apex - base)))
    fail(apex_value, join(path, "apex"), "too far from \"base\" (the axis length overflows)");
  double r0 = 0, r1 = 0;
  if (cylinder) {
    r0 = r1 = positive(require(v, path, "radius"), join(path, "radius"));
  } else {
    r0 = non_negative(require(v, path, "base_radius"), join(path, "base_radius"));
    const Value r1_value = require(v, path, "apex_radius");
    r1 = non_negative(r1_value, join(path, "apex_radius"));
    if (r0 == 0 && r1 == 0)
      fail(r1_value, join(path, "apex_radius"), "\"base_radius\" and \"apex_radius\" cannot both be 0");
  }
  bool caps = true;
  if (auto x = v.find("caps")) caps = boolean(*x, join(path, "caps"));
  return make_cone(base, apex, r0, r1, caps);
}

// A polygon: checked and triangulated by make_polygon (geometry/polygon.h).
uint32_t SceneReader::read_polygon(const Value& v, const Path& path, uint32_t material,
                                   const std::optional<Transform>& transform) {
  const Value verts = require(v, path, "vertices");
  const Path vp = join(path, "vertices");
  if (!verts.is_array())
    fail(verts, vp, std::string("expected an array of [x, y, z] vertices, got ") + verts.kind_name());
  std::vector<Vec3> vertices;
  vertices.reserve(verts.size());
  for (size_t i = 0; i < verts.size(); ++i) vertices.push_back(vec3(verts[i], index(vp, i)));
  std::vector<Vec3> normals;
  const auto normals_value = v.find("normals");
  const Path np = join(path, "normals");
  if (normals_value) {
    if (!normals_value->is_array())
      fail(*normals_value, np,
           std::string("expected an array of [x, y, z] normals, got ") + normals_value->kind_name());
    if (normals_value->size() != verts.size())
      fail(*normals_value, np,
           "expected one normal per vertex (" + std::to_string(verts.size()) + "), got " +
               std::to_string(normals_value->size()));
    normals.reserve(normals_value->size());
    for (size_t i = 0; i < normals_value->size(); ++i) normals.push_back(direction((*normals_value)[i], index(np, i)));
  }
  PolygonBuild built = make_polygon(std::move(vertices), std::move(normals));
  if (!built.error.empty()) {
    if (built.error_at_normals) fail(*normals_value, np, built.error);
    fail(verts, vp, built.error);
  }
  return add_polygon(scene_, std::move(built.polygon), material, transform);
}

}  // namespace glint::loader
