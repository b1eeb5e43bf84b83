// Structural and completeness checks of built kd-trees, for tests.
//
// Completeness: every non-degenerate triangle must be referenced by every leaf whose CLOSED cell
// it overlaps. Touching counts: the traversal stops at the first hit before a cell's exit and
// rounds plane distances and hit distances differently, so a hit on a cell border (an edge shared
// by two triangles in a split plane, a triangle in the plane) must be found from either side.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "tracegraph/backend/KdTree.h"

namespace tg {
namespace {

struct BoxD {
  Vec3d lower, upper;
};

/// Triangle/box overlap by the separating-axis theorem (Akenine-Möller 2001) in double, for a
/// CLOSED box: touching counts as overlap. Boxes may be flat (zero extent on some axes).
bool triangleOverlapsBox(const Vec3d (&tri)[3], const BoxD& box) {
  for (int a = 0; a < 3; ++a)
    if (box.lower[a] > box.upper[a]) return false;
  const Vec3d c = (box.lower + box.upper) * 0.5;
  const Vec3d h = (box.upper - box.lower) * 0.5;
  const Vec3d v[3] = {tri[0] - c, tri[1] - c, tri[2] - c};
  // The box's face normals.
  for (int a = 0; a < 3; ++a) {
    const double lo = std::min({v[0][a], v[1][a], v[2][a]});
    const double hi = std::max({v[0][a], v[1][a], v[2][a]});
    if (lo > h[a] || hi < -h[a]) return false;
  }
  // Cross products of the box axes with the triangle's edges.
  const Vec3d e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  for (const Vec3d& edge : e) {
    for (int a = 0; a < 3; ++a) {
      Vec3d unit{0.0, 0.0, 0.0};
      unit[a] = 1.0;
      const Vec3d axis = cross(unit, edge);
      const double p0 = dot(axis, v[0]), p1 = dot(axis, v[1]), p2 = dot(axis, v[2]);
      const double r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  }
  // The triangle's plane.
  const Vec3d n = cross(e[0], e[1]);
  const double r = h.x * std::abs(n.x) + h.y * std::abs(n.y) + h.z * std::abs(n.z);
  return std::abs(dot(n, v[0])) <= r;
}

std::string describe(const BoxD& b) {
  std::ostringstream s;
  s.precision(9);
  s << "[" << b.lower.x << " " << b.lower.y << " " << b.lower.z << " .. " << b.upper.x << " "
    << b.upper.y << " " << b.upper.z << "]";
  return s.str();
}

class Validator {
 public:
  Validator(const KdTree& tree, const std::vector<TriangleVertices>& triangles)
      : tree_(tree), triangles_(triangles) {}

  std::string run() {
    const std::size_t n = triangles_.size();
    degenerate_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const TriangleVertices& t = triangles_[i];
      degenerate_[i] = isDegenerateTriangle(t.v0, t.v1, t.v2);
    }
    if (tree_.nodes.empty()) return "tree has no nodes";
    if (tree_.nodes.size() > (std::size_t{1} << 30)) return "too many nodes";

    const BoxD root{Vec3d(tree_.bounds.lower), Vec3d(tree_.bounds.upper)};
    for (std::size_t i = 0; i < n; ++i) {
      if (degenerate_[i]) continue;
      const TriangleVertices& t = triangles_[i];
      if (!tree_.bounds.contains(t.v0) || !tree_.bounds.contains(t.v1) ||
          !tree_.bounds.contains(t.v2))
        return "triangle " + std::to_string(i) + " lies outside tree.bounds " + describe(root);
    }

    seen_.assign(tree_.nodes.size(), 0);
    stamp_.assign(n, 0);
    std::uint32_t next = 0;
    if (!checkStructure(0, 0, root, next)) return error_;
    if (next != tree_.nodes.size())
      return std::to_string(tree_.nodes.size() - next) + " nodes are not reachable from the root";

    for (std::size_t i = 0; i < n; ++i) {
      if (degenerate_[i]) continue;
      const TriangleVertices& t = triangles_[i];
      tri_[0] = Vec3d(t.v0);
      tri_[1] = Vec3d(t.v1);
      tri_[2] = Vec3d(t.v2);
      triangle_ = static_cast<std::uint32_t>(i);
      if (!covers(0, root)) return error_;
    }
    return {};
  }

 private:
  /// Checks the subtree at `node` (cell `cell`, depth `depth`) and sets `next` to the index
  /// just past it: the above child must start there (depth-first layout).
  bool checkStructure(std::uint32_t node, int depth, const BoxD& cell, std::uint32_t& next) {
    const auto where = [node] { return "node " + std::to_string(node) + ": "; };
    if (node >= tree_.nodes.size()) return fail(where() + "index out of range");
    if (seen_[node]) return fail(where() + "reached twice");
    seen_[node] = 1;
    if (depth > kKdMaxDepth) return fail(where() + "deeper than kKdMaxDepth");
    const KdNode& k = tree_.nodes[node];
    if (k.isLeaf()) {
      const std::uint64_t first = k.firstPrim(), count = k.primCount();
      if (first + count > tree_.primIndices.size())
        return fail(where() + "leaf range exceeds primIndices");
      for (std::uint64_t i = first; i < first + count; ++i) {
        const std::uint32_t prim = tree_.primIndices[i];
        if (prim >= triangles_.size())
          return fail(where() + "triangle id " + std::to_string(prim) + " out of range");
        if (degenerate_[prim])
          return fail(where() + "references degenerate triangle " + std::to_string(prim));
        if (stamp_[prim] == node + 1)
          return fail(where() + "references triangle " + std::to_string(prim) + " twice");
        stamp_[prim] = node + 1;
      }
      next = node + 1;
      return true;
    }
    const int a = k.axis();
    const double split = static_cast<double>(k.split());
    if (!(cell.lower[a] <= split && split <= cell.upper[a]))
      return fail(where() + "split " + std::to_string(split) + " on axis " + std::to_string(a) +
                  " outside cell " + describe(cell));
    if (depth + 1 > kKdMaxDepth) return fail(where() + "children deeper than kKdMaxDepth");
    BoxD below = cell, above = cell;
    below.upper[a] = split;
    above.lower[a] = split;
    std::uint32_t afterBelow = 0;
    if (!checkStructure(node + 1, depth + 1, below, afterBelow)) return false;
    if (k.aboveChild() != afterBelow)
      return fail(where() + "above child " + std::to_string(k.aboveChild()) +
                  " does not follow the below subtree (expected " + std::to_string(afterBelow) +
                  ")");
    return checkStructure(k.aboveChild(), depth + 1, above, next);
  }

  /// True when every leaf below `node` whose closed cell the current triangle overlaps references
  /// it. Children the triangle does not overlap are skipped: their leaves' cells lie inside.
  bool covers(std::uint32_t node, const BoxD& cell) {
    const KdNode& k = tree_.nodes[node];
    if (k.isLeaf()) {
      const auto begin = tree_.primIndices.begin() + k.firstPrim();
      if (std::find(begin, begin + k.primCount(), triangle_) != begin + k.primCount()) return true;
      return fail("triangle " + std::to_string(triangle_) + " overlaps the cell " + describe(cell) +
                  " of leaf " + std::to_string(node) + " but is not referenced there");
    }
    const int a = k.axis();
    const double split = static_cast<double>(k.split());
    BoxD below = cell, above = cell;
    below.upper[a] = split;
    above.lower[a] = split;
    if (triangleOverlapsBox(tri_, below) && !covers(node + 1, below)) return false;
    return !triangleOverlapsBox(tri_, above) || covers(k.aboveChild(), above);
  }

  bool fail(std::string message) {
    error_ = std::move(message);
    return false;
  }

  const KdTree& tree_;
  const std::vector<TriangleVertices>& triangles_;
  std::vector<std::uint8_t> degenerate_;
  std::vector<std::uint8_t> seen_;
  std::vector<std::uint32_t> stamp_;  ///< leaf node + 1 that last referenced each triangle
  Vec3d tri_[3];
  std::uint32_t triangle_ = 0;
  std::string error_;
};

}  // namespace

std::string validateKdTree(const KdTree& tree, const std::vector<TriangleVertices>& triangles) {
  return Validator(tree, triangles).run();
}

}  // namespace tg
