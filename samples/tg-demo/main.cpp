// tg-demo: builds a small scene in code and renders it with the Whitted ray tracer.
//
//   tg-demo [-o OUT.png] [--size WxH] [--mode M] [--threads N]
//
// Exit status: 0 on success, 1 when rendering or writing fails, 2 on bad usage.
#include <tbb/task_arena.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/render/Camera.h"
#include "tracegraph/backend/render/ImageIO.h"
#include "tracegraph/backend/render/RenderScene.h"
#include "tracegraph/backend/render/Renderer.h"

namespace {

constexpr const char* kUsage =
    "usage: tg-demo [-o OUT.png] [--size WxH] [--mode M] [--threads N]\n"
    "  -o OUT.png     output file (default tg-demo.png)\n"
    "  --size WxH     image size (default 640x480)\n"
    "  --mode M       opengl, whitted (default), normals, classes or instances\n"
    "  --threads N    worker threads (default: all cores)\n";

struct Options {
  std::string output = "tg-demo.png";
  std::uint32_t width = 640, height = 480;
  tg::RenderMode mode = tg::RenderMode::Whitted;
  int threads = 0;  // 0: oneTBB's default
};

template <typename T>
bool parseNumber(std::string_view s, T& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size();
}

/// Parses argv; returns false (after printing why) on bad usage.
bool parseArguments(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (arg == "-o") {
      const char* v = value();
      if (v == nullptr || *v == '\0') return false;
      o.output = v;
    } else if (arg == "--size") {
      const char* v = value();
      if (v == nullptr) return false;
      const std::string_view s = v;
      const std::size_t x = s.find('x');
      if (x == std::string_view::npos || !parseNumber(s.substr(0, x), o.width) ||
          !parseNumber(s.substr(x + 1), o.height) || o.width == 0 || o.height == 0 ||
          o.width > 16384 || o.height > 16384) {
        std::fprintf(stderr, "tg-demo: bad size '%s' (expected WxH, e.g. 640x480)\n", v);
        return false;
      }
    } else if (arg == "--mode") {
      const char* v = value();
      const auto mode = v ? tg::parseRenderMode(v) : std::nullopt;
      if (!mode) {
        std::fprintf(stderr, "tg-demo: unknown mode '%s'\n", v ? v : "");
        return false;
      }
      o.mode = *mode;
    } else if (arg == "--threads") {
      const char* v = value();
      if (v == nullptr || !parseNumber(std::string_view(v), o.threads) || o.threads < 1 ||
          o.threads > 1024) {
        std::fprintf(stderr, "tg-demo: bad thread count '%s'\n", v ? v : "");
        return false;
      }
    } else {
      std::fprintf(stderr, "tg-demo: unknown argument '%s'\n", argv[i]);
      return false;
    }
  }
  return true;
}

/// Quad (two triangles) with corner `origin` and edges `e1`, `e2`; uv spans [0, uvScale]^2.
tg::TriangleMesh makeQuad(const tg::Vec3f& origin, const tg::Vec3f& e1, const tg::Vec3f& e2,
                          float uvScale) {
  tg::TriangleMesh m;
  m.positions = {origin, origin + e1, origin + e1 + e2, origin + e2};
  m.uvs = {{0.0f, 0.0f}, {uvScale, 0.0f}, {uvScale, uvScale}, {0.0f, uvScale}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

/// Unit cube [-0.5, 0.5]^3 with flat faces (no shared normals).
tg::TriangleMesh makeCube() {
  tg::TriangleMesh m;
  const tg::Vec3f axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int a = 0; a < 3; ++a) {
    for (float sign : {-1.0f, 1.0f}) {
      const tg::Vec3f n = axes[a] * sign;
      const tg::Vec3f u = axes[(a + 1) % 3] * sign, v = axes[(a + 2) % 3];
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      const tg::Vec3f c = n * 0.5f;
      m.positions.insert(m.positions.end(), {c - u * 0.5f - v * 0.5f, c + u * 0.5f - v * 0.5f,
                                             c + u * 0.5f + v * 0.5f, c - u * 0.5f + v * 0.5f});
      m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  }
  return m;
}

/// Unit sphere as a latitude/longitude mesh with exact vertex normals and uvs.
tg::TriangleMesh makeSphere(std::uint32_t rings, std::uint32_t segments) {
  tg::TriangleMesh m;
  for (std::uint32_t i = 0; i <= rings; ++i) {
    const double theta = std::numbers::pi * i / rings;
    for (std::uint32_t j = 0; j <= segments; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / segments;
      const tg::Vec3d p(std::sin(theta) * std::cos(phi), std::cos(theta),
                        std::sin(theta) * std::sin(phi));
      m.positions.push_back(tg::Vec3f(p));
      m.normals.push_back(tg::Vec3f(p));
      m.uvs.push_back({static_cast<float>(j) / segments, static_cast<float>(i) / rings});
    }
  }
  const std::uint32_t row = segments + 1;
  for (std::uint32_t i = 0; i < rings; ++i) {
    for (std::uint32_t j = 0; j < segments; ++j) {
      const std::uint32_t a = i * row + j, b = a + row;
      // Skip the zero-area triangles at the poles.
      if (i != 0) m.indices.insert(m.indices.end(), {a, a + 1, b});
      if (i + 1 != rings) m.indices.insert(m.indices.end(), {a + 1, b + 1, b});
    }
  }
  return m;
}

/// A two-tone checkerboard texture of `squares` x `squares` squares.
std::shared_ptr<const tg::Texture> makeChecker(std::uint32_t squares, const tg::Vec3f& a,
                                               const tg::Vec3f& b) {
  constexpr std::uint32_t kTexelsPerSquare = 16;
  const std::uint32_t size = squares * kTexelsPerSquare;
  tg::Image image(size, size, 3);
  for (std::uint32_t y = 0; y < size; ++y)
    for (std::uint32_t x = 0; x < size; ++x)
      image.setRgb(x, y, ((x / kTexelsPerSquare + y / kTexelsPerSquare) % 2) ? a : b);
  return std::make_shared<const tg::Texture>(std::move(image), "checker");
}

tg::Affine3d placement(const tg::Vec3d& translation, const tg::Vec3d& scale,
                       double yRotationDegrees = 0.0) {
  return tg::Affine3d::translation(translation) *
         tg::Affine3d::rotation({0.0, 1.0, 0.0}, yRotationDegrees) * tg::Affine3d::scaling(scale);
}

/// Builds the demo scene into `scene` and returns its shading description.
tg::RenderScene buildScene(tg::Scene& scene) {
  tg::RenderScene rs;
  rs.scene = &scene;
  // Linear values: the PNG is sRGB-encoded, so 0.04 ambient already reads as a soft fill.
  rs.ambient = {0.04f, 0.04f, 0.05f};
  rs.background = {0.16f, 0.26f, 0.48f};
  rs.pointLights.push_back({{-5.0f, 10.0f, 7.0f}, {0.95f, 0.88f, 0.75f}, {}});
  rs.pointLights.push_back({{8.0f, 5.0f, 4.0f}, {0.18f, 0.22f, 0.30f}, {}});

  auto addMaterial = [&](const tg::Material& m) {
    rs.materials.push_back(m);
    return static_cast<std::uint32_t>(rs.materials.size() - 1);
  };
  auto setObjectMaterial = [&](tg::ObjectId object, std::uint32_t material) {
    if (rs.objectMaterials.size() <= object) rs.objectMaterials.resize(object + 1, tg::kInvalidId);
    rs.objectMaterials[object] = material;
  };
  auto setInstanceMaterial = [&](tg::InstanceId instance, std::uint32_t material) {
    if (rs.instanceMaterials.size() <= instance)
      rs.instanceMaterials.resize(instance + 1, tg::kInvalidId);
    rs.instanceMaterials[instance] = material;
  };

  rs.textures.push_back(makeChecker(2, {0.75f, 0.74f, 0.70f}, {0.06f, 0.07f, 0.09f}));
  tg::Material floorMaterial;
  floorMaterial.ambient = {1.0f, 1.0f, 1.0f};
  floorMaterial.diffuse = {1.0f, 1.0f, 1.0f};
  floorMaterial.specular = {0.08f, 0.08f, 0.08f};
  floorMaterial.shine = 40.0f;
  floorMaterial.texture = 0;
  const std::uint32_t floorMat = addMaterial(floorMaterial);

  auto diffuseMaterial = [&](const tg::Vec3f& color, float specular, float shine) {
    tg::Material m;
    m.ambient = color;
    m.diffuse = color;
    m.specular = {specular, specular, specular};
    m.shine = shine;
    return addMaterial(m);
  };
  const std::uint32_t red = diffuseMaterial({0.75f, 0.12f, 0.10f}, 0.35f, 60.0f);
  const std::uint32_t blue = diffuseMaterial({0.15f, 0.30f, 0.75f}, 0.15f, 30.0f);
  const std::uint32_t yellow = diffuseMaterial({0.85f, 0.70f, 0.15f}, 0.0f, 0.0f);
  const std::uint32_t green = diffuseMaterial({0.20f, 0.60f, 0.25f}, 0.2f, 80.0f);

  tg::Material mirror;
  mirror.ambient = {0.02f, 0.02f, 0.02f};
  mirror.diffuse = {0.03f, 0.03f, 0.03f};
  mirror.specular = {0.88f, 0.88f, 0.90f};
  mirror.shine = 200.0f;
  const std::uint32_t mirrorMat = addMaterial(mirror);

  tg::Material frame;
  frame.ambient = frame.diffuse = {0.25f, 0.18f, 0.12f};
  frame.specular = {0.1f, 0.1f, 0.1f};
  frame.shine = 20.0f;
  const std::uint32_t frameMat = addMaterial(frame);

  tg::Material glass;
  glass.diffuse = {0.0f, 0.0f, 0.0f};
  glass.specular = {0.0f, 0.0f, 0.0f};
  glass.transmittance = 0.95f;
  glass.ior = 1.5f;
  const std::uint32_t glassMat = addMaterial(glass);

  // Floor: 60 x 60 units, checker squares of 1.5 units (two per texture repeat).
  const tg::ObjectId floorObj = scene.createObject(
      makeQuad({-30.0f, 0.0f, 30.0f}, {60.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -60.0f}, 20.0f));
  setObjectMaterial(floorObj, floorMat);
  scene.createInstance(floorObj);

  // Shared meshes, placed by instances; materials per instance.
  const tg::ObjectId cube = scene.createObject(makeCube(), tg::ObjectUsage::Rigid);
  const tg::ObjectId sphere = scene.createObject(makeSphere(48, 96), tg::ObjectUsage::Rigid);
  setInstanceMaterial(
      scene.createInstance(cube, placement({-3.2, 0.75, -1.0}, {1.5, 1.5, 1.5}, 25)), blue);
  setInstanceMaterial(scene.createInstance(cube, placement({2.8, 0.5, 1.6}, {1.0, 1.0, 1.0}, -30)),
                      yellow);
  setInstanceMaterial(scene.createInstance(cube, placement({3.6, 1.25, -2.6}, {0.8, 2.5, 0.8}, 10)),
                      green);
  setInstanceMaterial(scene.createInstance(sphere, placement({-0.6, 1.0, -2.0}, {1, 1, 1})), red);
  setInstanceMaterial(scene.createInstance(sphere, placement({0.9, 1.1, 1.8}, {1.1, 1.1, 1.1})),
                      glassMat);
  setInstanceMaterial(
      scene.createInstance(sphere, placement({-1.9, 0.45, 1.6}, {0.45, 0.45, 0.45})), green);

  // A mirror in a wooden frame, standing at the back and turned towards the camera.
  const tg::Affine3d mirrorPlace = placement({0.5, 2.3, -5.5}, {1.0, 1.0, 1.0}, -12);
  setInstanceMaterial(
      scene.createInstance(cube, mirrorPlace * tg::Affine3d::scaling({6.0, 3.8, 0.1})), frameMat);
  setInstanceMaterial(
      scene.createInstance(cube, mirrorPlace * tg::Affine3d::translation({0.0, 0.0, 0.06}) *
                                     tg::Affine3d::scaling({5.6, 3.4, 0.02})),
      mirrorMat);
  scene.commit();
  return rs;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parseArguments(argc, argv, options)) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  try {
    tg::Scene scene;
    const tg::RenderScene rs = buildScene(scene);
    const tg::Camera camera =
        tg::Camera::lookAt({1.5f, 4.2f, 10.5f}, {0.0f, 1.2f, -1.0f}, {0.0f, 1.0f, 0.0f}, 42.0f,
                           options.width, options.height);
    tg::RenderSettings settings;
    settings.mode = options.mode;
    const tg::Renderer renderer(settings);
    tg::Frame frame;
    tg::RenderStats stats;
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    arena.execute([&] { stats = renderer.render(rs, camera, frame); });
    tg::writePng(frame.beauty, options.output);
    std::fprintf(stderr,
                 "tg-demo: %ux%u %s, %d threads, %.1f ms, %.2f Mrays/s (primary %llu, shadow "
                 "%llu, reflection %llu, refraction %llu), wrote %s\n",
                 stats.width, stats.height, std::string(tg::renderModeName(options.mode)).c_str(),
                 stats.threads, stats.traceShadeMs, stats.mraysPerSecond,
                 static_cast<unsigned long long>(stats.traced.primary),
                 static_cast<unsigned long long>(stats.traced.shadow),
                 static_cast<unsigned long long>(stats.traced.reflection),
                 static_cast<unsigned long long>(stats.traced.refraction), options.output.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tg-demo: %s\n", e.what());
    return 1;
  }
  return 0;
}
