#include "AccuracyGeometry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace tg::bench {

TriangleMesh makeIcosphereMesh(int level) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3d> points = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                               {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                               {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (Vec3d& p : points) p = normalize(p);
  std::vector<std::uint32_t> tris = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11,
                                     1, 5,  9, 5, 11, 4,  11, 10, 2,  10, 7, 6,  7, 1,  8,
                                     3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,
                                     4, 9,  5, 2, 4,  11, 6,  2,  10, 8,  6, 7,  9, 8,  1};
  for (int l = 0; l < level; ++l) {
    // Each edge's midpoint is created once and shared by both triangles on it.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto [it, fresh] = mid.emplace(key, static_cast<std::uint32_t>(points.size()));
      if (fresh) points.push_back(normalize((points[a] + points[b]) * 0.5));
      return it->second;
    };
    std::vector<std::uint32_t> next;
    next.reserve(tris.size() * 4);
    for (std::size_t i = 0; i < tris.size(); i += 3) {
      const std::uint32_t a = tris[i], b = tris[i + 1], c = tris[i + 2];
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    tris = std::move(next);
  }
  TriangleMesh mesh;
  for (const Vec3d& p : points) mesh.positions.push_back(Vec3f(p));
  mesh.indices = std::move(tris);
  return mesh;
}

TriangleMesh makeTorusMesh(double major, double minor, int segments, int rings) {
  TriangleMesh mesh;
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * std::numbers::pi * i / segments;
    for (int j = 0; j < rings; ++j) {
      const double b = 2.0 * std::numbers::pi * j / rings;
      const double r = major + minor * std::cos(b);
      mesh.positions.push_back(Vec3f(Vec3d(r * std::cos(a), minor * std::sin(b), r * std::sin(a))));
    }
  }
  const auto at = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % segments) * rings + (j % rings));
  };
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < rings; ++j)
      mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j),
                                               at(i + 1, j + 1), at(i, j + 1)});
  return mesh;
}

TriangleMesh makeClosedBox(const Vec3f& lo, const Vec3f& hi) {
  TriangleMesh mesh;
  for (int k = 0; k < 8; ++k)
    mesh.positions.push_back({(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z});
  // Two triangles per face, counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
  mesh.indices = {0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                  2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6};
  return mesh;
}

std::vector<AimedRay> makeAimedRays(const TriangleMesh& mesh, const Vec3f& origin) {
  std::vector<std::vector<std::uint32_t>> around(mesh.positions.size());
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> edges;
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const auto tri = static_cast<std::uint32_t>(i / 3);
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = mesh.indices[i + e], b = mesh.indices[i + (e + 1) % 3];
      around[a].push_back(tri);
      edges[std::minmax(a, b)].push_back(tri);
    }
  }
  std::vector<AimedRay> rays;
  const auto aim = [&](const Vec3f& target, const std::vector<std::uint32_t>& fan, bool vertex) {
    // Only rays that cross the surface there: on a saddle (the inside of a torus) a ray can be
    // tangent at a vertex, and then no triangle around it need be hit.
    const Vec3d d = Vec3d(target) - Vec3d(origin);
    int positive = 0, negative = 0;
    for (const std::uint32_t tri : fan) {
      const Vec3d a(mesh.positions[mesh.indices[3 * tri]]);
      const Vec3d b(mesh.positions[mesh.indices[3 * tri + 1]]);
      const Vec3d c(mesh.positions[mesh.indices[3 * tri + 2]]);
      const double s = dot(cross(b - a, c - a), d);
      positive += s > 0.0;
      negative += s < 0.0;
    }
    if (positive != 0 && negative != 0) return;
    AimedRay r;
    r.ray.origin = origin;
    r.ray.direction = target - origin;
    r.fan = fan;
    r.vertex = vertex;
    rays.push_back(std::move(r));
  };
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    if (!around[v].empty()) aim(mesh.positions[v], around[v], true);
  for (const auto& [edge, fan] : edges) {
    const Vec3f a = mesh.positions[edge.first], b = mesh.positions[edge.second];
    aim((a + b) * 0.5f, fan, false);
    aim(a + (b - a) * 0.25f, fan, false);
  }
  return rays;
}

}  // namespace tg::bench
