// Tests of the Assimp loader on the shared glTF samples (counts, bounds, sharing, classes,
// animated transforms, morph and skin points at chosen times, computed by hand from the
// files' accessors), on OBJ/PLY, and on broken files.
#define BOOST_TEST_MODULE loaders_gltf
#include <boost/test/unit_test.hpp>

#include <unistd.h>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "NodeQueries.h"
#include "SharedData.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AssimpLoader.h"
#include "tracegraph/nodes/Material.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/Texture.h"
#include "tracegraph/nodes/Transform.h"
#include "tracegraph/scenegraph/Group.h"
#include "tracegraph/scenegraph/SceneGraph.h"

namespace fs = std::filesystem;
namespace utf = boost::unit_test;
namespace tt = boost::test_tools;
using namespace tg;
using namespace tg::test;

namespace {

const fs::path kGltf = fs::path(TG_DATA_DIR) / "gltf";

tg::test::FilesAvailable SamplesAvailable() {
  return {"glTF samples", kGltf, {kGltf / "BoxAnimated/BoxAnimated.gltf"}};
}

bool near(const Vec3f& a, const Vec3f& b, float tol = 1e-4f) {
  return length(a - b) <= tol;
}

bool anyWarning(const LoadedScene& s, const std::string& part) {
  for (const std::string& w : s.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

/// Loads a sample and syncs it at each time, checking the triangles of each class.
struct Classes {
  std::size_t statics, rigid, deforming;
};
void checkClasses(const fs::path& file, Classes expected) {
  const LoadedScene s = loadAssimp(file);
  SceneGraph g;
  g.setRoot(s.root);
  for (const double t : {0.0, 0.4, 1.3}) {
    g.advanceTo(t);
    const FrameStats st = g.sync();
    BOOST_TEST(st.triangles.statics == expected.statics, file.filename() << " t=" << t);
    BOOST_TEST(st.triangles.rigid == expected.rigid, file.filename() << " t=" << t);
    BOOST_TEST(st.triangles.deforming == expected.deforming, file.filename() << " t=" << t);
  }
}

std::string base64(const std::vector<unsigned char>& b) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < b.size(); i += 3) {
    const unsigned v =
        b[i] << 16 | (i + 1 < b.size() ? b[i + 1] << 8 : 0) | (i + 2 < b.size() ? b[i + 2] : 0);
    out += k[v >> 18 & 63];
    out += k[v >> 12 & 63];
    out += i + 1 < b.size() ? k[v >> 6 & 63] : '=';
    out += i + 2 < b.size() ? k[v & 63] : '=';
  }
  return out;
}

/// Bytes of floats (little endian, as on every platform this builds for).
std::vector<unsigned char> bytes(const std::vector<float>& f) {
  std::vector<unsigned char> b(f.size() * 4);
  std::memcpy(b.data(), f.data(), b.size());
  return b;
}

/// One triangle plus an optional translation animation; `body` edits go into the JSON.
std::string triangleGltf(const std::vector<float>& positions, const std::string& extraNodes = "",
                         const std::string& animation = "", const std::string& scene = "[0]") {
  std::vector<float> data = positions;  // 9 floats, then animation times and values
  const bool cubic = animation == "CUBICSPLINE";
  const std::vector<float> times = {0.0f, 1.0f, 2.0f};
  // Cubic splines store (in-tangent, value, out-tangent) per key.
  const std::vector<float> values =
      cubic ? std::vector<float>{0, 0, 0, 0, 0, 0, 9, 9, 9, 9, 9, 9, 4, 0,
                                 0, 9, 9, 9, 9, 9, 9, 4, 8, 0, 0, 0, 0}
            : std::vector<float>{0, 0, 0, 4, 0, 0, 4, 8, 0};
  const std::string valueCount = cubic ? "9" : "3";
  data.insert(data.end(), times.begin(), times.end());
  data.insert(data.end(), values.begin(), values.end());
  const std::string uri = "data:application/octet-stream;base64," + base64(bytes(data));
  std::string anim;
  if (!animation.empty())
    anim = R"(,"animations":[{"samplers":[{"input":1,"output":2,"interpolation":")" + animation +
           R"("}],"channels":[{"sampler":0,"target":{"node":0,"path":"translation"}}]}])";
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":)" + scene +
         R"(}],"nodes":[{"mesh":0})" + extraNodes +
         R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"buffers":[{"byteLength":)" +
         std::to_string(data.size() * 4) + R"(,"uri":")" + uri +
         R"("}],"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":12},)"
         R"({"buffer":0,"byteOffset":48,"byteLength":)" +
         std::to_string(values.size() * 4) +
         R"(}],"accessors":[)"
         R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
         R"({"bufferView":1,"componentType":5126,"count":3,"type":"SCALAR"},)"
         R"({"bufferView":2,"componentType":5126,"count":)" +
         valueCount + R"(,"type":"VEC3"}])" + anim + "}";
}

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("tg_gltf_test_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return path / name;
  }
};

template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

}  // namespace

BOOST_AUTO_TEST_SUITE(samples, *utf::precondition(SamplesAvailable()))

BOOST_AUTO_TEST_CASE(box_textured_material_and_bounds) {
  const LoadedScene s = loadAssimp(kGltf / "BoxTextured-glTF/BoxTextured.gltf");
  BOOST_TEST(s.warnings.empty());
  const auto textures = distinct<nodes::Texture>(s.root.get());
  BOOST_REQUIRE(textures.size() == 1u);
  BOOST_TEST(fs::path((*textures.begin())->fileName()).filename() == "CesiumLogoFlat.png");
  // Base colour white (default factor), metallic 0, roughness 1 (default).
  const auto mats = distinct<nodes::Material>(s.root.get());
  BOOST_REQUIRE(mats.size() == 1u);
  const nodes::Material& m = **mats.begin();
  BOOST_TEST(m.diffuseColor.getValue().r == 1.0f);
  BOOST_TEST(m.specularColor.getValue().g == 0.04f, tt::tolerance(1e-6f));
  BOOST_TEST(m.shininess.getValue() == 0.0f);
  SceneGraph g;
  g.setRoot(s.root);
  g.sync();
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 12u);
  BOOST_TEST(near(g.backendScene().bounds().lower, {-0.5f, -0.5f, -0.5f}));
  BOOST_TEST(near(g.backendScene().bounds().upper, {0.5f, 0.5f, 0.5f}));
  checkClasses(kGltf / "BoxTextured-glTF/BoxTextured.gltf", {12, 0, 0});
}

BOOST_AUTO_TEST_CASE(engine_reuses_meshes) {
  const LoadedScene s = loadAssimp(kGltf / "2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
  // 29 glTF meshes of 34 primitives, placed 115 times by the node tree.
  BOOST_TEST(distinct<nodes::Mesh>(s.root.get()).size() == 34u);
  std::size_t placements = 0;
  walk(s.root.get(), [&](Node* n) { placements += dynamic_cast<nodes::Mesh*>(n) != nullptr; });
  BOOST_TEST(placements == 115u);
  BOOST_TEST(s.cameras.size() == 1u);
  BOOST_TEST(s.cameras[0]->fov.getValue() == 0.3143464f, tt::tolerance(1e-5f));
  SceneGraph g;
  g.setRoot(s.root);
  g.sync();
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 121496u);
  BOOST_TEST(g.backendScene().objectCount() < g.backendScene().instanceCount());
  const Box3f b = g.backendScene().bounds();
  BOOST_TEST(b.upper.x == 371.692f, tt::tolerance(1e-4f));
  BOOST_TEST(b.lower.x == -371.692f, tt::tolerance(1e-4f));
}

BOOST_AUTO_TEST_CASE(cameras_sample) {
  const LoadedScene s = loadAssimp(kGltf / "cameras/Cameras.gltf");
  BOOST_TEST(anyWarning(s, "orthographic camera"));
  BOOST_REQUIRE(s.cameras.size() == 1u);
  BOOST_TEST(s.cameras[0]->fov.getValue() == 0.7f);
  SceneGraph g;
  g.setRoot(s.root);
  g.sync();
  const auto cam = g.camera();
  BOOST_REQUIRE(cam.has_value());
  BOOST_TEST(near(cam->position, {0.5f, 0.5f, 3.0f}));
  BOOST_TEST(near(cam->direction, {0.0f, 0.0f, -1.0f}));
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 2u);
}

BOOST_AUTO_TEST_CASE(animated_triangle_rotates) {
  const LoadedScene s = loadAssimp(kGltf / "AnimatedTriangle/AnimatedTriangle.gltf");
  BOOST_TEST(s.animationDuration == 1.0, tt::tolerance(1e-6));
  auto* t = named<nodes::Transform>(s.root.get(), "nodes[0]");
  BOOST_REQUIRE(t);
  SceneGraph g;
  g.setRoot(s.root);
  // Keys every 0.25 s, 90 degrees apart about +Z: 45 degrees at 0.125 s.
  g.advanceTo(0.125);
  g.sync();
  BOOST_TEST(t->rotation.getValue().angle == 0.785398f, tt::tolerance(1e-3f));
  BOOST_TEST(t->rotation.getValue().axis.z == 1.0f, tt::tolerance(1e-4f));
  g.advanceTo(0.25);
  g.sync();
  // (1,0,0) -> (0,1,0), (0,1,0) -> (-1,0,0).
  BOOST_TEST(near(g.backendScene().bounds().lower, {-1.0f, 0.0f, 0.0f}, 1e-3f));
  BOOST_TEST(near(g.backendScene().bounds().upper, {0.0f, 1.0f, 0.0f}, 1e-3f));
  checkClasses(kGltf / "AnimatedTriangle/AnimatedTriangle.gltf", {0, 1, 0});
}

BOOST_AUTO_TEST_CASE(box_animated_parent_and_child) {
  const fs::path file = kGltf / "BoxAnimated/BoxAnimated.gltf";
  const LoadedScene s = loadAssimp(file);
  BOOST_TEST(s.animationDuration == 3.70833, tt::tolerance(1e-5));
  auto* parent = named<nodes::Transform>(s.root.get(), "nodes[0]");
  auto* child = named<nodes::Transform>(s.root.get(), "nodes[2]");
  BOOST_REQUIRE((parent && child));
  SceneGraph g;
  g.setRoot(s.root);
  // Translation keys (0, 0) (1.25, 2.52) (2.5, 2.52) (3.708, 0): y = 1.26 at 0.625 s.
  g.advanceTo(0.625);
  g.sync();
  BOOST_TEST(near(parent->translation.getValue(), {0.0f, 1.26f, 0.0f}));
  // Rotation keys identity (1.25 s) to 180 degrees about X (2.5 s): 90 degrees at 1.875 s,
  // which turns the inner box (half extents 0.335, 0.5, 0.335) on its side at y = 2.52.
  g.advanceTo(1.875);
  g.sync();
  BOOST_TEST(child->rotation.getValue().angle == 1.570796f, tt::tolerance(1e-3f));
  BOOST_TEST(g.backendScene().bounds().upper.y == 2.52f + 0.33504f, tt::tolerance(1e-3f));
  checkClasses(file, {192, 62, 0});
}

BOOST_AUTO_TEST_CASE(simple_morph_weights) {
  const fs::path file = kGltf / "SimpleMorph/glTF/SimpleMorph.gltf";
  const LoadedScene s = loadAssimp(file);
  BOOST_TEST(s.animationDuration == 4.0);
  const auto meshes = distinct<nodes::Mesh>(s.root.get());
  BOOST_REQUIRE(meshes.size() == 1u);
  nodes::Mesh& m = **meshes.begin();
  SceneGraph g;
  g.setRoot(s.root);
  // Base (0.5,0.5,0) at vertex 2, targets add (-1,1,0) and (1,1,0); weights (0,0) (0,1)
  // (1,1) (1,0) (0,0) at 0..4 s.
  for (const auto& [t, v] :
       {std::pair{0.5, Vec3f(1.0f, 1.0f, 0.0f)}, std::pair{2.0, Vec3f(0.5f, 2.5f, 0.0f)},
        std::pair{3.5, Vec3f(0.0f, 1.0f, 0.0f)}}) {
    g.advanceTo(t);
    g.sync();
    BOOST_TEST(near(m.points[2], v), "t=" << t);
    BOOST_TEST(near(m.points[1], {1.0f, 0.0f, 0.0f}));
  }
  checkClasses(file, {0, 0, 1});
  checkClasses(kGltf / "AnimatedMorphCube/glTF/AnimatedMorphCube.gltf", {0, 0, 12});
  checkClasses(kGltf / "AnimatedMorphSphere/glTF/AnimatedMorphSphere.gltf", {0, 0, 960});
}

BOOST_AUTO_TEST_CASE(simple_skin_bends) {
  const fs::path file = kGltf / "simple_skin/simple_skin.gltf";
  const LoadedScene s = loadAssimp(file);
  BOOST_TEST(s.animationDuration == 5.5);
  nodes::Mesh& m = **distinct<nodes::Mesh>(s.root.get()).begin();
  SceneGraph g;
  g.setRoot(s.root);
  // Joints at (0,1,0); inverse bind matrices translate by (-0.5,-1,0), so the rest pose is
  // shifted by -0.5 in x. At 1 s the second joint is turned 90 degrees about Z.
  g.advanceTo(0.0);
  g.sync();
  BOOST_TEST(near(m.points[9], {0.5f, 2.0f, 0.0f}));
  g.advanceTo(1.0);
  g.sync();
  BOOST_TEST(near(m.points[8], {-1.0f, 0.5f, 0.0f}, 1e-3f));  // weight 1 on the turned joint
  BOOST_TEST(near(m.points[9], {-1.0f, 1.5f, 0.0f}, 1e-3f));
  BOOST_TEST(near(m.points[4], {-0.25f, 0.75f, 0.0f}, 1e-3f));  // half and half
  BOOST_TEST(near(m.points[0], {-0.5f, 0.0f, 0.0f}, 1e-3f));    // first joint only
  checkClasses(file, {0, 0, 8});
  checkClasses(kGltf / "simple_skin/quad_skin.glb", {0, 0, 2});
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_CASE(step_and_cubic_interpolation) {
  TempDir dir;
  for (const auto& [mode, at05, at15] :
       {std::tuple{"LINEAR", Vec3f(2, 0, 0), Vec3f(4, 4, 0)},
        std::tuple{"STEP", Vec3f(0, 0, 0), Vec3f(4, 0, 0)},
        std::tuple{"CUBICSPLINE", Vec3f(2, 0, 0), Vec3f(4, 4, 0)}}) {
    const LoadedScene s = loadAssimp(dir.write("anim.gltf", triangleGltf(kTriangle, "", mode)));
    BOOST_TEST(anyWarning(s, "CUBICSPLINE") == (std::string(mode) == "CUBICSPLINE"));
    auto* t = named<nodes::Transform>(s.root.get(), "nodes[0]");
    BOOST_REQUIRE(t);
    SceneGraph g;
    g.setRoot(s.root);
    g.advanceTo(0.5);
    g.sync();
    BOOST_TEST(near(t->translation.getValue(), at05), mode);
    g.advanceTo(1.5);
    const FrameStats st = g.sync();
    BOOST_TEST(near(t->translation.getValue(), at15), mode);
    BOOST_TEST(st.triangles.rigid == 1u);
    g.advanceTo(5.0);  // held at the last key
    g.sync();
    BOOST_TEST(near(t->translation.getValue(), {4, 8, 0}), mode);
  }
  // Looping wraps the clip (2 s): 2.5 s is 0.5 s into the second cycle.
  AssimpOptions loop;
  loop.loop = true;
  const LoadedScene s =
      loadAssimp(dir.write("loop.gltf", triangleGltf(kTriangle, "", "LINEAR")), loop);
  SceneGraph g;
  g.setRoot(s.root);
  g.advanceTo(2.5);
  g.sync();
  BOOST_TEST(
      near(named<nodes::Transform>(s.root.get(), "nodes[0]")->translation.getValue(), {2, 0, 0}));
}

BOOST_AUTO_TEST_CASE(obj_and_ply_load_through_the_same_path) {
  TempDir dir;
  const fs::path obj =
      dir.write("cube.obj",
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n");
  const fs::path ply = dir.write("tri.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                 "property float y\nproperty float z\nelement face 1\n"
                                 "property list uchar int vertex_indices\nend_header\n"
                                 "0 0 0\n2 0 0\n0 3 0\n3 0 1 2\n");
  for (const auto& [file, tris, upper] :
       {std::tuple{obj, 12u, Vec3f(1, 1, 1)}, std::tuple{ply, 1u, Vec3f(2, 3, 0)}}) {
    const LoadedScene s = loadAssimp(file);
    SceneGraph g;
    g.setRoot(s.root);
    const FrameStats st = g.sync();
    BOOST_TEST(g.backendScene().instancedTriangleCount() == tris, file.filename());
    BOOST_TEST(st.triangles.statics == tris);
    BOOST_TEST(near(g.backendScene().bounds().upper, upper));
  }
}

BOOST_AUTO_TEST_CASE(broken_files_are_rejected_with_the_file_name) {
  TempDir dir;
  const std::string good = triangleGltf(kTriangle);
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const std::size_t at = t.find(from);
    BOOST_REQUIRE(at != std::string::npos);
    return t.replace(at, from.size(), to);
  };
  const float nan = std::nanf("");
  const std::pair<std::string, std::string> cases[] = {
      {R"({"asset": {"version": "2.0"}, "nodes": [)", "malformed JSON"},
      {triangleGltf(kTriangle, R"(,{"children":[2]},{"children":[1]})", "", "[0,1]"),
       "recursive node reference"},
      {triangleGltf(kTriangle, R"(,{"children":[1]})", "", "[0,1]"), "node 1 is its own child"},
      {triangleGltf(kTriangle, R"(,{"children":[7]})", "", "[0,1]"), "child index out of range"},
      {triangleGltf(kTriangle, "", "", "[]"), "the scene has no nodes"},
      {triangleGltf(kTriangle, "", "", "[4]"), "scene node index out of range"},
      {replaced(R"("nodes":[{"mesh":0})", R"("nodes":[{"mesh":5})"), "names mesh 5 of 1"},
      {replaced(R"("meshes":[{)", R"("meshes":5,"x":[{)"), "names mesh 0 of 0"},
      {triangleGltf({0, 0, 0, 1, nan, 0, 0, 1, 0}), "NaN or infinite vertex position"},
      {replaced("data:application/octet-stream;base64,", "missing.bin#"), ""},
      {replaced(R"("count":3,"type":"VEC3"},)", R"("count":300,"type":"VEC3"},)"),
       "accessor 0 reads past the end"},
      {replaced(R"("componentType":5126,"count":3,"type":"VEC3"},)",
                R"("componentType":"float","count":3,"type":"VEC3"},)"),
       "accessor 0 has a missing or wrongly typed componentType"},
      {replaced(R"("byteOffset":48,)", R"("byteOffset":4800,)"), "bufferView 2 lies outside"},
  };
  for (const auto& [text, expected] : cases) {
    const fs::path file = dir.write("bad.gltf", text);
    const std::string e = errorOf([&] { loadAssimp(file); });
    BOOST_TEST(e.find(file.string()) == 0u, "no file name in '" << e << "' for " << text);
    BOOST_TEST(e.find(expected) != std::string::npos, "got '" << e << "', wanted " << expected);
  }
  BOOST_TEST(errorOf([&] { loadAssimp(dir.path / "none.gltf"); }).find("no such file") !=
             std::string::npos);
  // A missing texture only drops the texture.
  const std::string textured =
      replaced(R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}])",
               R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],)"
               R"("materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},)"
               R"("baseColorFactor":[1,0.5,0.25,1],"metallicFactor":0.5,"roughnessFactor":0.5}}],)"
               R"("textures":[{"source":0}],"images":[{"uri":"nope.png"}])");
  const LoadedScene s = loadAssimp(dir.write("tex.gltf", textured));
  BOOST_TEST(anyWarning(s, "texture image 'nope.png' not found"));
  BOOST_TEST(distinct<nodes::Texture>(s.root.get()).empty());
  // Metallic 0.5: diffuse = base / 2, specular = mix(0.04, base, 0.5); roughness 0.5:
  // exponent 2 / 0.0625 - 2 = 30, shininess 30 / 128.
  const nodes::Material& m = **distinct<nodes::Material>(s.root.get()).begin();
  BOOST_TEST(m.diffuseColor.getValue().g == 0.25f, tt::tolerance(1e-6f));
  BOOST_TEST(m.specularColor.getValue().r == 0.52f, tt::tolerance(1e-6f));
  BOOST_TEST(m.shininess.getValue() == 30.0f / 128.0f, tt::tolerance(1e-6f));
}
