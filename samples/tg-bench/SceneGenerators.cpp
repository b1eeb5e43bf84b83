#include "SceneGenerators.h"

#include <cmath>
#include <numbers>

#include "tracegraph/backend/Error.h"

namespace tg::bench {
namespace {

void addTriangle(TriangleMesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  mesh.indices.insert(mesh.indices.end(), {a, b, c});
}

double radians(double degrees) {
  return degrees * std::numbers::pi / 180.0;
}

/// Direction at the given azimuth and elevation (degrees) in a frame whose "up" is `axis`.
Vec3d directionInFrame(const Vec3d& axis, double azimuthDeg, double elevationDeg) {
  // Any unit vector perpendicular to the axis works as the frame's first tangent; the helper
  // is chosen away from the axis so the cross product never degenerates.
  const Vec3d helper = std::abs(axis.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 0, 1);
  const Vec3d tangent = normalize(cross(helper, axis));
  const Vec3d bitangent = cross(axis, tangent);
  const double az = radians(azimuthDeg), el = radians(elevationDeg);
  return tangent * (std::cos(el) * std::cos(az)) + axis * std::sin(el) +
         bitangent * (std::cos(el) * std::sin(az));
}

struct FlakeSphere {
  Vec3d centre;
  double radius;
  Vec3d axis;  ///< direction away from the parent
};

/// `parent` is taken by value: callers pass elements of `out`, which this function grows.
void addFlakeChildren(const FlakeSphere parent, int levelsLeft, std::vector<FlakeSphere>& out) {
  if (levelsLeft == 0) return;
  // Six children just above the parent's equator and three higher up, all facing away from
  // the grandparent, as in the Standard Procedural Databases' sphereflake.
  static constexpr double kLayout[9][2] = {{0, 10},   {60, 10}, {120, 10}, {180, 10}, {240, 10},
                                           {300, 10}, {30, 60}, {150, 60}, {270, 60}};
  const double childRadius = parent.radius / 3.0;
  for (const auto& [azimuth, elevation] : kLayout) {
    const Vec3d dir = directionInFrame(parent.axis, azimuth, elevation);
    const FlakeSphere child{parent.centre + dir * (parent.radius + childRadius), childRadius, dir};
    out.push_back(child);
    addFlakeChildren(child, levelsLeft - 1, out);
  }
}

}  // namespace

Vec3d BenchRandom::unitVector() {
  // Rejection sampling in the unit ball keeps the distribution uniform on the sphere.
  for (;;) {
    const Vec3d v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    const double len2 = dot(v, v);
    if (len2 > 1e-6 && len2 <= 1.0) return v / std::sqrt(len2);
  }
}

TriangleMesh makeBoxMesh(const Vec3f& halfExtent) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.emplace_back((i & 1) ? halfExtent.x : -halfExtent.x,
                                (i & 2) ? halfExtent.y : -halfExtent.y,
                                (i & 4) ? halfExtent.z : -halfExtent.z);
  }
  // Corner i has bit 0 = +x, bit 1 = +y, bit 2 = +z; each quad is listed counter-clockwise
  // seen from outside.
  static constexpr std::uint32_t kQuads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                                 {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : kQuads) {
    addTriangle(mesh, q[0], q[1], q[2]);
    addTriangle(mesh, q[0], q[2], q[3]);
  }
  return mesh;
}

TriangleMesh makeSphereMesh(int slices, int stacks) {
  if (slices < 3 || stacks < 2) throw Error("makeSphereMesh: needs slices >= 3 and stacks >= 2");
  TriangleMesh mesh;
  mesh.positions.emplace_back(0.0f, 1.0f, 0.0f);  // north pole
  for (int i = 1; i < stacks; ++i) {
    const double theta = std::numbers::pi * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / slices;
      mesh.positions.push_back(Vec3f(Vec3d(std::sin(theta) * std::cos(phi), std::cos(theta),
                                           std::sin(theta) * std::sin(phi))));
    }
  }
  mesh.positions.emplace_back(0.0f, -1.0f, 0.0f);  // south pole
  const auto ring = [&](int i, int j) {
    return static_cast<std::uint32_t>(1 + (i - 1) * slices + (j % slices));
  };
  const auto south = static_cast<std::uint32_t>(mesh.positions.size() - 1);
  for (int j = 0; j < slices; ++j) addTriangle(mesh, 0, ring(1, j + 1), ring(1, j));
  for (int i = 1; i + 1 < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      addTriangle(mesh, ring(i, j), ring(i, j + 1), ring(i + 1, j + 1));
      addTriangle(mesh, ring(i, j), ring(i + 1, j + 1), ring(i + 1, j));
    }
  }
  for (int j = 0; j < slices; ++j)
    addTriangle(mesh, south, ring(stacks - 1, j), ring(stacks - 1, j + 1));
  mesh.normals = mesh.positions;  // a unit sphere's normals are its points
  return mesh;
}

double randomTriangleCubeSide(std::size_t count) {
  return std::cbrt(static_cast<double>(count == 0 ? 1 : count));
}

TriangleMesh makeRandomTriangles(std::size_t count, std::uint64_t seed) {
  BenchRandom rng(seed);
  const double side = randomTriangleCubeSide(count);
  TriangleMesh mesh;
  mesh.positions.reserve(3 * count);
  mesh.indices.reserve(3 * count);
  for (std::size_t t = 0; t < count; ++t) {
    const Vec3d centre(rng.uniform(0, side), rng.uniform(0, side), rng.uniform(0, side));
    for (int k = 0; k < 3; ++k) {
      const Vec3d offset(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5));
      mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
      mesh.positions.push_back(Vec3f(centre + offset));
    }
  }
  return mesh;
}

std::vector<Affine3d> makeRandomPlacements(std::size_t count, double cubeSide, std::uint64_t seed) {
  BenchRandom rng(seed);
  std::vector<Affine3d> placements;
  placements.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3d axis = rng.unitVector();
    const double degrees = rng.uniform(0, 360);
    const Vec3d position(rng.uniform(0, cubeSide), rng.uniform(0, cubeSide),
                         rng.uniform(0, cubeSide));
    placements.push_back(Affine3d::translation(position) * Affine3d::rotation(axis, degrees));
  }
  return placements;
}

void perturbPositions(std::span<const Vec3f> base, float amplitude, std::uint64_t seed,
                      std::span<Vec3f> out) {
  if (out.size() != base.size()) throw Error("perturbPositions: size mismatch");
  BenchRandom rng(seed);
  const double a = amplitude;
  for (std::size_t i = 0; i < base.size(); ++i) {
    out[i] =
        Vec3f(Vec3d(base[i]) + Vec3d(rng.uniform(-a, a), rng.uniform(-a, a), rng.uniform(-a, a)));
  }
}

BenchScene makeSphereflakeScene(int depth) {
  if (depth < 0 || depth > 6) throw Error("sphereflake depth must be in 0..6");
  BenchScene scene;
  scene.meshes.push_back(makeSphereMesh(32, 16));
  std::vector<FlakeSphere> spheres = {{Vec3d(0, 0, 0), 1.0, Vec3d(0, 1, 0)}};
  addFlakeChildren(spheres.front(), depth, spheres);
  for (const FlakeSphere& s : spheres) {
    scene.instances.push_back({0, Affine3d::translation(s.centre) *
                                      Affine3d::scaling(Vec3d(s.radius, s.radius, s.radius))});
  }
  // The ground sits a little below the root sphere's south pole, so that nothing touches it
  // exactly (touching geometry makes hit/miss comparisons between tracers depend on ties).
  TriangleMesh ground;
  const float half = 2.5f, y = -1.05f;
  ground.positions = {{-half, y, -half}, {half, y, -half}, {half, y, half}, {-half, y, half}};
  ground.indices = {0, 2, 1, 0, 3, 2};
  scene.meshes.push_back(std::move(ground));
  scene.instances.push_back({1, Affine3d::identity()});
  return scene;
}

BenchScene makeRandomTriangleScene(std::size_t count) {
  BenchScene scene;
  scene.meshes.push_back(makeRandomTriangles(count, 0x5EED0001u));
  scene.instances.push_back({0, Affine3d::identity()});
  return scene;
}

}  // namespace tg::bench
