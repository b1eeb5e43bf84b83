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
#include <limits>
#include <memory>
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

/// A growable array of events that, unlike std::vector, does not zero what it allocates: the
/// split writes every child list in full, so zeroing would only add a pass over memory.
class EventList {
 public:
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  Event* data() { return data_.get(); }
  const Event* data() const { return data_.get(); }
  const Event* begin() const { return data_.get(); }
  const Event* end() const { return data_.get() + size_; }
  const Event& operator[](std::size_t i) const { return data_[i]; }

  void clear() { size_ = 0; }
  /// Makes room for `capacity` events, keeping the current ones.
  void reserve(std::size_t capacity) {
    if (capacity <= capacity_) return;
    capacity = std::max(capacity, capacity_ + capacity_ / 2);
    auto grown = std::make_unique_for_overwrite<Event[]>(capacity);
    std::copy(begin(), end(), grown.get());
    data_ = std::move(grown);
    capacity_ = capacity;
  }
  /// Sets the size after writing through data(); `size` must not exceed the capacity.
  void setSize(std::size_t size) { size_ = size; }
  void push_back(const Event& e) {
    if (size_ == capacity_) reserve(std::max<std::size_t>(16, 2 * capacity_));
    data_[size_++] = e;
  }
  void sort() { std::sort(data_.get(), data_.get() + size_); }

 private:
  std::unique_ptr<Event[]> data_;
  std::size_t size_ = 0, capacity_ = 0;
};

using EventLists = std::array<EventList, 3>;

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

/// Merges the sorted `extra` into the sorted first `size` events of `list`, which has room for
/// both, from the back: only events after the first new one move.
void mergeInto(Event* list, std::size_t size, const EventList& extra) {
  std::size_t a = size, b = extra.size(), w = size + extra.size();
  while (b > 0) {
    if (a > 0 && extra[b - 1] < list[a - 1]) {
      list[--w] = list[--a];
    } else {
      list[--w] = extra[--b];
    }
  }
}

/// Convex polygon for Sutherland–Hodgman clipping. A triangle clipped by six planes has at most
/// nine vertices; the spare room absorbs the extra crossings rounding can add to a sliver.
struct Polygon {
  static constexpr int kCapacity = 16;
  Vec3d v[kCapacity];
  std::uint8_t exact[kCapacity];  ///< bit a: coordinate a carries no rounding error
  int n = 0;
};

/// Keeps the part of `in` with coordinate `axis` >= bound (keepAbove) or <= bound. Returns false
/// when the output would overflow (only possible for numerically degenerate input).
///
/// Coordinates are tracked as exact when they are the triangle's own, the clip plane's, or shared
/// by both ends of the clipped edge. Only the others get a rounding margin in the bounds, so that
/// a bound reached at a vertex stays on the vertex and does not turn into a new candidate plane a
/// few ulps beside it.
bool clipPolygon(const Polygon& in, Polygon& out, int axis, double bound, bool keepAbove) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const int j = i + 1 == in.n ? 0 : i + 1;
    const Vec3d& a = in.v[i];
    const Vec3d& b = in.v[j];
    const double da = keepAbove ? a[axis] - bound : bound - a[axis];
    const double db = keepAbove ? b[axis] - bound : bound - b[axis];
    if (out.n + 2 > Polygon::kCapacity) return false;
    if (da >= 0.0) {
      out.v[out.n] = a;
      out.exact[out.n++] = in.exact[i];
    }
    // A crossing strictly between the ends; an end on the plane is itself kept.
    if ((da > 0.0 && db < 0.0) || (da < 0.0 && db > 0.0)) {
      const double t = (bound - a[axis]) / (b[axis] - a[axis]);
      Vec3d p = a + (b - a) * t;
      std::uint8_t exact = static_cast<std::uint8_t>(1u << axis);
      p[axis] = bound;  // exactly on the plane, whatever the rounding of t
      for (int c = 0; c < 3; ++c) {
        if (c == axis || a[c] != b[c]) continue;
        p[c] = a[c];
        exact |= in.exact[i] & in.exact[j] & (1u << c);
      }
      out.v[out.n] = p;
      out.exact[out.n++] = exact;
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

/// Where a triangle goes during a split. Those that keep their bounds on a side (they lie
/// within that child's cell) copy their events there; the others get new events from a clip.
constexpr std::uint8_t kLeftOnly = 0;    ///< ends before the plane
constexpr std::uint8_t kRightOnly = 1;   ///< starts after the plane
constexpr std::uint8_t kInPlane = 2;     ///< flat in the plane: same bounds on both sides
constexpr std::uint8_t kLeftTouch = 3;   ///< ends on the plane: keeps left, clipped right
constexpr std::uint8_t kRightTouch = 4;  ///< starts on the plane: keeps right, clipped left
constexpr std::uint8_t kStraddles = 5;   ///< spans the plane: clipped on both sides
constexpr std::uint8_t kKeepLeft[6] = {1, 0, 1, 1, 0, 0};
constexpr std::uint8_t kKeepRight[6] = {0, 1, 1, 0, 1, 0};

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
    for (auto& list : root) list.reserve(2 * n + 1);
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
    for (auto& list : root) list.sort();

    // Clipping runs in double; the margin bounds its rounding (a few ulps of the largest
    // coordinate per clip plane) with ample room, and stays far below float resolution.
    const double scale =
        std::max(maxComponent(abs(Vec3d(bounds.lower))), maxComponent(abs(Vec3d(bounds.upper))));
    margin_ = scale * 0x1p-45;

    const double log2n = std::log2(static_cast<double>(count));
    maxDepth_ = std::min(kKdMaxDepth, options_.maxDepth > 0 ? options_.maxDepth
                                                            : static_cast<int>(8.0 + 1.3 * log2n));
    side_.assign(n, 0);
    levels_.resize(static_cast<std::size_t>(maxDepth_) + 1);
    tree_.nodes.reserve(static_cast<std::size_t>(count) + 1);
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
    tree_.nodes[nodeIndex] =
        KdNode::makeInner(split.axis, split.pos, static_cast<std::uint32_t>(tree_.nodes.size()));
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
      const EventList& list = events[k];
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
    const EventList& axisEvents = events[k];
    // Events are sorted, so a triangle's start comes before its end.
    clipped_.clear();
    std::uint32_t kept[6] = {0, 0, 0, 0, 0, 0};
    for (const Event& e : axisEvents) {
      const std::uint32_t t = e.triangle();
      std::uint8_t& s = side_[t];
      switch (e.type()) {
        case kStart:
          s = e.pos > p ? kRightOnly : (e.pos == p ? kRightTouch : kStraddles);
          break;
        case kEnd:
          if (e.pos < p) {
            s = kLeftOnly;
          } else {
            if (s == kStraddles && e.pos == p) s = kLeftTouch;
            if (s != kRightOnly) clipped_.push_back(t);
          }
          ++kept[s];
          break;
        default:  // planar
          s = e.pos < p ? kLeftOnly : (e.pos > p ? kRightOnly : kInPlane);
          ++kept[s];
          break;
      }
    }

    // Perfect splits: bounds of the triangles reaching a child whose cell does not contain their
    // current bounds, from their polygon clipped to that child's cell.
    for (int a = 0; a < 3; ++a) {
      newLeft_[a].clear();
      newRight_[a].clear();
    }
    std::uint32_t clippedLeft = 0, clippedRight = 0;
    for (const std::uint32_t t : clipped_) {
      const std::uint8_t s = side_[t];
      Box3f lb, rb;
      const bool inLeft = s != kLeftTouch && clipToCell(t, leftCell, lb);
      const bool inRight = s != kRightTouch && clipToCell(t, rightCell, rb);
      if (inLeft) {
        appendEvents(newLeft_, lb, t);
        ++clippedLeft;
      }
      if (inRight) {
        appendEvents(newRight_, rb, t);
        ++clippedRight;
      }
      if (s == kStraddles && !inLeft && !inRight) {
        // Cannot happen in exact arithmetic (the triangle overlaps the parent cell); keep the
        // triangle on both sides rather than lose it.
        appendEvents(newLeft_, boxInCell(t, leftCell), t);
        appendEvents(newRight_, boxInCell(t, rightCell), t);
        ++clippedLeft;
        ++clippedRight;
      }
    }
    leftCount = kept[kLeftOnly] + kept[kInPlane] + kept[kLeftTouch] + clippedLeft;
    rightCount = kept[kRightOnly] + kept[kInPlane] + kept[kRightTouch] + clippedRight;

    for (int a = 0; a < 3; ++a) {
      EventList& newL = newLeft_[a];
      EventList& newR = newRight_[a];
      newL.sort();
      newR.sort();
      const EventList& in = events[a];
      EventList& outL = level.left[a];
      EventList& outR = level.right[a];
      outL.clear();
      outR.clear();
      outL.reserve(in.size() + newL.size());
      outR.reserve(in.size() + newR.size());
      // Every event is written to both lists and kept where its triangle goes: which side that
      // is has nothing to do with the order on this axis, so a branch would mispredict often.
      Event* l = outL.data();
      Event* r = outR.data();
      std::size_t nl = 0, nr = 0;
      for (const Event& e : in) {
        const std::uint8_t s = side_[e.triangle()];
        l[nl] = e;
        nl += kKeepLeft[s];
        r[nr] = e;
        nr += kKeepRight[s];
      }
      mergeInto(l, nl, newL);
      mergeInto(r, nr, newR);
      outL.setSize(nl + newL.size());
      outR.setSize(nr + newR.size());
    }
  }

  /// Bounds of triangle `t` clipped to `cell`, conservative: every point of the exact
  /// intersection lies inside. Returns false when nothing is left.
  bool clipToCell(std::uint32_t t, const Box3f& cell, Box3f& out) const {
    // Rounding in the clip can make a sliver along a face vanish; before dropping the triangle,
    // clip again with the planes pushed out by the margin, which can only keep too much.
    for (const double push : {0.0, margin_}) {
      Polygon bufferA, bufferB;
      const Polygon* clipped = nullptr;
      const ClipResult r = clipTriangle(t, cell, push, bufferA, bufferB, clipped);
      if (r == ClipResult::kOverflow) {
        out = boxInCell(t, cell);
        return true;
      }
      if (r == ClipResult::kEmpty) continue;
      const Polygon& poly = *clipped;
      constexpr double kInf = std::numeric_limits<double>::infinity();
      Vec3d lo{kInf, kInf, kInf}, hi = -lo;
      for (int i = 0; i < poly.n; ++i) {
        for (int a = 0; a < 3; ++a) {
          const double slack = (poly.exact[i] >> a) & 1u ? 0.0 : margin_;
          lo[a] = std::min(lo[a], poly.v[i][a] - slack);
          hi[a] = std::max(hi[a], poly.v[i][a] + slack);
        }
      }
      for (int a = 0; a < 3; ++a) {
        // Clamping both ends into the cell keeps lower <= upper.
        out.lower[a] = std::clamp(roundDown(lo[a]), cell.lower[a], cell.upper[a]);
        out.upper[a] = std::clamp(roundUp(hi[a]), cell.lower[a], cell.upper[a]);
      }
      return true;
    }
    return false;
  }

  enum class ClipResult { kEmpty, kNonEmpty, kOverflow };

  /// Sutherland–Hodgman clip of triangle `t` against `cell` grown by `push` on every side.
  /// The result is in `out` or in `scratch`; returns which through `result`.
  ClipResult clipTriangle(std::uint32_t t, const Box3f& cell, double push, Polygon& out,
                          Polygon& scratch, const Polygon*& result) const {
    const TriangleVertices& tri = triangles_[t];
    Polygon* cur = &out;
    Polygon* next = &scratch;
    cur->n = 3;
    cur->v[0] = Vec3d(tri.v0);
    cur->v[1] = Vec3d(tri.v1);
    cur->v[2] = Vec3d(tri.v2);
    cur->exact[0] = cur->exact[1] = cur->exact[2] = 7;
    for (int axis = 0; axis < 3 && cur->n > 0; ++axis) {
      // The polygon lies within the triangle: a plane the whole triangle is inside cuts nothing.
      const float lo = std::min({tri.v0[axis], tri.v1[axis], tri.v2[axis]});
      const float hi = std::max({tri.v0[axis], tri.v1[axis], tri.v2[axis]});
      const double lower = static_cast<double>(cell.lower[axis]) - push;
      const double upper = static_cast<double>(cell.upper[axis]) + push;
      if (static_cast<double>(lo) < lower) {
        if (!clipPolygon(*cur, *next, axis, lower, true)) return ClipResult::kOverflow;
        std::swap(cur, next);
      }
      if (static_cast<double>(hi) > upper) {
        if (!clipPolygon(*cur, *next, axis, upper, false)) return ClipResult::kOverflow;
        std::swap(cur, next);
      }
    }
    result = cur;
    return cur->n > 0 ? ClipResult::kNonEmpty : ClipResult::kEmpty;
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

  void makeLeaf(std::uint32_t nodeIndex, const EventList& events, int depth) {
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
  std::vector<std::uint8_t> side_;      ///< per triangle, valid during one split
  std::vector<Level> levels_;           ///< children's event lists, reused per depth
  std::vector<std::uint32_t> clipped_;  ///< triangles the current split clips
  EventLists newLeft_, newRight_;       ///< events of the straddling triangles' pieces
};

}  // namespace

KdTree buildSahKdTree(const std::vector<TriangleVertices>& triangles,
                      const SahKdTreeOptions& options) {
  KdTree tree;
  SahBuilder(triangles, options, tree).run();
  return tree;
}

}  // namespace tg
