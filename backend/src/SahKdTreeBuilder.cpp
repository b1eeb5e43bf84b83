// SAH kd-tree construction in O(N log N) after Wald & Havran 2006, "On building fast kd-trees
// for ray tracing, and on doing that in O(N log N)".
//
// The three per-axis event lists are built and sorted once. Every node sweeps its (sorted)
// lists to find the cheapest plane, then splits them in linear time: events of triangles that
// lie on one side keep their order, and only the triangles reaching both children get new
// events, from their polygon clipped to each child cell ("perfect splits"); those few are sorted
// and merged in.
//
// Unlike the paper, a child references every triangle that touches its CLOSED cell: a triangle
// ending exactly at the plane, or lying in it, goes to both children, and the sweep counts it on
// both sides. The traversal stops at the first hit before the cell's exit distance and compares
// plane distances and hit distances rounded differently; a hit point on a split plane must
// therefore be found from either side, or an exact tie (two triangles sharing an edge in the
// plane) could be resolved against the tie rule, and a ray grazing a cell corner could miss.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/KdTree.h"

namespace tg {
namespace {

constexpr std::uint32_t kTriangleBits = 30;
constexpr std::uint32_t kTriangleMask = (1u << kTriangleBits) - 1;

// Event types; the sweep takes all events at one position together, so their order among
// equal positions only has to be fixed, not meaningful.
constexpr std::uint32_t kEnd = 0;
constexpr std::uint32_t kPlanar = 1;
constexpr std::uint32_t kStart = 2;

/// One end of a triangle's (clipped) bounds on one axis, 8 bytes.
struct Event {
  float pos;
  std::uint32_t code;  ///< type << 30 | triangle

  std::uint32_t type() const { return code >> kTriangleBits; }
  std::uint32_t triangle() const { return code & kTriangleMask; }
};

// Ordering on the triangle id too makes every sort and merge produce one canonical order, so the
// tree never depends on the sort implementation.
inline bool operator<(const Event& a, const Event& b) {
  return a.pos < b.pos || (a.pos == b.pos && a.code < b.code);
}

inline Event makeEvent(float pos, std::uint32_t type, std::uint32_t triangle) {
  return {pos, (type << kTriangleBits) | triangle};
}

using EventLists = std::array<std::vector<Event>, 3>;

/// Appends the events of bounds `b` of `triangle`: one planar event on an axis where the bounds
/// are flat, a start and an end event elsewhere.
inline void appendEvents(EventLists& lists, const Box3f& b, std::uint32_t triangle) {
  for (int a = 0; a < 3; ++a) {
    if (b.lower[a] == b.upper[a]) {
      lists[a].push_back(makeEvent(b.lower[a], kPlanar, triangle));
    } else {
      lists[a].push_back(makeEvent(b.lower[a], kStart, triangle));
      lists[a].push_back(makeEvent(b.upper[a], kEnd, triangle));
    }
  }
}

/// Convex polygon for Sutherland–Hodgman clipping. A triangle clipped by six planes has at most
/// nine vertices; the spare room absorbs the extra crossings rounding can add to a sliver.
struct Polygon {
  static constexpr int kCapacity = 16;
  Vec3d v[kCapacity];
  int n = 0;
};

/// Keeps the part of `in` with coordinate `axis` >= bound (keepAbove) or <= bound. Returns false
/// when the output would overflow (only possible for numerically degenerate input).
bool clipPolygon(const Polygon& in, Polygon& out, int axis, double bound, bool keepAbove) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const Vec3d& a = in.v[i];
    const Vec3d& b = in.v[i + 1 == in.n ? 0 : i + 1];
    const bool insideA = keepAbove ? a[axis] >= bound : a[axis] <= bound;
    const bool insideB = keepAbove ? b[axis] >= bound : b[axis] <= bound;
    if (out.n + 2 > Polygon::kCapacity) return false;
    if (insideA) out.v[out.n++] = a;
    if (insideA != insideB) {
      const double t = (bound - a[axis]) / (b[axis] - a[axis]);
      Vec3d p = a + (b - a) * t;
      p[axis] = bound;  // exactly on the plane, whatever the rounding of t
      out.v[out.n++] = p;
    }
  }
  return true;
}

/// Largest float <= x.
inline float roundDown(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -kInfinity);
  return f;
}

/// Smallest float >= x.
inline float roundUp(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, kInfinity);
  return f;
}

/// Which child(ren) a triangle goes to during a split.
constexpr std::uint8_t kLeftOnly = 1;
constexpr std::uint8_t kRightOnly = 2;
constexpr std::uint8_t kBoth = 3;         ///< reaches both children: clipped to each
constexpr std::uint8_t kBothPlanar = 4;   ///< lies in the plane: same bounds in both children

struct Split {
  int axis = 0;
  float pos = 0.0f;
};

class SahBuilder {
 public:
  SahBuilder(const std::vector<TriangleVertices>& triangles, const SahKdTreeOptions& options,
             KdTree& tree)
      : triangles_(triangles), options_(options), tree_(tree) {}

  void run() {
    const std::size_t n = triangles_.size();
    if (n > kTriangleMask) throw Error("buildSahKdTree: more than 2^30 - 1 triangles");
    EventLists root;
    for (auto& list : root) list.reserve(2 * n);
    std::uint32_t count = 0;
    Box3f bounds;
    for (std::size_t i = 0; i < n; ++i) {
      const TriangleVertices& t = triangles_[i];
      if (isDegenerateTriangle(t.v0, t.v1, t.v2)) {
        ++tree_.stats.degenerate;
        continue;
      }
      Box3f b;
      b.extend(t.v0);
      b.extend(t.v1);
      b.extend(t.v2);
      bounds.extend(b);
      appendEvents(root, b, static_cast<std::uint32_t>(i));
      ++count;
    }
    tree_.bounds = bounds;
    if (count == 0) {
      tree_.nodes.push_back(KdNode::makeLeaf(0, 0));
      tree_.stats.nodes = tree_.stats.leaves = tree_.stats.emptyLeaves = 1;
      return;
    }
    for (auto& list : root) std::sort(list.begin(), list.end());

    // Clipping runs in double; the margin bounds its rounding (a few ulps of the largest
    // coordinate per clip plane) with ample room, and stays far below float resolution.
    const double scale = std::max(maxComponent(abs(Vec3d(bounds.lower))),
                                  maxComponent(abs(Vec3d(bounds.upper))));
    margin_ = scale * 0x1p-45;

    maxDepth_ = options_.maxDepth > 0
                    ? std::min(options_.maxDepth, kKdMaxDepth)
                    : std::min(kKdMaxDepth,
                               static_cast<int>(8.0 + 1.3 * std::log2(static_cast<double>(count))));
    side_.assign(n, 0);
    levels_.resize(static_cast<std::size_t>(maxDepth_) + 1);
    tree_.nodes.reserve(static_cast<std::size_t>(count) / 2 + 1);
    tree_.primIndices.reserve(static_cast<std::size_t>(count) * 2);
    build(root, bounds, count, 0);
  }

 private:
  struct Level {
    EventLists left, right;
  };

  void build(const EventLists& events, const Box3f& cell, std::uint32_t count, int depth) {
    const auto nodeIndex = static_cast<std::uint32_t>(tree_.nodes.size());
    tree_.nodes.emplace_back();
    ++tree_.stats.nodes;
    Split split;
    if (count == 0 || depth >= maxDepth_ || !findSplit(events, cell, count, split)) {
      makeLeaf(nodeIndex, events[0], depth);
      return;
    }
    Box3f leftCell = cell, rightCell = cell;
    leftCell.upper[split.axis] = split.pos;
    rightCell.lower[split.axis] = split.pos;
    Level& level = levels_[static_cast<std::size_t>(depth)];
    std::uint32_t leftCount = 0, rightCount = 0;
    splitEvents(events, split, leftCell, rightCell, level, leftCount, rightCount);
    build(level.left, leftCell, leftCount, depth + 1);
    tree_.nodes[nodeIndex] = KdNode::makeInner(
        split.axis, split.pos, static_cast<std::uint32_t>(tree_.nodes.size()));
    build(level.right, rightCell, rightCount, depth + 1);
  }

  /// SAH sweep over the sorted events of each axis. Returns false when no plane beats making a
  /// leaf (K_I * count).
  bool findSplit(const EventLists& events, const Box3f& cell, std::uint32_t count, Split& best) {
    const float area = cell.area();
    // A cell flat in two axes has no surface area to weigh children by.
    if (!(area > 0.0f)) return false;
    const float invArea = 1.0f / area;
    const float kt = options_.traversalCost, ki = options_.intersectionCost;
    const float bonus = options_.emptyBonus;
    const Vec3f d = cell.extent();
    float bestCost = ki * static_cast<float>(count);
    bool found = false;
    for (int k = 0; k < 3; ++k) {
      // Every plane on an axis of zero extent gives both children the parent's cell.
      if (!(d[k] > 0.0f)) continue;
      const float lo = cell.lower[k], hi = cell.upper[k];
      const float cross = d[(k + 1) % 3] * d[(k + 2) % 3];
      const float sum = d[(k + 1) % 3] + d[(k + 2) % 3];
      const std::vector<Event>& list = events[k];
      const std::size_t size = list.size();
      // Triangles with (clipped) bounds [lo, hi] go left when lo <= p and right when hi >= p.
      std::uint32_t startedBefore = 0, endedBefore = 0;
      std::size_t i = 0;
      while (i < size) {
        const float p = list[i].pos;
        std::uint32_t ends = 0, planars = 0, starts = 0;
        while (i < size && list[i].pos == p && list[i].type() == kEnd) ++ends, ++i;
        while (i < size && list[i].pos == p && list[i].type() == kPlanar) ++planars, ++i;
        while (i < size && list[i].pos == p && list[i].type() == kStart) ++starts, ++i;
        const std::uint32_t left = startedBefore + planars + starts;
        const std::uint32_t right = count - endedBefore;
        startedBefore += planars + starts;
        endedBefore += planars + ends;
        // A plane on the cell's border gives one child the parent's cell and every triangle:
        // no progress.
        if (p <= lo || p >= hi) continue;
        const float pl = 2.0f * (cross + (p - lo) * sum) * invArea;
        const float pr = 2.0f * (cross + (hi - p) * sum) * invArea;
        float cost = kt + ki * (pl * static_cast<float>(left) + pr * static_cast<float>(right));
        if (left == 0 || right == 0) cost *= bonus;
        if (cost < bestCost) {
          bestCost = cost;
          best = {k, p};
          found = true;
        }
      }
    }
    return found;
  }

  /// Classifies the node's triangles against `split` and writes the children's sorted event
  /// lists into `level`.
  void splitEvents(const EventLists& events, const Split& split, const Box3f& leftCell,
                   const Box3f& rightCell, Level& level, std::uint32_t& leftCount,
                   std::uint32_t& rightCount) {
    const int k = split.axis;
    const float p = split.pos;
    const std::vector<Event>& axisEvents = events[k];
    for (const Event& e : axisEvents) side_[e.triangle()] = kBoth;
    straddling_.clear();
    for (const Event& e : axisEvents) {
      std::uint8_t& s = side_[e.triangle()];
      switch (e.type()) {
        case kEnd:
          if (e.pos < p) {
            s = kLeftOnly;
          } else if (s == kBoth) {
            straddling_.push_back(e.triangle());  // started at or before p: reaches both sides
          }
          break;
        case kStart:
          if (e.pos > p) s = kRightOnly;
          break;
        default:  // planar
          s = e.pos < p ? kLeftOnly : (e.pos > p ? kRightOnly : kBothPlanar);
          break;
      }
    }
    std::uint32_t leftOnly = 0, rightOnly = 0, inPlane = 0;
    for (const Event& e : axisEvents) {
      if (e.type() == kEnd) continue;  // count each triangle once, at its start or planar event
      const std::uint8_t s = side_[e.triangle()];
      leftOnly += s == kLeftOnly;
      rightOnly += s == kRightOnly;
      inPlane += s == kBothPlanar;
    }

    // Perfect splits: new bounds from the straddling triangles' polygons clipped to each child.
    for (int a = 0; a < 3; ++a) {
      newLeft_[a].clear();
      newRight_[a].clear();
    }
    std::uint32_t bothLeft = 0, bothRight = 0;
    for (const std::uint32_t t : straddling_) {
      Box3f lb, rb;
      bool inLeft = clipToCell(t, leftCell, lb);
      bool inRight = clipToCell(t, rightCell, rb);
      if (!inLeft && !inRight) {
        // Cannot happen in exact arithmetic (the triangle overlaps the parent cell); keep the
        // triangle in both children rather than lose it.
        lb = boxInCell(t, leftCell);
        rb = boxInCell(t, rightCell);
        inLeft = inRight = true;
      }
      if (inLeft) {
        appendEvents(newLeft_, lb, t);
        ++bothLeft;
      }
      if (inRight) {
        appendEvents(newRight_, rb, t);
        ++bothRight;
      }
    }
    leftCount = leftOnly + inPlane + bothLeft;
    rightCount = rightOnly + inPlane + bothRight;

    for (int a = 0; a < 3; ++a) {
      std::vector<Event>& newL = newLeft_[a];
      std::vector<Event>& newR = newRight_[a];
      std::sort(newL.begin(), newL.end());
      std::sort(newR.begin(), newR.end());
      std::vector<Event>& outL = level.left[a];
      std::vector<Event>& outR = level.right[a];
      outL.clear();
      outR.clear();
      std::size_t il = 0, ir = 0;
      for (const Event& e : events[a]) {
        const std::uint8_t s = side_[e.triangle()];
        if (s == kLeftOnly) {
          while (il < newL.size() && newL[il] < e) outL.push_back(newL[il++]);
          outL.push_back(e);
        } else if (s == kRightOnly) {
          while (ir < newR.size() && newR[ir] < e) outR.push_back(newR[ir++]);
          outR.push_back(e);
        } else if (s == kBothPlanar) {
          // Flat at p on the split axis and unchanged on the others: valid in both cells.
          while (il < newL.size() && newL[il] < e) outL.push_back(newL[il++]);
          outL.push_back(e);
          while (ir < newR.size() && newR[ir] < e) outR.push_back(newR[ir++]);
          outR.push_back(e);
        }
      }
      outL.insert(outL.end(), newL.begin() + static_cast<std::ptrdiff_t>(il), newL.end());
      outR.insert(outR.end(), newR.begin() + static_cast<std::ptrdiff_t>(ir), newR.end());
    }
  }

  /// Bounds of triangle `t` clipped to `cell`, conservative: every point of the exact
  /// intersection lies inside. The clip planes are pushed out by the margin, so that rounding in
  /// the clip can only keep too much, never lose a piece. Returns false when nothing is left.
  bool clipToCell(std::uint32_t t, const Box3f& cell, Box3f& out) const {
    const TriangleVertices& tri = triangles_[t];
    Polygon a, b;
    a.n = 3;
    a.v[0] = Vec3d(tri.v0);
    a.v[1] = Vec3d(tri.v1);
    a.v[2] = Vec3d(tri.v2);
    for (int axis = 0; axis < 3 && a.n > 0; ++axis) {
      if (!clipPolygon(a, b, axis, static_cast<double>(cell.lower[axis]) - margin_, true) ||
          !clipPolygon(b, a, axis, static_cast<double>(cell.upper[axis]) + margin_, false)) {
        out = boxInCell(t, cell);
        return true;
      }
    }
    if (a.n == 0) return false;
    Vec3d lo = a.v[0], hi = a.v[0];
    for (int i = 1; i < a.n; ++i) {
      lo = min(lo, a.v[i]);
      hi = max(hi, a.v[i]);
    }
    for (int axis = 0; axis < 3; ++axis) {
      // Clamping both ends into the cell keeps lower <= upper.
      out.lower[axis] = std::clamp(roundDown(lo[axis] - margin_), cell.lower[axis], cell.upper[axis]);
      out.upper[axis] = std::clamp(roundUp(hi[axis] + margin_), cell.lower[axis], cell.upper[axis]);
    }
    return true;
  }

  /// The triangle's bounding box clamped into `cell` (conservative fallback for clipping).
  Box3f boxInCell(std::uint32_t t, const Box3f& cell) const {
    const TriangleVertices& tri = triangles_[t];
    Box3f b;
    b.extend(tri.v0);
    b.extend(tri.v1);
    b.extend(tri.v2);
    for (int axis = 0; axis < 3; ++axis) {
      b.lower[axis] = std::clamp(b.lower[axis], cell.lower[axis], cell.upper[axis]);
      b.upper[axis] = std::clamp(b.upper[axis], cell.lower[axis], cell.upper[axis]);
    }
    return b;
  }

  void makeLeaf(std::uint32_t nodeIndex, const std::vector<Event>& events, int depth) {
    const auto first = static_cast<std::uint32_t>(tree_.primIndices.size());
    for (const Event& e : events)
      if (e.type() != kEnd) tree_.primIndices.push_back(e.triangle());
    std::sort(tree_.primIndices.begin() + first, tree_.primIndices.end());
    const auto count = static_cast<std::uint32_t>(tree_.primIndices.size() - first);
    tree_.nodes[nodeIndex] = KdNode::makeLeaf(first, count);
    BuildStats& s = tree_.stats;
    ++s.leaves;
    if (count == 0) ++s.emptyLeaves;
    s.primReferences += count;
    s.maxDepth = std::max(s.maxDepth, static_cast<std::size_t>(depth));
  }

  const std::vector<TriangleVertices>& triangles_;
  SahKdTreeOptions options_;
  KdTree& tree_;
  double margin_ = 0.0;
  int maxDepth_ = 0;
  std::vector<std::uint8_t> side_;           ///< per triangle, valid during one split
  std::vector<Level> levels_;                ///< children's event lists, reused per depth
  std::vector<std::uint32_t> straddling_;    ///< triangles spanning the current plane
  EventLists newLeft_, newRight_;            ///< events of the straddling triangles' pieces
};

}  // namespace

KdTree buildSahKdTree(const std::vector<TriangleVertices>& triangles,
                      const SahKdTreeOptions& options) {
  KdTree tree;
  SahBuilder(triangles, options, tree).run();
  return tree;
}

}  // namespace tg
