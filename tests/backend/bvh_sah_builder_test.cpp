// The binned-SAH BVH4 builder on its own: tree structure (every primitive in exactly one leaf,
// tight boxes, leaf sizes), awkward inputs (no primitive, one, equal centroids, point boxes),
// the same tree whatever the thread count on the parallel paths (subtree tasks, subtrees
// numbered on their own thread, the SAH cost gathered on the way), the listener told of every
// node after its children (and the eight-wide collapse solved that way), chunked partitions
// giving the tree of serial ones, and the SSE bin mapping agreeing with the scalar one the
// partition uses.
#define BOOST_TEST_MODULE bvh_sah_builder
#include <boost/test/unit_test.hpp>

#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include "Bvh4TreeWalk.h"
#include "Bvh8Twin.h"
#include "BvhBinning.h"
#include "BvhBuilder.h"

using namespace tg;
using namespace tg::detail;

namespace {

using TreeCheck = tg::test::Bvh4TreeCheck;
using tg::test::sameBox;

/// Builds over `boxes` and checks the result; returns the tree description.
TreeCheck buildAndCheck(const std::vector<Box3f>& boxes, const BvhBuildOptions& options,
                        bool allowBigLeaves, BvhPrimArray& prims, BvhBuildResult& out) {
  prims.clear();
  for (std::size_t i = 0; i < boxes.size(); ++i)
    prims.push_back(BvhPrim::make(boxes[i], static_cast<std::uint32_t>(i)));
  buildBvh4(prims, options, out);
  TreeCheck c;
  if (boxes.empty()) {
    if (!out.nodes.empty()) c.fail("nodes for an empty input");
    return c;
  }
  // The primitives are a permutation of the input.
  std::vector<int> ids(boxes.size(), 0);
  for (const BvhPrim& p : prims) {
    if (p.id >= boxes.size() || !sameBox(p.box(), boxes[p.id])) c.fail("primitive changed");
    if (p.id < boxes.size()) ++ids[p.id];
  }
  for (const int n : ids)
    if (n != 1) c.fail("primitives are not a permutation of the input");
  std::vector<int> seen(prims.size(), 0);
  std::vector<Box3f> primBoxes;
  for (const BvhPrim& p : prims) primBoxes.push_back(p.box());
  const Box3f all = tg::test::walkBvh4(
      out.nodes, 0, 0, primBoxes,
      {options.maxLeafSize, allowBigLeaves, tg::test::SlotBoxRule::Exact}, seen, c);
  for (const int n : seen)
    if (n != 1) c.fail("a primitive is not in exactly one leaf");
  if (!sameBox(all, out.bounds)) c.fail("result bounds differ from the root's slots");
  if (c.leaves != out.leaves) c.fail("leaf count differs from the walk");
  if (c.maxDepth != out.maxDepth) c.fail("depth differs from the walk");
  // The SAH cost gathered during the build is the walk's, summed in another order.
  const double walked = bvh4SahCost(out.nodes, options.traversalCost, options.intersectionCost);
  if (!(std::abs(out.sahCost - walked) <= 1e-9 * walked)) c.fail("gathered SAH cost is wrong");
  return c;
}

std::vector<Box3f> randomBoxes(std::size_t n, std::uint32_t seed, float side, float size) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(0.0f, side), ext(0.0f, size);
  std::vector<Box3f> boxes;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3f lo{pos(rng), pos(rng), pos(rng)};
    boxes.push_back({lo, lo + Vec3f{ext(rng), ext(rng), ext(rng)}});
  }
  return boxes;
}

}  // namespace

BOOST_AUTO_TEST_CASE(random_boxes_give_valid_trees_in_both_modes) {
  for (const bool allAxes : {true, false}) {
    BvhBuildOptions options;
    options.allAxes = allAxes;
    options.bins = allAxes ? 32 : 16;
    options.maxLeafSize = allAxes ? 4 : 2;
    for (const std::size_t n : {2, 3, 5, 17, 100, 1000, 20000}) {
      BvhPrimArray prims;
      BvhBuildResult out;
      const TreeCheck c =
          buildAndCheck(randomBoxes(n, 7 + static_cast<std::uint32_t>(n), 100.0f, 2.0f), options,
                        false, prims, out);
      BOOST_TEST(c.errors == 0u, "n=" << n << " allAxes=" << allAxes << ": " << c.firstError);
      BOOST_TEST(out.maxDepth <= static_cast<std::size_t>(kBvh4MaxDepth));
    }
  }
}

BOOST_AUTO_TEST_CASE(awkward_inputs) {
  BvhBuildOptions options;
  BvhPrimArray prims;
  BvhBuildResult out;

  TreeCheck c = buildAndCheck({}, options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);
  BOOST_TEST(out.leaves == 0u);

  const Box3f one{{1, 2, 3}, {4, 5, 6}};
  c = buildAndCheck({one}, options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);
  BOOST_TEST(out.leaves == 1u);
  BOOST_TEST(out.nodes.size() == 1u);

  // All boxes equal: no plane separates them, so median splits bound the leaves.
  c = buildAndCheck(std::vector<Box3f>(100, one), options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);

  // Point boxes at one place, and points along a line (zero area everywhere).
  c = buildAndCheck(std::vector<Box3f>(50, Box3f{{1, 1, 1}, {1, 1, 1}}), options, false, prims,
                    out);
  BOOST_TEST(c.errors == 0u, c.firstError);
  std::vector<Box3f> line;
  for (int i = 0; i < 300; ++i) {
    const Vec3f p{static_cast<float>(i), 0.0f, 0.0f};
    line.push_back({p, p});
  }
  c = buildAndCheck(line, options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);

  // Equal centroids on two axes, spread on the third: only one axis can be binned.
  std::vector<Box3f> column;
  for (int i = 0; i < 200; ++i)
    column.push_back({{-1.0f, -1.0f, static_cast<float>(i)}, {1.0f, 1.0f, i + 0.5f}});
  for (const bool allAxes : {true, false}) {
    options.allAxes = allAxes;
    c = buildAndCheck(column, options, false, prims, out);
    BOOST_TEST(c.errors == 0u, c.firstError);
  }
}

BOOST_AUTO_TEST_CASE(two_clusters_are_separated_at_the_root) {
  // Two far-apart clusters: any SAH split puts them on different sides, so no root slot may
  // hold primitives of both.
  std::vector<Box3f> boxes = randomBoxes(500, 3, 10.0f, 1.0f);
  for (Box3f b : randomBoxes(500, 4, 10.0f, 1.0f)) {
    b.lower.y += 1000.0f;
    b.upper.y += 1000.0f;
    boxes.push_back(b);
  }
  for (const bool allAxes : {true, false}) {
    BvhBuildOptions options;
    options.allAxes = allAxes;
    BvhPrimArray prims;
    BvhBuildResult out;
    const TreeCheck c = buildAndCheck(boxes, options, false, prims, out);
    BOOST_TEST(c.errors == 0u, c.firstError);
    for (int s = 0; s < 4; ++s) {
      if (out.nodes[0].child[s] == kInvalidId) continue;
      const Box3f slot = out.nodes[0].slotBounds(s);
      BOOST_TEST((slot.upper.y < 100.0f || slot.lower.y > 900.0f), "root slot " << s);
    }
  }
}

BOOST_AUTO_TEST_CASE(trees_do_not_depend_on_the_thread_count) {
  const std::vector<Box3f> boxes = randomBoxes(60000, 11, 200.0f, 3.0f);
  for (const bool allAxes : {true, false}) {
    BvhBuildOptions options;
    options.allAxes = allAxes;
    options.parallelThreshold = 512;  // the parallel binning and subtree tasks run
    BvhPrimArray prims[2];
    BvhBuildResult out[2];
    TreeCheck c[2];
    tbb::task_arena(1).execute(
        [&] { c[0] = buildAndCheck(boxes, options, false, prims[0], out[0]); });
    tbb::task_arena(2).execute(
        [&] { c[1] = buildAndCheck(boxes, options, false, prims[1], out[1]); });
    BOOST_TEST(c[0].errors == 0u, c[0].firstError);
    BOOST_TEST(c[1].errors == 0u, c[1].firstError);
    BOOST_TEST((c[0].shape == c[1].shape));
    bool sameOrder = prims[0].size() == prims[1].size();
    for (std::size_t k = 0; sameOrder && k < prims[0].size(); ++k)
      sameOrder = prims[0][k].id == prims[1][k].id;
    BOOST_TEST(sameOrder);
    BOOST_TEST(bvh4SahCost(out[0].nodes, 1.0, 1.0) == bvh4SahCost(out[1].nodes, 1.0, 1.0));
    // Subtrees report their SAH sums in slot order, whichever thread built them.
    BOOST_TEST(out[0].sahCost == out[1].sahCost);
  }
}

BOOST_AUTO_TEST_CASE(the_callers_bounds_give_the_same_tree) {
  // BvhAccel passes the bounds it gathered while making the primitives; the tree must be the
  // one the builder's own pass over them gives, node for node and primitive for primitive.
  // Boxes at and around the origin put zeros of both signs into the bounds.
  std::vector<Box3f> boxes = randomBoxes(20000, 17, 50.0f, 2.0f);
  boxes.push_back({{-0.0f, -1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}});
  boxes.push_back({{0.0f, -0.0f, -0.0f}, {1.0f, 0.0f, 0.0f}});
  BvhPrimBounds known;
  for (const Box3f& b : boxes) {
    known.bounds.extend(b);
    known.centroids.extend(b.lower + b.upper);
  }
  for (const bool allAxes : {true, false}) {
    BvhBuildOptions options;
    options.allAxes = allAxes;
    options.parallelThreshold = 1024;
    BvhPrimArray prims[2];
    BvhBuildResult out[2];
    for (int k = 0; k < 2; ++k) {
      for (std::size_t i = 0; i < boxes.size(); ++i)
        prims[k].push_back(BvhPrim::make(boxes[i], static_cast<std::uint32_t>(i)));
      tbb::task_arena(1).execute(
          [&] { buildBvh4(prims[k], options, out[k], k == 0 ? nullptr : &known); });
    }
    BOOST_TEST(out[0].nodes.size() == out[1].nodes.size());
    BOOST_TEST(std::memcmp(out[0].nodes.data(), out[1].nodes.data(),
                           out[0].nodes.size() * sizeof(Bvh4Node)) == 0);
    bool sameOrder = prims[0].size() == prims[1].size();
    for (std::size_t i = 0; sameOrder && i < prims[0].size(); ++i)
      sameOrder = prims[0][i].id == prims[1][i].id;
    BOOST_TEST(sameOrder);
    BOOST_TEST(sameBox(out[0].bounds, out[1].bounds));
    BOOST_TEST(out[0].sahCost == out[1].sahCost);
  }
}

/// Records what a build tells its listener: the order of the nodes and a copy of each as it
/// was when told.
class RecordingListener final : public Bvh4BuildListener {
 public:
  void nodeBuilt(const Bvh4NodeArray& nodes, std::uint32_t index) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    order.push_back(index);
    seen.push_back(nodes[index]);
  }
  std::vector<std::uint32_t> order;
  std::vector<Bvh4Node> seen;

 private:
  std::mutex mutex_;
};

BOOST_AUTO_TEST_CASE(listeners_hear_of_every_node_once_after_its_children) {
  // The eight-wide collapse solves each node as the builder reports it, and needs its children
  // solved and the node final by then: on the paths of two threads (nodes numbered in the tree
  // and subtrees numbered on their own thread) and of one, and for a root that is a leaf.
  const std::vector<Box3f> boxes = randomBoxes(30000, 23, 200.0f, 3.0f);
  const std::vector<Box3f> one = {Box3f{{0, 0, 0}, {1, 1, 1}}};
  for (const int threads : {1, 2}) {
    for (const std::vector<Box3f>* input : {&boxes, &one}) {
      BvhBuildOptions options;
      options.parallelThreshold = 512;
      BvhPrimArray prims;
      for (std::size_t i = 0; i < input->size(); ++i)
        prims.push_back(BvhPrim::make((*input)[i], static_cast<std::uint32_t>(i)));
      BvhBuildResult out;
      RecordingListener listener;
      tbb::task_arena(threads).execute([&] { buildBvh4(prims, options, out, nullptr, &listener); });
      const std::size_t n = out.nodes.size();
      BOOST_TEST_REQUIRE(listener.order.size() == n);
      std::vector<int> position(n, -1);
      bool inRange = true, finalWhenTold = true;
      for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t i = listener.order[k];
        if (i >= n || position[i] >= 0) {
          inRange = false;
          break;
        }
        position[i] = static_cast<int>(k);
        finalWhenTold =
            finalWhenTold && std::memcmp(&listener.seen[k], &out.nodes[i], sizeof(Bvh4Node)) == 0;
      }
      BOOST_TEST_REQUIRE(inRange, "a node told of twice or outside the tree");
      BOOST_TEST(finalWhenTold);
      int childrenFirst = 0, inner = 0;
      for (std::size_t i = 0; i < n; ++i)
        for (int s = 0; s < 4; ++s)
          if (out.nodes[i].isInner(s)) {
            ++inner;
            childrenFirst += position[out.nodes[i].child[s]] < position[i] ? 1 : 0;
          }
      BOOST_TEST(childrenFirst == inner);
      BOOST_TEST((input == &one ? inner == 0 : inner > 1000));
    }
  }
}

BOOST_AUTO_TEST_CASE(a_plan_solved_during_the_build_gives_the_wide_tree_of_one_solved_after) {
  // Bvh8CollapsePlan as the builder's listener, on two threads, against the plan solved over the
  // finished tree: the same eight-wide nodes, bit for bit, and the same subtree entries.
  const std::vector<Box3f> boxes = randomBoxes(40000, 29, 300.0f, 2.0f);
  BvhBuildOptions options;
  options.parallelThreshold = 1024;
  BvhPrimArray prims;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    prims.push_back(BvhPrim::make(boxes[i], static_cast<std::uint32_t>(i)));
  BvhBuildResult out;
  Bvh8CollapsePlan duringBuild;
  duringBuild.reset(prims.size());
  tbb::task_arena(2).execute([&] { buildBvh4(prims, options, out, nullptr, &duringBuild); });
  Bvh8NodeArray wide[2];
  std::vector<Bvh8Entry> entries[2];
  buildBvh8(out.nodes, duringBuild, wide[0], &entries[0]);
  buildBvh8(out.nodes, wide[1], &entries[1]);
  BOOST_TEST_REQUIRE(wide[0].size() == wide[1].size());
  BOOST_TEST(wide[0].size() > out.nodes.size() / 4);
  BOOST_TEST(std::memcmp(wide[0].data(), wide[1].data(), wide[0].size() * sizeof(Bvh8Node)) == 0);
  BOOST_TEST_REQUIRE(entries[0].size() == entries[1].size());
  BOOST_TEST(!entries[0].empty());
  bool sameEntries = true;
  for (std::size_t k = 0; k < entries[0].size(); ++k)
    sameEntries = sameEntries && entries[0][k].bvh4Node == entries[1][k].bvh4Node &&
                  entries[0][k].wideNode == entries[1][k].wideNode;
  BOOST_TEST(sameEntries);
}

BOOST_AUTO_TEST_CASE(the_programme_solved_eight_budgets_at_a_time_gives_the_same_wide_tree) {
  // Bvh8CollapsePlan solves the budgets in AVX2 lanes where the CPU runs AVX2: the same
  // eight-wide nodes, bit for bit, as one budget at a time. A grid of equal cubes gives equal
  // spreads over different budgets, which both must break alike (the first budget wins); random
  // boxes of two sizes give the rest.
  std::vector<Box3f> boxes = randomBoxes(20000, 31, 300.0f, 2.0f);
  const std::vector<Box3f> large = randomBoxes(300, 37, 300.0f, 60.0f);
  boxes.insert(boxes.end(), large.begin(), large.end());
  for (int x = 0; x < 24; ++x)
    for (int y = 0; y < 24; ++y)
      for (int z = 0; z < 24; ++z) {
        const Vec3f corner{400.0f + 2.0f * x, 2.0f * y, 2.0f * z};
        boxes.push_back({corner, corner + Vec3f{1.0f, 1.0f, 1.0f}});
      }
  BvhPrimArray prims;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    prims.push_back(BvhPrim::make(boxes[i], static_cast<std::uint32_t>(i)));
  BvhBuildResult out;
  buildBvh4(prims, BvhBuildOptions{}, out);
  Bvh8CollapsePlan plans[2];
  plans[0].setVectorSolve(false);
  BOOST_TEST(!plans[0].vectorSolve());
  if (!plans[1].vectorSolve()) {
    BOOST_TEST_MESSAGE("no AVX2 on this CPU: both plans solve one budget at a time");
  }
  Bvh8NodeArray wide[2];
  for (int k = 0; k < 2; ++k) {
    plans[k].solveTree(out.nodes);
    buildBvh8(out.nodes, plans[k], wide[k]);
  }
  BOOST_TEST_REQUIRE(wide[0].size() == wide[1].size());
  BOOST_TEST(wide[0].size() > out.nodes.size() / 4);
  BOOST_TEST(std::memcmp(wide[0].data(), wide[1].data(), wide[0].size() * sizeof(Bvh8Node)) == 0);
}

BOOST_AUTO_TEST_CASE(chunked_partitions_give_the_serial_tree) {
  // Large ranges are partitioned chunk by chunk, and the misplaced primitives trade places
  // afterwards. That changes the order within a side, never the sides: the tree must be the
  // one of serial partitions, with the same primitives in every leaf. Small chunks give many
  // runs of misplaced primitives on both sides.
  const std::vector<Box3f> boxes = randomBoxes(30000, 13, 200.0f, 3.0f);
  // Ids of every leaf, each leaf's sorted, depth first from the root (node numbers depend on
  // which thread took a number first; the walk does not).
  const auto leafIds = [](const BvhBuildResult& out, const BvhPrimArray& prims) {
    std::vector<std::uint32_t> ids;
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
      const Bvh4Node& node = out.nodes[stack.back()];
      stack.pop_back();
      for (int s = 0; s < 4; ++s) {
        if (node.child[s] == kInvalidId) continue;
        if (node.count[s] == 0) {
          stack.push_back(node.child[s]);
          continue;
        }
        const std::size_t first = ids.size();
        for (std::uint32_t k = 0; k < node.count[s]; ++k)
          ids.push_back(prims[node.child[s] + k].id);
        std::sort(ids.begin() + static_cast<std::ptrdiff_t>(first), ids.end());
      }
    }
    return ids;
  };
  for (const bool allAxes : {true, false}) {
    BvhBuildOptions options;
    options.allAxes = allAxes;
    BvhPrimArray prims[2];
    BvhBuildResult out[2];
    TreeCheck c[2];
    options.partitionChunk = boxes.size();  // every partition serial
    c[0] = buildAndCheck(boxes, options, false, prims[0], out[0]);
    options.partitionChunk = 777;
    c[1] = buildAndCheck(boxes, options, false, prims[1], out[1]);
    BOOST_TEST(c[0].errors == 0u, c[0].firstError);
    BOOST_TEST(c[1].errors == 0u, c[1].firstError);
    BOOST_TEST((c[0].shape == c[1].shape));
    BOOST_TEST((leafIds(out[0], prims[0]) == leafIds(out[1], prims[1])));
    BOOST_TEST(out[0].sahCost == out[1].sahCost);
  }
}

BOOST_AUTO_TEST_CASE(pairs_split_only_when_the_sah_says_so) {
  // Ranges of two take their split without binning; it must be the one binning gives.
  BvhBuildOptions options;
  BvhPrimArray prims;
  BvhBuildResult out;
  // Two small boxes far apart: two leaves, the smaller centroid on the first axis in slot 0.
  const Box3f far{{10, 0, 0}, {11, 1, 1}}, near{{0, 0, 0}, {1, 1, 1}};
  TreeCheck c = buildAndCheck({far, near}, options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);
  BOOST_TEST(out.leaves == 2u);
  BOOST_TEST(sameBox(out.nodes[0].slotBounds(0), near));
  BOOST_TEST(sameBox(out.nodes[0].slotBounds(1), far));
  // Two large overlapping boxes: testing both costs less than a node, so one leaf of two.
  const std::vector<Box3f> overlapping{{{0, 0, 0}, {10, 10, 10}}, {{1, 1, 1}, {10, 10, 10}}};
  c = buildAndCheck(overlapping, options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);
  BOOST_TEST(out.leaves == 1u);
  // Unless leaves hold one primitive at most, on either binning mode.
  options.maxLeafSize = 1;
  for (const bool allAxes : {true, false}) {
    options.allAxes = allAxes;
    c = buildAndCheck(overlapping, options, false, prims, out);
    BOOST_TEST(c.errors == 0u, c.firstError);
    BOOST_TEST(out.leaves == 2u);
  }
}

BOOST_AUTO_TEST_CASE(primitive_loads_clear_the_id_lane) {
  // In memory, lane 3 of the lower corner is the id; read as a float it is a denormal, which
  // would slow every centroid sum down, so the load clears it.
  const BvhPrim p = BvhPrim::make({{1, 2, 3}, {4, 5, 6}}, 12345u);
  alignas(16) float lo[4], hi[4];
  _mm_store_ps(lo, primLower(p));
  _mm_store_ps(hi, primUpper(p));
  BOOST_TEST(std::bit_cast<std::uint32_t>(lo[3]) == 0u);
  BOOST_TEST(std::bit_cast<std::uint32_t>(hi[3]) == 0u);
  BOOST_TEST((lo[0] == 1.0f && lo[1] == 2.0f && lo[2] == 3.0f));
  BOOST_TEST((hi[0] == 4.0f && hi[1] == 5.0f && hi[2] == 6.0f));
}

BOOST_AUTO_TEST_CASE(sse_bins_equal_scalar_bins) {
  // Single-axis binning uses the scalar binOf and the partition the SSE mapping; they must agree
  // exactly, NaN and overflowing products included.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> any(-1e6f, 1e6f);
  const float origin[3] = {-3.5f, 0.0f, 1e5f};
  const float scale[3] = {0.37f, 31.99f, 1e-3f};
  const int bins = 32;
  const BinMapping map{_mm_setr_ps(origin[0], origin[1], origin[2], 0.0f),
                       _mm_setr_ps(scale[0], scale[1], scale[2], 0.0f),
                       _mm_set1_ps(static_cast<float>(bins - 1))};
  std::vector<Box3f> boxes;
  for (int i = 0; i < 10000; ++i) {
    const Vec3f lo{any(rng), any(rng), any(rng)};
    boxes.push_back({lo, lo + Vec3f{1.0f, 2.0f, 3.0f}});
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  boxes.push_back({{nan, inf, -inf}, {nan, inf, -inf}});
  boxes.push_back({{3e38f, -3e38f, 0.0f}, {3e38f, -3e38f, 0.0f}});
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const BvhPrim p = BvhPrim::make(boxes[i], static_cast<std::uint32_t>(i));
    alignas(16) std::int32_t b[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(b), map.bins(primLower(p), primUpper(p)));
    for (int a = 0; a < 3; ++a) {
      const int scalar = binOf(p.lower[a] + p.upper[a], origin[a], scale[a], bins);
      if (b[a] != scalar || scalar < 0 || scalar >= bins) ++mismatches;
    }
  }
  BOOST_TEST(mismatches == 0u);
}
