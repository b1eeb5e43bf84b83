// Tests of the X3D loader: the shared samples (counts, bounds, classes, animation values
// computed by hand from the files), hand-written scenes for each geometry and animation
// feature, and every kind of bad input.
#define BOOST_TEST_MODULE loaders_x3d
#include <boost/test/unit_test.hpp>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "NodeQueries.h"
#include "SharedData.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/X3dLoader.h"
#include "tracegraph/nodes/Material.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/Switch.h"
#include "tracegraph/nodes/Texture.h"
#include "tracegraph/nodes/Transform.h"
#include "tracegraph/scenegraph/Group.h"
#include "tracegraph/scenegraph/SceneGraph.h"

namespace fs = std::filesystem;
namespace utf = boost::unit_test;
using namespace tg;
using namespace tg::test;

namespace {

const fs::path kX3d = fs::path(TG_DATA_DIR) / "x3d";

tg::test::FilesAvailable SamplesAvailable() {
  return {"X3D samples", kX3d, {kX3d / "HelloWorld.x3d", kX3d / "ComputerKeyboard.x3d"}};
}

/// Wraps a Scene body into a minimal X3D document.
std::string doc(const std::string& body) {
  return "<?xml version='1.0' encoding='UTF-8'?>\n<X3D profile='Immersive' version='3.3'>\n"
         "<Scene>\n" +
         body + "\n</Scene>\n</X3D>\n";
}

LoadedScene fromText(const std::string& body, const X3dOptions& o = {}) {
  return loadX3dString(doc(body), fs::temp_directory_path(), "test.x3d", o);
}

bool anyWarning(const LoadedScene& s, const std::string& part) {
  for (const std::string& w : s.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

/// The message of the tg::Error thrown by `f` (empty when none is thrown).
template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

double meshArea(const nodes::Mesh& m) {
  double a = 0.0;
  const auto& p = m.points.getValues();
  const auto& i = m.indices.getValues();
  for (std::size_t t = 0; t + 2 < i.size(); t += 3) {
    const Vec3d e1 = Vec3d(p[i[t + 1]]) - Vec3d(p[i[t]]), e2 = Vec3d(p[i[t + 2]]) - Vec3d(p[i[t]]);
    a += 0.5 * length(cross(e1, e2));
  }
  return a;
}

bool near(const Vec3f& a, const Vec3f& b, float tol = 1e-5f) {
  return length(a - b) <= tol;
}

/// A folder of its own under the temp directory, removed at the end.
struct TempDir {
  fs::path path = fs::temp_directory_path() / ("tg_x3d_test_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return path / name;
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// Shared samples

BOOST_AUTO_TEST_CASE(hello_world_sample, *utf::precondition(SamplesAvailable())) {
  const LoadedScene s = loadX3d(kX3d / "HelloWorld.x3d");
  BOOST_TEST(s.title == "Hello World!");
  // Text is not supported: one warning naming it and its line; the sphere still loads.
  BOOST_TEST(s.warnings.size() == 1u);
  BOOST_TEST(anyWarning(s, "HelloWorld.x3d:47: unsupported geometry Text"));
  BOOST_REQUIRE(s.cameras.size() == 1u);
  BOOST_TEST(near(s.cameras[0]->position.getValue(), {0.0f, -1.0f, 7.0f}));
  BOOST_TEST(distinct<nodes::Mesh>(s.root.get()).size() == 1u);
  const auto textures = distinct<nodes::Texture>(s.root.get());
  BOOST_REQUIRE(textures.size() == 1u);
  BOOST_TEST(fs::exists((*textures.begin())->fileName()));
  BOOST_TEST(s.animationDuration == 0.0);
  SceneGraph g;
  g.setRoot(s.root);
  const FrameStats st = g.sync();
  // Sphere: 32 slices x 16 stacks, one triangle per slice in the two pole rows.
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 2u * 32u * 15u);
  BOOST_TEST(st.triangles.statics == 960u);
  const Box3f b = g.backendScene().bounds();
  BOOST_TEST(b.lower.y == -1.0f, boost::test_tools::tolerance(1e-5f));
  BOOST_TEST(b.upper.y == 1.0f, boost::test_tools::tolerance(1e-5f));
  for (const float v : {b.lower.x, b.lower.z}) BOOST_TEST((v < -0.99f && v >= -1.0001f));
  for (const float v : {b.upper.x, b.upper.z}) BOOST_TEST((v > 0.99f && v <= 1.0001f));
}

BOOST_AUTO_TEST_CASE(computer_keyboard_sample, *utf::precondition(SamplesAvailable())) {
  const LoadedScene s = loadX3d(kX3d / "ComputerKeyboard.x3d");
  BOOST_TEST(anyWarning(s, "ComputerKeyboard.x3d:30: unsupported node TouchSensor"));
  BOOST_TEST(anyWarning(s, "ComputerKeyboard.x3d:228: ROUTE: no node named 'TouchButton'"));
  BOOST_TEST(s.warnings.size() == 2u);
  // Body, one key (DEF EscapeButton, used 97 more times), space bar: three meshes.
  BOOST_TEST(distinct<nodes::Mesh>(s.root.get()).size() == 3u);
  auto* key = named<nodes::Transform>(s.root.get(), "EscapeButton");
  BOOST_REQUIRE(key);
  BOOST_TEST(key->parents().size() == 1u);  // the Transform sits in the shared Separator
  BOOST_TEST(key->parents()[0]->parents().size() ==
             58u);  // 57 USEs; the row group of 20 is used 3 times
  // TimeSensor 'push': startTime 0, stopTime 0.5, cycle 1 s.
  BOOST_TEST(s.animationDuration == 0.5);
  SceneGraph g;
  g.setRoot(s.root);
  // Extrusions: body 11 side quads + two 11-corner caps = 40; key and space bar: 4 x 2 quads
  // + two quads = 20 each; the key is instanced 98 times and driven (rigid).
  const std::pair<double, float> expected[] = {{0.0, -0.065f}, {0.25, -0.0575f}, {1.0, -0.05f}};
  for (const auto& [t, z] : expected) {
    g.advanceTo(t);
    const FrameStats st = g.sync();
    BOOST_TEST(g.backendScene().instancedTriangleCount() == 40u + 20u + 98u * 20u);
    BOOST_TEST(st.triangles.statics == 60u);
    BOOST_TEST(st.triangles.rigid == 98u * 20u);
    BOOST_TEST(st.triangles.deforming == 0u);
    BOOST_TEST(g.backendScene().objectCount() < g.backendScene().instanceCount());
    // PositionInterpolator 'Move' keys 0 0.5 1; the fraction freezes at stopTime (0.5).
    BOOST_TEST(near(key->translation.getValue(), {0.1f, 0.95f, z}), "t=" << t);
  }
  // The body is rotated a quarter turn about X: its spine (0..0.98 along Y) runs along Z.
  const Box3f b = g.backendScene().bounds();
  BOOST_TEST(b.lower.x == 0.0f, boost::test_tools::tolerance(1e-3f));
  BOOST_TEST(b.upper.x == 0.45f, boost::test_tools::tolerance(1e-3f));
  BOOST_TEST(std::abs(b.lower.z) < 1e-3f);
  BOOST_TEST(b.upper.z == 0.98f, boost::test_tools::tolerance(1e-3f));
}

// ---------------------------------------------------------------------------------------------
// Geometry

BOOST_AUTO_TEST_CASE(concave_polygon_is_ear_clipped) {
  // An L-shaped hexagon of area 3: a fan from corner 0 would cover the notch.
  const LoadedScene s = fromText(
      "<Shape><IndexedFaceSet coordIndex='0 1 2 3 4 5 -1'>"
      "<Coordinate point='0 0 0, 2 0 0, 2 1 0, 1 1 0, 1 2 0, 0 2 0'/></IndexedFaceSet></Shape>");
  const auto meshes = distinct<nodes::Mesh>(s.root.get());
  BOOST_REQUIRE(meshes.size() == 1u);
  const nodes::Mesh& m = **meshes.begin();
  BOOST_TEST(m.triangleCount() == 4u);
  BOOST_TEST(meshArea(m) == 3.0, boost::test_tools::tolerance(1e-9));
  for (const Vec3f& n : m.normals.getValues()) BOOST_TEST(near(n, {0.0f, 0.0f, 1.0f}));
}

BOOST_AUTO_TEST_CASE(ccw_false_reverses_the_winding) {
  const LoadedScene s = fromText(
      "<Shape><IndexedFaceSet ccw='false' coordIndex='0 1 2'>"
      "<Coordinate point='0 0 0, 1 0 0, 0 1 0'/></IndexedFaceSet></Shape>");
  const nodes::Mesh& m = **distinct<nodes::Mesh>(s.root.get()).begin();
  const auto& p = m.points.getValues();
  const auto& i = m.indices.getValues();
  const Vec3f n = cross(p[i[1]] - p[i[0]], p[i[2]] - p[i[0]]);
  BOOST_TEST(n.z < 0.0f);
  BOOST_TEST(near(m.normals[0], {0.0f, 0.0f, -1.0f}));
}

BOOST_AUTO_TEST_CASE(crease_angle_splits_or_shares_vertices) {
  const std::string cube =
      "<Coordinate point='0 0 0, 1 0 0, 1 1 0, 0 1 0, 0 0 1, 1 0 1, 1 1 1, 0 1 1'/>";
  const std::string faces =
      "coordIndex='0 3 2 1 -1 4 5 6 7 -1 0 1 5 4 -1 2 3 7 6 -1 "
      "1 2 6 5 -1 0 4 7 3 -1'";
  for (const auto& [crease, vertices] : {std::pair{"0", 24u}, std::pair{"2", 8u}}) {
    const LoadedScene s = fromText("<Shape><IndexedFaceSet creaseAngle='" + std::string(crease) +
                                   "' " + faces + ">" + cube + "</IndexedFaceSet></Shape>");
    const nodes::Mesh& m = **distinct<nodes::Mesh>(s.root.get()).begin();
    BOOST_TEST(m.triangleCount() == 12u);
    BOOST_TEST(m.points.size() == vertices, "creaseAngle " << crease);
    BOOST_TEST(m.validate().empty());
  }
  // Smooth corners of a cube point along the diagonals, away from the centre.
  const LoadedScene s = fromText("<Shape><IndexedFaceSet creaseAngle='2' " + faces + ">" + cube +
                                 "</IndexedFaceSet></Shape>");
  const nodes::Mesh& m = **distinct<nodes::Mesh>(s.root.get()).begin();
  for (std::size_t v = 0; v < m.points.size(); ++v) {
    const Vec3f out = normalize(m.points[v] - Vec3f(0.5f, 0.5f, 0.5f));
    BOOST_TEST(dot(out, m.normals[v]) > 0.999f);
  }
}

BOOST_AUTO_TEST_CASE(colours_split_meshes_and_normals_follow_the_file) {
  const LoadedScene s = fromText(
      "<Shape><Appearance><Material specularColor='0.5 0.5 0.5'/></Appearance>"
      "<IndexedFaceSet colorPerVertex='false' colorIndex='1 0' normalPerVertex='false' "
      "coordIndex='0 1 2 -1 0 2 3'><Coordinate point='0 0 0, 1 0 0, 1 1 0, 0 1 0'/>"
      "<Color color='1 0 0, 0 0 1'/><Normal vector='0 0 2, 0 0 -1'/></IndexedFaceSet></Shape>");
  const auto meshes = distinct<nodes::Mesh>(s.root.get());
  BOOST_TEST(meshes.size() == 2u);
  std::set<std::tuple<float, float, float>> diffuse;
  for (nodes::Material* m : distinct<nodes::Material>(s.root.get())) {
    const Color c = m->diffuseColor.getValue();
    diffuse.insert({c.r, c.g, c.b});
    BOOST_TEST(m->specularColor.getValue().r == 0.5f);
  }
  BOOST_TEST(diffuse.count({1.0f, 0.0f, 0.0f}) == 1u);
  BOOST_TEST(diffuse.count({0.0f, 0.0f, 1.0f}) == 1u);
  // Per-face normals as given (normalised): the first face +Z, the second -Z.
  std::set<float> nz;
  for (nodes::Mesh* m : meshes) nz.insert(m->normals[0].z);
  BOOST_TEST((nz == std::set<float>{-1.0f, 1.0f}));
}

BOOST_AUTO_TEST_CASE(triangle_sets_and_strips) {
  const LoadedScene s = fromText(
      "<Shape><IndexedTriangleSet index='0 1 2 0 2 3'><Coordinate point='0 0 0, 1 0 0, 1 1 0, "
      "0 1 0'/></IndexedTriangleSet></Shape>"
      "<Shape><TriangleSet><Coordinate point='0 0 0, 1 0 0, 0 1 0, 0 0 1, 1 0 1, 0 1 1, 5 5 5'/>"
      "</TriangleSet></Shape>"
      "<Shape><IndexedTriangleStripSet index='0 1 2 3 -1'><Coordinate point='0 0 0, 1 0 0, 0 1 0, "
      "1 1 0'/></IndexedTriangleStripSet></Shape>");
  SceneGraph g;
  g.setRoot(s.root);
  g.sync();
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 2u + 2u + 2u);
  // The strip's second triangle is flipped back to the first one's facing.
  for (nodes::Mesh* m : distinct<nodes::Mesh>(s.root.get()))
    for (const Vec3f& n : m->normals.getValues()) BOOST_TEST(n.z > 0.99f);
}

BOOST_AUTO_TEST_CASE(primitives_are_tessellated) {
  X3dOptions o;
  o.sphereSlices = 8, o.sphereStacks = 4, o.cylinderSlices = 6;
  const LoadedScene s = fromText(
      "<Shape><Box size='2 4 6'/></Shape><Transform translation='10 0 0'><Shape>"
      "<Sphere radius='2'/></Shape></Transform><Transform translation='20 0 0'><Shape>"
      "<Cone bottomRadius='1' height='3'/></Shape></Transform><Transform translation='30 0 0'>"
      "<Shape><Cylinder radius='1' height='2' top='false'/></Shape></Transform>",
      o);
  std::map<std::size_t, Box3f> byTriangles;
  for (nodes::Mesh* m : distinct<nodes::Mesh>(s.root.get())) {
    BOOST_TEST(m->validate().empty());
    BOOST_TEST(m->texCoords.size() == m->points.size());
    byTriangles[m->triangleCount()] = m->localBounds();
  }
  // Box 12; sphere 2*8*(4-1) = 48; cone 6 side + 6 bottom = 12 (ties with the box);
  // cylinder 2*6 side + 6 bottom = 18.
  BOOST_TEST(byTriangles.count(48u) == 1u);
  BOOST_TEST(byTriangles.count(18u) == 1u);
  BOOST_TEST(near(byTriangles[48].upper, {2.0f * std::sin(3.14159265f / 2.0f), 2.0f, 2.0f}, 1e-4f));
  SceneGraph g;
  g.setRoot(s.root);
  g.sync();
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 12u + 48u + 12u + 18u);
  const Box3f b = g.backendScene().bounds();
  BOOST_TEST(near(b.lower, {-1.0f, -2.0f, -3.0f}, 1e-5f));
  // Six slices: the widest corners are at 60 degrees from the back.
  BOOST_TEST(b.upper.x == 30.0f + std::sin(3.14159265f / 3.0f),
             boost::test_tools::tolerance(1e-5f));
}

BOOST_AUTO_TEST_CASE(def_use_shares_nodes_and_objects) {
  const LoadedScene s = fromText(
      "<Transform DEF='spin'><Shape DEF='ball'><Sphere/></Shape></Transform>"
      "<Transform translation='3 0 0'><Shape USE='ball'/></Transform>"
      "<Transform translation='6 0 0'><Shape USE='ball'/></Transform>"
      "<TimeSensor DEF='clock' loop='true'/>"
      "<OrientationInterpolator DEF='rot' key='0 1' keyValue='0 1 0 0, 0 1 0 3'/>"
      "<ROUTE fromNode='clock' fromField='fraction_changed' toNode='rot' toField='set_fraction'/>"
      "<ROUTE fromNode='rot' fromField='value_changed' toNode='spin' toField='rotation'/>");
  BOOST_TEST(s.warnings.empty());
  const auto meshes = distinct<nodes::Mesh>(s.root.get());
  BOOST_REQUIRE(meshes.size() == 1u);
  BOOST_TEST((*meshes.begin())->parents()[0]->parents().size() == 3u);
  SceneGraph g;
  g.setRoot(s.root);
  g.advanceTo(0.5);
  const FrameStats st = g.sync();
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 3u * 960u);
  BOOST_TEST(g.instancesOf(**meshes.begin()).size() == 3u);
  BOOST_TEST(g.backendScene().objectCount() < g.backendScene().instanceCount());
  BOOST_TEST(st.triangles.rigid == 960u);  // only the first ball turns
  BOOST_TEST(st.triangles.statics == 2u * 960u);
}

BOOST_AUTO_TEST_CASE(switch_keeps_choice_numbers) {
  const LoadedScene s = fromText(
      "<Switch whichChoice='2'><Shape><Box/></Shape><Text/><Shape><Sphere/></Shape></Switch>");
  auto sw = distinct<nodes::Switch>(s.root.get());
  BOOST_REQUIRE(sw.size() == 1u);
  BOOST_TEST((*sw.begin())->numChildren() == 3u);
  SceneGraph g;
  g.setRoot(s.root);
  g.sync();
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 960u);  // the sphere
}

// ---------------------------------------------------------------------------------------------
// Animation

BOOST_AUTO_TEST_CASE(interpolators_drive_fields_on_the_scene_clock) {
  const LoadedScene s = fromText(
      "<Transform DEF='T'><Shape><Appearance><Material DEF='M'/></Appearance><Box/></Shape>"
      "</Transform>"
      "<TimeSensor DEF='clock' cycleInterval='2' loop='true'/>"
      "<PositionInterpolator DEF='P' key='0 0.5 1' keyValue='0 0 0, 4 0 0, 4 8 0'/>"
      "<OrientationInterpolator DEF='R' key='0 1' keyValue='0 0 1 0, 0 0 1 2'/>"
      "<ScalarInterpolator DEF='A' key='0 1' keyValue='0 1'/>"
      "<ROUTE fromNode='clock' fromField='fraction_changed' toNode='P' toField='set_fraction'/>"
      "<ROUTE fromNode='clock' fromField='fraction_changed' toNode='R' toField='set_fraction'/>"
      "<ROUTE fromNode='clock' fromField='fraction_changed' toNode='A' toField='set_fraction'/>"
      "<ROUTE fromNode='P' fromField='value_changed' toNode='T' toField='set_translation'/>"
      "<ROUTE fromNode='R' fromField='value_changed' toNode='T' toField='set_rotation'/>"
      "<ROUTE fromNode='A' fromField='value_changed' toNode='M' toField='set_transparency'/>");
  BOOST_TEST(s.warnings.empty());
  BOOST_TEST(s.animationDuration == 2.0);  // one cycle of a looping sensor
  auto* t = named<nodes::Transform>(s.root.get(), "T");
  auto* m = *distinct<nodes::Material>(s.root.get()).begin();
  BOOST_REQUIRE(t);
  SceneGraph g;
  g.setRoot(s.root);
  // t = 0.5 s: fraction 0.25, half way to key 0.5; t = 3 s: loop, fraction 0.5.
  for (const auto& [time, pos, angle, alpha] :
       {std::tuple{0.5, Vec3f(2.0f, 0.0f, 0.0f), 0.5f, 0.25f},
        std::tuple{1.5, Vec3f(4.0f, 4.0f, 0.0f), 1.5f, 0.75f},
        std::tuple{3.0, Vec3f(4.0f, 0.0f, 0.0f), 1.0f, 0.5f}}) {
    g.advanceTo(time);
    const FrameStats st = g.sync();
    BOOST_TEST(near(t->translation.getValue(), pos), "t=" << time);
    BOOST_TEST(t->rotation.getValue().angle == angle, boost::test_tools::tolerance(1e-5f));
    BOOST_TEST(m->transmittance.getValue() == alpha, boost::test_tools::tolerance(1e-6f));
    BOOST_TEST(st.triangles.rigid == 12u);
    BOOST_TEST(st.triangles.statics == 0u);
  }
}

BOOST_AUTO_TEST_CASE(coordinate_and_normal_interpolators_deform_meshes) {
  // A quad whose corner 2 rises; the Coordinate is shared by two shapes (both deform).
  const LoadedScene s = fromText(
      "<Shape><IndexedFaceSet coordIndex='0 1 2 3'><Coordinate DEF='C' point='0 0 0, 1 0 0, "
      "1 1 0, 0 1 0'/></IndexedFaceSet></Shape>"
      "<Transform translation='5 0 0'><Shape><IndexedFaceSet coordIndex='0 1 2'>"
      "<Coordinate USE='C'/></IndexedFaceSet></Shape></Transform>"
      "<Shape><IndexedFaceSet coordIndex='0 1 2'><Coordinate point='0 0 -5, 1 0 -5, 0 1 -5'/>"
      "<Normal DEF='N' vector='0 0 1, 0 0 1, 0 0 1'/></IndexedFaceSet></Shape>"
      "<Shape><Box/></Shape>"
      "<TimeSensor DEF='clock' cycleInterval='4'/>"
      "<CoordinateInterpolator DEF='CI' key='0 1' keyValue='0 0 0, 1 0 0, 1 1 0, 0 1 0, "
      "0 0 0, 1 0 0, 1 1 2, 0 1 0'/>"
      "<NormalInterpolator DEF='NI' key='0 1' keyValue='0 0 1, 0 0 1, 0 0 1, 1 0 0, 1 0 0, 1 0 0'/>"
      "<ROUTE fromNode='clock' fromField='fraction_changed' toNode='CI' toField='set_fraction'/>"
      "<ROUTE fromNode='clock' fromField='fraction_changed' toNode='NI' toField='set_fraction'/>"
      "<ROUTE fromNode='CI' fromField='value_changed' toNode='C' toField='set_point'/>"
      "<ROUTE fromNode='NI' fromField='value_changed' toNode='N' toField='vector'/>");
  BOOST_TEST(s.warnings.empty());
  BOOST_TEST(s.animationDuration == 4.0);
  SceneGraph g;
  g.setRoot(s.root);
  for (const double time : {0.0, 2.0, 4.0}) {
    g.advanceTo(time);
    const FrameStats st = g.sync();
    BOOST_TEST(st.triangles.deforming == 2u + 1u + 1u);
    BOOST_TEST(st.triangles.statics == 12u);
  }
  // At the end the quad's corner 2 is at z = 2 and the normal-routed triangle faces +X.
  float maxZ = -1.0f;
  bool turned = false;
  for (nodes::Mesh* m : distinct<nodes::Mesh>(s.root.get())) {
    for (const Vec3f& p : m->points.getValues()) maxZ = std::max(maxZ, p.z);
    if (m->points[0].z == -5.0f) turned = near(m->normals[0], {1.0f, 0.0f, 0.0f});
  }
  BOOST_TEST(maxZ == 2.0f);
  BOOST_TEST(turned);
}

BOOST_AUTO_TEST_CASE(inline_files_are_shared_and_cycles_rejected) {
  TempDir dir;
  dir.write("part.x3d", doc("<Shape><Box/></Shape>"));
  const fs::path main = dir.write(
      "main.x3d", doc("<Inline url='\"missing.x3d\" \"part.x3d\"'/><Transform translation='4 0 0'>"
                      "<Inline url='\"part.x3d\"'/></Transform><Inline url='\"nowhere.x3d\"'/>"));
  const LoadedScene s = loadX3d(main);
  BOOST_TEST(distinct<nodes::Mesh>(s.root.get()).size() == 1u);
  BOOST_TEST(anyWarning(s, "main.x3d:4: Inline: no url"));
  SceneGraph g;
  g.setRoot(s.root);
  g.sync();
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 24u);
  dir.write("a.x3d", doc("<Inline url='\"b.x3d\"'/>"));
  dir.write("b.x3d", doc("<Group><Inline url='\"a.x3d\"'/></Group>"));
  const std::string e = errorOf([&] { loadX3d(dir.path / "a.x3d"); });
  BOOST_TEST(e.find("b.x3d:4: Inline cycle") != std::string::npos, e);
}

// ---------------------------------------------------------------------------------------------
// Bad input

BOOST_AUTO_TEST_CASE(rejected_input_names_file_and_line) {
  const auto err = [](const std::string& text) {
    return errorOf([&] { loadX3dString(text, fs::temp_directory_path(), "bad.x3d"); });
  };
  const std::pair<std::string, std::string> cases[] = {
      {"<X3D><Scene>\n<Group>\n</Scene></X3D>", "bad.x3d:3: malformed XML"},
      {"<html><body/></html>", "bad.x3d:1: not an X3D file"},
      {"<X3D>\n<head/>\n</X3D>", "bad.x3d:1: X3D file without a Scene"},
      {doc("<Transform translation='1 2'/>"),
       "bad.x3d:4: Transform translation: 2 numbers is not a multiple of 3"},
      {doc("<Transform translation='1 2 x'/>"), "bad.x3d:4: Transform translation: 'x' is not"},
      {doc("<Shape><Box size='1 nan 1'/></Shape>"), "bad.x3d:4: Box size: NaN"},
      {doc("<Shape><IndexedFaceSet coordIndex='0 1 2'><Coordinate point='0 0 0 1 0 0 inf 1 0'/>"
           "</IndexedFaceSet></Shape>"),
       "bad.x3d:4: Coordinate point: NaN, infinite"},
      {doc("<Shape><IndexedFaceSet coordIndex='0 1.5 2'/></Shape>"),
       "IndexedFaceSet coordIndex: expected integers"},
      {doc("<Switch whichChoice='true'/>"), "Switch whichChoice: 'true' is not a number"},
      {doc("<Group DEF='g'>\n<Transform><Group USE='g'/></Transform></Group>"),
       "bad.x3d:5: Group USE='g' inside its own definition (line 4)"},
      {doc("<Shape><Appearance><Material shininess='0.5 0.5'/></Appearance></Shape>"),
       "Material shininess: expected one number"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string e = err(text);
    BOOST_TEST(e.find(expected) != std::string::npos, "got '" << e << "' for " << text);
  }
  BOOST_TEST(errorOf([] { loadX3d("/nonexistent/scene.x3d"); }).find("scene.x3d") !=
             std::string::npos);
  std::string deep;
  for (int i = 0; i < 300; ++i) deep += "<Group>";
  for (int i = 0; i < 300; ++i) deep += "</Group>";
  BOOST_TEST(err(doc(deep)).find("nested deeper than 256") != std::string::npos);
  X3dOptions small;
  small.maxTriangles = 100;
  BOOST_TEST(errorOf([&] {
               fromText("<Shape><Sphere/></Shape>", small);
             }).find("more than 100 triangles") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(dropped_parts_warn_and_the_rest_loads) {
  const LoadedScene s = fromText(
      "<Shape><Text string='\"hi\"'/></Shape>\n"
      "<FancyNode><Shape><Box/></Shape></FancyNode>\n"
      "<Shape><IndexedFaceSet coordIndex='0 1 2 -1 0 1 9 -1 0 1' texCoordIndex='0 0 7 -1'>"
      "<Coordinate point='0 0 0, 1 0 0, 0 1 0'/><TextureCoordinate point='0 0'/>"
      "</IndexedFaceSet></Shape>\n"
      "<Shape USE='nothing'/>\n"
      "<Shape><Appearance><ImageTexture url='\"no-such-image.png\"'/></Appearance><Box/></Shape>\n"
      "<PositionInterpolator DEF='P' key='1 0' keyValue='0 0 0, 1 1 1'/>\n"
      "<Transform DEF='T'/>\n"
      "<ROUTE fromNode='P' fromField='value_changed' toNode='T' toField='bogus'/>\n"
      "<ROUTE fromNode='T' fromField='translation' toNode='T' toField='scale'/>\n"
      "<ROUTE fromNode='P' fromField='value_changed' toNode='T' toField='rotation'/>\n"
      "<Appearance USE='T'/>\n"
      "<Shape><IndexedFaceSet coordIndex='0 1 2'><Coordinate USE='T'/></IndexedFaceSet></Shape>");
  const char* expected[] = {
      "test.x3d:4: unsupported geometry Text",
      "test.x3d:5: unsupported node FancyNode",
      "test.x3d:6: IndexedFaceSet: 1 face(s) with coordinate indices out of range dropped",
      "test.x3d:6: IndexedFaceSet: 1 face(s) with fewer than 3 corners dropped",
      "test.x3d:6: IndexedFaceSet: texture coordinate index out of range",
      "test.x3d:7: Shape USE='nothing': no node of that name",
      "test.x3d:8: ImageTexture: no url names an existing local image ('no-such-image.png')",
      "test.x3d:9: PositionInterpolator keys decrease",
      "test.x3d:11: ROUTE: Transform 'T' has no supported field 'bogus'",
      "test.x3d:12: ROUTE from Transform 'T'",
      "test.x3d:13: ROUTE P.value_changed TO T.rotation ignored",
      "test.x3d:14: Appearance USE='T' names a Transform",
      "test.x3d:15: Coordinate USE='T' names a Transform",
      "test.x3d:15: IndexedFaceSet: 1 face(s) with coordinate indices out of range dropped",
  };
  for (const char* w : expected) BOOST_TEST(anyWarning(s, w), "missing warning: " << w);
  BOOST_TEST(s.warnings.size() == std::size(expected));
  SceneGraph g;
  g.setRoot(s.root);
  g.sync();
  BOOST_TEST(g.backendScene().instancedTriangleCount() == 1u + 12u);  // the good face, a box
}

BOOST_AUTO_TEST_CASE(viewpoint_lights_background_worldinfo) {
  const LoadedScene s = fromText(
      "<WorldInfo title='lit'/><Background skyColor='0.1 0.2 0.3, 1 1 1'/>"
      "<Transform translation='0 0 5'><Viewpoint position='0 1 2' fieldOfView='0.5'/></Transform>"
      "<PointLight location='1 2 3' intensity='0.5' color='1 0 0'/>"
      "<DirectionalLight direction='0 -1 0'/>"
      "<SpotLight location='0 4 0' direction='0 -1 0' cutOffAngle='0.3' beamWidth='0.2'/>"
      "<Shape><Box/></Shape>");
  BOOST_TEST(s.title == "lit");
  BOOST_TEST(s.hasBackground);
  BOOST_TEST(near(s.background, {0.1f, 0.2f, 0.3f}));
  SceneGraph g;
  g.setRoot(s.root);
  g.sync();
  const auto cam = g.camera();
  BOOST_REQUIRE(cam.has_value());
  BOOST_TEST(near(cam->position, {0.0f, 1.0f, 7.0f}));
  BOOST_TEST(cam->fov == 0.5f);
  const std::vector<WorldLight> lights = g.lights();
  BOOST_REQUIRE(lights.size() == 3u);
  BOOST_TEST((lights[0].data.kind == LightKind::Point));
  BOOST_TEST(near(lights[0].data.position, {1.0f, 2.0f, 3.0f}));
  BOOST_TEST(lights[0].data.intensity == 0.5f);
  BOOST_TEST((lights[1].data.kind == LightKind::Directional));
  BOOST_TEST(near(lights[1].data.direction, {0.0f, -1.0f, 0.0f}));
  BOOST_TEST((lights[2].data.kind == LightKind::Spot));
  BOOST_TEST(lights[2].data.cutOffAngle == 0.3f);
}
