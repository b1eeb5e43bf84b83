/// @file AccuracyGeometry.h
/// Inputs of the accuracy suite: closed meshes with shared vertices, the rays aimed exactly at
/// their vertices and edges, and simple boxes and quads.
#pragma once

#include <cstdint>
#include <vector>

#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/TriangleMesh.h"

namespace tg::bench {

/// Icosahedron subdivided `level` times and projected onto the unit sphere: 20 * 4^level
/// triangles sharing their vertices (level 5: 20,480 triangles). Closed.
TriangleMesh makeIcosphereMesh(int level);

/// Torus around the y axis with radii `major` > `minor`: 2 * segments * rings triangles
/// sharing their vertices. Closed.
TriangleMesh makeTorusMesh(double major, double minor, int segments, int rings);

/// Axis-aligned box [lo, hi] with 8 shared corners and 12 triangles, outward winding.
TriangleMesh makeClosedBox(const Vec3f& lo, const Vec3f& hi);

/// A ray from inside a closed mesh aimed exactly at a vertex or at a point of an edge, with
/// the triangles that share that vertex or edge (the only ones it can hit there).
struct AimedRay {
  Ray ray;
  std::vector<std::uint32_t> fan;  ///< triangle indices around the target
  bool vertex = false;             ///< aimed at a vertex (else at an edge point)
};

/// Rays from `origin` at every vertex, and at the midpoint and the quarter point of every edge,
/// leaving out those that are tangent to the surface there (the triangles around the target
/// do not all face the same way along the ray).
std::vector<AimedRay> makeAimedRays(const TriangleMesh& mesh, const Vec3f& origin);

}  // namespace tg::bench
