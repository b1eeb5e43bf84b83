// The OpenRT-style API: it must build exactly the scene the C++ API builds, reject every misuse
// with an error naming the call while leaving the scene as it was, and report errors like GL.
#define BOOST_TEST_MODULE openrt
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tracegraph/backend/OpenRT.h"

namespace {

using namespace tg;

struct Tri {
  Vec3f v[3];
};

std::vector<Tri> cubeTriangles() {
  // Unit cube [-0.5, 0.5]^3, two triangles per face.
  std::vector<Tri> tris;
  for (int axis = 0; axis < 3; ++axis) {
    for (float side : {-0.5f, 0.5f}) {
      Vec3f c[4];
      const float corners[4][2] = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}};
      for (int k = 0; k < 4; ++k) {
        c[k][static_cast<std::size_t>(axis)] = side;
        c[k][static_cast<std::size_t>((axis + 1) % 3)] = corners[k][0];
        c[k][static_cast<std::size_t>((axis + 2) % 3)] = corners[k][1];
      }
      tris.push_back({{c[0], c[1], c[2]}});
      tris.push_back({{c[0], c[2], c[3]}});
    }
  }
  return tris;
}

std::vector<Tri> tetraTriangles() {
  const Vec3f a{1, 1, 1}, b{1, -1, -1}, c{-1, 1, -1}, d{-1, -1, 1};
  return {{{a, b, c}}, {{a, d, b}}, {{a, c, d}}, {{b, d, c}}};
}

/// A wavy 6x6 grid, used as a deforming object.
std::vector<Tri> gridTriangles() {
  std::vector<Tri> tris;
  auto p = [](int i, int j) {
    const float x = static_cast<float>(i) * 0.4f - 1.2f, y = static_cast<float>(j) * 0.4f - 1.2f;
    return Vec3f{x, y, 0.2f * std::sin(3.0f * x) * std::cos(2.0f * y)};
  };
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      tris.push_back({{p(i, j), p(i + 1, j), p(i + 1, j + 1)}});
      tris.push_back({{p(i, j), p(i + 1, j + 1), p(i, j + 1)}});
    }
  return tris;
}

// Per-vertex attributes of objects defined "with attributes" (any deterministic function).
Vec3f attributeNormal(const Vec3f& p) {
  return {p.x + 0.1f, p.y - 0.2f, p.z + 1.0f};
}
Vec2f attributeUv(const Vec3f& p) {
  return {p.x * 0.5f + 0.5f, p.y * 0.25f};
}

/// The mesh the OpenRT path must produce: one vertex per triangle corner, in call order.
TriangleMesh meshOf(const std::vector<Tri>& tris, bool attributes) {
  TriangleMesh mesh;
  for (const Tri& t : tris)
    for (const Vec3f& p : t.v) {
      mesh.positions.push_back(p);
      if (attributes) {
        mesh.normals.push_back(attributeNormal(p));
        mesh.uvs.push_back(attributeUv(p));
      }
    }
  mesh.indices.resize(mesh.positions.size());
  std::iota(mesh.indices.begin(), mesh.indices.end(), 0u);
  return mesh;
}

void defineObject(RTuint id, const std::vector<Tri>& tris, bool attributes) {
  rtBeginObject(id);
  rtBegin(RT_TRIANGLES);
  for (const Tri& t : tris)
    for (const Vec3f& p : t.v) {
      if (attributes) {
        const Vec3f n = attributeNormal(p);
        const Vec2f uv = attributeUv(p);
        rtNormal3f(n.x, n.y, n.z);
        rtTexCoord2f(uv.u, uv.v);
      }
      rtVertex3f(p.x, p.y, p.z);
    }
  rtEnd();
  rtEndObject();
}

bool sameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  return a.positions == b.positions && a.indices == b.indices && a.normals == b.normals &&
         a.uvs == b.uvs;
}

std::vector<Ray> randomRays(std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> origin(-14.0f, 14.0f), target(-6.0f, 6.0f);
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    r.origin = {origin(rng), origin(rng), origin(rng)};
    const Vec3f to{target(rng), target(rng), target(rng) - 5.0f};
    r.direction = to - r.origin;
  }
  return rays;
}

std::vector<Hit> traceAll(const Scene& scene, const std::vector<Ray>& rays) {
  std::vector<Hit> hits(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) scene.intersect(rays[i], hits[i]);
  return hits;
}

bool sameHit(const Hit& a, const Hit& b) {
  return a.valid() == b.valid() && a.t == b.t && a.u == b.u && a.v == b.v && a.primId == b.primId &&
         a.instanceId == b.instanceId && a.objectId == b.objectId &&
         a.geometricNormal == b.geometricNormal;
}

std::size_t countMismatches(const std::vector<Hit>& a, const std::vector<Hit>& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += sameHit(a[i], b[i]) ? 0 : 1;
  return n;
}

/// Random parameters of one placement, drawn once and replayed through both APIs.
struct Placement {
  Vec3f translate, axis, scale, innerAxis, innerTranslate;
  float degrees = 0.0f, innerDegrees = 0.0f;
};

std::vector<Placement> randomPlacements(std::size_t count) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-6.0f, 6.0f), unit(-1.0f, 1.0f), deg(-180.0f, 180.0f),
      scale(0.3f, 1.6f);
  std::vector<Placement> out(count);
  for (Placement& p : out) {
    p.translate = {pos(rng), pos(rng), pos(rng)};
    p.axis = {unit(rng), unit(rng), unit(rng)};
    p.degrees = deg(rng);
    p.scale = {scale(rng), scale(rng), scale(rng)};
    p.innerAxis = {unit(rng), unit(rng), unit(rng)};
    p.innerDegrees = deg(rng);
    p.innerTranslate = {unit(rng), unit(rng), unit(rng)};
  }
  return out;
}

Affine3d translation(const Vec3f& t) {
  return Affine3d::translation(Vec3d(t));
}
Affine3d rotation(float degrees, const Vec3f& axis) {
  return Affine3d::rotation(Vec3d(axis), static_cast<double>(degrees));
}
Affine3d scaling(const Vec3f& s) {
  return Affine3d::scaling(Vec3d(s));
}

// A sheared affine matrix, column-major as rtMultMatrixf takes it.
constexpr float kShear[16] = {1.0f, 0.2f, 0.0f, 0.0f, 0.3f, 1.1f,  -0.1f, 0.0f,
                              0.0f, 0.4f, 0.9f, 0.0f, 2.0f, -1.0f, -4.0f, 1.0f};

Affine3d shearMatrix() {
  Affine3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m.m[r][c] = static_cast<double>(kShear[4 * c + r]);
  return m;
}

/// Makes a fresh context current for the test and destroys it afterwards.
struct ContextGuard {
  RTcontext ctx = rtCreateContext();
  ContextGuard() { rtMakeCurrent(ctx); }
  ~ContextGuard() { rtDestroyContext(ctx); }
  ContextGuard(const ContextGuard&) = delete;
  ContextGuard& operator=(const ContextGuard&) = delete;
};

std::array<double, 16> currentMatrix() {
  std::array<double, 16> m{};
  rtGetMatrixd(m.data());
  return m;
}

}  // namespace

BOOST_AUTO_TEST_CASE(openrt_builds_the_same_scene_as_the_cpp_api) {
  ContextGuard guard;
  const std::vector<Tri> cube = cubeTriangles(), tetra = tetraTriangles(), grid = gridTriangles();
  const std::vector<Placement> placements = randomPlacements(24);

  // OpenRT path.
  const RTuint rtCube = rtNewObject();
  const RTuint rtTetra = rtNewObject(RT_RIGID);
  const RTuint rtGrid = rtNewObject(RT_DEFORMING);
  const RTuint rtEmpty = rtNewObject();
  defineObject(rtCube, cube, false);
  defineObject(rtTetra, tetra, true);
  defineObject(rtGrid, grid, false);
  defineObject(rtEmpty, {}, false);
  const RTuint rtObjects[3] = {rtCube, rtTetra, rtGrid};
  rtLoadIdentity();
  rtTranslatef(0.0f, 0.0f, -5.0f);
  rtPushMatrix();
  {
    rtTranslatef(1.0f, 2.0f, 3.0f);
    rtRotatef(30.0f, 0.0f, 1.0f, 0.0f);
    rtScalef(2.0f, 1.0f, 0.5f);
    rtInstantiateObject(rtCube);
    rtPushMatrix();
    rtRotatef(45.0f, 1.0f, 1.0f, 0.0f);
    rtTranslatef(0.5f, 0.0f, 0.0f);
    rtInstantiateObject(rtTetra);
    rtPopMatrix();
    rtTranslatef(-3.0f, 0.0f, 0.0f);
    rtInstantiateObject(rtCube);
  }
  rtPopMatrix();
  rtPushMatrix();
  rtMultMatrixf(kShear);
  rtInstantiateObject(rtTetra);
  rtInstantiateObject(rtEmpty);
  rtPopMatrix();
  for (std::size_t i = 0; i < placements.size(); ++i) {
    const Placement& p = placements[i];
    rtPushMatrix();
    rtTranslatef(p.translate.x, p.translate.y, p.translate.z);
    rtRotatef(p.degrees, p.axis.x, p.axis.y, p.axis.z);
    rtScalef(p.scale.x, p.scale.y, p.scale.z);
    rtInstantiateObject(rtObjects[i % 3]);
    if (i % 4 == 0) {
      rtPushMatrix();
      rtRotatef(p.innerDegrees, p.innerAxis.x, p.innerAxis.y, p.innerAxis.z);
      rtTranslatef(p.innerTranslate.x, p.innerTranslate.y, p.innerTranslate.z);
      rtInstantiateObject(rtObjects[(i + 1) % 3]);
      rtPopMatrix();
    }
    rtPopMatrix();
  }
  rtCommit();
  BOOST_TEST(rtGetError() == RT_NO_ERROR, rtGetErrorString());

  // The same scene through tg::Scene, matrices composed by hand in the same order.
  Scene scene;
  const ObjectId cubeId = scene.createObject(meshOf(cube, false));
  const ObjectId tetraId = scene.createObject(meshOf(tetra, true), ObjectUsage::Rigid);
  const ObjectId gridId = scene.createObject(meshOf(grid, false), ObjectUsage::Deforming);
  const ObjectId emptyId = scene.createObject(TriangleMesh{});
  const ObjectId objects[3] = {cubeId, tetraId, gridId};
  const Affine3d world = translation({0.0f, 0.0f, -5.0f});
  const Affine3d a = world * translation({1.0f, 2.0f, 3.0f}) * rotation(30.0f, {0.0f, 1.0f, 0.0f}) *
                     scaling({2.0f, 1.0f, 0.5f});
  scene.createInstance(cubeId, a);
  scene.createInstance(tetraId,
                       a * rotation(45.0f, {1.0f, 1.0f, 0.0f}) * translation({0.5f, 0.0f, 0.0f}));
  scene.createInstance(cubeId, a * translation({-3.0f, 0.0f, 0.0f}));
  scene.createInstance(tetraId, world * shearMatrix());
  scene.createInstance(emptyId, world * shearMatrix());
  for (std::size_t i = 0; i < placements.size(); ++i) {
    const Placement& p = placements[i];
    const Affine3d m =
        world * translation(p.translate) * rotation(p.degrees, p.axis) * scaling(p.scale);
    scene.createInstance(objects[i % 3], m);
    if (i % 4 == 0)
      scene.createInstance(objects[(i + 1) % 3], m * rotation(p.innerDegrees, p.innerAxis) *
                                                     translation(p.innerTranslate));
  }
  scene.commit();

  const Scene& rtScene = rtGetScene();
  BOOST_TEST(rtScene.objectCount() == scene.objectCount());
  BOOST_TEST(rtScene.instanceCount() == scene.instanceCount());
  for (ObjectId id = 0; id < scene.objectCount(); ++id) {
    BOOST_TEST(sameMesh(rtScene.objectMesh(id), scene.objectMesh(id)), "object " << id);
    BOOST_TEST((rtScene.objectUsage(id) == scene.objectUsage(id)), "object " << id);
  }
  BOOST_TEST(rtScene.objectMesh(tetraId).normals.size() == 12u);
  BOOST_TEST(rtScene.objectMesh(cubeId).normals.empty());
  for (InstanceId id = 0; id < scene.instanceCount(); ++id) {
    BOOST_TEST(rtScene.instanceObject(id) == scene.instanceObject(id), "instance " << id);
    BOOST_TEST((rtScene.instanceTransform(id) == scene.instanceTransform(id)), "instance " << id);
  }

  const std::vector<Ray> rays = randomRays(10000, 1);
  const std::vector<Hit> rtHits = traceAll(rtScene, rays), hits = traceAll(scene, rays);
  std::size_t hitCount = 0, mismatches = 0, surfaceMismatches = 0, occlusionMismatches = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    hitCount += hits[i].valid() ? 1 : 0;
    if (!sameHit(rtHits[i], hits[i])) {
      ++mismatches;
      continue;
    }
    occlusionMismatches += rtScene.occluded(rays[i]) == scene.occluded(rays[i]) ? 0 : 1;
    if (!hits[i].valid()) continue;
    const Scene::SurfaceData s1 = rtScene.surfaceAt(rays[i], rtHits[i]);
    const Scene::SurfaceData s2 = scene.surfaceAt(rays[i], hits[i]);
    surfaceMismatches += (s1.shadingNormal == s2.shadingNormal && s1.uv == s2.uv) ? 0 : 1;
  }
  BOOST_TEST(hitCount > rays.size() / 5);
  BOOST_TEST(mismatches == 0u);
  BOOST_TEST(surfaceMismatches == 0u);
  BOOST_TEST(occlusionMismatches == 0u);
}

BOOST_AUTO_TEST_CASE(matrix_calls_compose_like_opengl) {
  ContextGuard guard;
  rtMultMatrixf(kShear);
  const std::array<double, 16> m = currentMatrix();
  for (int i = 0; i < 16; ++i)
    BOOST_TEST(m[static_cast<std::size_t>(i)] == static_cast<double>(kShear[i]));
  rtLoadIdentity();
  rtTranslatef(1.0f, 2.0f, 3.0f);
  rtScalef(2.0f, 2.0f, 2.0f);
  // M = T * S: the scale applies first, so the translation column is unscaled.
  const std::array<double, 16> ts = currentMatrix();
  BOOST_TEST(ts[0] == 2.0);
  BOOST_TEST(ts[12] == 1.0);
  BOOST_TEST(ts[13] == 2.0);
  BOOST_TEST(ts[14] == 3.0);
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
}

BOOST_AUTO_TEST_CASE(normals_and_uvs_are_all_or_nothing_per_object) {
  ContextGuard guard;
  const RTuint id = rtNewObject();
  rtBeginObject(id);
  rtBegin(RT_TRIANGLES);
  rtVertex3f(0, 0, 0);
  rtNormal3f(1, 0, 0);
  rtVertex3f(1, 0, 0);
  rtVertex3f(0, 1, 0);
  rtEnd();
  rtEndObject();
  rtCommit();
  BOOST_TEST(rtGetError() == RT_NO_ERROR, rtGetErrorString());
  const TriangleMesh& mesh = rtGetScene().objectMesh(id);
  BOOST_TEST_REQUIRE(mesh.normals.size() == 3u);
  // The vertex before the first rtNormal3f gets GL's default current normal.
  BOOST_TEST((mesh.normals[0] == Vec3f{0, 0, 1}));
  BOOST_TEST((mesh.normals[1] == Vec3f{1, 0, 0}));
  BOOST_TEST((mesh.normals[2] == Vec3f{1, 0, 0}));
  BOOST_TEST(mesh.uvs.empty());
}

// ---- Misuse: rejected, reported with the call's name, and the scene is left as it was. ----

namespace {

/// Everything observable about a committed scene and the matrix state.
struct Snapshot {
  std::size_t objects = 0, instances = 0;
  std::vector<TriangleMesh> meshes;
  std::vector<Affine3d> transforms;
  std::vector<Hit> hits;
  std::array<double, 16> matrix{};
};

const std::vector<Ray>& probeRays() {
  static const std::vector<Ray> rays = randomRays(3000, 2);
  return rays;
}

Snapshot snapshot() {
  const Scene& scene = rtGetScene();
  Snapshot s;
  s.objects = scene.objectCount();
  s.instances = scene.instanceCount();
  for (ObjectId id = 0; id < s.objects; ++id) s.meshes.push_back(scene.objectMesh(id));
  for (InstanceId id = 0; id < s.instances; ++id)
    s.transforms.push_back(scene.instanceTransform(id));
  s.hits = traceAll(scene, probeRays());
  s.matrix = currentMatrix();
  return s;
}

/// A committed scene with two objects and three instances, a non-trivial current matrix and one
/// pushed matrix, so that every kind of state a misuse could damage is present.
struct Reference {
  ContextGuard guard;
  RTuint cube = RT_INVALID_ID, tetra = RT_INVALID_ID, instance = RT_INVALID_ID;
  Snapshot before;

  Reference() {
    cube = rtNewObject();
    tetra = rtNewObject();
    defineObject(cube, cubeTriangles(), false);
    defineObject(tetra, tetraTriangles(), true);
    rtTranslatef(0.0f, 0.0f, -5.0f);
    instance = rtInstantiateObject(cube);
    rtPushMatrix();
    rtRotatef(20.0f, 0.0f, 0.0f, 1.0f);
    rtScalef(3.0f, 3.0f, 3.0f);
    rtInstantiateObject(tetra);
    rtTranslatef(1.0f, 1.0f, 0.0f);
    rtInstantiateObject(cube);
    rtCommit();
    BOOST_TEST_REQUIRE(rtGetError() == RT_NO_ERROR, rtGetErrorString());
    before = snapshot();
    BOOST_TEST_REQUIRE(countMismatches(before.hits, std::vector<Hit>(before.hits.size())) > 100u);
  }

  /// The next error is `code`, its message starts with "<call>:", and then there is no other.
  void expectError(RTerror code, const std::string& call, const std::string& detail = {}) {
    BOOST_TEST(rtGetError() == code, "after " << call);
    const std::string message = rtGetErrorString();
    BOOST_TEST(message.rfind(call + ": ", 0) == 0u, message);
    if (!detail.empty()) BOOST_TEST(message.find(detail) != std::string::npos, message);
    BOOST_TEST(rtGetError() == RT_NO_ERROR, "after " << call);
  }

  /// Nothing is pending in the scene, and the scene, the current matrix and the stack depth are
  /// as before.
  void expectUnchanged() {
    BOOST_TEST(!rtGetScene().hasPendingChanges());
    rtCommit();
    BOOST_TEST(rtGetError() == RT_NO_ERROR, rtGetErrorString());
    const Snapshot now = snapshot();
    BOOST_TEST(now.objects == before.objects);
    BOOST_TEST(now.instances == before.instances);
    BOOST_TEST_REQUIRE(now.meshes.size() == before.meshes.size());
    for (std::size_t i = 0; i < now.meshes.size(); ++i)
      BOOST_TEST(sameMesh(now.meshes[i], before.meshes[i]), "object " << i);
    BOOST_TEST((now.transforms == before.transforms));
    BOOST_TEST(countMismatches(now.hits, before.hits) == 0u);
    BOOST_TEST((now.matrix == before.matrix));
    // The stack depth (current matrix plus the fixture's one push) is as before: count the
    // pushes that still fit, then undo them.
    int pushes = 0;
    for (; pushes <= RT_MAX_MATRIX_STACK_DEPTH; ++pushes) {
      rtPushMatrix();
      if (rtGetError() != RT_NO_ERROR) break;
    }
    BOOST_TEST(pushes == RT_MAX_MATRIX_STACK_DEPTH - 2);
    for (int i = 0; i < pushes; ++i) rtPopMatrix();
    BOOST_TEST(rtGetError() == RT_NO_ERROR, rtGetErrorString());
    BOOST_TEST((currentMatrix() == before.matrix));
  }

  /// Emits the first `count` vertices of the cube (inside an open rtBegin).
  static void cubeVertices(std::size_t count) {
    std::size_t n = 0;
    for (const Tri& t : cubeTriangles())
      for (const Vec3f& p : t.v)
        if (n++ < count) rtVertex3f(p.x, p.y, p.z);
  }
};

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

}  // namespace

BOOST_FIXTURE_TEST_SUITE(misuse, Reference)

BOOST_AUTO_TEST_CASE(unbalanced_begin_end) {
  rtEnd();
  expectError(RT_INVALID_OPERATION, "rtEnd");
  rtEndObject();
  expectError(RT_INVALID_OPERATION, "rtEndObject");
  rtBegin(RT_TRIANGLES);  // outside any object definition
  expectError(RT_INVALID_OPERATION, "rtBegin");
  expectUnchanged();

  // rtBegin twice: the redefinition of the cube is spoilt and discarded at rtEndObject.
  rtBeginObject(cube);
  rtBegin(RT_TRIANGLES);
  rtBegin(RT_TRIANGLES);
  expectError(RT_INVALID_OPERATION, "rtBegin");
  cubeVertices(3);
  rtEnd();
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  rtEndObject();
  expectError(RT_INVALID_OPERATION, "rtEndObject", "discarded");
  expectUnchanged();

  // rtBeginObject inside another definition.
  rtBeginObject(cube);
  rtBeginObject(tetra);
  expectError(RT_INVALID_OPERATION, "rtBeginObject");
  rtEndObject();
  expectError(RT_INVALID_OPERATION, "rtEndObject", "discarded");
  rtEndObject();  // the failed rtBeginObject opened nothing
  expectError(RT_INVALID_OPERATION, "rtEndObject", "no object definition");
  expectUnchanged();

  // rtEndObject inside rtBegin/rtEnd closes and discards the definition.
  rtBeginObject(cube);
  rtBegin(RT_TRIANGLES);
  cubeVertices(6);
  rtEndObject();
  expectError(RT_INVALID_OPERATION, "rtEndObject", "discarded");
  rtEnd();
  expectError(RT_INVALID_OPERATION, "rtEnd");
  expectUnchanged();

  // A vertex count that is not a multiple of 3.
  rtBeginObject(cube);
  rtBegin(RT_TRIANGLES);
  cubeVertices(4);
  rtEnd();
  expectError(RT_INVALID_OPERATION, "rtEnd", "4 vertices");
  rtEndObject();
  expectError(RT_INVALID_OPERATION, "rtEndObject", "discarded");
  expectUnchanged();

  // An unsupported primitive mode.
  rtBeginObject(cube);
  rtBegin(static_cast<RTenum>(0x0007));
  expectError(RT_INVALID_ENUM, "rtBegin");
  rtEndObject();
  expectError(RT_INVALID_OPERATION, "rtEndObject", "discarded");
  expectUnchanged();
}

BOOST_AUTO_TEST_CASE(calls_not_allowed_inside_an_object_definition) {
  rtBeginObject(tetra);
  BOOST_TEST(rtInstantiateObject(cube) == RT_INVALID_ID);
  expectError(RT_INVALID_OPERATION, "rtInstantiateObject");
  rtSetInstanceMatrix(instance);
  expectError(RT_INVALID_OPERATION, "rtSetInstanceMatrix");
  rtCommit();
  expectError(RT_INVALID_OPERATION, "rtCommit");
  rtEndObject();
  expectError(RT_INVALID_OPERATION, "rtEndObject", "discarded");
  expectUnchanged();
}

BOOST_AUTO_TEST_CASE(vertex_outside_begin_end) {
  rtVertex3f(0, 0, 0);
  expectError(RT_INVALID_OPERATION, "rtVertex3f");
  rtNormal3f(0, 0, 1);
  expectError(RT_INVALID_OPERATION, "rtNormal3f");
  rtTexCoord2f(0, 0);
  expectError(RT_INVALID_OPERATION, "rtTexCoord2f");
  expectUnchanged();
  rtBeginObject(cube);
  rtVertex3f(0, 0, 0);
  expectError(RT_INVALID_OPERATION, "rtVertex3f");
  rtEndObject();
  expectError(RT_INVALID_OPERATION, "rtEndObject", "discarded");
  expectUnchanged();
}

BOOST_AUTO_TEST_CASE(unknown_ids) {
  rtBeginObject(999);
  expectError(RT_INVALID_VALUE, "rtBeginObject", "999");
  rtBeginObject(RT_INVALID_ID);
  expectError(RT_INVALID_VALUE, "rtBeginObject");
  BOOST_TEST(rtInstantiateObject(999) == RT_INVALID_ID);
  expectError(RT_INVALID_VALUE, "rtInstantiateObject", "999");
  rtSetInstanceMatrix(999);
  expectError(RT_INVALID_VALUE, "rtSetInstanceMatrix", "999");
  BOOST_TEST(rtNewObject(static_cast<RTenum>(77)) == RT_INVALID_ID);
  expectError(RT_INVALID_ENUM, "rtNewObject");
  expectUnchanged();
}

BOOST_AUTO_TEST_CASE(non_finite_geometry) {
  rtBeginObject(cube);
  rtBegin(RT_TRIANGLES);
  cubeVertices(7);
  rtVertex3f(0.0f, kNaN, 0.0f);
  BOOST_TEST(rtGetError() == RT_INVALID_VALUE);
  BOOST_TEST(std::string(rtGetErrorString()) == "rtVertex3f: vertex is NaN or infinite (object " +
                                                    std::to_string(cube) + ", vertex 7)");
  rtVertex3f(kInf, 0.0f, 0.0f);
  expectError(RT_INVALID_VALUE, "rtVertex3f");
  rtNormal3f(0.0f, 0.0f, -kInf);
  expectError(RT_INVALID_VALUE, "rtNormal3f");
  rtTexCoord2f(kNaN, 0.0f);
  expectError(RT_INVALID_VALUE, "rtTexCoord2f");
  cubeVertices(2);
  rtEnd();
  BOOST_TEST(rtGetError() == RT_NO_ERROR);  // 9 vertices: the rejected ones were not added
  rtEndObject();
  expectError(RT_INVALID_OPERATION, "rtEndObject", "rtVertex3f: vertex is NaN");
  expectUnchanged();
}

BOOST_AUTO_TEST_CASE(non_finite_and_non_affine_matrices) {
  rtTranslatef(kNaN, 0.0f, 0.0f);
  expectError(RT_INVALID_VALUE, "rtTranslatef");
  rtRotatef(kInf, 0.0f, 1.0f, 0.0f);
  expectError(RT_INVALID_VALUE, "rtRotatef");
  rtRotatef(30.0f, 0.0f, kNaN, 0.0f);
  expectError(RT_INVALID_VALUE, "rtRotatef");
  rtScalef(1.0f, -kInf, 1.0f);
  expectError(RT_INVALID_VALUE, "rtScalef");
  float m[16];
  std::copy(std::begin(kShear), std::end(kShear), m);
  m[5] = kNaN;
  rtMultMatrixf(m);
  expectError(RT_INVALID_VALUE, "rtMultMatrixf");
  std::copy(std::begin(kShear), std::end(kShear), m);
  m[11] = -1.0f;  // a perspective projection's last row
  rtMultMatrixf(m);
  expectError(RT_INVALID_VALUE, "rtMultMatrixf", "last row");
  m[11] = 0.0f;
  m[15] = 2.0f;
  rtMultMatrixf(m);
  expectError(RT_INVALID_VALUE, "rtMultMatrixf", "last row");
  rtMultMatrixf(nullptr);
  expectError(RT_INVALID_VALUE, "rtMultMatrixf");
  // Finite arguments whose product overflows double.
  rtPushMatrix();
  for (int i = 0; i < 12; ++i) rtScalef(1e30f, 1e30f, 1e30f);
  BOOST_TEST(rtGetError() == RT_INVALID_VALUE);
  BOOST_TEST(std::string(rtGetErrorString()).rfind("rtScalef: ", 0) == 0u);
  BOOST_TEST(std::isfinite(currentMatrix()[0]));
  rtPopMatrix();
  expectUnchanged();
}

BOOST_AUTO_TEST_CASE(matrix_stack_limits) {
  rtPopMatrix();  // pops the fixture's one pushed matrix
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  const std::array<double, 16> base = currentMatrix();
  rtPopMatrix();
  expectError(RT_STACK_UNDERFLOW, "rtPopMatrix");
  BOOST_TEST((currentMatrix() == base));
  // The current matrix counts towards the depth, as in GL.
  for (int i = 1; i < RT_MAX_MATRIX_STACK_DEPTH; ++i) {
    rtPushMatrix();
    rtTranslatef(1.0f, 0.0f, 0.0f);
  }
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  const std::array<double, 16> top = currentMatrix();
  rtPushMatrix();
  expectError(RT_STACK_OVERFLOW, "rtPushMatrix");
  BOOST_TEST((currentMatrix() == top));
  for (int i = 1; i < RT_MAX_MATRIX_STACK_DEPTH; ++i) rtPopMatrix();
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  BOOST_TEST((currentMatrix() == base));
  rtPopMatrix();
  expectError(RT_STACK_UNDERFLOW, "rtPopMatrix");
  BOOST_TEST(!rtGetScene().hasPendingChanges());
}

BOOST_AUTO_TEST_CASE(singular_and_overflowing_instance_matrices) {
  rtPushMatrix();
  rtScalef(1.0f, 0.0f, 1.0f);
  BOOST_TEST(rtGetError() == RT_NO_ERROR);                 // allowed on the stack...
  BOOST_TEST(rtInstantiateObject(cube) == RT_INVALID_ID);  // ...but not for an instance
  expectError(RT_INVALID_VALUE, "rtInstantiateObject", "singular");
  rtSetInstanceMatrix(instance);
  expectError(RT_INVALID_VALUE, "rtSetInstanceMatrix", "singular");
  rtPopMatrix();
  rtPushMatrix();
  const float rankTwo[16] = {1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 0, 1};
  rtMultMatrixf(rankTwo);
  BOOST_TEST(rtInstantiateObject(tetra) == RT_INVALID_ID);
  expectError(RT_INVALID_VALUE, "rtInstantiateObject", "singular");
  rtPopMatrix();
  rtPushMatrix();
  rtScalef(1e30f, 1e30f, 1e30f);
  rtScalef(1e30f, 1e30f, 1e30f);  // fine in double, infinite in float
  BOOST_TEST(rtInstantiateObject(cube) == RT_INVALID_ID);
  expectError(RT_INVALID_VALUE, "rtInstantiateObject", "float");
  rtPopMatrix();
  expectUnchanged();
}

BOOST_AUTO_TEST_CASE(empty_objects_may_be_instantiated) {
  const RTuint defined = rtNewObject();
  defineObject(defined, {}, false);
  const RTuint undefined = rtNewObject();
  BOOST_TEST(rtInstantiateObject(defined) != RT_INVALID_ID);
  BOOST_TEST(rtInstantiateObject(undefined) != RT_INVALID_ID);
  rtCommit();
  BOOST_TEST(rtGetError() == RT_NO_ERROR, rtGetErrorString());
  BOOST_TEST(rtGetScene().objectCount() == before.objects + 2);
  BOOST_TEST(rtGetScene().instanceCount() == before.instances + 2);
  BOOST_TEST(countMismatches(traceAll(rtGetScene(), probeRays()), before.hits) == 0u);
}

BOOST_AUTO_TEST_CASE(redefinition_replaces_the_mesh_and_set_instance_matrix_moves) {
  defineObject(cube, tetraTriangles(), false);
  rtLoadIdentity();
  rtTranslatef(0.0f, 0.0f, -8.0f);
  rtSetInstanceMatrix(instance);
  rtCommit();
  BOOST_TEST(rtGetError() == RT_NO_ERROR, rtGetErrorString());
  BOOST_TEST(sameMesh(rtGetScene().objectMesh(cube), meshOf(tetraTriangles(), false)));
  BOOST_TEST((rtGetScene().instanceTransform(instance) == Affine3d::translation({0.0, 0.0, -8.0})));
  BOOST_TEST(rtGetScene().objectCount() == before.objects);
  BOOST_TEST(countMismatches(traceAll(rtGetScene(), probeRays()), before.hits) > 0u);
}

BOOST_AUTO_TEST_CASE(no_current_context) {
  rtMakeCurrent(nullptr);
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  BOOST_TEST(rtNewObject() == RT_INVALID_ID);
  BOOST_TEST(rtGetError() == RT_INVALID_OPERATION);
  BOOST_TEST(std::string(rtGetErrorString()) == "rtNewObject: no current context");
  rtBegin(RT_TRIANGLES);
  rtVertex3f(0, 0, 0);
  rtPopMatrix();
  BOOST_TEST(rtInstantiateObject(0) == RT_INVALID_ID);
  rtCommit();
  BOOST_TEST(rtGetError() == RT_INVALID_OPERATION);
  BOOST_TEST(std::string(rtGetErrorString()) == "rtCommit: no current context");
  BOOST_TEST(rtGetScene().objectCount() == 0u);
  BOOST_TEST(rtGetScene().instanceCount() == 0u);
  BOOST_TEST(rtGetError() == RT_INVALID_OPERATION);  // rtGetScene itself
  Hit hit;
  BOOST_TEST(!rtGetScene().intersect(probeRays()[0], hit));
  BOOST_TEST(rtGetError() == RT_INVALID_OPERATION);
  // Back on the context: its own error state is untouched.
  rtMakeCurrent(guard.ctx);
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  expectUnchanged();
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_CASE(errors_behave_like_gl) {
  ContextGuard guard;
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  BOOST_TEST(std::string(rtGetErrorString()).empty());
  rtPopMatrix();
  rtTranslatef(kNaN, 0, 0);
  rtLoadIdentity();  // a successful call does not clear the error
  // The oldest unreported code, the most recent message.
  BOOST_TEST(rtGetError() == RT_STACK_UNDERFLOW);
  BOOST_TEST(std::string(rtGetErrorString()).rfind("rtTranslatef: ", 0) == 0u);
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  BOOST_TEST(std::string(rtGetErrorString()).rfind("rtTranslatef: ", 0) == 0u);
  rtEnd();
  BOOST_TEST(rtGetError() == RT_INVALID_OPERATION);
  BOOST_TEST(rtGetError() == RT_NO_ERROR);

  // Contexts keep separate error state.
  RTcontext other = rtCreateContext();
  rtMakeCurrent(other);
  rtPopMatrix();
  rtMakeCurrent(guard.ctx);
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
  rtMakeCurrent(other);
  BOOST_TEST(rtGetError() == RT_STACK_UNDERFLOW);
  rtDestroyContext(other);  // current: the thread is left without a context
  BOOST_TEST(rtGetCurrentContext() == nullptr);
  rtMakeCurrent(guard.ctx);
}

BOOST_AUTO_TEST_CASE(current_context_is_per_thread) {
  ContextGuard guard;
  RTcontext seen = guard.ctx;
  RTerror error = RT_NO_ERROR;
  std::thread worker([&] {
    seen = rtGetCurrentContext();
    rtPopMatrix();
    error = rtGetError();
  });
  worker.join();
  BOOST_TEST(seen == nullptr);
  BOOST_TEST(error == RT_INVALID_OPERATION);
  BOOST_TEST(rtGetCurrentContext() == guard.ctx);
  BOOST_TEST(rtGetError() == RT_NO_ERROR);
}
