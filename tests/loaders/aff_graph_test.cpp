// Tests of the AFF → scene-graph conversion: the BART scenes synced through a SceneGraph
// (triangle counts and classes from data/README.md, lights and camera against the parsed
// document, animation over time), small hand-written files for the node structure, and
// failed loads that must leave an existing graph untouched.
#define BOOST_TEST_MODULE aff_graph
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <ostream>
#include <string>
#include <vector>

#include "SharedData.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AffLoader.h"
#include "tracegraph/nodes/KeyframeDeformer.h"
#include "tracegraph/nodes/Material.h"
#include "tracegraph/nodes/MatrixTransform.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/Texture.h"
#include "tracegraph/scenegraph/SceneGraph.h"

// Printers for Boost.Test messages.
namespace tg {
template <typename T>
std::ostream& operator<<(std::ostream& os, const Vec3<T>& v) {
  return os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
}
std::ostream& operator<<(std::ostream& os, const Color& c) {
  return os << '(' << c.r << ", " << c.g << ", " << c.b << ')';
}
}  // namespace tg

namespace fs = std::filesystem;
namespace utf = boost::unit_test;

namespace {

const fs::path kData = TG_DATA_DIR;
const fs::path kKitchen = kData / "bart/kitchen/aff/kitchen.aff";
const fs::path kRobots = kData / "bart/robots/aff/Robot.aff";
const fs::path kMuseum = kData / "bart/museum/aff/museum5.aff";

/// Skips a test (with the reason) when the shared BART scenes are not installed.
tg::test::FilesAvailable BartAvailable() {
  return {"BART scenes", kData, {kKitchen, kRobots, kMuseum}};
}

/// Each scene is loaded once (with its document) and shared by the tests; every test puts
/// the root into a SceneGraph of its own.
const tg::AffScene& scene(const fs::path& file) {
  static std::map<fs::path, tg::AffScene> cache;
  auto it = cache.find(file);
  if (it == cache.end()) {
    tg::AffLoadOptions options;
    options.keepDocument = true;
    it = cache.emplace(file, tg::loadAff(file, options)).first;
  }
  return it->second;
}

/// Static-primitive triangles under an `x` block whose track exists (what an animator
/// drives), and under any `x` block at all.
struct DrivenCounts {
  std::size_t driven = 0;
  std::size_t underX = 0;
};

void countDriven(const tg::AffDocument& doc, const tg::AffBlock& b, bool underX, bool driven,
                 DrivenCounts& out) {
  if (b.kind == tg::AffBlock::Kind::Animated) {
    underX = true;
    driven = driven || doc.findTrack(b.name) != nullptr;
  }
  for (const tg::AffMesh& m : b.meshes) {
    if (underX) out.underX += m.triangleCount();
    if (driven) out.driven += m.triangleCount();
  }
  for (const tg::AffBlock& c : b.children) countDriven(doc, c, underX, driven, out);
}

DrivenCounts drivenCounts(const tg::AffDocument& doc) {
  DrivenCounts n;
  countDriven(doc, doc.root, false, false, n);
  return n;
}

double distance(const tg::Vec3f& a, const tg::Vec3d& b) {
  return length(tg::Vec3d(a) - b);
}

/// Checks SceneGraph::camera() against AffDocument::camera(t).
void checkCamera(const tg::SceneGraph& sg, const tg::AffDocument& doc, double t) {
  const std::optional<tg::WorldCamera> cam = sg.camera();
  BOOST_TEST_REQUIRE(cam.has_value());
  const tg::AffCamera ref = doc.camera(t);
  const double scale = std::max(1.0, length(ref.eye));
  BOOST_TEST(distance(cam->position, ref.eye) < 1e-6 * scale, cam->position << " vs " << ref.eye);
  BOOST_TEST(distance(cam->direction, ref.direction) < 1e-5);
  // The graph's up is orthogonalised against the direction; the track's already is.
  const tg::Vec3d refUp = normalize(ref.up - ref.direction * dot(ref.up, ref.direction));
  BOOST_TEST(distance(cam->up, refUp) < 1e-5);
  BOOST_TEST(std::abs(static_cast<double>(cam->fov) - ref.angle * std::numbers::pi / 180.0) < 1e-6);
  BOOST_TEST(cam->hither == static_cast<float>(ref.hither));
  BOOST_TEST(cam->aspect == static_cast<float>(ref.width) / static_cast<float>(ref.height));
}

/// Checks SceneGraph::lights() against the document's lights.
void checkLights(const tg::SceneGraph& sg, const tg::AffDocument& doc) {
  const std::vector<tg::WorldLight> lights = sg.lights();
  BOOST_TEST_REQUIRE(lights.size() == doc.lights.size());
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const tg::LightData& l = lights[i].data;
    BOOST_TEST((l.kind == tg::LightKind::Point));
    BOOST_TEST(l.on);
    BOOST_TEST(distance(l.position, doc.lights[i].position) < 1e-4);
    BOOST_TEST(l.color.r == doc.lights[i].colour.x);
    BOOST_TEST(l.color.g == doc.lights[i].colour.y);
    BOOST_TEST(l.color.b == doc.lights[i].colour.z);
    BOOST_TEST(l.attenuation == tg::Vec3f(1.0f, 0.0f, 0.0f));  // AFF: no attenuation
  }
}

/// Every driven MatrixTransform in the graph, by track name.
void drivenTransforms(tg::Node& node, std::vector<tg::nodes::MatrixTransform*>& out) {
  if (auto* xf = dynamic_cast<tg::nodes::MatrixTransform*>(&node)) {
    if (xf->matrix.isConnected()) out.push_back(xf);
  }
  if (auto* g = dynamic_cast<tg::Group*>(&node))
    for (const tg::ref_ptr<tg::Node>& c : g->children()) drivenTransforms(*c, out);
}

/// Instance matrices of the rigid instances.
std::map<tg::InstanceId, tg::Affine3d> rigidMatrices(tg::SceneGraph& sg) {
  std::map<tg::InstanceId, tg::Affine3d> m;
  for (const tg::InstanceId id : sg.instanceIds())
    if (sg.instanceClass(id) == tg::DynamicsClass::Rigid)
      m[id] = sg.backendScene().instanceTransform(id);
  return m;
}

struct Expected {
  std::size_t triangles;
  std::size_t deforming;
};

/// Loads, syncs frame 0 and checks counts, classes, lights and camera; then a later frame.
void checkBartScene(const fs::path& file, const Expected& expected, double laterFraction) {
  const tg::AffScene& s = scene(file);
  const tg::AffDocument& doc = *s.document;
  tg::SceneGraph sg;
  sg.setRoot(s.root);
  const double t0 = s.frameTime(0);
  sg.advanceTo(t0);
  const tg::FrameStats f0 = sg.sync();
  const DrivenCounts driven = drivenCounts(doc);
  BOOST_TEST_MESSAGE(file.filename().string()
                     << ": frame 0 static " << f0.triangles.statics << ", rigid "
                     << f0.triangles.rigid << ", deforming " << f0.triangles.deforming
                     << "; under x blocks " << driven.underX << " (driven by a track "
                     << driven.driven << "); instances " << f0.instances);
  BOOST_TEST(sg.backendScene().instancedTriangleCount() == expected.triangles);
  BOOST_TEST(f0.triangles.statics + f0.triangles.rigid + f0.triangles.deforming ==
             expected.triangles);
  BOOST_TEST(f0.triangles.deforming == expected.deforming);
  // On the first frame every track-driven transform counts as moving; `x` blocks without a
  // track are plain identity transforms and stay static.
  BOOST_TEST(f0.triangles.rigid == driven.driven);
  BOOST_TEST(s.triangles.total() == expected.triangles);
  checkLights(sg, doc);
  checkCamera(sg, doc, t0);

  // A later frame: the camera and the animated parts move, the counts stay.
  const std::map<tg::InstanceId, tg::Affine3d> before = rigidMatrices(sg);
  const tg::Vec3f eye0 = sg.camera()->position;
  const int later = static_cast<int>(laterFraction * (s.frameCount() - 1));
  const double t1 = s.frameTime(later);
  sg.advanceTo(t1);
  const tg::FrameStats f1 = sg.sync();
  BOOST_TEST(f1.triangles.statics + f1.triangles.rigid + f1.triangles.deforming ==
             expected.triangles);
  BOOST_TEST(f1.triangles.deforming == expected.deforming);
  checkCamera(sg, doc, t1);
  BOOST_TEST(sg.camera()->position != eye0);
  checkLights(sg, doc);

  std::vector<tg::nodes::MatrixTransform*> transforms;
  drivenTransforms(*s.root, transforms);
  for (const tg::nodes::MatrixTransform* xf : transforms) {
    const tg::AffTrack* track = doc.findTrack(xf->name());
    BOOST_TEST_REQUIRE(track);
    BOOST_TEST((xf->matrix.value() == track->evaluate(t1)), xf->name());
  }
  if (driven.driven > 0) {
    const std::map<tg::InstanceId, tg::Affine3d> after = rigidMatrices(sg);
    std::size_t moved = 0;
    for (const auto& [id, m] : after) {
      const auto it = before.find(id);
      if (it != before.end() && !(it->second == m)) ++moved;
    }
    BOOST_TEST_MESSAGE(file.filename().string()
                       << ": frame " << later << " (t = " << t1 << "): " << moved << " of "
                       << after.size() << " rigid instances moved");
    BOOST_TEST(moved > 0);
  }
}

/// A small file exercising the mapping: a track shared by two `x` blocks, a material shared
/// by meshes in different blocks, a textured triangle, an animated triangle.
constexpr const char* kSmall = R"(a 0 2 3
fm .1 .1 .1  .5 .5 .5  .2 .2 .2  20 0 1
k spin {
  rot 4
  -1  0 1 0  0   0 0 0
   0  0 1 0  0   0 0 0
   2  0 1 0  90  0 0 0
   3  0 1 0  90  0 0 0
}
x spin {
  m vertices 3  0 0 0  1 0 0  0 1 0  triangles 1  0 1 2
}
xs 1 1 1  0 1 0 0  5 0 0 {
  x spin {
    m vertices 3  0 0 0  1 0 0  0 1 0  triangles 1  0 1 2
  }
  tt nosuch.ppm  0 0 0 0 0  1 0 0 1 0  0 1 0 0 1
  m vertices 3  0 0 0  1 0 0  0 1 0  triangles 1  0 1 2
}
fm .1 .1 .1  .9 .1 .1  0 0 0  0 0.5 0
tpa 2
  0  0 0 0 0 0 1  1 0 0 0 0 1  0 1 0 0 0 1
  2  0 0 2 0 0 1  1 0 2 0 0 1  0 1 2 0 0 1
l 0 10 0 .5 .5 .5
)";

template <typename T>
std::vector<T*> findAll(tg::Node& node) {
  std::vector<T*> out;
  if (auto* n = dynamic_cast<T*>(&node)) out.push_back(n);
  if (auto* g = dynamic_cast<tg::Group*>(&node))
    for (const tg::ref_ptr<tg::Node>& c : g->children()) {
      std::vector<T*> sub = findAll<T>(*c);
      out.insert(out.end(), sub.begin(), sub.end());
    }
  return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(kitchen_synced, *utf::precondition(BartAvailable())) {
  // Toycar moves in [3, 20] s; the middle of the animation is well inside.
  checkBartScene(kKitchen, {110'561, 0}, 0.5);
}

BOOST_AUTO_TEST_CASE(robots_synced, *utf::precondition(BartAvailable())) {
  checkBartScene(kRobots, {71'708, 0}, 0.3);
}

BOOST_AUTO_TEST_CASE(museum_synced, *utf::precondition(BartAvailable())) {
  // 10,284 static + 8 cones × 32 triangles (16 segments) + 1,024 tpa.
  checkBartScene(kMuseum, {11'564, 1'024}, 0.5);
  const tg::AffScene& s = scene(kMuseum);
  BOOST_TEST(s.triangles.cones == 256u);
  BOOST_TEST(s.frameCount() == 300);
  BOOST_TEST(s.frameTime(0) == -1.0);
  BOOST_TEST(s.width == 800);
  BOOST_TEST(s.height == 600);
}

BOOST_AUTO_TEST_CASE(scene_level_facts, *utf::precondition(BartAvailable())) {
  const tg::AffScene& k = scene(kKitchen);
  BOOST_TEST(k.background == tg::Vec3f(0.5f, 0.5f, 1.0f));
  BOOST_TEST(k.ambient == tg::Vec3f(2.5f, 2.5f, 2.5f));
  BOOST_TEST(k.frameCount() == 800);
  BOOST_TEST(k.frameTime(799) == 20.0);
  BOOST_TEST(k.lights.size() == 6u);
  BOOST_TEST_REQUIRE(k.camera.get() != nullptr);
  BOOST_TEST(k.root->child(0) == k.camera.get());
  // Kitchen: 5 track names drive 7 blocks, one animator per name, plus the camera's.
  BOOST_TEST(k.animators.size() == 6u);
  const tg::AffScene& r = scene(kRobots);
  BOOST_TEST(r.background == tg::Vec3f(0.0f, 0.0f, 0.0f));
  const auto noTrack = std::count_if(r.warnings.begin(), r.warnings.end(), [](const auto& w) {
    return w.find("has no k block") != std::string::npos;
  });
  BOOST_TEST(noTrack == 5);
}

BOOST_AUTO_TEST_CASE(materials_are_shared_and_mapped, *utf::precondition(BartAvailable())) {
  const tg::AffScene& s = scene(kKitchen);
  const tg::AffDocument& doc = *s.document;
  const std::vector<tg::nodes::Material*> uses = findAll<tg::nodes::Material>(*s.root);
  std::vector<tg::nodes::Material*> distinct = uses;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  BOOST_TEST_MESSAGE("kitchen: " << uses.size() << " Material links, " << distinct.size()
                                 << " Material nodes, " << doc.materials.size()
                                 << " document materials");
  BOOST_TEST(distinct.size() <= doc.materials.size());
  BOOST_TEST(uses.size() > distinct.size());  // shared between blocks
  // Glass: T 0.85, ior 1.55.
  const bool glass = std::any_of(distinct.begin(), distinct.end(), [](const auto* m) {
    return m->transmittance.value() == 0.85f && m->ior.value() == 1.55f;
  });
  BOOST_TEST(glass);
  // Textures: one node per file, each in a Separator with its mesh.
  const std::vector<tg::nodes::Texture*> textures = findAll<tg::nodes::Texture>(*s.root);
  BOOST_TEST(!textures.empty());
  for (const tg::nodes::Texture* t : textures) {
    BOOST_TEST(fs::exists(t->fileName()), t->fileName());
    for (const tg::Group* p : t->parents()) BOOST_TEST(p->numChildren() == 2u);
  }
}

BOOST_AUTO_TEST_CASE(small_file_structure_and_animation) {
  const tg::AffScene s = tg::loadAffText(kSmall, fs::temp_directory_path(), {}, "small.aff");
  BOOST_TEST_REQUIRE(s.root.get() != nullptr);
  BOOST_TEST(s.camera.get() == nullptr);  // no `v`, no `camera` track
  // One animator for the shared track, one deformer.
  BOOST_TEST(s.animators.size() == 2u);
  const auto missing = std::count_if(s.warnings.begin(), s.warnings.end(), [](const auto& w) {
    return w.find("nosuch.ppm") != std::string::npos;
  });
  BOOST_TEST(missing >= 1);

  std::vector<tg::nodes::MatrixTransform*> driven;
  drivenTransforms(*s.root, driven);
  BOOST_TEST_REQUIRE(driven.size() == 2u);
  BOOST_TEST(driven[0]->matrix.connectedFrom() == driven[1]->matrix.connectedFrom());
  // One Material node per document material (an `fm` state with or without a texture):
  // the untextured one is linked before the meshes of both blocks.
  const std::vector<tg::nodes::Material*> links = findAll<tg::nodes::Material>(*s.root);
  std::vector<tg::nodes::Material*> mats = links;
  std::sort(mats.begin(), mats.end());
  mats.erase(std::unique(mats.begin(), mats.end()), mats.end());
  BOOST_TEST_REQUIRE(mats.size() == 3u);
  std::sort(mats.begin(), mats.end(), [&](const auto* a, const auto* b) {
    return std::count(links.begin(), links.end(), a) > std::count(links.begin(), links.end(), b);
  });
  if (mats[1]->shininess.value() == 0.0f) std::swap(mats[1], mats[2]);
  BOOST_TEST(std::count(links.begin(), links.end(), mats[0]) >= 2);
  BOOST_TEST(mats[0]->shininess.value() == 20.0f);
  BOOST_TEST(mats[0]->ambientColor.value() == (tg::Color{0.1f, 0.1f, 0.1f}));
  BOOST_TEST(mats[0]->diffuseColor.value() == (tg::Color{0.5f, 0.5f, 0.5f}));
  BOOST_TEST(mats[0]->specularColor.value() == (tg::Color{0.2f, 0.2f, 0.2f}));
  BOOST_TEST(mats[1]->shininess.value() == 20.0f);  // the textured triangle's
  // Exponent 0 is stored so that SceneRenderer's 128·s reading gives 0.
  BOOST_TEST(mats[2]->shininess.value() == 0.0f);
  BOOST_TEST(mats[2]->transmittance.value() == 0.5f);
  BOOST_TEST(mats[2]->ior.value() == 1.0f);  // ior 0 read as 1

  tg::SceneGraph sg;
  sg.setRoot(s.root);
  sg.advanceTo(s.frameTime(0));
  const tg::FrameStats f0 = sg.sync();
  BOOST_TEST(f0.triangles.rigid == 2u);
  BOOST_TEST(f0.triangles.statics == 2u);
  BOOST_TEST(f0.triangles.deforming == 1u);
  // Only the textured triangle carries the texture.
  std::size_t textured = 0, untextured = 0;
  for (const tg::InstanceId id : sg.instanceIds())
    for (const tg::MeshSegment& seg : sg.segments(id))
      (seg.texture ? textured : untextured) += seg.primEnd - seg.primBegin;
  BOOST_TEST(textured == 1u);
  BOOST_TEST(untextured == 4u);
  BOOST_TEST(sg.lights().size() == 1u);

  // t = 1: the tpa triangle is halfway (z = 1), the track has turned (spline between 0 and 90°).
  sg.advanceTo(1.0);
  sg.sync();
  const std::vector<tg::nodes::Mesh*> meshes = findAll<tg::nodes::Mesh>(*s.root);
  const auto tpa = std::find_if(meshes.begin(), meshes.end(),
                                [](const auto* m) { return m->points.isConnected(); });
  BOOST_TEST_REQUIRE((tpa != meshes.end()));
  for (const tg::Vec3f& p : (*tpa)->points.values()) BOOST_TEST(p.z == 1.0f);
  for (const tg::Vec3f& n : (*tpa)->normals.values()) BOOST_TEST(n == tg::Vec3f(0, 0, 1));
  BOOST_TEST(!(driven[0]->matrix.value() == tg::Affine3d::identity()));
}

BOOST_AUTO_TEST_CASE(failed_load_leaves_graph_alone) {
  const fs::path dir = fs::temp_directory_path() / "tg_aff_graph_test";
  fs::create_directories(dir);
  const fs::path bad = dir / "bad.aff";
  {
    std::ofstream out(bad, std::ios::binary);
    out << "fm .1 .1 .1 .5 .5 .5 0 0 0 1 0 1\n"
           "m vertices 3\n"
           "0 0 0\n1 0 0\n0 1 0\n"
           "triangles 1\n"
           "0 1 7\n";
  }
  const tg::AffScene good = tg::loadAffText(kSmall, dir, {}, "small.aff");
  tg::SceneGraph sg;
  sg.setRoot(good.root);
  sg.advanceTo(0.0);
  const tg::FrameStats before = sg.sync();

  std::string message;
  try {
    tg::AffScene replaced = tg::loadAff(bad);
    sg.setRoot(replaced.root);
  } catch (const tg::Error& e) {
    message = e.what();
  }
  BOOST_TEST_MESSAGE("bad file: " << message);
  BOOST_TEST(message.find("bad.aff:7") != std::string::npos, message);
  BOOST_TEST(sg.root() == good.root.get());
  sg.advanceTo(0.0);
  const tg::FrameStats after = sg.sync();
  BOOST_TEST(after.triangles.statics == before.triangles.statics);
  BOOST_TEST(after.triangles.rigid == before.triangles.rigid);
  BOOST_TEST(after.triangles.deforming == before.triangles.deforming);
  BOOST_TEST(sg.backendScene().instancedTriangleCount() == 5u);

  // A missing file names the file too.
  BOOST_CHECK_THROW(tg::loadAff(dir / "missing.aff"), tg::Error);
  fs::remove_all(dir);
}
