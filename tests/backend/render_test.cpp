// Renderer tests with analytic answers: Phong shading of a sphere, shadow acne across scene
// translations, refraction through slabs, Fresnel and total internal reflection, recursion
// limits between mirrors, thread-count determinism, AOVs and image/texture files
// (hard cases 13-17 and 21).
#define BOOST_TEST_MODULE render
#include <boost/test/unit_test.hpp>

#include <tbb/task_arena.h>
#include <unistd.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "IsaGuard.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/Simd.h"
#include "tracegraph/backend/render/Camera.h"
#include "tracegraph/backend/render/ImageIO.h"
#include "tracegraph/backend/render/Optics.h"
#include "tracegraph/backend/render/RayOffset.h"
#include "tracegraph/backend/render/RenderScene.h"
#include "tracegraph/backend/render/Renderer.h"
#include "tracegraph/backend/render/Texture.h"

using namespace tg;
using tg::test::IsaGuard;

namespace {

/// Quad (two triangles) with corner `o` and edges `e1`, `e2`, normal along e1 x e2.
TriangleMesh makeQuad(const Vec3f& o, const Vec3f& e1, const Vec3f& e2) {
  TriangleMesh m;
  m.positions = {o, o + e1, o + e1 + e2, o + e2};
  m.uvs = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

/// Axis-aligned box as 12 outward-facing triangles; faces in the order -x, +x, -y, +y, -z, +z
/// (triangles 2k and 2k + 1 belong to face k).
TriangleMesh makeBox(const Vec3f& lo, const Vec3f& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  const std::uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads)
    m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  return m;
}

/// Sphere as a latitude/longitude mesh with exact vertex normals.
TriangleMesh makeSphere(const Vec3f& centre, float radius, std::uint32_t rings,
                        std::uint32_t segments) {
  TriangleMesh m;
  for (std::uint32_t i = 0; i <= rings; ++i) {
    const double theta = std::numbers::pi * i / rings;
    for (std::uint32_t j = 0; j <= segments; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / segments;
      const Vec3d n(std::sin(theta) * std::cos(phi), std::cos(theta),
                    std::sin(theta) * std::sin(phi));
      m.positions.push_back(Vec3f(Vec3d(centre) + n * static_cast<double>(radius)));
      m.normals.push_back(Vec3f(n));
    }
  }
  const std::uint32_t row = segments + 1;
  for (std::uint32_t i = 0; i < rings; ++i)
    for (std::uint32_t j = 0; j < segments; ++j) {
      const std::uint32_t a = i * row + j, b = a + row;
      if (i != 0) m.indices.insert(m.indices.end(), {a, a + 1, b});
      if (i + 1 != rings) m.indices.insert(m.indices.end(), {a + 1, b + 1, b});
    }
  return m;
}

Material diffuseMaterial(const Vec3f& c) {
  Material m;
  m.diffuse = c;
  return m;
}

Material mirrorMaterial(float reflectance) {
  Material m;
  m.diffuse = {0.0f, 0.0f, 0.0f};
  m.specular = {reflectance, reflectance, reflectance};
  return m;
}

Material glassMaterial(float ior) {
  Material m;
  m.diffuse = {0.0f, 0.0f, 0.0f};
  m.transmittance = 1.0f;
  m.ior = ior;
  return m;
}

/// A Scene and its RenderScene, one material per object.
struct TestScene {
  Scene scene;
  RenderScene rs;

  TestScene() { rs.scene = &scene; }
  TestScene(const TestScene&) = delete;
  TestScene& operator=(const TestScene&) = delete;

  InstanceId add(TriangleMesh mesh, const Material& material, const Affine3d& m = Affine3d{}) {
    const ObjectId object = scene.createObject(std::move(mesh));
    rs.materials.push_back(material);
    if (rs.objectMaterials.size() <= object) rs.objectMaterials.resize(object + 1, kInvalidId);
    rs.objectMaterials[object] = static_cast<std::uint32_t>(rs.materials.size() - 1);
    return scene.createInstance(object, m);
  }
};

Frame render(const TestScene& ts, const Camera& camera, const RenderSettings& settings,
             RenderStats* stats = nullptr) {
  Frame frame;
  const RenderStats s = Renderer(settings).render(ts.rs, camera, frame);
  if (stats) *stats = s;
  return frame;
}

RenderSettings settingsFor(RenderMode mode) {
  RenderSettings s;
  s.mode = mode;
  return s;
}

/// A fresh path in the temporary directory.
std::filesystem::path tempPath(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("tg_render_test_" + std::to_string(::getpid()) + "_" + name);
}

std::vector<unsigned char> readBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Camera

BOOST_AUTO_TEST_CASE(camera_samples_pixel_centres_with_row_zero_on_top) {
  const Camera cam = Camera::lookAt({1.0f, 2.0f, 3.0f}, {1.0f, 2.0f, -7.0f}, {0.0f, 1.0f, 0.0f},
                                    90.0f, 5, 5, 0.25f);
  const Ray centre = cam.primaryRay(2, 2);
  BOOST_TEST(std::abs(centre.direction.z + 1.0f) < 1e-6f);
  BOOST_TEST(centre.tnear == 0.25f);
  BOOST_TEST((centre.origin == Vec3f{1.0f, 2.0f, 3.0f}));
  const Ray topLeft = cam.primaryRay(0, 0);
  BOOST_TEST(topLeft.direction.x < 0.0f);
  BOOST_TEST(topLeft.direction.y > 0.0f);
  // fov 90: the image plane at distance 1 spans [-1, 1]; pixel 0's centre is at -0.8.
  const Vec3f d = topLeft.direction / -topLeft.direction.z;
  BOOST_TEST(std::abs(d.x + 0.8f) < 1e-6f);
  BOOST_TEST(std::abs(d.y - 0.8f) < 1e-6f);
  for (std::uint32_t y = 0; y < 5; ++y)
    for (std::uint32_t x = 0; x < 5; ++x)
      BOOST_TEST(std::abs(length(cam.primaryRay(x, y).direction) - 1.0f) < 2e-7f);
  // The renderer forms each column's and row's plane coordinate once; the rays are the same.
  const Camera wide = Camera::lookAt({0.3f, -2.0f, 7.0f}, {1.0f, 0.5f, -3.0f}, {0.1f, 1.0f, 0.2f},
                                     63.7f, 37, 23, 0.01f);
  for (std::uint32_t y = 0; y < 23; ++y)
    for (std::uint32_t x = 0; x < 37; ++x) {
      const Ray a = wide.primaryRay(x, y);
      const Ray b = wide.rayThroughPlane(wide.planeX(x + 0.5), wide.planeY(y + 0.5));
      BOOST_TEST((std::bit_cast<std::array<std::uint32_t, 3>>(a.direction) ==
                  std::bit_cast<std::array<std::uint32_t, 3>>(b.direction)));
      BOOST_TEST((a.origin == b.origin && a.tnear == b.tnear && a.tfar == b.tfar));
    }
  BOOST_CHECK_THROW(Camera::lookAt({0, 0, 0}, {0, 1, 0}, {0, 1, 0}, 45.0f, 4, 4), Error);
  BOOST_CHECK_THROW(Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 180.0f, 4, 4), Error);
  BOOST_CHECK_THROW(Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 45.0f, 0, 4), Error);
}

// ---------------------------------------------------------------------------------------------
// Phong shading against the closed form

BOOST_AUTO_TEST_CASE(tessellated_sphere_matches_closed_form_phong) {
  TestScene ts;
  Material m;
  m.ambient = {0.2f, 0.2f, 0.2f};
  m.diffuse = {0.6f, 0.3f, 0.2f};
  m.specular = {0.3f, 0.3f, 0.3f};
  m.shine = 20.0f;
  const Vec3d centre(0.0, 0.0, 0.0);
  const double radius = 1.0;
  ts.add(makeSphere(Vec3f(centre), static_cast<float>(radius), 96, 192), m);
  ts.scene.commit();
  const Vec3d lightPos(3.0, 4.0, 5.0);
  const Vec3d lightColor(0.9, 0.8, 0.7);
  ts.rs.pointLights.push_back({Vec3f(lightPos), Vec3f(lightColor), {}});
  ts.rs.ambient = {0.5f, 0.5f, 0.5f};
  const Camera cam =
      Camera::lookAt({0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 35.0f, 80, 80);

  for (RenderMode mode : {RenderMode::Whitted, RenderMode::OpenGL}) {
    RenderStats stats;
    const Frame frame = render(ts, cam, settingsFor(mode), &stats);
    double maxError = 0.0;
    int compared = 0;
    for (std::uint32_t y = 0; y < cam.height(); ++y) {
      for (std::uint32_t x = 0; x < cam.width(); ++x) {
        const Ray r = cam.primaryRay(x, y);
        const Vec3d o(r.origin), d(r.direction);
        // Exact ray/sphere intersection in double.
        const Vec3d oc = o - centre;
        const double b = dot(oc, d), c = dot(oc, oc) - radius * radius;
        const double disc = b * b - c;
        if (disc <= 0.0) {
          BOOST_TEST(frame.depth.at(x, y) == kInfinity);
          continue;
        }
        const Vec3d p = o + d * (-b - std::sqrt(disc));
        const Vec3d n = (p - centre) / radius;
        const Vec3d l = normalize(lightPos - p);
        const Vec3d v = -d;
        const double nl = dot(n, l);
        // Stay away from the terminator and the silhouette, where a tessellated sphere
        // legitimately differs from the exact one.
        if (nl < 0.15 || dot(n, v) < 0.3) continue;
        const Vec3d refl = n * (2.0 * nl) - l;
        const double rv = std::max(0.0, dot(refl, v));
        const Vec3d amb = Vec3d(m.ambient) * Vec3d(ts.rs.ambient);
        const Vec3d expected =
            amb + lightColor * (Vec3d(m.diffuse) * nl + Vec3d(m.specular) * std::pow(rv, 20.0));
        const Vec3d got(frame.beauty.rgb(x, y));
        for (int k = 0; k < 3; ++k) maxError = std::max(maxError, std::abs(got[k] - expected[k]));
        ++compared;
      }
    }
    BOOST_TEST_MESSAGE("sphere " << renderModeName(mode) << ": " << compared
                                 << " pixels, max error " << maxError);
    BOOST_TEST(compared > 1000);
    BOOST_TEST(maxError < 0.01);
    if (mode == RenderMode::OpenGL) BOOST_TEST(stats.traced.shadow == 0u);
  }
}

// ---------------------------------------------------------------------------------------------
// Shadow acne (hard case 13)

namespace {

struct AcneResult {
  int lit = 0, expectedLit = 0, wrong = 0, nearBoundary = 0, floorPixels = 0;
};

/// A floor y = T lit at `elevationDegrees` by a directional light, with a wall x = T of height
/// h casting a straight shadow edge at x = T + h / tan(elevation); the camera looks straight
/// down at the edge. The whole scene is translated by (T, T, T).
AcneResult renderShadowEdge(double translation, double elevationDegrees, RenderMode mode) {
  const double h = 1000.0;
  const double theta = elevationDegrees * std::numbers::pi / 180.0;
  const double edge = h / std::tan(theta);
  const float T = static_cast<float>(translation);
  TestScene ts;
  const float floorLo = -1000.0f, floorHi = static_cast<float>(2.0 * edge + 5000.0);
  ts.add(makeQuad({T + floorLo, T, T + 8000.0f}, {floorHi - floorLo, 0.0f, 0.0f},
                  {0.0f, 0.0f, -16000.0f}),
         diffuseMaterial({1.0f, 1.0f, 1.0f}));
  ts.add(makeQuad({T, T, T - 8000.0f}, {0.0f, static_cast<float>(h), 0.0f}, {0.0f, 0.0f, 16000.0f}),
         diffuseMaterial({1.0f, 1.0f, 1.0f}));
  ts.scene.commit();
  const Vec3f lightDir(static_cast<float>(std::cos(theta)), static_cast<float>(-std::sin(theta)),
                       0.0f);
  ts.rs.directionalLights.push_back({lightDir, {1.0f, 1.0f, 1.0f}});

  // The analytic edge from the float scene data: wall top over the floor, along the light.
  const double floorY = T, wallX = T, wallTop = static_cast<double>(T + static_cast<float>(h));
  const double edgeX = wallX + (wallTop - floorY) * static_cast<double>(lightDir.x) /
                                   -static_cast<double>(lightDir.y);

  const float eyeX = static_cast<float>(translation + edge);
  const Camera cam =
      Camera::lookAt({eyeX, T + 3000.0f, T}, {eyeX, T, T}, {0.0f, 0.0f, -1.0f}, 60.0f, 64, 64);
  const Frame frame = render(ts, cam, settingsFor(mode));
  const double footprint = 2.0 * 3000.0 * std::tan(std::numbers::pi / 6.0) / 64.0;
  AcneResult res;
  for (std::uint32_t y = 0; y < 64; ++y) {
    for (std::uint32_t x = 0; x < 64; ++x) {
      const Ray r = cam.primaryRay(x, y);
      const double t =
          (static_cast<double>(r.origin.y) - floorY) / -static_cast<double>(r.direction.y);
      const double hitX = static_cast<double>(r.origin.x) + t * static_cast<double>(r.direction.x);
      const bool expected = hitX > edgeX;
      const bool lit = frame.beauty.at(x, y, 0) > 0.0f;
      ++res.floorPixels;
      res.lit += lit;
      res.expectedLit += expected;
      if (lit != expected) {
        if (std::abs(hitX - edgeX) < 1.5 * footprint)
          ++res.nearBoundary;
        else
          ++res.wrong;
      }
    }
  }
  return res;
}

}  // namespace

BOOST_AUTO_TEST_CASE(shadow_edge_is_exact_at_all_translations) {
  for (double elevation : {10.0, 3.0}) {
    for (double translation : {1.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6}) {
      const AcneResult r = renderShadowEdge(translation, elevation, RenderMode::Whitted);
      BOOST_TEST_MESSAGE("elevation " << elevation << " translation " << translation << ": lit "
                                      << r.lit << " expected " << r.expectedLit << " of "
                                      << r.floorPixels << ", boundary mismatches "
                                      << r.nearBoundary);
      BOOST_TEST(r.wrong == 0, "elevation " << elevation << ", translation " << translation << ": "
                                            << r.wrong << " wrongly lit/shadowed pixels");
      BOOST_TEST(r.nearBoundary <= 64);  // at most one column
      BOOST_TEST(r.expectedLit > 1000);
      BOOST_TEST(r.expectedLit < 3000);
    }
  }
  // OpenGL mode casts no shadows: every floor pixel is lit.
  const AcneResult gl = renderShadowEdge(1e3, 10.0, RenderMode::OpenGL);
  BOOST_TEST(gl.lit == gl.floorPixels);
}

BOOST_AUTO_TEST_CASE(offset_origins_never_self_intersect_tilted_planes) {
  // Rays hit a randomly tilted large quad; secondary rays leave towards random directions down
  // to grazing ones, on both sides (reflection and refraction). None may hit the quad again.
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  std::uint64_t naiveSelfHits = 0;
  for (double translation : {0.0, 1.0, 1e2, 1e4, 1e6}) {
    TestScene ts;
    const Vec3f c(static_cast<float>(translation), static_cast<float>(-translation),
                  static_cast<float>(0.5 * translation));
    const Vec3f e1 = normalize(Vec3f{1.0f, 0.3f, -0.2f}) * 400.0f;
    const Vec3f e2 = normalize(cross(Vec3f{0.2f, 0.4f, 1.0f}, e1)) * 300.0f;
    ts.add(makeQuad(c - e1 * 0.5f - e2 * 0.5f, e1, e2), diffuseMaterial({1, 1, 1}));
    // The same quad once more through a rotated, non-uniformly scaled instance, further out.
    const Affine3d m = Affine3d::translation(Vec3d(c) + Vec3d(0.0, 0.0, 3000.0)) *
                       Affine3d::rotation({0.3, 0.2, 1.0}, 37.0) *
                       Affine3d::scaling({1.7, 0.6, 2.3});
    ts.add(makeQuad(-e1 * 0.5f - e2 * 0.5f, e1, e2), diffuseMaterial({1, 1, 1}), m);
    ts.scene.commit();
    int selfHits = 0, hits = 0;
    for (int i = 0; i < 4000; ++i) {
      const Vec3f local = e1 * (0.45f * uni(rng)) + e2 * (0.45f * uni(rng));
      const Vec3f target = i % 2 == 0 ? c + local : Vec3f(m.transformPoint(Vec3d(local)));
      Ray r;
      r.origin = target + Vec3f{uni(rng), uni(rng), uni(rng)} * 500.0f;
      r.direction = target - r.origin;
      Hit hit;
      if (!ts.scene.intersect(r, hit)) continue;
      ++hits;
      const SurfacePoint sp = refineHitPoint(ts.scene, r, hit);
      const Vec3f n = sp.geometricNormal;
      for (int k = 0; k < 4; ++k) {
        Vec3f w = normalize(Vec3f{uni(rng), uni(rng), uni(rng)});
        // Push some directions to grazing: nearly within the plane.
        if (k >= 2) w = normalize(w - n * dot(w, n) * 0.999f);
        if (dot(w, n) == 0.0f) continue;
        // Only the quad left counts: rays may legitimately hit the other one.
        Hit again;
        if (ts.scene.intersect(spawnRay(sp, w), again) && again.instanceId == hit.instanceId)
          ++selfHits;
        Ray naive;
        naive.origin = r.origin + r.direction * hit.t;
        naive.direction = w;
        if (ts.scene.intersect(naive, again) && again.instanceId == hit.instanceId) ++naiveSelfHits;
      }
    }
    BOOST_TEST(hits > 2000);
    BOOST_TEST(selfHits == 0, "translation " << translation << ": " << selfHits << " self-hits");
  }
  // The check is sensitive: without the offset, rays do hit the surface they leave.
  BOOST_TEST_MESSAGE("self-hits without offset: " << naiveSelfHits);
  BOOST_TEST(naiveSelfHits > 0u);
}

BOOST_AUTO_TEST_CASE(phong_highlights_below_the_cutoff_are_exactly_zero) {
  // The shader skips powf(r.v, shine) below exp2(-160 / shine) because powf returns exactly +0
  // there; check that premise against this platform's powf, up to just below the cutoff.
  std::size_t checked = 0, nonZero = 0;
  for (float shine = 0.25f; shine < 2000.0f; shine *= 1.0173f) {
    const float cutoff = std::exp2(-160.0f / shine);
    float rv = std::nextafter(cutoff, 0.0f);
    for (int i = 0; i < 64 && rv > 0.0f; ++i, rv *= 0.83f) {
      const float p = std::pow(rv, shine);
      nonZero += std::bit_cast<std::uint32_t>(p) != 0u;
      ++checked;
    }
  }
  BOOST_TEST(checked > 10000u);
  BOOST_TEST(nonZero == 0u);
}

BOOST_AUTO_TEST_CASE(offset_origins_step_outwards_exactly_as_nextafter_does) {
  // offsetRayOrigin as first written, with std::nextafter.
  auto reference = [](const SurfacePoint& sp, const Vec3f& w) {
    const Vec3f& n = sp.geometricNormal;
    const float distance = sp.error * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
    Vec3f offset = n * distance;
    if (dot(w, n) < 0.0f) offset = -offset;
    Vec3f o = sp.position + offset;
    for (int i = 0; i < 3; ++i) {
      if (offset[i] > 0.0f)
        o[i] = std::nextafter(o[i], kInfinity);
      else if (offset[i] < 0.0f)
        o[i] = std::nextafter(o[i], -kInfinity);
    }
    return o;
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_int_distribution<int> exponent(-140, 127);
  const float special[] = {0.0f,
                           -0.0f,
                           1e-45f,
                           -1e-45f,
                           1e-38f,
                           -1e-38f,
                           std::numeric_limits<float>::max(),
                           -std::numeric_limits<float>::max(),
                           kInfinity,
                           -kInfinity,
                           1.0f,
                           -1.0f};
  std::size_t differing = 0;
  for (int i = 0; i < 20000; ++i) {
    SurfacePoint sp;
    auto coordinate = [&] {
      return i % 4 == 0 ? special[static_cast<std::size_t>(rng() % std::size(special))]
                        : std::ldexp(unit(rng), exponent(rng));
    };
    sp.position = {coordinate(), coordinate(), coordinate()};
    sp.geometricNormal = normalize(Vec3f{unit(rng), unit(rng), unit(rng)});
    if (i % 5 == 0) sp.geometricNormal = {0.0f, i % 10 == 0 ? 1.0f : -1.0f, 0.0f};
    sp.error = i % 7 == 0 ? 0.0f : std::ldexp(std::abs(unit(rng)), exponent(rng) / 2);
    const Vec3f w{unit(rng), unit(rng), unit(rng)};
    const Vec3f got = offsetRayOrigin(sp, w), want = reference(sp, w);
    differing += std::memcmp(&got, &want, sizeof got) != 0;
  }
  BOOST_TEST(differing == 0u);
}

BOOST_AUTO_TEST_CASE(shadow_rays_stop_short_of_a_light_on_a_surface) {
  // A point light exactly on a wall: the wall must not shadow the floor it lights.
  for (double translation : {0.0, 1e3, 1e5}) {
    TestScene ts;
    const float T = static_cast<float>(translation);
    ts.add(makeQuad({T - 50.0f, T, T + 50.0f}, {100.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -100.0f}),
           diffuseMaterial({1, 1, 1}));
    ts.add(makeQuad({T - 50.0f, T, T - 10.0f}, {100.0f, 0.0f, 0.0f}, {0.0f, 40.0f, 0.0f}),
           diffuseMaterial({1, 1, 1}));
    ts.scene.commit();
    ts.rs.pointLights.push_back({{T, T + 10.0f, T - 10.0f}, {1, 1, 1}, {}});
    const Camera cam =
        Camera::lookAt({T, T + 30.0f, T + 30.0f}, {T, T, T}, {0, 1, 0}, 40.0f, 24, 24);
    const Frame frame = render(ts, cam, settingsFor(RenderMode::Whitted));
    int floorLit = 0, floorPixels = 0;
    for (std::uint32_t y = 0; y < 24; ++y)
      for (std::uint32_t x = 0; x < 24; ++x)
        if (frame.primId.at(x, y) != kInvalidId && frame.instanceId.at(x, y) == 0) {
          ++floorPixels;
          floorLit += frame.beauty.at(x, y, 0) > 0.0f;
        }
    BOOST_TEST(floorPixels > 100);
    BOOST_TEST(floorLit == floorPixels, "translation " << translation);
  }
}

BOOST_AUTO_TEST_CASE(rays_spawned_in_place_equal_returned_rays_even_from_their_own_fields) {
  // The in-place forms write a ray that the shader keeps in a table; they must give the
  // returned forms' bits, also when the target or direction is a field of the ray written.
  const auto sameBits = [](const Ray& a, const Ray& b) {
    return std::memcmp(&a, &b, sizeof(Ray)) == 0;
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-1e3f, 1e3f);
  for (int i = 0; i < 200; ++i) {
    SurfacePoint sp;
    sp.position = {coord(rng), coord(rng), coord(rng)};
    sp.geometricNormal = normalize(Vec3f{coord(rng), coord(rng), coord(rng)});
    sp.error = 1e-4f;
    const Vec3f target{coord(rng), coord(rng), coord(rng)};
    const Vec3f w = normalize(target - sp.position);
    const Ray towards = spawnRayTo(sp, target), along = spawnRay(sp, w);

    Ray r;
    spawnRayTo(sp, target, r);
    BOOST_TEST(sameBits(r, towards));
    r = Ray{};
    r.origin = target;  // the target is the origin being overwritten
    spawnRayTo(sp, r.origin, r);
    BOOST_TEST(sameBits(r, towards));
    r.direction = target;  // ... or the direction
    spawnRayTo(sp, r.direction, r);
    BOOST_TEST(sameBits(r, towards));

    spawnRay(sp, w, r);
    BOOST_TEST(sameBits(r, along));
    r = Ray{};
    r.origin = w;
    spawnRay(sp, r.origin, r);
    BOOST_TEST(sameBits(r, along));
    r.direction = w;
    spawnRay(sp, r.direction, r);
    BOOST_TEST(sameBits(r, along));
  }
}

BOOST_AUTO_TEST_CASE(ray_origins_depend_on_the_direction_only_through_its_side) {
  // The shader makes one origin per side of a surface (leavesBelow) and spawns the shadow rays
  // of all the lights on that side from it (spawnRayFrom): that must give spawnRayTo's bits.
  const auto sameBits = [](const auto& a, const auto& b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coord(-1e3f, 1e3f);
  std::size_t below = 0, above = 0;
  for (int i = 0; i < 2000; ++i) {
    SurfacePoint sp;
    sp.position = {coord(rng), coord(rng), coord(rng)};
    sp.geometricNormal = normalize(Vec3f{coord(rng), coord(rng), coord(rng)});
    sp.error = std::ldexp(1.0f, -static_cast<int>(rng() % 30));
    const Vec3f first{coord(rng), coord(rng), coord(rng)};
    const Vec3f shared = offsetRayOrigin(sp, first - sp.position);
    for (int k = 0; k < 8; ++k) {
      // Targets in the plane of the surface too, where the side is decided by a zero.
      const Vec3f target = k == 0 ? sp.position : Vec3f{coord(rng), coord(rng), coord(rng)};
      const Vec3f w = target - sp.position;
      if (leavesBelow(sp, w) != leavesBelow(sp, first - sp.position)) continue;
      (leavesBelow(sp, w) ? below : above) += 1;
      BOOST_TEST(sameBits(offsetRayOrigin(sp, w), shared));
      Ray fromShared;
      spawnRayFrom(shared, target, fromShared);
      BOOST_TEST(sameBits(fromShared, spawnRayTo(sp, target)));
    }
  }
  BOOST_TEST(below > 1000u);
  BOOST_TEST(above > 1000u);
}

// ---------------------------------------------------------------------------------------------
// Refraction (hard cases 15 and 16)

BOOST_AUTO_TEST_CASE(parallel_slab_leaves_direction_unchanged) {
  // Within 1e-6 up to 60 degrees of incidence. Beyond, the float rounding of the direction
  // inside the slab (~6e-8) is amplified at the exit by about 1/cos(incidence), so the bound
  // grows as (0.5 / cos)^2 down to grazing 80 degrees.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  double worstWithin60 = 0.0, worstRatio = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3f n = normalize(Vec3f{uni(rng), uni(rng), uni(rng)});  // slab normal, entry side
    const Vec3f d = normalize(Vec3f{uni(rng), uni(rng), uni(rng)});
    const float cosI = -dot(d, n);
    if (cosI < 0.17f) continue;  // arrive from the n side, at most 80 degrees from the normal
    const float ior = 1.0f + 1.5f * (0.5f + 0.5f * uni(rng));
    const FresnelSplit in = fresnelRefract(d, n, 1.0f, ior);
    BOOST_REQUIRE(!in.totalInternalReflection);
    // The exit face is parallel; facing the ray inside, its normal is n again.
    const FresnelSplit out = fresnelRefract(in.refracted, n, ior, 1.0f);
    BOOST_REQUIRE(!out.totalInternalReflection);
    const double change = length(Vec3d(out.refracted) - Vec3d(d));
    if (cosI >= 0.5f) worstWithin60 = std::max(worstWithin60, change);
    const double bound = cosI >= 0.5f ? 1e-6 : 1e-6 * std::pow(0.5 / static_cast<double>(cosI), 2);
    worstRatio = std::max(worstRatio, change / bound);
  }
  BOOST_TEST_MESSAGE("slab: worst direction change within 60 degrees " << worstWithin60);
  BOOST_TEST(worstWithin60 < 1e-6);
  BOOST_TEST(worstRatio < 1.0);
}

BOOST_AUTO_TEST_CASE(ray_crosses_a_thin_slab_and_exits_on_the_far_side) {
  for (double translation : {0.0, 1.0, 10.0}) {
    for (float thickness : {1e-2f, 1e-4f}) {
      TestScene ts;
      const float T = static_cast<float>(translation);
      ts.add(makeBox({T - 1.0f, T - thickness, T - 1.0f}, {T + 1.0f, T, T + 1.0f}),
             glassMaterial(1.5f));
      ts.scene.commit();
      for (const Vec3f dir :
           {Vec3f{0.3f, -1.0f, 0.1f}, Vec3f{0.0f, -1.0f, 0.0f}, Vec3f{2.0f, -1.0f, -1.0f}}) {
        Ray r;
        r.direction = normalize(dir);
        r.origin = Vec3f{T + 0.1f, T, T - 0.05f} - r.direction * 3.0f;
        Hit top;
        BOOST_REQUIRE(ts.scene.intersect(r, top));
        BOOST_TEST(top.primId / 2 == 3u);  // +y face
        const SurfacePoint sp1 = refineHitPoint(ts.scene, r, top);
        const Vec3f n1 = dot(top.geometricNormal, r.direction) < 0.0f ? top.geometricNormal
                                                                      : -top.geometricNormal;
        const FresnelSplit in = fresnelRefract(r.direction, n1, 1.0f, 1.5f);
        const Ray inside = spawnRay(sp1, in.refracted);
        BOOST_TEST(inside.origin.y < T);  // started below the top face
        Hit bottom;
        BOOST_REQUIRE(ts.scene.intersect(inside, bottom));
        BOOST_TEST(bottom.primId / 2 == 2u,
                   "thickness " << thickness << ": hit face " << bottom.primId / 2);  // -y face
        BOOST_TEST(bottom.t > 0.0f);
        const SurfacePoint sp2 = refineHitPoint(ts.scene, inside, bottom);
        const Vec3f n2 = dot(bottom.geometricNormal, inside.direction) < 0.0f
                             ? bottom.geometricNormal
                             : -bottom.geometricNormal;
        const FresnelSplit out = fresnelRefract(inside.direction, n2, 1.5f, 1.0f);
        BOOST_REQUIRE(!out.totalInternalReflection);
        const Ray exiting = spawnRay(sp2, out.refracted);
        BOOST_TEST(exiting.origin.y < T - thickness);  // on the far side
        Hit none;
        BOOST_TEST(!ts.scene.intersect(exiting, none));  // no double hit
        BOOST_TEST(length(out.refracted - r.direction) < 1e-6f);
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(fresnel_weights_sum_to_one_and_total_internal_reflection) {
  const float ior = 1.5f;
  const double critical = std::asin(1.0 / static_cast<double>(ior));
  const Vec3f n{0.0f, 1.0f, 0.0f};
  for (int i = 0; i <= 900; ++i) {
    const double angle = (std::numbers::pi / 2.0) * i / 900.0 * 0.9999;
    const Vec3f d(static_cast<float>(std::sin(angle)), static_cast<float>(-std::cos(angle)), 0.0f);
    // Entering the dense medium: never total reflection, weights sum to 1.
    const FresnelSplit enter = fresnelRefract(d, n, 1.0f, ior);
    BOOST_TEST(!enter.totalInternalReflection);
    BOOST_TEST(std::abs(enter.reflectance + enter.transmittance - 1.0f) < 1e-6f);
    // Leaving it: total internal reflection beyond the critical angle.
    const FresnelSplit leave = fresnelRefract(d, n, ior, 1.0f);
    if (angle > critical + 1e-6) {
      BOOST_TEST(leave.totalInternalReflection);
      BOOST_TEST(leave.reflectance == 1.0f);
      BOOST_TEST(leave.transmittance == 0.0f);
    } else if (angle < critical - 1e-6) {
      BOOST_TEST(!leave.totalInternalReflection);
      BOOST_TEST(std::abs(leave.reflectance + leave.transmittance - 1.0f) < 1e-6f);
      BOOST_TEST(std::abs(length(leave.refracted) - 1.0f) < 1e-6f);
    }
  }
  // Normal incidence: ((n1 - n2) / (n1 + n2))^2 = 0.04 for glass.
  BOOST_TEST(std::abs(fresnelReflectance(1.0f, 1.0f, 1.5f) - 0.04f) < 1e-6f);
  // Equal indices: nothing reflected, direction unchanged (robots' ior 0 is read as 1).
  const FresnelSplit same = fresnelRefract(normalize(Vec3f{1, -2, 0}), n, 1.0f, 1.0f);
  BOOST_TEST(same.reflectance == 0.0f);
  BOOST_TEST(length(same.refracted - normalize(Vec3f{1, -2, 0})) < 1e-7f);
  BOOST_TEST(glassMaterial(0.0f).effectiveIor() == 1.0f);
}

BOOST_AUTO_TEST_CASE(renderer_reflects_totally_beyond_the_critical_angle) {
  TestScene ts;
  ts.add(makeBox({-10, -10, -10}, {10, 10, 10}), glassMaterial(1.5f));
  ts.scene.commit();
  RenderSettings s = settingsFor(RenderMode::Whitted);
  s.maxDepth = 1;
  const std::uint64_t pixels = 16 * 16;
  {  // Looking at a face head-on from inside: every primary ray refracts out.
    RenderStats st;
    render(ts, Camera::lookAt({0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 10.0f, 16, 16), s, &st);
    BOOST_TEST(st.traced.refraction == pixels);
    BOOST_TEST(st.totalInternalReflections == 0u);
    BOOST_TEST(st.traced.reflection == pixels);  // the Fresnel reflection
  }
  {  // Grazing (incidence 71..81 degrees > 41.8): no refraction ray at all.
    RenderStats st;
    render(ts, Camera::lookAt({0, 0, 9}, {4, 0, 10}, {0, 1, 0}, 10.0f, 16, 16), s, &st);
    BOOST_TEST(st.traced.refraction == 0u);
    BOOST_TEST(st.totalInternalReflections == pixels);
    BOOST_TEST(st.traced.reflection == pixels);
    BOOST_TEST(st.depthLimited >= pixels);  // the reflected rays could not go on
  }
}

BOOST_AUTO_TEST_CASE(renderer_refracts_through_a_thin_glass_slab) {
  TestScene ts;
  ts.add(makeQuad({-50, 0, 50}, {100, 0, 0}, {0, 0, -100}), diffuseMaterial({0.5f, 0.5f, 0.5f}));
  ts.add(makeBox({-5.0f, 1.0f, -5.0f}, {5.0f, 1.0001f, 5.0f}), glassMaterial(1.5f));
  ts.scene.commit();
  ts.rs.pointLights.push_back({{0, 20, 0}, {1, 1, 1}, {}});
  RenderStats st;
  render(ts, Camera::lookAt({0, 6, 0.5f}, {0, 0, 0}, {0, 1, 0}, 30.0f, 16, 16),
         settingsFor(RenderMode::Whitted), &st);
  // Every pixel sees the floor through the slab: in and out, both refracted.
  BOOST_TEST(st.traced.refraction >= 2 * 16 * 16u);
}

// ---------------------------------------------------------------------------------------------
// Recursion limits (hard case 17)

BOOST_AUTO_TEST_CASE(facing_mirrors_end_by_depth_limit_and_by_weight_cutoff) {
  const std::uint32_t size = 24;
  const std::uint64_t pixels = size * size;
  const Camera cam = Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 20.0f, size, size);
  {
    TestScene ts;
    ts.add(makeQuad({-1000, -1000, -5}, {2000, 0, 0}, {0, 2000, 0}), mirrorMaterial(1.0f));
    ts.add(makeQuad({-1000, -1000, 5}, {0, 2000, 0}, {2000, 0, 0}), mirrorMaterial(1.0f));
    ts.scene.commit();
    RenderSettings s = settingsFor(RenderMode::Whitted);
    s.maxDepth = 5;
    RenderStats st;
    const Frame a = render(ts, cam, s, &st);
    BOOST_TEST(st.traced.reflection == 5 * pixels);
    BOOST_TEST(st.depthLimited == pixels);
    BOOST_TEST(st.weightCutoff == 0u);
    const Frame b = render(ts, cam, s);
    BOOST_TEST(a.beauty.bitwiseEqual(b.beauty));
  }
  {
    TestScene ts;
    ts.add(makeQuad({-1000, -1000, -5}, {2000, 0, 0}, {0, 2000, 0}), mirrorMaterial(0.5f));
    ts.add(makeQuad({-1000, -1000, 5}, {0, 2000, 0}, {2000, 0, 0}), mirrorMaterial(0.5f));
    ts.scene.commit();
    RenderSettings s = settingsFor(RenderMode::Whitted);
    s.maxDepth = 50;
    s.minWeight = 0.01f;
    RenderStats st;
    render(ts, cam, s, &st);
    // Weights 0.5, 0.25, ..., 0.015625 are traced; 0.0078125 < 0.01 is cut.
    BOOST_TEST(st.traced.reflection == 6 * pixels);
    BOOST_TEST(st.weightCutoff == pixels);
    BOOST_TEST(st.depthLimited == 0u);
  }
}

// ---------------------------------------------------------------------------------------------
// Model only what the scene needs

BOOST_AUTO_TEST_CASE(useless_rays_are_saved_and_counted) {
  TestScene ts;
  ts.add(makeQuad({-10, 0, 10}, {20, 0, 0}, {0, 0, -20}), diffuseMaterial({0.5f, 0.5f, 0.5f}));
  ts.scene.commit();
  ts.rs.pointLights.push_back({{0, -5, 0}, {1, 1, 1}, {}});  // below the floor: N.L <= 0
  ts.rs.pointLights.push_back({{0, 5, 0}, {0, 0, 0}, {}});   // black
  ts.rs.pointLights.push_back({{1, 5, 0}, {1, 1, 1}, {}});   // useful
  const Camera cam = Camera::lookAt({0, 3, 0}, {0, 0, 0}, {0, 0, -1}, 60.0f, 16, 16);
  RenderStats st;
  render(ts, cam, settingsFor(RenderMode::Whitted), &st);
  const std::uint64_t pixels = 16 * 16;
  BOOST_TEST(st.traced.primary == pixels);
  BOOST_TEST(st.traced.shadow == pixels);
  BOOST_TEST(st.saved.shadow == 2 * pixels);
  BOOST_TEST(st.traced.reflection == 0u);
  BOOST_TEST(st.saved.reflection == pixels);
  BOOST_TEST(st.traced.refraction == 0u);
  BOOST_TEST(st.saved.refraction == pixels);
  BOOST_TEST(st.mraysPerSecond >= 0.0);

  // A black material needs no shadow ray for any light.
  ts.rs.materials[0].diffuse = {0, 0, 0};
  render(ts, cam, settingsFor(RenderMode::Whitted), &st);
  BOOST_TEST(st.traced.shadow == 0u);
  BOOST_TEST(st.saved.shadow == 3 * pixels);
}

namespace {

bool isBlackColor(const Vec3f& c) {
  return !(c.x > 0.0f || c.y > 0.0f || c.z > 0.0f);
}

/// The OpenGL-mode colour of pixel (x, y) of a scene lit by point lights, as the shader first
/// computed it: a single ray, then light after light in scalar arithmetic.
Vec3f referenceOpenGlPixel(const TestScene& ts, const Camera& cam, std::uint32_t x,
                           std::uint32_t y) {
  const Ray ray = cam.primaryRay(x, y);
  Hit hit;
  TraversalContext ctx;
  if (!ts.scene.intersect(ray, hit, ctx)) return ts.rs.background;
  const Scene::SurfaceData sd = ts.scene.surfaceAt(ray, hit);
  const Material& m = ts.rs.material(hit.instanceId, hit.objectId, hit.primId);
  const bool backFace = dot(sd.geometricNormal, ray.direction) > 0.0f;
  const Vec3f ng = backFace ? -sd.geometricNormal : sd.geometricNormal;
  const Vec3f ns = backFace ? -sd.shadingNormal : sd.shadingNormal;
  const Vec3f v = -normalize(ray.direction);
  Vec3f color = m.ambient * ts.rs.ambient;
  for (const PointLight& l : ts.rs.pointLights) {
    const Vec3f toLight = l.position - sd.position;
    const float distance = length(toLight);
    if (!(distance > 0.0f)) continue;
    const Vec3f direction = toLight / distance;
    const Vec3f arriving =
        l.attenuation.none() ? l.color : l.color * l.attenuation.factor(distance);
    const float nl = dot(ns, direction);
    if (!m.lit() || isBlackColor(arriving) || nl <= 0.0f || dot(ng, direction) <= 0.0f) continue;
    Vec3f c = m.diffuse * nl;
    const float rv = dot(ns * (2.0f * nl) - direction, v);
    if (m.reflective() && rv > 0.0f) c += m.specular * std::pow(rv, m.shine);
    const Vec3f local = arriving * c;
    if (!isBlackColor(local)) color += local;
  }
  return color;
}

}  // namespace

BOOST_AUTO_TEST_CASE(point_light_terms_match_the_scalar_shading_bit_for_bit) {
  // The shader takes point lights four at a time, or eight with AVX2 when none is attenuated;
  // seven lights fill one group and part of the next (or most of one), with every way a light
  // can drop out, attenuation, and highlights. Every SIMD kernel set must give the scalar
  // shading's bits, with the attenuated lights and without them.
  TestScene ts;
  Material floor = diffuseMaterial({0.6f, 0.5f, 0.4f});
  floor.specular = {0.3f, 0.3f, 0.3f};
  floor.shine = 13.7f;
  floor.ambient = {0.2f, 0.2f, 0.2f};
  ts.add(makeQuad({-10, 0, 10}, {20, 0, 0}, {0, 0, -20}), floor);
  Material box = diffuseMaterial({0.2f, 0.7f, 0.3f});
  box.specular = {0.5f, 0.4f, 0.3f};
  box.shine = 97.43f;
  ts.add(makeBox({-1, 0, -1}, {1, 1.5f, 1}), box);
  // Normals off the axes, so that every product of a dot product counts.
  ts.add(makeSphere({2.0f, 0.8f, 1.5f}, 0.8f, 12, 24), box);
  ts.scene.commit();
  ts.rs.ambient = {0.1f, 0.1f, 0.1f};
  ts.rs.pointLights.push_back({{0, -5, 0}, {1, 1, 1}, {}});  // below the floor
  ts.rs.pointLights.push_back({{3, 4, 2}, {0.7f, 0.6f, 0.5f}, {}});
  ts.rs.pointLights.push_back({{0, 5, 0}, {0, 0, 0}, {}});  // black
  ts.rs.pointLights.push_back({{-3, 2, 3}, {0.9f, 0.9f, 0.9f}, {1.0f, 0.3f, 0.05f}});
  ts.rs.pointLights.push_back({{2, 0.5f, -3}, {0.4f, 0.8f, 0.4f}, {}});
  ts.rs.pointLights.push_back({{-2, 6, -2}, {0.3f, 0.3f, 1.0f}, {0.5f, 0.0f, 0.2f}});
  ts.rs.pointLights.push_back({{1, 3, 4}, {0.5f, 0.0f, 0.5f}, {}});
  const std::uint32_t w = 48, h = 36;
  const Camera cam = Camera::lookAt({4, 5, 6}, {0, 0.5f, 0}, {0, 1, 0}, 50.0f, w, h);
  std::size_t differing = 0, highlighted = 0;
  // The reference computes with denormals, as the test runs.
  RenderSettings settings = settingsFor(RenderMode::OpenGL);
  settings.flushDenormals = false;
  auto compare = [&] {
    const IsaGuard guard;
    for (SimdIsa isa : supportedSimdIsas()) {
      BOOST_REQUIRE(setSimdIsa(isa));
      const Frame f = render(ts, cam, settings);
      for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
          const Vec3f got = f.beauty.rgb(x, y), want = referenceOpenGlPixel(ts, cam, x, y);
          differing += std::memcmp(&got, &want, sizeof got) != 0;
          highlighted += want.x > want.y + 0.3f;  // the box is green; a white highlight evens it
        }
    }
  };
  compare();
  BOOST_TEST(differing == 0u);
  BOOST_TEST(highlighted > 0u);
  const std::vector<PointLight> attenuatedLights = ts.rs.pointLights;
  for (PointLight& l : ts.rs.pointLights) l.attenuation = {};
  compare();
  BOOST_TEST(differing == 0u);
  ts.rs.pointLights = attenuatedLights;
  // Highlights too faint to change the diffuse term skip their power: vary the exponent, how
  // bright the highlight is against the diffuse term, and a diffuse channel of 0, which
  // absorbs nothing.
  for (const float shine : {0.5f, 3.0f, 40.0f, 400.0f, 5000.0f})
    for (const Vec3f& diffuse : {Vec3f{0.6f, 0.5f, 0.4f}, Vec3f{0.01f, 0.3f, 0.0f}})
      for (const float specular : {1e-6f, 0.3f, 50.0f}) {
        for (Material& m : ts.rs.materials) {
          m.shine = shine;
          m.diffuse = diffuse;
          m.specular = {specular, specular * 0.5f, specular};
        }
        compare();
      }
  BOOST_TEST(differing == 0u);
  for (PointLight& l : ts.rs.pointLights) l.attenuation = {};
  compare();
  BOOST_TEST(differing == 0u);
}

// ---------------------------------------------------------------------------------------------
// Determinism (hard case 21) and AOVs

namespace {

void buildBusyScene(TestScene& ts) {
  Material floor = diffuseMaterial({1, 1, 1});
  floor.texture = 0;
  floor.specular = {0.1f, 0.1f, 0.1f};
  floor.shine = 30.0f;
  Image checker(8, 8, 3);
  for (std::uint32_t y = 0; y < 8; ++y)
    for (std::uint32_t x = 0; x < 8; ++x)
      checker.setRgb(x, y, ((x + y) % 2) ? Vec3f{0.9f, 0.9f, 0.9f} : Vec3f{0.1f, 0.2f, 0.3f});
  ts.rs.textures.push_back(std::make_shared<const Texture>(std::move(checker), "checker"));
  TriangleMesh floorMesh = makeQuad({-20, 0, 20}, {40, 0, 0}, {0, 0, -40});
  for (Vec2f& uv : floorMesh.uvs) uv = {uv.u * 5.0f, uv.v * 5.0f};
  ts.add(std::move(floorMesh), floor);
  Material red = diffuseMaterial({0.8f, 0.1f, 0.1f});
  red.specular = {0.3f, 0.3f, 0.3f};
  red.shine = 40.0f;
  ts.add(makeSphere({-1.5f, 1.0f, 0.0f}, 1.0f, 24, 48), red);
  Material glass = glassMaterial(1.5f);
  glass.specular = {0.05f, 0.05f, 0.05f};
  ts.add(makeSphere({1.2f, 1.0f, 0.8f}, 1.0f, 24, 48), glass);
  ts.add(makeBox({-4, 0, -4}, {4, 3, -3.8f}), mirrorMaterial(0.8f),
         Affine3d::rotation({0, 1, 0}, 10.0));
  ts.scene.commit();
  ts.rs.pointLights.push_back({{-4, 8, 5}, {0.8f, 0.8f, 0.7f}, {}});
  ts.rs.spotLights.push_back(
      {{4, 6, 4}, {-0.5f, -1.0f, -0.5f}, {0.5f, 0.5f, 0.6f}, 0.7f, 0.5f, {}});
  ts.rs.ambient = {0.1f, 0.1f, 0.1f};
  ts.rs.background = {0.2f, 0.3f, 0.5f};
}

}  // namespace

BOOST_AUTO_TEST_CASE(threads_tiles_and_packets_give_bit_identical_images) {
  TestScene ts;
  buildBusyScene(ts);
  const Camera cam = Camera::lookAt({0, 3, 8}, {0, 1, 0}, {0, 1, 0}, 45.0f, 72, 54);
  for (RenderMode mode : {RenderMode::Whitted, RenderMode::OpenGL, RenderMode::Normals,
                          RenderMode::Classes, RenderMode::Instances}) {
    RenderSettings s = settingsFor(mode);
    // Whitted mode through the mip-mapped lookups, the other modes through bilinear ones.
    if (mode == RenderMode::Whitted) s.textureFilter = TextureFilter::Trilinear;
    std::vector<Frame> frames;
    std::vector<RenderStats> stats;
    for (int threads : {1, 2, 1, 2}) {
      tbb::task_arena arena(threads);
      arena.execute([&] {
        RenderStats st;
        frames.push_back(render(ts, cam, s, &st));
        stats.push_back(st);
      });
    }
    // Different tiling must not matter either: pixels are independent. Small tiles on one
    // thread share per-thread scratch memory from tile to tile; nothing may leak between them.
    s.tileSize = 7;
    tbb::task_arena one(1);
    one.execute([&] {
      RenderStats st;
      frames.push_back(render(ts, cam, s, &st));
      stats.push_back(st);
    });
    // Nor packets (odd tiles leave partial 4 x 2 blocks) with any SIMD kernel, or none.
    {
      const IsaGuard guard;
      for (SimdIsa isa : supportedSimdIsas()) {
        BOOST_REQUIRE(setSimdIsa(isa));
        frames.push_back(render(ts, cam, s));
      }
    }
    s.packets = false;
    RenderStats single;
    frames.push_back(render(ts, cam, s, &single));
    // Whitted packets trace a tile depth by depth; the rays counted must be the same.
    stats.push_back(single);
    for (std::size_t i = 1; i < frames.size(); ++i) {
      BOOST_TEST(frames[i].beauty.bitwiseEqual(frames[0].beauty), renderModeName(mode) << " " << i);
      BOOST_TEST(frames[i].depth.bitwiseEqual(frames[0].depth));
      BOOST_TEST(frames[i].normal.bitwiseEqual(frames[0].normal));
      BOOST_TEST((frames[i].instanceId == frames[0].instanceId));
      BOOST_TEST((frames[i].primId == frames[0].primId));
    }
    for (const RenderStats& st : stats) {
      BOOST_TEST((st.traced == stats[0].traced));
      BOOST_TEST((st.saved == stats[0].saved));
    }
    if (mode == RenderMode::Whitted) {
      BOOST_TEST(stats[0].traced.shadow > 0u);
      BOOST_TEST(stats[0].traced.reflection > 0u);
      BOOST_TEST(stats[0].traced.refraction > 0u);
    }
  }
}

BOOST_AUTO_TEST_CASE(depth_aov_is_distance_along_unit_ray_and_inf_on_miss) {
  TestScene ts;
  // A tilted quad covering only part of the view.
  ts.add(makeQuad({-3, -20, -10}, {30, 0, -5}, {0, 40, 0}), diffuseMaterial({1, 1, 1}));
  ts.scene.commit();
  const Camera cam = Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60.0f, 32, 32);
  const Frame f = render(ts, cam, settingsFor(RenderMode::Whitted));
  int hits = 0, misses = 0;
  const Vec3d a(-3, -20, -10), e1(30, 0, -5), e2(0, 40, 0);
  const Vec3d n = normalize(cross(e1, e2));
  for (std::uint32_t y = 0; y < 32; ++y) {
    for (std::uint32_t x = 0; x < 32; ++x) {
      const Ray r = cam.primaryRay(x, y);
      const Vec3d o(r.origin), d = normalize(Vec3d(r.direction));
      const double t = dot(a - o, n) / dot(d, n);
      const Vec3d p = o + d * t;
      const double s1 = dot(p - a, e1) / dot(e1, e1);
      const bool inside = t > 0.0 && s1 > 0.0 && s1 < 1.0;
      if (inside && std::abs(s1 - 0.0) > 1e-3) {
        ++hits;
        BOOST_TEST(std::abs(static_cast<double>(f.depth.at(x, y)) - t) < 1e-5 * t);
        BOOST_TEST(f.instanceId.at(x, y) == 0u);
        BOOST_TEST(f.primId.at(x, y) <= 1u);
        BOOST_TEST(std::abs(f.normal.at(x, y, 2) - static_cast<float>(n.z)) < 1e-5f);
      } else if (!inside && s1 < -1e-3) {
        ++misses;
        BOOST_TEST(std::isinf(f.depth.at(x, y)));
        BOOST_TEST(f.depth.at(x, y) > 0.0f);
        BOOST_TEST(f.instanceId.at(x, y) == kInvalidId);
        BOOST_TEST(f.primId.at(x, y) == kInvalidId);
        BOOST_TEST(f.normal.at(x, y, 0) == 0.0f);
      }
    }
  }
  BOOST_TEST(hits > 100);
  BOOST_TEST(misses > 100);

  // Through a PFM file: one channel, +inf survives.
  const auto path = tempPath("depth.pfm");
  writePfm(f.depth, path.string());
  const std::vector<unsigned char> bytes = readBytes(path);
  BOOST_TEST(std::string(bytes.begin(), bytes.begin() + 3) == "Pf\n");
  const Image back = readPfm(path.string());
  BOOST_TEST(back.bitwiseEqual(f.depth));
  const Image ids = f.instanceId.toFloat();
  BOOST_TEST(ids.at(0, 0) == (f.instanceId.at(0, 0) == kInvalidId ? -1.0f : 0.0f));
  std::filesystem::remove(path);
}

// ---------------------------------------------------------------------------------------------
// Image files

BOOST_AUTO_TEST_CASE(pfm_round_trips_and_stores_bottom_row_first) {
  Image img(3, 2, 3);
  for (std::uint32_t y = 0; y < 2; ++y)
    for (std::uint32_t x = 0; x < 3; ++x)
      img.setRgb(x, y,
                 {static_cast<float>(x), static_cast<float>(y), 0.5f + static_cast<float>(x * y)});
  img.at(2, 1, 2) = -kInfinity;
  const auto path = tempPath("rgb.pfm");
  writePfm(img, path.string());
  const std::vector<unsigned char> bytes = readBytes(path);
  const std::string header = "PF\n3 2\n-1.0\n";
  BOOST_REQUIRE(bytes.size() == header.size() + 3 * 2 * 3 * sizeof(float));
  BOOST_TEST(std::string(bytes.begin(), bytes.begin() + static_cast<long>(header.size())) ==
             header);
  // The first stored pixel is (0, 1): the bottom row, little-endian.
  float first[3];
  std::memcpy(first, bytes.data() + header.size(), sizeof(first));
  BOOST_TEST(first[0] == 0.0f);
  BOOST_TEST(first[1] == 1.0f);
  BOOST_TEST(first[2] == 0.5f);
  BOOST_TEST(bytes[header.size() + 4 + 3] == 0x3F);  // 1.0f = 0x3F800000, high byte last
  const Image back = readPfm(path.string());
  BOOST_TEST(back.bitwiseEqual(img));

  // Big-endian files (positive scale) are read too.
  std::string be = "PF\n1 1\n1.0\n";
  for (float v : {1.0f, 2.0f, -3.0f}) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    for (int k = 3; k >= 0; --k) be.push_back(static_cast<char>((bits >> (8 * k)) & 0xFFu));
  }
  writeBytes(path, be);
  const Image big = readPfm(path.string());
  BOOST_TEST((big.rgb(0, 0) == Vec3f{1.0f, 2.0f, -3.0f}));

  writeBytes(path, "PF\n2 2\n-1.0\n1234");
  BOOST_CHECK_EXCEPTION(readPfm(path.string()), Error, [&](const Error& e) {
    return std::string(e.what()).find(path.string()) != std::string::npos;
  });
  BOOST_CHECK_THROW(writePfm(Image(2, 2, 2), path.string()), Error);
  std::filesystem::remove(path);
}

BOOST_AUTO_TEST_CASE(png_is_srgb_encoded_and_textures_read_it_back) {
  BOOST_TEST(std::abs(srgbEncode(0.5f) - 0.7353569f) < 1e-5f);
  BOOST_TEST(std::abs(srgbDecode(srgbEncode(0.2f)) - 0.2f) < 1e-6f);
  Image img(4, 2, 3);
  for (std::uint32_t y = 0; y < 2; ++y)
    for (std::uint32_t x = 0; x < 4; ++x)
      img.setRgb(x, y, {0.25f * static_cast<float>(x), 0.5f * static_cast<float>(y), 0.18f});
  img.at(3, 1, 0) = 7.0f;  // clamped
  const auto path = tempPath("img.png");
  writePng(img, path.string());
  const Texture tex = Texture::load(path.string());  // sRGB decode on load
  BOOST_TEST(tex.width() == 4u);
  BOOST_TEST(tex.height() == 2u);
  for (std::uint32_t y = 0; y < 2; ++y)
    for (std::uint32_t x = 0; x < 4; ++x)
      for (std::uint32_t c = 0; c < 3; ++c) {
        const float expected = std::min(img.at(x, y, c), 1.0f);
        BOOST_TEST(std::abs(tex.image().at(x, y, c) - expected) < 0.01f);
      }
  std::filesystem::remove(path);
}

BOOST_AUTO_TEST_CASE(ppm_textures_load_and_sample_with_repeat) {
  const auto path = tempPath("tex.ppm");
  // P6, 2x2, comments in the header, trailing garbage after the raster.
  std::string p6 = "P6\n# a comment\n2 # another\n2\n255\n";
  const unsigned char raster[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
  p6.append(reinterpret_cast<const char*>(raster), 12);
  p6 += "trailing bytes\n";
  writeBytes(path, p6);
  const Texture tex = Texture::load(path.string(), ColorEncoding::Linear);
  BOOST_TEST((tex.texel(0, 0) == Vec3f{1, 0, 0}));  // first row of the file is v = 0
  BOOST_TEST((tex.texel(1, 1) == Vec3f{1, 1, 1}));
  BOOST_TEST((tex.sample({0.25f, 0.25f}, TextureFilter::Nearest) == Vec3f{1, 0, 0}));
  BOOST_TEST((tex.sample({0.75f, 0.25f}, TextureFilter::Nearest) == Vec3f{0, 1, 0}));
  BOOST_TEST((tex.sample({0.25f, 0.75f}, TextureFilter::Nearest) == Vec3f{0, 0, 1}));
  // GL_REPEAT, including negative coordinates.
  BOOST_TEST((tex.sample({1.25f, -0.75f}, TextureFilter::Nearest) == Vec3f{1, 0, 0}));
  BOOST_TEST((tex.sample({-0.75f, 2.75f}, TextureFilter::Nearest) == Vec3f{0, 0, 1}));
  BOOST_TEST((tex.sample({-1.25f, 3.75f}, TextureFilter::Nearest) == Vec3f{1, 1, 1}));
  // Bilinear: exact at texel centres, the mean of all four at the shared corner, wrapping.
  BOOST_TEST((tex.sample({0.25f, 0.25f}, TextureFilter::Bilinear) == Vec3f{1, 0, 0}));
  const Vec3f mid = tex.sample({0.5f, 0.5f}, TextureFilter::Bilinear);
  BOOST_TEST(std::abs(mid.x - 0.5f) < 1e-6f);
  BOOST_TEST(std::abs(mid.y - 0.5f) < 1e-6f);
  BOOST_TEST(std::abs(mid.z - 0.5f) < 1e-6f);
  const Vec3f corner = tex.sample({0.0f, 0.0f}, TextureFilter::Bilinear);
  BOOST_TEST(std::abs(corner.x - 0.5f) < 1e-6f);

  // P3 with a 16-bit maxval; sRGB decoding by default.
  writeBytes(path, "P3\n1 1\n65535\n65535 0 32768\n");
  const Texture t3 = Texture::load(path.string());
  BOOST_TEST(t3.texel(0, 0).x == 1.0f);
  BOOST_TEST(std::abs(t3.texel(0, 0).z - srgbDecode(32768.0f / 65535.0f)) < 1e-6f);
  // Binary 16-bit samples are big-endian.
  std::string p6w = "P6 1 1 65535\n";
  for (unsigned char b : {0xFF, 0xFF, 0x00, 0x00, 0x80, 0x00}) p6w.push_back(static_cast<char>(b));
  writeBytes(path, p6w);
  const Texture t16 = Texture::load(path.string(), ColorEncoding::Linear);
  BOOST_TEST(std::abs(t16.texel(0, 0).z - 32768.0f / 65535.0f) < 1e-7f);

  auto namesFile = [&](const Error& e) {
    return std::string(e.what()).find(path.string()) != std::string::npos;
  };
  writeBytes(path, "P6\n4 4\n255\n" + std::string(10, 'x'));  // truncated raster
  BOOST_CHECK_EXCEPTION(Texture::load(path.string()), Error, namesFile);
  writeBytes(path, "P6\n4 4\n70000\n");  // maxval too large
  BOOST_CHECK_EXCEPTION(Texture::load(path.string()), Error, namesFile);
  writeBytes(path, "P3\n1 1\n255\n1 2 300\n");  // sample above maxval
  BOOST_CHECK_EXCEPTION(Texture::load(path.string()), Error, namesFile);
  writeBytes(path, "P6\n99999999 99999999\n255\n");  // absurd size
  BOOST_CHECK_EXCEPTION(Texture::load(path.string()), Error, namesFile);
  writeBytes(path, "not an image");
  BOOST_CHECK_EXCEPTION(Texture::load(path.string()), Error, namesFile);
  std::filesystem::remove(path);
  BOOST_CHECK_EXCEPTION(Texture::load(path.string()), Error, namesFile);  // missing
}

namespace {

/// Texture::sample as first written: fmod of the scaled coordinate, then every texel index
/// wrapped with an integer remainder. The faster sampler must return exactly this.
Vec3f referenceSample(const Texture& tex, const Vec2f& uv, TextureFilter filter) {
  const double w = tex.width(), h = tex.height();
  const double x = std::fmod(static_cast<double>(uv.u) * w, w);
  const double y = std::fmod(static_cast<double>(uv.v) * h, h);
  auto texel = [&](long long i, long long j) {
    const long long n = tex.width(), m = tex.height();
    const long long a = ((i % n) + n) % n, b = ((j % m) + m) % m;
    return tex.image().rgb(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b));
  };
  if (!std::isfinite(x) || !std::isfinite(y)) return texel(0, 0);
  if (filter == TextureFilter::Nearest)
    return texel(static_cast<long long>(std::floor(x)), static_cast<long long>(std::floor(y)));
  const double fx = x - 0.5, fy = y - 0.5;
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  const float ax = static_cast<float>(fx - x0), ay = static_cast<float>(fy - y0);
  const long long ix = static_cast<long long>(x0), iy = static_cast<long long>(y0);
  const Vec3f top = texel(ix, iy) * (1.0f - ax) + texel(ix + 1, iy) * ax;
  const Vec3f bottom = texel(ix, iy + 1) * (1.0f - ax) + texel(ix + 1, iy + 1) * ax;
  return top * (1.0f - ay) + bottom * ay;
}

}  // namespace

BOOST_AUTO_TEST_CASE(texture_sampling_is_bit_identical_to_the_fmod_reference) {
  std::mt19937 rng(7);
  // Texel borders and centres of both axes, one ulp either side, wrapped copies, huge and
  // non-finite coordinates, and random ones.
  std::vector<float> coords = {1e-30f, -1e-30f, 0.9999999f, -0.9999999f, 1e6f, -1e7f, 12345.678f};
  // Either side of 2^23, where floats stop having fractions, and far beyond int32.
  coords.insert(coords.end(), {8388607.5f, -8388607.5f, 8388608.0f, -8388609.0f, 3e9f, -3e9f});
  coords.push_back(std::numeric_limits<float>::infinity());
  coords.push_back(std::numeric_limits<float>::quiet_NaN());
  for (int i = -12; i <= 12; ++i)
    for (const float d : {0.0f, 0.5f})
      for (const float n : {5.0f, 3.0f}) {
        const float c = (static_cast<float>(i) + d) / n;
        coords.insert(coords.end(), {c, std::nextafter(c, -10.0f), std::nextafter(c, 10.0f)});
      }
  coords.push_back(-0.0f);
  std::uniform_real_distribution<float> any(-4.0f, 4.0f);
  for (int i = 0; i < 200; ++i) coords.push_back(any(rng));

  // Random floats (more than 256 values: sampled from the float image), and 8-bit levels as a
  // file gives them, with a negative zero (sampled through the palette of codes).
  Image floats(5, 3, 3), levels(5, 3, 3);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  std::uniform_int_distribution<int> level(0, 255);
  for (float& v : floats.data()) v = value(rng);
  for (float& v : levels.data()) v = static_cast<float>(level(rng)) / 255.0f;
  levels.data()[4] = -0.0f;
  for (const Texture& tex : {Texture(floats, "floats"), Texture(levels, "levels")}) {
    std::size_t checked = 0, differing = 0;
    for (const float u : coords)
      for (const float v : coords)
        for (const TextureFilter f : {TextureFilter::Nearest, TextureFilter::Bilinear}) {
          // The cache hint takes any coordinates (the sanitizer build checks its conversions)
          // and changes no answer.
          tex.prefetch({u, v});
          const Vec3f got = tex.sample({u, v}, f), want = referenceSample(tex, {u, v}, f);
          differing += std::memcmp(&got, &want, sizeof got) != 0;
          ++checked;
        }
    BOOST_TEST(checked > 100000u);
    BOOST_TEST(differing == 0u, tex.name());
  }
}

BOOST_AUTO_TEST_CASE(mip_levels_are_box_means_and_trilinear_blends_them) {
  // Red left half, blue right half, one green texel in the corner.
  Image img(4, 4, 3);
  for (std::uint32_t y = 0; y < 4; ++y)
    for (std::uint32_t x = 0; x < 4; ++x) img.setRgb(x, y, x < 2 ? Vec3f{1, 0, 0} : Vec3f{0, 0, 1});
  img.setRgb(0, 0, {0, 1, 0});
  const Texture tex(std::move(img), "halves");
  BOOST_TEST(tex.levelCount() == 3u);
  BOOST_TEST((tex.mipTexel(1, 0, 0) == Vec3f{0.75f, 0.25f, 0.0f}));
  BOOST_TEST((tex.mipTexel(1, 0, 1) == Vec3f{1, 0, 0}));
  BOOST_TEST((tex.mipTexel(1, 1, 0) == Vec3f{0, 0, 1}));
  const Vec3f mean{0.4375f, 0.0625f, 0.5f};  // of level 1, and so of the image
  BOOST_TEST((tex.mipTexel(2, 0, 0) == mean));
  BOOST_TEST((tex.mipTexel(2, 5, -3) == mean));  // wraps like texel()
  BOOST_CHECK_THROW(tex.mipTexel(0, 0, 0), Error);
  BOOST_CHECK_THROW(tex.mipTexel(3, 0, 0), Error);
  const auto same = [](const Vec3f& a, const Vec3f& b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
  };
  for (const Vec2f uv : {Vec2f{0.1f, 0.2f}, Vec2f{0.37f, 0.81f}, Vec2f{-2.6f, 7.45f}}) {
    // No footprint, or one under a texel: the full image, exactly as Bilinear reads it.
    for (const float lod : {0.0f, -3.0f, -kInfinity, std::numeric_limits<float>::quiet_NaN()})
      BOOST_TEST(same(tex.sample(uv, TextureFilter::Trilinear, lod),
                      tex.sample(uv, TextureFilter::Bilinear)));
    // Beyond the last level: its one texel.
    BOOST_TEST(same(tex.sample(uv, TextureFilter::Trilinear, 40.0f), mean));
    BOOST_TEST(same(tex.sample(uv, TextureFilter::Trilinear, kInfinity), mean));
    // The other filters ignore the footprint.
    BOOST_TEST(same(tex.sample(uv, TextureFilter::Bilinear, 1.5f),
                    tex.sample(uv, TextureFilter::Bilinear)));
  }
  // (0.25, 0.75) is the centre of level 1's texel (0, 1): red there, halfway to the mean at 1.5.
  BOOST_TEST(same(tex.sample({0.25f, 0.75f}, TextureFilter::Trilinear, 1.0f), Vec3f{1, 0, 0}));
  BOOST_TEST(same(tex.sample({0.25f, 0.75f}, TextureFilter::Trilinear, 1.5f),
                  Vec3f{0.71875f, 0.03125f, 0.25f}));
}

BOOST_AUTO_TEST_CASE(trilinear_lookups_stay_within_the_texels_for_any_input) {
  // Thin and odd sizes (levels of one texel's width, odd sides left out), special and huge
  // coordinates, special footprints: every lookup is a convex blend of texel values.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> value(0.1f, 0.9f);
  const std::vector<float> coords = {0.0f,       -0.0f,
                                     0.5f,       -0.25f,
                                     0.9999999f, 1.0f,
                                     -1.0f,      7.3f,
                                     -1234.56f,  4.0e6f,
                                     -3.0e9f,    kInfinity,
                                     -kInfinity, std::numeric_limits<float>::quiet_NaN(),
                                     1e-40f};
  const std::vector<float> lods = {
      -kInfinity, -1.0f,  0.0f,  1e-40f, 0.3f,      1.0f,
      1.5f,       2.999f, 17.0f, 1e30f,  kInfinity, std::numeric_limits<float>::quiet_NaN()};
  for (const auto& [w, h] : {std::pair<std::uint32_t, std::uint32_t>{1, 1},
                             {1, 7},
                             {7, 1},
                             {3, 5},
                             {64, 2},
                             {300, 301}}) {
    Image img(w, h, 3);
    for (float& v : img.data()) v = value(rng);
    const Texture tex(std::move(img), "odd");
    BOOST_TEST(tex.levelCount() ==
               1u + static_cast<std::size_t>(std::bit_width(std::max(w, h)) - 1));
    std::size_t outside = 0;
    for (const float u : coords)
      for (const float v : coords)
        for (const float lod : lods) {
          const Vec3f c = tex.sample({u, v}, TextureFilter::Trilinear, lod);
          for (const float x : {c.x, c.y, c.z})
            outside += !(x >= 0.1f - 1e-6f && x <= 0.9f + 1e-6f);
        }
    BOOST_TEST(outside == 0u, w << " x " << h);
  }
}

BOOST_AUTO_TEST_CASE(trilinear_filtering_averages_distant_texels_and_keeps_close_ones) {
  // A floor with a one-texel checker repeated 20 times over 400 units, seen from just above
  // it towards the horizon: far away the checker is far below a pixel and bilinear lookups
  // alias, while mip-mapped ones converge on its grey; near the camera a texel spans
  // several pixels and both filters read the full image alike.
  TestScene ts;
  Image checker(64, 64, 3);
  for (std::uint32_t y = 0; y < 64; ++y)
    for (std::uint32_t x = 0; x < 64; ++x)
      checker.setRgb(x, y, ((x + y) % 2) ? Vec3f{1, 1, 1} : Vec3f{0, 0, 0});
  ts.rs.textures.push_back(std::make_shared<const Texture>(std::move(checker), "checker"));
  Material floor = diffuseMaterial({1, 1, 1});
  floor.texture = 0;
  floor.textureMode = TextureMode::Replace;
  floor.ambient = {1, 1, 1};
  TriangleMesh mesh = makeQuad({-200, 0, 200}, {400, 0, 0}, {0, 0, -400});
  for (Vec2f& uv : mesh.uvs) uv = {uv.u * 20.0f, uv.v * 20.0f};
  ts.add(std::move(mesh), floor);
  ts.scene.commit();
  ts.rs.ambient = {1, 1, 1};  // colour = texel: no lights
  const std::uint32_t w = 64, h = 48;
  const Camera cam = Camera::lookAt({0, 1, 0}, {0, 0.6f, -10}, {0, 1, 0}, 60.0f, w, h);
  RenderSettings bilinear = settingsFor(RenderMode::OpenGL), trilinear = bilinear;
  trilinear.textureFilter = TextureFilter::Trilinear;
  const Frame b = render(ts, cam, bilinear), t = render(ts, cam, trilinear);
  // Mean distance from mid grey over the floor's farthest rows (just below the horizon).
  const auto spread = [&](const Frame& f, std::uint32_t y0, std::uint32_t y1) {
    double sum = 0.0;
    for (std::uint32_t y = y0; y < y1; ++y)
      for (std::uint32_t x = 0; x < w; ++x)
        sum += std::abs(static_cast<double>(f.beauty.at(x, y, 0)) - 0.5);
    return sum / static_cast<double>(w * (y1 - y0));
  };
  // The view dips 0.4 / 10 below level: the horizon lies at row 24 - 24 * 0.04 / tan(30 deg)
  // = 22.3, and rows 23 to 26 show the floor's far end, where a pixel covers many texels.
  BOOST_TEST(spread(b, 23, 27) > 0.1);
  BOOST_TEST(spread(t, 23, 27) < 0.01);
  // The bottom row: texels larger than pixels, the same bits.
  for (std::uint32_t x = 0; x < w; ++x) {
    const Vec3f pb = b.beauty.rgb(x, h - 1), pt = t.beauty.rgb(x, h - 1);
    BOOST_TEST(std::memcmp(&pb, &pt, sizeof pb) == 0);
  }
  // A mirror overhead reflects the floor: the reflected rays' cones go on widening from the
  // mirror, so that the far floor in it is mip-mapped too.
  Material mirror = mirrorMaterial(1.0f);
  mirror.ambient = {0, 0, 0};
  ts.add(makeQuad({-200, 2, 200}, {0, 0, -400}, {400, 0, 0}), mirror);
  ts.scene.commit();
  RenderSettings whitted = trilinear;
  whitted.mode = RenderMode::Whitted;
  const Frame mb = render(ts, cam,
                          [&] {
                            RenderSettings s = whitted;
                            s.textureFilter = TextureFilter::Bilinear;
                            return s;
                          }()),
              mt = render(ts, cam, whitted);
  // Rows 14 to 21 show the floor's far end in the mirror, row 22 the horizon.
  BOOST_TEST(spread(mb, 14, 22) > 0.05);
  BOOST_TEST(spread(mt, 14, 22) < 0.01);
  // Packets and single rays, the wave and the recursive Whitted paths: the same footprints.
  for (const RenderMode mode : {RenderMode::OpenGL, RenderMode::Whitted}) {
    RenderSettings s = trilinear;
    s.mode = mode;
    const Frame packets = render(ts, cam, s);
    s.packets = false;
    BOOST_TEST(render(ts, cam, s).beauty.bitwiseEqual(packets.beauty));
  }
}

BOOST_AUTO_TEST_CASE(textures_modulate_or_replace_the_diffuse_colour) {
  TestScene ts;
  Image img(1, 1, 3);
  img.setRgb(0, 0, {0.5f, 0.25f, 1.0f});
  ts.rs.textures.push_back(std::make_shared<const Texture>(std::move(img)));
  Material m = diffuseMaterial({0.8f, 0.8f, 0.4f});
  m.texture = 0;
  ts.add(makeQuad({-10, 0, 10}, {20, 0, 0}, {0, 0, -20}), m);
  ts.scene.commit();
  ts.rs.directionalLights.push_back({{0, -1, 0}, {1, 1, 1}});
  const Camera cam = Camera::lookAt({0, 5, 0}, {0, 0, 0}, {0, 0, -1}, 30.0f, 4, 4);
  Frame f = render(ts, cam, settingsFor(RenderMode::Whitted));
  BOOST_TEST(std::abs(f.beauty.at(1, 1, 0) - 0.4f) < 1e-6f);
  BOOST_TEST(std::abs(f.beauty.at(1, 1, 2) - 0.4f) < 1e-6f);
  ts.rs.materials[0].textureMode = TextureMode::Replace;
  f = render(ts, cam, settingsFor(RenderMode::Whitted));
  BOOST_TEST(std::abs(f.beauty.at(1, 1, 1) - 0.25f) < 1e-6f);
}

BOOST_AUTO_TEST_CASE(material_lookup_order_and_validation) {
  TestScene ts;
  ts.add(makeQuad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), diffuseMaterial({1, 0, 0}));  // material 0
  ts.rs.materials.push_back(diffuseMaterial({0, 1, 0}));                          // 1
  ts.rs.materials.push_back(diffuseMaterial({0, 0, 1}));                          // 2
  BOOST_TEST(ts.rs.materialIndex(0, 0, 1) == 0u);
  ts.rs.primitiveMaterials = {{kInvalidId, 1}};
  BOOST_TEST(ts.rs.materialIndex(0, 0, 0) == 0u);
  BOOST_TEST(ts.rs.materialIndex(0, 0, 1) == 1u);
  ts.rs.instanceMaterials = {2};
  BOOST_TEST(ts.rs.materialIndex(0, 0, 1) == 2u);
  BOOST_TEST(ts.rs.materialIndex(5, 7, 9) == kInvalidId);
  BOOST_TEST((ts.rs.material(5, 7, 9).diffuse == Material{}.diffuse));
  BOOST_TEST(ts.rs.validate().empty());
  ts.rs.instanceMaterials = {3};
  BOOST_TEST(!ts.rs.validate().empty());
  ts.scene.commit();
  Frame f;
  BOOST_CHECK_THROW(Renderer().render(ts.rs, Camera(CameraParams{}), f), Error);
  ts.rs.instanceMaterials = {};
  ts.rs.materials[0].transmittance = 2.0f;
  BOOST_TEST(!ts.rs.validate().empty());
  BOOST_TEST((ts.rs.dynamicsClass(0) == DynamicsClass::Static));
  BOOST_TEST((parseRenderMode("whitted").value() == RenderMode::Whitted));
  BOOST_TEST(!parseRenderMode("raster").has_value());
  BOOST_TEST(renderModeName(RenderMode::Instances) == "instances");
  const Material nff = Material::fromNff({1.0f, 0.5f, 0.0f}, 0.8f, 0.2f, 10.0f, 0.0f, 0.0f);
  BOOST_TEST((nff.diffuse == Vec3f{0.8f, 0.4f, 0.0f}));
  BOOST_TEST((nff.specular == Vec3f{0.2f, 0.2f, 0.2f}));
}
