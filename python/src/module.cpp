// glint._glint: the pybind11 layer between Python and glint's public C++ API
// (include/glint/). It stays thin: the Pythonic API (views, Render, docs)
// lives in python/glint/__init__.py. What must be native is here: the GIL
// released while rendering, Ctrl-C seen on the calling thread, images handed
// to numpy without a copy, mesh arrays read (checked and converted) in one
// pass straight into the scene's own arrays, and glint::Error raised as
// glint.SceneError.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <glint/glint.h>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <string>
#include <type_traits>
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
// width and height > 0 render the scene's view at that size, as the CLI's
// --width and --height do (an NFF view's fov_y follows the height).
py::tuple render(const Renderer& renderer, const std::vector<std::string>& passes, int threads,
                 const py::object& progress, CancelToken* token, int width, int height) {
  CancelToken own;
  if (!token) token = &own;
  std::atomic<bool>& cancel = token->cancelled;
  std::exception_ptr failure;
  glint::api::RenderOptions options;
  options.threads = threads;
  options.passes = passes;
  options.width = width;
  options.height = height;
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
// Each array is read once, element by element through its strides, into the
// float32 / uint32 arrays the scene keeps (glint::api::MeshArrays): no
// intermediate array, no JSON. Values are checked as they are read.

std::string shape_text(const py::array& a) {
  std::string got = "(";
  // Appends only: GCC 12's LTO warns falsely (-Wstringop-overflow) on "..." + std::string here.
  for (py::ssize_t i = 0; i < a.ndim(); ++i) {
    if (i) got += ", ";
    got += std::to_string(a.shape(i));
  }
  got += a.ndim() == 1 ? ",)" : ")";
  return got;
}

// A numpy array as it is (a sequence of numbers becomes one first).
py::array array_of(const py::object& value, const char* name, const char* expected) {
  py::array a = py::array::ensure(value);
  if (!a) throw py::type_error(std::string(name) + ": expected " + expected);
  return a;
}

template <class T>
void read_float_rows(const py::array& a, py::ssize_t k, const char* name, std::vector<float>& out) {
  const auto r = a.unchecked<T, 2>();
  out.resize(static_cast<size_t>(r.shape(0) * k));
  float* o = out.data();
  for (py::ssize_t i = 0; i < r.shape(0); ++i)
    for (py::ssize_t c = 0; c < k; ++c) {
      const T x = r(i, c);
      const float f = static_cast<float>(x);
      if (!std::isfinite(f))
        throw py::value_error(
            std::string(name) + "[" + std::to_string(i) +
            "]: " + (std::isfinite(static_cast<double>(x)) ? "does not fit in a 32-bit float" : "not a finite number"));
      *o++ = f;
    }
}

// vertices / normals / uvs: (rows, k), float32 or float64 read as they are
// (integers and other floats are converted to float64 first), finite.
std::vector<float> float_rows(const py::object& value, const char* name, py::ssize_t k, py::ssize_t rows) {
  py::array a = array_of(value, name, "a numpy array (or a sequence of numbers)");
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + ": expected float32 or float64 values, got dtype " +
                         py::str(a.dtype()).cast<std::string>());
  if (a.ndim() != 2 || a.shape(1) != k || (rows >= 0 && a.shape(0) != rows))
    throw py::value_error(std::string(name) + ": expected shape (" + (rows >= 0 ? std::to_string(rows) : "n") + ", " +
                          std::to_string(k) + "), got " + shape_text(a));
  std::vector<float> out;
  if (py::isinstance<py::array_t<float>>(a)) {
    read_float_rows<float>(a, k, name, out);
  } else if (py::isinstance<py::array_t<double>>(a)) {
    read_float_rows<double>(a, k, name, out);
  } else {
    read_float_rows<double>(py::array(a.attr("astype")("float64")), k, name, out);
  }
  return out;
}

template <class T>
void read_indices(const py::array& a, size_t vertices, std::vector<uint32_t>& out) {
  const auto r = a.unchecked<T, 2>();
  out.resize(static_cast<size_t>(r.shape(0)) * 3);
  uint32_t* o = out.data();
  for (py::ssize_t t = 0; t < r.shape(0); ++t)
    for (py::ssize_t c = 0; c < 3; ++c) {
      const T i = r(t, c);
      bool bad = false;
      if constexpr (std::is_signed_v<T>) bad = i < 0;
      if (bad || static_cast<uint64_t>(i) >= vertices)
        throw py::value_error("triangles[" + std::to_string(t) + "]: vertex index " + std::to_string(i) +
                              " out of range (" + std::to_string(vertices) + " vertices)");
      *o++ = static_cast<uint32_t>(i);
    }
}

// triangles: (m, 3), m > 0, int32 or int64 (any integer type), 0-based.
std::vector<uint32_t> index_rows(const py::object& value, size_t vertices) {
  py::array t = array_of(value, "triangles", "a numpy array of integers");
  if (t.dtype().kind() != 'i' && t.dtype().kind() != 'u')
    throw py::type_error("triangles: expected int32 or int64 indices, got dtype " +
                         py::str(t.dtype()).cast<std::string>());
  if (t.ndim() != 2 || t.shape(1) != 3 || t.shape(0) == 0)
    throw py::value_error("triangles: expected shape (m, 3) with m > 0, got " + shape_text(t));
  std::vector<uint32_t> out;
  if (py::isinstance<py::array_t<int32_t>>(t)) read_indices<int32_t>(t, vertices, out);
  else if (py::isinstance<py::array_t<int64_t>>(t)) read_indices<int64_t>(t, vertices, out);
  else if (py::isinstance<py::array_t<uint32_t>>(t)) read_indices<uint32_t>(t, vertices, out);
  else if (py::isinstance<py::array_t<uint64_t>>(t)) read_indices<uint64_t>(t, vertices, out);
  else read_indices<int64_t>(py::array(t.attr("astype")("int64")), vertices, out);  // 8- and 16-bit integers
  return out;
}

// Scene.add_mesh: the arrays read into the scene's own (the one copy), then
// the object added with `object_json`'s keys (material, transform...).
void add_mesh(Scene& scene, const std::string& object_json, const py::object& vertices, const py::object& triangles,
              const py::object& normals, const py::object& uvs) {
  glint::api::MeshArrays arrays;
  arrays.positions = float_rows(vertices, "vertices", 3, -1);
  const size_t n = arrays.positions.size() / 3;
  if (n == 0) throw py::value_error("vertices: no vertices");
  arrays.triangles = index_rows(triangles, n);
  const auto rows = static_cast<py::ssize_t>(n);
  if (!normals.is_none()) arrays.normals = float_rows(normals, "normals", 3, rows);
  if (!uvs.is_none()) arrays.uvs = float_rows(uvs, "uvs", 2, rows);
  scene.add_mesh(std::move(arrays), object_json);
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
      .def("update_json", &Scene::update_json, py::arg("path"), py::arg("json"))
      .def("add_mesh", &add_mesh, py::arg("object_json"), py::arg("vertices"), py::arg("triangles"), py::arg("normals"),
           py::arg("uvs"))
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
      .def("render", &render, py::arg("passes"), py::arg("threads"), py::arg("progress"), py::arg("cancel"),
           py::arg("width") = 0, py::arg("height") = 0)
      .def("explain_json", &Renderer::explain_json, py::arg("x"), py::arg("y"), py::arg("width") = 0,
           py::arg("height") = 0)
      .def("explain_text", &Renderer::explain_text, py::arg("x"), py::arg("y"), py::arg("width") = 0,
           py::arg("height") = 0);

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

  m.def(
      "encode_image",
      [](const py::object& array, const std::string& format, double exposure, const std::string& tonemap) {
        glint::api::WriteOptions o;
        o.exposure = exposure;
        o.tonemap = tonemap_of(tonemap);
        const std::vector<unsigned char> bytes = glint::api::encode_image(image_from_array(array), format, o);
        return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
      },
      py::arg("image"), py::arg("format"), py::arg("exposure") = 0.0, py::arg("tonemap") = "clamp");
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
      "read_image", [](const std::string& path) { return image_array(glint::api::read_image(path)); }, py::arg("path"));
}
