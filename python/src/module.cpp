// glint._glint: the pybind11 layer between Python and glint's public C++ API
// (include/glint/). It stays thin: the Pythonic API (views, Render, docs)
// lives in python/glint/__init__.py. What must be native is here: the GIL
// released while rendering, Ctrl-C seen on the calling thread, images handed
// to numpy without a copy, meshes checked and turned into scene JSON in one
// pass over the arrays, and glint::Error raised as glint.SceneError.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <cmath>
#include <exception>
#include <glint/glint.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace py = pybind11;
using glint::api::Renderer;
using glint::api::Scene;

namespace {

// glint.SceneError, created at import (a ValueError: a bad value was given).
py::object& scene_error_type() {
  static py::object* type = nullptr;
  if (!type) type = new py::object();  // lives as long as the interpreter's module
  return *type;
}

void raise_scene_error(const glint::Error& e) {
  py::object error = scene_error_type()(py::str(e.what()));
  const glint::SourceLocation& at = e.location();
  error.attr("file") = at.file.empty() ? py::object(py::none()) : py::object(py::str(at.file));
  error.attr("line") = at.line > 0 ? py::object(py::int_(at.line)) : py::object(py::none());
  error.attr("column") = at.column > 0 ? py::object(py::int_(at.column)) : py::object(py::none());
  error.attr("path") = e.path().empty() ? py::object(py::none()) : py::object(py::str(e.path()));
  error.attr("message") = py::str(e.message());
  PyErr_SetObject(scene_error_type().ptr(), error.ptr());
}

// A vector of floats handed to numpy as it is: the array's buffer is the
// vector's, and the capsule that owns the vector frees it with the array.
py::array_t<float> adopt(std::vector<float>&& values, std::vector<py::ssize_t> shape,
                         std::vector<py::ssize_t> strides) {
  auto* owned = new std::vector<float>(std::move(values));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<float>*>(p); });
  return py::array_t<float>(std::move(shape), std::move(strides), owned->data(), owner);
}

py::array_t<float> image_array(glint::api::Image&& image) {
  const py::ssize_t h = image.height, w = image.width, f = sizeof(float);
  return adopt(std::move(image.rgb), {h, w, 3}, {3 * w * f, 3 * f, f});
}

// Depth is stored in all three channels: its (H, W) view is a strided one.
py::array_t<float> depth_array(glint::api::Image&& image) {
  const py::ssize_t h = image.height, w = image.width, f = sizeof(float);
  return adopt(std::move(image.rgb), {h, w}, {3 * w * f, 3 * f});
}

py::dict stats_dict(const glint::api::RenderStats& s, bool complete) {
  py::dict d;
  d["camera_rays"] = s.camera_rays;
  d["shadow_rays"] = s.shadow_rays;
  d["reflection_rays"] = s.reflection_rays;
  d["refraction_rays"] = s.refraction_rays;
  d["rays"] = s.camera_rays + s.shadow_rays + s.reflection_rays + s.refraction_rays;
  d["render_seconds"] = s.render_seconds;
  d["build_seconds"] = s.build_seconds;
  d["builds"] = s.builds;
  d["threads"] = s.threads;
  d["complete"] = complete;
  return d;
}

// A flag another thread may set to stop a render (glint.CancelToken);
// `running` is true while a render that uses it is in its pixel loop.
struct CancelToken {
  std::atomic<bool> cancelled{false};
  std::atomic<bool> running{false};
};

// Renders with the GIL released. The progress callback runs on this thread
// (the API promises it) with the GIL taken back: it checks for signals, so
// Ctrl-C sets the cancel flag and the render stops within a row of pixels,
// then calls the user's callback. An exception from either cancels the
// render and is raised once it has stopped.
py::tuple render(const Renderer& renderer, const std::vector<std::string>& passes, int threads,
                 const py::object& progress, CancelToken* token) {
  CancelToken own;
  if (!token) token = &own;
  std::atomic<bool>& cancel = token->cancelled;
  std::exception_ptr failure;
  glint::api::RenderOptions options;
  options.threads = threads;
  options.passes = passes;
  options.cancel = &cancel;
  options.progress = [&](double fraction) {
    if (failure) return;
    py::gil_scoped_acquire gil;
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!progress.is_none()) progress(fraction);
    } catch (...) {
      failure = std::current_exception();
      cancel = true;
    }
  };
  glint::api::RenderResult result;
  {
    py::gil_scoped_release release;
    token->running = true;
    try {
      result = renderer.render(options);
    } catch (...) {
      token->running = false;
      throw;
    }
    token->running = false;
  }
  if (failure) std::rethrow_exception(failure);
  const auto address = reinterpret_cast<uintptr_t>(result.image.rgb.data());
  py::dict pass_arrays;
  for (auto& [name, image] : result.passes)
    pass_arrays[py::str(name)] = name == "depth" ? depth_array(std::move(image)) : image_array(std::move(image));
  py::dict stats = stats_dict(result.stats, result.complete);
  return py::make_tuple(image_array(std::move(result.image)), pass_arrays, stats, address);
}

// --- meshes from arrays -------------------------------------------------

// vertices / normals / uvs: float32 or float64, shape (n, k), finite.
py::array_t<double, py::array::c_style | py::array::forcecast> float_rows(const py::object& value, const char* name,
                                                                         py::ssize_t k, py::ssize_t rows) {
  py::array a = py::array::ensure(value);
  if (!a) throw py::type_error(std::string(name) + ": expected a numpy array (or a sequence of numbers)");
  const char kind = a.dtype().kind();
  if (kind != 'f' && !(kind == 'i' || kind == 'u'))
    throw py::type_error(std::string(name) + ": expected float32 or float64 values, got dtype " +
                         py::str(a.dtype()).cast<std::string>());
  if (a.ndim() != 2 || a.shape(1) != k || (rows >= 0 && a.shape(0) != rows)) {
    std::string got = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) got += (i ? ", " : "") + std::to_string(a.shape(i));
    got += a.ndim() == 1 ? ",)" : ")";
    throw py::value_error(std::string(name) + ": expected shape (" + (rows >= 0 ? std::to_string(rows) : "n") + ", " +
                          std::to_string(k) + "), got " + got);
  }
  auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  const double* p = d.data();
  for (py::ssize_t i = 0; i < d.size(); ++i)
    if (!std::isfinite(p[i]) || std::abs(p[i]) > 3.4028234663852886e38)
      throw py::value_error(std::string(name) + "[" + std::to_string(i / k) + "]: " +
                            (std::isfinite(p[i]) ? "does not fit in a 32-bit float" : "not a finite number"));
  return d;
}

nlohmann::ordered_json rows_json(const double* p, py::ssize_t n, py::ssize_t k) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  out.get_ref<nlohmann::ordered_json::array_t&>().reserve(static_cast<size_t>(n));
  for (py::ssize_t i = 0; i < n; ++i) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (py::ssize_t c = 0; c < k; ++c) row.push_back(p[i * k + c]);
    out.push_back(std::move(row));
  }
  return out;
}

// The mesh object's JSON: `object` (type, material, transform... as JSON
// text) with the arrays added as "vertices", "triangles", "normals", "uvs".
std::string mesh_object_json(const std::string& object_json, const py::object& vertices, const py::object& triangles,
                             const py::object& normals, const py::object& uvs) {
  auto v = float_rows(vertices, "vertices", 3, -1);
  const py::ssize_t n = v.shape(0);
  if (n == 0) throw py::value_error("vertices: no vertices");
  py::array t = py::array::ensure(triangles);
  if (!t) throw py::type_error("triangles: expected a numpy array of integers");
  if (t.dtype().kind() != 'i' && t.dtype().kind() != 'u')
    throw py::type_error("triangles: expected int32 or int64 indices, got dtype " + py::str(t.dtype()).cast<std::string>());
  if (t.ndim() != 2 || t.shape(1) != 3 || t.shape(0) == 0) {
    std::string got = "(";
    for (py::ssize_t i = 0; i < t.ndim(); ++i) got += (i ? ", " : "") + std::to_string(t.shape(i));
    got += t.ndim() == 1 ? ",)" : ")";
    throw py::value_error("triangles: expected shape (m, 3) with m > 0, got " + got);
  }
  auto ti = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(t);
  if (t.dtype().kind() == 'u' && t.itemsize() == 8) {
    // uint64 above 2^63 would wrap in the cast: check the originals.
    auto tu = py::array_t<uint64_t, py::array::c_style | py::array::forcecast>::ensure(t);
    for (py::ssize_t i = 0; i < tu.size(); ++i)
      if (tu.data()[i] >= static_cast<uint64_t>(n))
        throw py::value_error("triangles[" + std::to_string(i / 3) + "]: vertex index " +
                              std::to_string(tu.data()[i]) + " out of range (" + std::to_string(n) + " vertices)");
  }
  nlohmann::ordered_json object = nlohmann::ordered_json::parse(object_json);
  object["vertices"] = rows_json(v.data(), n, 3);
  nlohmann::ordered_json tris = nlohmann::ordered_json::array();
  const int64_t* ip = ti.data();
  for (py::ssize_t i = 0; i < t.shape(0); ++i) {
    for (int c = 0; c < 3; ++c)
      if (ip[3 * i + c] < 0 || ip[3 * i + c] >= n)
        throw py::value_error("triangles[" + std::to_string(i) + "]: vertex index " + std::to_string(ip[3 * i + c]) +
                              " out of range (" + std::to_string(n) + " vertices)");
    tris.push_back({ip[3 * i], ip[3 * i + 1], ip[3 * i + 2]});
  }
  object["triangles"] = std::move(tris);
  if (!normals.is_none()) {
    auto a = float_rows(normals, "normals", 3, n);
    object["normals"] = rows_json(a.data(), n, 3);
  }
  if (!uvs.is_none()) {
    auto a = float_rows(uvs, "uvs", 2, n);
    object["uvs"] = rows_json(a.data(), n, 2);
  }
  return object.dump();
}

// --- images ---------------------------------------------------------------

glint::api::Image image_from_array(const py::object& value) {
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.ndim() != 3 || a.shape(2) != 3) throw py::value_error("image: expected an array of shape (H, W, 3)");
  glint::api::Image image;
  image.height = static_cast<int>(a.shape(0));
  image.width = static_cast<int>(a.shape(1));
  image.rgb.assign(a.data(), a.data() + a.size());
  return image;
}

glint::api::ToneMap tonemap_of(const std::string& name) {
  if (name == "clamp") return glint::api::ToneMap::clamp;
  if (name == "reinhard") return glint::api::ToneMap::reinhard;
  if (name == "aces") return glint::api::ToneMap::aces;
  throw py::value_error("tonemap: expected \"clamp\", \"reinhard\" or \"aces\", got \"" + name + "\"");
}

}  // namespace

PYBIND11_MODULE(_glint, m) {
  m.doc() = "glint's native layer (use the glint package, not this module)";
  m.attr("__version__") = glint::version();
  m.attr("embree_available") = glint::api::embree_available();

  scene_error_type() = py::reinterpret_steal<py::object>(
      PyErr_NewExceptionWithDoc("glint.SceneError",
                                "A scene (or an edit of one) that glint's loader refuses.\n\n"
                                "str(e) is the message the glint CLI prints after 'error: '. Attributes:\n"
                                "file, line, column (None where they do not apply), path (the value's\n"
                                "path in the scene document, e.g. 'materials.floor.shininess', or None)\n"
                                "and message (the problem, path first, without the file location).",
                                PyExc_ValueError, nullptr));
  m.attr("SceneError") = scene_error_type();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const glint::Error& e) {
      raise_scene_error(e);
    }
  });

  py::class_<Scene>(m, "Scene")
      .def_static("load", &Scene::load, py::arg("path"))
      .def_static("from_json", &Scene::from_json, py::arg("text"), py::arg("base_dir"), py::arg("name"))
      .def("copy", [](const Scene& s) { return Scene(s); })
      .def("to_json", &Scene::to_json, py::arg("indent") = -1)
      .def_property_readonly("base_dir", [](const Scene& s) { return s.base_dir().string(); })
      .def_property_readonly("name", &Scene::name)
      .def("get", &Scene::get, py::arg("path"))
      .def("has", &Scene::has, py::arg("path"))
      .def("set_json", &Scene::set_json, py::arg("path"), py::arg("json"))
      .def("erase", &Scene::erase, py::arg("path"))
      .def("append_json", &Scene::append_json, py::arg("path"), py::arg("json"))
      .def_property_readonly("warnings", &Scene::warnings)
      .def_property_readonly("width", &Scene::width)
      .def_property_readonly("height", &Scene::height)
      .def_property_readonly("object_count", &Scene::object_count)
      .def_property_readonly("light_count", &Scene::light_count)
      .def_property_readonly("material_names", &Scene::material_names)
      .def_property_readonly("geometry_key", &Scene::geometry_key);

  py::class_<Renderer>(m, "Renderer")
      .def(py::init([](const Scene& scene, int threads, const std::string& accel, int frame) {
             glint::api::PrepareOptions o;
             o.threads = threads;
             o.frame = frame;
             if (accel == "embree") {
               if (!glint::api::embree_available())
                 throw py::value_error("accel: this build of glint has no Embree backend");
               o.accel = glint::api::Accel::embree;
             } else if (accel != "bvh") {
               throw py::value_error("accel: expected \"bvh\" or \"embree\", got \"" + accel + "\"");
             }
             py::gil_scoped_release release;  // building a large BVH takes a while
             return std::make_unique<Renderer>(scene, o);
           }),
           py::arg("scene"), py::arg("threads") = 0, py::arg("accel") = "bvh", py::arg("frame") = 0)
      .def(
          "update",
          [](Renderer& r, const Scene& scene) {
            py::gil_scoped_release release;
            r.update(scene);
          },
          py::arg("scene"))
      .def("render", &render, py::arg("passes"), py::arg("threads"), py::arg("progress"), py::arg("cancel"))
      .def("explain_json", &Renderer::explain_json, py::arg("x"), py::arg("y"))
      .def("explain_text", &Renderer::explain_text, py::arg("x"), py::arg("y"));

  py::class_<CancelToken>(m, "CancelToken",
                          "Stops a render from another thread: pass it as glint.render(..., cancel=token)\n"
                          "and call token.cancel(); the render stops within a row of pixels and returns\n"
                          "what it has (stats['complete'] is False).")
      .def(py::init<>())
      .def(
          "cancel", [](CancelToken& t) { t.cancelled = true; }, "Asks the render to stop (any thread).")
      .def(
          "reset", [](CancelToken& t) { t.cancelled = false; }, "Clears the request, for the next render.")
      .def_property_readonly(
          "cancelled", [](const CancelToken& t) { return t.cancelled.load(); }, "Whether cancel() was called.")
      .def_property_readonly(
          "running", [](const CancelToken& t) { return t.running.load(); },
          "True while a render using this token is rendering its pixels.");

  m.def("mesh_object_json", &mesh_object_json, py::arg("object_json"), py::arg("vertices"), py::arg("triangles"),
        py::arg("normals"), py::arg("uvs"));
  m.def(
      "write_image",
      [](const py::object& array, const std::string& path, double exposure, const std::string& tonemap) {
        glint::api::WriteOptions o;
        o.exposure = exposure;
        o.tonemap = tonemap_of(tonemap);
        glint::api::write_image(image_from_array(array), path, o);
      },
      py::arg("image"), py::arg("path"), py::arg("exposure") = 0.0, py::arg("tonemap") = "clamp");
  m.def(
      "read_image",
      [](const std::string& path) { return image_array(glint::api::read_image(path)); }, py::arg("path"));
}
