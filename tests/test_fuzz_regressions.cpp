// Every input the fuzzers (fuzz/) ever crashed on, kept in fuzz/regressions/,
// and the seed corpus in fuzz/corpus/: the JSON reader and the scene loader
// must accept each one or throw glint::Error, and nothing else. A sanitizer
// build (scripts/test.sh's build-asan) runs this too, so a memory error or UB
// on any of these files fails the suite. Below those: one focused test per bug
// the fuzzers found, pinning the fixed behaviour.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include "glint/error.h"
#include "glint/io/json.h"
#include "glint/io/mesh_file.h"
#include "glint/io/scene_loader.h"
#include "glint/io/texture_file.h"
#include "needs_assimp.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

const fs::path kFuzzDir = fs::path(GLINT_SOURCE_DIR) / "fuzz";
constexpr size_t kTextureBudget = size_t(512) << 20;  // fuzz_texture_*'s

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Regular files under `dir` (recursively), sorted for stable output.
std::vector<fs::path> files_under(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().filename() != "README.md") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// What escaped from `f`: "" for nothing or a glint::Error, else a description.
template <class F>
std::string only_glint_errors(F&& f) {
  try {
    f();
  } catch (const Error&) {
    return "";
  } catch (const std::exception& e) {
    return std::string("non-glint exception ") + typeid(e).name() + ": " + e.what();
  } catch (...) {
    return "non-std exception";
  }
  return "";
}

// Runs the fuzz targets' entry points on one input, as the fuzzers do:
// json::parse and parse_scene throw nothing but glint::Error, and
// validate_scene throws nothing and finds no error exactly when parse_scene
// (reading relative paths from the same folder) loads the scene.
// Mesh files (.obj, .ply, .gltf, .glb) also go through the mesh reader, as
// fuzz_mesh_* do.
void expect_only_glint_errors(const fs::path& file) {
  const fs::path ext = file.extension();
  if (ext == ".nff") {
    // NFF (fuzz_nff's seeds) is read by load_scene's NFF path, not as JSON.
    bool loaded = false;
    EXPECT_EQ(only_glint_errors([&] {
                load_scene(file);
                loaded = true;
              }),
              "")
        << "load_scene on " << file;
    std::vector<Error> errors;
    EXPECT_NO_THROW(errors = validate_scene(file)) << file;
    EXPECT_EQ(errors.empty(), loaded) << "validate_scene and load_scene disagree on " << file;
    return;
  }
  if (ext == ".obj" || ext == ".ply" || ext == ".gltf" || ext == ".glb") {
    EXPECT_EQ(only_glint_errors([&] { load_mesh_file(file); }), "") << "load_mesh_file on " << file;
  }
  if (ext == ".png" || ext == ".jpg" || ext == ".bmp" || ext == ".tga" || ext == ".hdr" || ext == ".pfm" ||
      ext == ".exr") {
    // As fuzz_texture_* read them, with their memory budget.
    EXPECT_EQ(only_glint_errors([&] { load_texture_image(file, kTextureBudget); }), "")
        << "load_texture_image on " << file;
    return;
  }
  const std::string text = read_bytes(file);
  const std::string name = file.filename().string();
  EXPECT_EQ(only_glint_errors([&] { json::parse(text, name); }), "") << "json::parse on " << file;
  EXPECT_EQ(only_glint_errors([&] { parse_scene(text, name, {}); }), "") << "parse_scene on " << file;
  bool loaded = false;
  EXPECT_EQ(only_glint_errors([&] {
              parse_scene(text, name, file.parent_path());
              loaded = true;
            }),
            "")
      << "parse_scene on " << file;
  std::vector<Error> errors;
  try {
    errors = validate_scene(file);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "validate_scene threw on " << file << ": " << e.what();
    return;
  }
  EXPECT_EQ(errors.empty(), loaded) << "validate_scene and parse_scene disagree on " << file
                                    << (errors.empty() ? std::string() : ": " + std::string(errors.front().what()));
}

TEST(FuzzRegressions, EveryCrashInputGivesOnlyGlintErrors) {
  const auto files = files_under(kFuzzDir / "regressions");
  ASSERT_FALSE(files.empty()) << "no regression inputs in " << kFuzzDir / "regressions";
  for (const auto& file : files) {
    SCOPED_TRACE(file.string());
    expect_only_glint_errors(file);
  }
}

TEST(FuzzRegressions, SeedCorpusGivesOnlyGlintErrors) {
  const auto start = std::chrono::steady_clock::now();
  const auto files = files_under(kFuzzDir / "corpus");
  ASSERT_GE(files.size(), 20u) << "seed corpus missing under " << kFuzzDir / "corpus";
  for (const auto& file : files) {
    SCOPED_TRACE(file.string());
    expect_only_glint_errors(file);
  }
  // The corpus is small seeds; this must stay a quick test (even under ASan).
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
}

// The repository's own scenes are in the corpus and must load.
TEST(FuzzRegressions, SceneSeedsFromScenesFolderLoad) {
  for (const auto& file : files_under(fs::path(GLINT_SOURCE_DIR) / "scenes")) {
    if (file.extension() != ".json") continue;
    SCOPED_TRACE(file.string());
    EXPECT_NO_THROW(load_scene(file));
  }
}

// --- one test per fixed finding ---------------------------------------------

Error json_error(const std::string& text) {
  try {
    json::parse(text, "t.json");
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error for: " << text;
  return Error("no error");
}

// nlohmann's lexer skips a byte-order mark itself, so a second BOM after the
// one json::parse skips used to be skipped silently too, leaving every token
// position 3 bytes off and the error pointing at the BOM's last byte (1:3,
// "unexpected byte 0xBF"). Only one leading BOM is allowed; a second one is
// an error at its first byte.
TEST(FuzzRegressions, SecondByteOrderMarkIsAnErrorAtItsStart) {
  for (const char* text :
       {"\xEF\xBB\xBF\xEF\xBB\xBF{}", "\xEF\xBB\xBF\xEF\xBB\xBF[\"\",\"\",\"\"]", "\xEF\xBB\xBF\xEF\xBB\xBF 5"}) {
    const Error e = json_error(text);
    EXPECT_EQ(e.location().line, 1) << e.what();
    EXPECT_EQ(e.location().column, 1) << e.what();
    EXPECT_EQ(e.message(), "syntax error: unexpected byte-order mark (only one may start the file)");
  }
  // Without a first BOM, a BOM is still skipped once (the first is allowed).
  EXPECT_NO_THROW(json::parse("\xEF\xBB\xBF{}", "t.json"));
  // A BOM anywhere else is an unexpected byte where it is.
  const Error e = json_error("{} \xEF\xBB\xBF");
  EXPECT_EQ(e.location().column, 4) << e.what();
}

}  // namespace
}  // namespace glint

namespace glint {
namespace {

// The error a regression mesh gives ("" if it loads).
std::string mesh_error(const std::string& name) {
  try {
    load_mesh_file(kFuzzDir / "regressions/mesh" / name);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// fuzz_mesh_ply: header lines broken by bare carriage returns, which this
// reader and assimp split differently; assimp crashed (SEGV) in its binary
// reader. Refused now.
TEST(FuzzRegressions, PlyHeaderWithBareCarriageReturnsIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  const std::string e = mesh_error("ply-bare-carriage-returns-in-header.ply");
  EXPECT_NE(e.find("PLY header line has a carriage return inside it"), std::string::npos) << e;
}

// fuzz_mesh_ply: a PLY header with two format lines reached assimp, which
// leaked; it is now refused by our header check.
TEST(FuzzRegressions, PlyWithTwoFormatLinesIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  EXPECT_NE(mesh_error("ply-two-format-lines.ply").find("more than one format line"), std::string::npos);
}

// fuzz_mesh_ply: a header with two 'face' elements (a damaged header line
// turned the rest into a second copy) made assimp leak the first face list.
TEST(FuzzRegressions, PlyWithARepeatedElementIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  const std::string e = mesh_error("ply-two-face-elements.ply");
  EXPECT_NE(e.find(":13:9: PLY element 'face' declared twice (first on line 7)"), std::string::npos) << e;
}

// fuzz_mesh_glb: an index accessor without componentType made assimp leak
// the faces it had built; every accessor now needs a valid componentType
// and type (both required by the glTF specification).
TEST(FuzzRegressions, GltfAccessorWithoutComponentTypeIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  const std::string e = mesh_error("glb-accessor-without-component-type.glb");
  EXPECT_NE(e.find(".glb: accessors[1]: needs a componentType of 5120"), std::string::npos) << e;
}

// fuzz_mesh_gltf: a node with a skin whose inverseBindMatrices are missing
// (optional in the specification) made assimp 5.2 dereference null. Skins
// (with animations, morph targets, cameras and unused vertex attributes) no
// longer reach assimp: glint ignores them, so the mesh loads.
TEST(FuzzRegressions, GltfSkinWithoutInverseBindMatricesLoadsWithoutTheSkin) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  EXPECT_EQ(mesh_error("gltf-skin-without-inverse-bind-matrices.gltf"), "");
  EXPECT_EQ(load_mesh_file(kFuzzDir / "regressions/mesh/gltf-skin-without-inverse-bind-matrices.gltf").triangle_count(),
            8u);  // its index accessor counts 24
}

// fuzz_mesh_gltf: a sparse accessor without its 'indices' made assimp 5.2
// dereference null (and one whose count its buffer views cannot hold made
// it read past the buffer); sparse accessors are checked whole first.
TEST(FuzzRegressions, GltfSparseAccessorWithoutIndicesIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  const std::string e = mesh_error("gltf-sparse-without-indices.gltf");
  EXPECT_NE(e.find(".gltf:1:238: accessors[0].sparse: needs 'indices' and 'values' objects"), std::string::npos) << e;
}

// fuzz_mesh_ply: an ASCII vertex line with more values than the header
// declares (and garbage among them): glint's walk read the line's first six,
// assimp reads values as one stream, met the garbage and leaked.
TEST(FuzzRegressions, PlyLineWithExtraValuesIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  const std::string e = mesh_error("ply-extra-values-on-a-line.ply");
  EXPECT_NE(e.find(":17:13: vertex 1: more values on the line than the header declares"), std::string::npos) << e;
}

// fuzz_mesh_glb: an index accessor on a buffer view with a byte stride,
// reaching past the view: assimp checks count x element size only, reads
// the strided indices one by one, throws half-way and leaks the faces.
TEST(FuzzRegressions, GltfAccessorBeyondItsStridedViewIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  const std::string e = mesh_error("glb-indices-beyond-their-strided-view.glb");
  EXPECT_NE(e.find(".glb: accessors[1]: 36 elements need 424 bytes of buffer view 0, which has 288"), std::string::npos)
      << e;
}

// fuzz_mesh_glb: a LINE_LOOP primitive (mode 2) with out-of-range indices
// made assimp 5.2 dereference null (in Release too). Line loops reach it as
// line strips now (glint ignores lines), so the indices are the error.
TEST(FuzzRegressions, GltfLineLoopWithIndicesOutOfRangeIsAnError) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  const std::string e = mesh_error("glb-line-loop-indices-out-of-range.glb");
  EXPECT_NE(e.find(".glb: face with a vertex index out of range"), std::string::npos) << e;
}

// Found by hand next to the LINE_LOOP finding: primitives with fewer indices
// than one point, line or triangle needs made assimp leak (a line strip of
// one index, a fan of two) or wrap the face count to 2^64 and fail to
// allocate (a strip of one). Such primitives are refused first.
TEST(FuzzRegressions, GltfPrimitivesWithTooFewIndicesAreRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  EXPECT_NE(mesh_error("gltf-strip-with-one-index.gltf")
                .find(".gltf:1:270: meshes[0].primitives[0]: 1 indices are too few for mode 5 (at least 3)"),
            std::string::npos);
  EXPECT_NE(mesh_error("gltf-fan-with-two-indices.gltf").find("2 indices are too few for mode 6 (at least 3)"),
            std::string::npos);
  EXPECT_NE(mesh_error("gltf-line-strip-with-one-index.gltf").find("1 indices are too few for mode 3 (at least 2)"),
            std::string::npos);
}

// fuzz_mesh_glb: a TRIANGLE_STRIP primitive without attributes (the key was
// damaged): assimp computed 0 - 2 faces and tried to allocate 64 GiB.
TEST(FuzzRegressions, GltfStripWithoutPositionsIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  const std::string e = mesh_error("glb-strip-without-attributes.glb");
  EXPECT_NE(e.find(".glb: meshes[0].primitives[0]: 0 vertices are too few for mode 5 (at least 3)"), std::string::npos)
      << e;
}

// fuzz_mesh_gltf: an embedded PNG whose base64 had a bad character: assimp's
// decoder threw and leaked its buffer. glint never decodes images, so a bad
// one reaches assimp as 3 zero bytes and the mesh loads.
TEST(FuzzRegressions, GltfImageWithBadBase64IsNotDecoded) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  EXPECT_EQ(mesh_error("gltf-image-with-bad-base64.gltf"), "");
}

// fuzz_mesh_gltf: an embedded image whose data URI had a media type without
// '/' ("data:im5125png;base64,...", a textured box) made assimp 5.2 call
// strcmp on strchr(type, '/') + 1, that is on address 1; so did an image in a
// buffer view with such a "mimeType" (by hand). glint never reads embedded
// images: they reach assimp as the same 3 zero bytes, and the mesh loads.
TEST(FuzzRegressions, GltfImageMediaTypeWithoutSlashLoads) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  for (const char* name : {"gltf-image-media-type-without-slash.gltf", "gltf-image-mime-type-without-slash.gltf",
                           "gltf-image-data-uri-long-header.gltf"}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(mesh_error(name), "");
    EXPECT_EQ(load_mesh_file(kFuzzDir / "regressions/mesh" / name).triangle_count(), 2u);  // two nodes
  }
}

// By hand, from assimp's data URI parser (next to the finding above): it
// stores the offsets of a URI's parts in the string's own first bytes as
// chars, so a header of 127 bytes or more before the ',' wrapped negative
// (a leak; the payload read from before the string), and a URI starting with
// byte 0x10 counted as parsed already (a 2^62-byte allocation). Buffers'
// URIs are checked for both.
TEST(FuzzRegressions, GltfBufferDataUriAssimpWouldMisreadIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  std::string e = mesh_error("gltf-buffer-data-uri-long-header.gltf");
  EXPECT_NE(e.find("buffers[0].uri: a data URI whose header (before the first ',') is longer than 126 bytes"),
            std::string::npos)
      << e;
  e = mesh_error("gltf-buffer-uri-starting-with-0x10.gltf");
  EXPECT_NE(e.find("buffers[0].uri: starts with a control character (not a URI)"), std::string::npos) << e;
}

// Found by fuzz_texture_*: each an error now, without a double free, a leak
// (the sanitized suite checks both) or a hang.
std::string texture_error(const std::string& name) {
  try {
    load_texture_image(kFuzzDir / "regressions/texture" / name, kTextureBudget);
  } catch (const Error& e) {
    return e.message();
  }
  return "no error";
}

TEST(FuzzRegressions, ExrWhosePixelsFailToDecodeIsFreedOnce) {
  EXPECT_TRUE(texture_error("exr-corrupt-pixels-double-free.exr").starts_with("cannot read texture: corrupt EXR data"))
      << texture_error("exr-corrupt-pixels-double-free.exr");
}

// A data window from y = -2^31 to 5: its height overflows an int, and
// tinyexr asked for 2^63 bytes of chunk offsets before reading a pixel.
TEST(FuzzRegressions, ExrWhoseDataWindowOverflowsIsRefused) {
  EXPECT_TRUE(texture_error("exr-data-window-overflows-int.exr").starts_with("cannot read texture: invalid EXR data window"))
      << texture_error("exr-data-window-overflows-int.exr");
}

TEST(FuzzRegressions, HdrWithARunOfLengthZeroIsRefused) {
  EXPECT_EQ(texture_error("hdr-run-of-length-zero.hdr"),
            "cannot read texture: corrupt or unsupported image: a run-length encoded scanline of the Radiance file "
            "holds a run of length 0 or ends early");
}

TEST(FuzzRegressions, TgaClaimingMoreThanTheBudgetIsRefusedBeforeDecoding) {
  EXPECT_EQ(texture_error("tga-claims-a-gigabyte.tga"),
            "cannot read texture: an image of 64264x1536 pixels needs 2.21 GiB, more than the memory budget of "
            "512 MiB");
}

}  // namespace
}  // namespace glint
