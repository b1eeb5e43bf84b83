// Tests of the two kd-tree builders (SAH after Wald & Havran 2006, and the paper's fast builder
// for deforming objects) and of validateKdTree: structure and completeness on awkward inputs,
// statistics, determinism, tree quality, and closest hits against brute force.
#define BOOST_TEST_MODULE kdtree_build
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tracegraph/backend/KdTree.h"

namespace tg {
namespace {

using Triangles = std::vector<TriangleVertices>;

struct Builder {
  const char* name;
  std::function<KdTree(const Triangles&)> build;
};

const Builder kBuilders[] = {
    {"sah", [](const Triangles& t) { return buildSahKdTree(t); }},
    {"fast", [](const Triangles& t) { return buildFastKdTree(t); }},
};

/// n random triangles with centres in [0, 1]^3 and vertices within `size` of the centre.
Triangles randomSoup(std::size_t n, std::uint32_t seed, float size = 0.05f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(0.0f, 1.0f), off(-size, size);
  Triangles t(n);
  for (TriangleVertices& tri : t) {
    const Vec3f c{pos(rng), pos(rng), pos(rng)};
    tri.v0 = c + Vec3f{off(rng), off(rng), off(rng)};
    tri.v1 = c + Vec3f{off(rng), off(rng), off(rng)};
    tri.v2 = c + Vec3f{off(rng), off(rng), off(rng)};
  }
  return t;
}

/// Random triangles all lying in the plane z = 0 (a flat object: zero extent on z).
Triangles flatSoup(std::size_t n, std::uint32_t seed) {
  Triangles t = randomSoup(n, seed, 0.1f);
  for (TriangleVertices& tri : t) tri.v0.z = tri.v1.z = tri.v2.z = 0.0f;
  return t;
}

/// Unit quads (two triangles each) on every plane x = i, y = i, z = i (i = 0..g) of a g^3 grid:
/// every triangle lies in a plane both builders are likely to split at.
Triangles gridQuads(int g) {
  Triangles t;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int i = 0; i <= g; ++i)
      for (int j = 0; j < g; ++j)
        for (int k = 0; k < g; ++k) {
          Vec3f p[4];
          for (int q = 0; q < 4; ++q) {
            p[q][a] = static_cast<float>(i);
            p[q][b] = static_cast<float>(j + (q == 1 || q == 2));
            p[q][c] = static_cast<float>(k + (q >= 2));
          }
          t.push_back({p[0], p[1], p[2]});
          t.push_back({p[0], p[2], p[3]});
        }
  }
  return t;
}

/// A bumpy height field of g x g quads with shared vertices: rays aimed at vertices and edges
/// hit several triangles at the same t, exercising the tie rule.
Triangles heightField(int g, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> h(0.0f, 0.25f);
  std::vector<float> z(static_cast<std::size_t>((g + 1) * (g + 1)));
  for (float& v : z) v = h(rng);
  auto vertex = [&](int i, int j) {
    return Vec3f{static_cast<float>(i) / static_cast<float>(g),
                 static_cast<float>(j) / static_cast<float>(g),
                 z[static_cast<std::size_t>(i * (g + 1) + j)]};
  };
  Triangles t;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      t.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
      t.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
    }
  return t;
}

Box3f boundsOfValid(const Triangles& tris) {
  Box3f b;
  for (const TriangleVertices& t : tris) {
    if (isDegenerateTriangle(t.v0, t.v1, t.v2)) continue;
    b.extend(t.v0);
    b.extend(t.v1);
    b.extend(t.v2);
  }
  return b;
}

/// Checks the statistics against the node array (nodes, leaves, empty leaves, references, depth).
std::string checkStats(const KdTree& tree) {
  std::size_t leaves = 0, empty = 0, refs = 0, maxDepth = 0;
  std::vector<std::pair<std::uint32_t, std::size_t>> stack{{0u, 0u}};
  while (!stack.empty()) {
    const auto [index, depth] = stack.back();
    stack.pop_back();
    const KdNode& n = tree.nodes[index];
    if (n.isLeaf()) {
      ++leaves;
      empty += n.primCount() == 0;
      refs += n.primCount();
      maxDepth = std::max(maxDepth, depth);
    } else {
      stack.push_back({index + 1, depth + 1});
      stack.push_back({n.aboveChild(), depth + 1});
    }
  }
  std::ostringstream s;
  const BuildStats& st = tree.stats;
  if (st.nodes != tree.nodes.size())
    s << "nodes " << st.nodes << " != " << tree.nodes.size() << "; ";
  if (st.leaves != leaves) s << "leaves " << st.leaves << " != " << leaves << "; ";
  if (st.emptyLeaves != empty) s << "emptyLeaves " << st.emptyLeaves << " != " << empty << "; ";
  if (st.primReferences != refs)
    s << "primReferences " << st.primReferences << " != " << refs << "; ";
  if (st.maxDepth != maxDepth) s << "maxDepth " << st.maxDepth << " != " << maxDepth << "; ";
  if (maxDepth > static_cast<std::size_t>(kKdMaxDepth)) s << "deeper than kKdMaxDepth; ";
  return s.str();
}

std::size_t countDegenerate(const Triangles& tris) {
  std::size_t n = 0;
  for (const TriangleVertices& t : tris) n += isDegenerateTriangle(t.v0, t.v1, t.v2);
  return n;
}

/// Builds with both builders and checks validity, statistics and bounds.
void checkBoth(const Triangles& tris, const std::string& what) {
  for (const Builder& b : kBuilders) {
    BOOST_TEST_CONTEXT(b.name << " builder, " << what) {
      const KdTree tree = b.build(tris);
      BOOST_TEST(validateKdTree(tree, tris) == "");
      BOOST_TEST(checkStats(tree) == "");
      BOOST_TEST(tree.stats.degenerate == countDegenerate(tris));
      BOOST_TEST((tree.bounds == boundsOfValid(tris)));
    }
  }
}

/// Expected cost of a ray through the tree by the surface area heuristic (K_T = 1, K_I = 1.5):
/// inner nodes weigh K_T, leaves K_I per triangle, each by its cell's area over the root's.
double sahCost(const KdTree& tree) {
  struct Item {
    std::uint32_t node;
    Box3f cell;
  };
  const double rootArea = static_cast<double>(tree.bounds.area());
  double cost = 0.0;
  std::vector<Item> stack{{0u, tree.bounds}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    const KdNode& n = tree.nodes[it.node];
    const double p = static_cast<double>(it.cell.area()) / rootArea;
    if (n.isLeaf()) {
      cost += 1.5 * p * n.primCount();
    } else {
      cost += p;
      Box3f below = it.cell, above = it.cell;
      below.upper[n.axis()] = n.split();
      above.lower[n.axis()] = n.split();
      stack.push_back({it.node + 1, below});
      stack.push_back({n.aboveChild(), above});
    }
  }
  return cost;
}

struct TestRay {
  Vec3f origin, direction;
};

/// Rays from random points around [0, 1]^3 towards random points (or given targets) inside it.
std::vector<TestRay> randomRays(std::size_t n, std::uint32_t seed,
                                const std::vector<Vec3f>& targets = {}) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> outer(-0.5f, 1.5f), inner(0.0f, 1.0f);
  std::vector<TestRay> rays(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3f o{outer(rng), outer(rng), outer(rng)};
    Vec3f target{inner(rng), inner(rng), inner(rng)};
    if (!targets.empty() && i % 2 == 0) target = targets[rng() % targets.size()];
    Vec3f d = target - o;
    if (d == Vec3f{0.0f, 0.0f, 0.0f}) d = {0.0f, 0.0f, 1.0f};
    rays[i] = {o, d};
  }
  return rays;
}

/// Closest hit by testing every triangle, with the same tie rule as the traversal.
Hit bruteForce(const Triangles& tris, const TestRay& r) {
  const WatertightRay wt(r.origin, r.direction, 0.0f);
  Hit best;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const TriangleVertices& t = tris[i];
    TriangleHit th;
    const auto id = static_cast<std::uint32_t>(i);
    if (!intersectWatertight(wt, t.v0, t.v1, t.v2, best.t, th)) continue;
    if (!hitPrecedes(th.t, 0, id, best)) continue;
    best.t = th.t;
    best.primId = id;
    best.instanceId = 0;
  }
  return best;
}

/// Number of rays whose kd-tree closest hit differs from brute force (t or primId).
std::size_t countMismatches(const KdTree& tree, const Triangles& tris,
                            const std::vector<TestRay>& rays, std::string& firstMismatch) {
  std::size_t mismatches = 0;
  for (const TestRay& r : rays) {
    ObjectRay ray(r.origin, r.direction, 0.0f, kInfinity, 0, 0);
    Hit hit;
    TraversalContext ctx;
    intersectKdTree(tree, tris, ray, hit, ctx);
    const Hit expected = bruteForce(tris, r);
    if (hit.primId == expected.primId && (hit.t == expected.t || !expected.valid())) continue;
    if (mismatches++ == 0) {
      std::ostringstream s;
      s.precision(9);
      s << "origin " << r.origin.x << " " << r.origin.y << " " << r.origin.z << " direction "
        << r.direction.x << " " << r.direction.y << " " << r.direction.z << ": tree prim "
        << hit.primId << " t " << hit.t << ", brute force prim " << expected.primId << " t "
        << expected.t;
      firstMismatch = s.str();
    }
  }
  return mismatches;
}

}  // namespace

BOOST_AUTO_TEST_CASE(empty_input_gives_single_empty_leaf) {
  const Triangles none;
  for (const Builder& b : kBuilders) {
    BOOST_TEST_CONTEXT(b.name) {
      const KdTree tree = b.build(none);
      BOOST_TEST(tree.nodes.size() == 1u);
      BOOST_TEST(tree.nodes[0].isLeaf());
      BOOST_TEST(tree.nodes[0].primCount() == 0u);
      BOOST_TEST(tree.bounds.empty());
      BOOST_TEST(tree.stats.nodes == 1u);
      BOOST_TEST(tree.stats.leaves == 1u);
      BOOST_TEST(tree.stats.emptyLeaves == 1u);
      BOOST_TEST(validateKdTree(tree, none) == "");
      ObjectRay ray(Vec3f{0.0f, 0.0f, -1.0f}, Vec3f{0.0f, 0.0f, 1.0f}, 0.0f, kInfinity, 0, 0);
      Hit hit;
      TraversalContext ctx;
      BOOST_TEST(!intersectKdTree(tree, none, ray, hit, ctx));
    }
  }
}

// The validator itself: a hand-built tree, then one defect at a time.
BOOST_AUTO_TEST_CASE(validator_reports_defects) {
  // Two triangles in z = 0 that meet at the vertex (0.5, 0, 0), on the split plane x = 0.5: each
  // touches the other side's closed cell and must be referenced there.
  const Triangles tris = {{{0.0f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}},
                          {{0.5f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.0f}},
                          {{0.2f, 0.2f, 0.0f}, {0.4f, 0.4f, 0.0f}, {0.6f, 0.6f, 0.0f}}};
  KdTree good;
  good.bounds = Box3f({0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.0f});
  good.nodes = {KdNode::makeInner(0, 0.5f, 2), KdNode::makeLeaf(0, 2), KdNode::makeLeaf(2, 2)};
  good.primIndices = {0, 1, 0, 1};
  BOOST_TEST(validateKdTree(good, tris) == "");

  // Each defect must be reported, by a message naming it.
  auto expectFailure = [&](const KdTree& tree, const std::string& what,
                           const std::string& keyword) {
    BOOST_TEST_CONTEXT(what) {
      const std::string message = validateKdTree(tree, tris);
      BOOST_TEST(message.find(keyword) != std::string::npos, "message: '" << message << "'");
    }
  };
  KdTree t = good;
  t.nodes[2] = KdNode::makeLeaf(3, 1);  // triangle 0 only touches the right cell: still required
  expectFailure(t, "touching triangle missing", "not referenced");
  t = good;
  t.primIndices = {0, 1, 1, 1};
  expectFailure(t, "triangle referenced twice in a leaf", "twice");
  t = good;
  t.primIndices = {0, 1, 0, 2};
  expectFailure(t, "degenerate triangle referenced", "degenerate");
  t = good;
  t.primIndices = {0, 1, 0, 7};
  expectFailure(t, "triangle id out of range", "out of range");
  t = good;
  t.nodes[0] = KdNode::makeInner(0, 1.5f, 2);
  expectFailure(t, "split outside the cell", "outside cell");
  t = good;
  t.nodes[0] = KdNode::makeInner(0, 0.5f, 1);
  expectFailure(t, "above child is the below child", "does not follow");
  t = good;
  t.nodes.pop_back();
  expectFailure(t, "above child out of range", "out of range");
  t = good;
  t.nodes[2] = KdNode::makeLeaf(3, 2);
  expectFailure(t, "leaf range past primIndices", "exceeds primIndices");
  t = good;
  t.bounds = Box3f({0.0f, 0.0f, 0.0f}, {0.9f, 1.0f, 0.0f});
  expectFailure(t, "bounds not covering a triangle", "outside tree.bounds");
  t = good;
  t.nodes.push_back(KdNode::makeLeaf(0, 0));
  expectFailure(t, "unreachable node", "not reachable");
  t = good;
  t.nodes.clear();
  expectFailure(t, "no nodes", "no nodes");
  // A well-formed chain of inner nodes (depth-first: the chain, then its leaves from the deepest
  // up), one level deeper than kKdMaxDepth allows.
  auto chain = [&](int depth) {
    KdTree c = good;
    c.nodes.clear();
    for (int i = 0; i < depth; ++i)
      c.nodes.push_back(KdNode::makeInner(0, 0.5f, static_cast<std::uint32_t>(2 * depth - i)));
    for (int i = 0; i <= depth; ++i) c.nodes.push_back(KdNode::makeLeaf(0, 2));
    return c;
  };
  BOOST_TEST(validateKdTree(chain(kKdMaxDepth), tris) == "");
  const std::string deep = validateKdTree(chain(kKdMaxDepth + 1), tris);
  BOOST_TEST(deep.find("kKdMaxDepth") != std::string::npos, deep);
}

BOOST_AUTO_TEST_CASE(random_soups_are_valid) {
  for (const std::size_t n : {0u, 1u, 2u, 3u, 17u, 1000u, 20000u}) {
    checkBoth(randomSoup(n, 7u + static_cast<std::uint32_t>(n)), "soup of " + std::to_string(n));
  }
  // Large triangles overlap many cells: many straddling triangles and perfect splits.
  checkBoth(randomSoup(2000, 11, 0.4f), "soup of 2000 large triangles");
  // Far from the origin, where float spacing is coarse relative to the object.
  Triangles far = randomSoup(3000, 12);
  for (TriangleVertices& t : far)
    for (Vec3f* v : {&t.v0, &t.v1, &t.v2}) *v = *v * 3.0f + Vec3f{1.0e4f, -2.0e5f, 3.0e3f};
  checkBoth(far, "soup far from the origin");
}

BOOST_AUTO_TEST_CASE(flat_objects_are_valid) {
  checkBoth(flatSoup(1, 3), "one flat triangle");
  checkBoth(flatSoup(1000, 3), "1000 triangles in z = 0");
  // A flat grid: extent 0 on z, and every edge on a likely split plane.
  Triangles grid = gridQuads(4);
  Triangles plane;
  for (const TriangleVertices& t : grid)
    if (t.v0.z == 0.0f && t.v1.z == 0.0f && t.v2.z == 0.0f) plane.push_back(t);
  BOOST_TEST(plane.size() == 32u);
  checkBoth(plane, "flat grid of quads");
}

BOOST_AUTO_TEST_CASE(identical_triangles_are_valid) {
  const TriangleVertices t{{0.1f, 0.2f, 0.3f}, {0.9f, 0.25f, 0.35f}, {0.4f, 0.8f, 0.7f}};
  checkBoth(Triangles(1000, t), "1000 identical triangles");
  // Identical triangles mixed with a soup, and identical axis-aligned ones in a split plane.
  Triangles mixed = randomSoup(500, 5);
  mixed.insert(mixed.end(), 500, t);
  checkBoth(mixed, "identical triangles in a soup");
  const TriangleVertices flat{{0.0f, 0.0f, 0.5f}, {1.0f, 0.0f, 0.5f}, {0.0f, 1.0f, 0.5f}};
  Triangles stack = randomSoup(300, 6);
  stack.insert(stack.end(), 300, flat);
  checkBoth(stack, "identical triangles in the plane z = 0.5");
}

BOOST_AUTO_TEST_CASE(triangles_in_split_planes_are_valid) {
  for (const int g : {1, 2, 3, 6}) checkBoth(gridQuads(g), "grid of quads " + std::to_string(g));
  // Grid quads mixed with a soup, so that planes are chosen for other triangles too.
  Triangles mixed = gridQuads(3);
  for (TriangleVertices& t : mixed)
    for (Vec3f* v : {&t.v0, &t.v1, &t.v2}) *v = *v * (1.0f / 3.0f);
  const Triangles soup = randomSoup(2000, 9);
  mixed.insert(mixed.end(), soup.begin(), soup.end());
  checkBoth(mixed, "grid quads in a soup");
  checkBoth(heightField(40, 4), "height field");
}

BOOST_AUTO_TEST_CASE(degenerate_triangles_are_counted_and_left_out) {
  Triangles tris = randomSoup(500, 21);
  // Dyadic coordinates: the third point below is exactly on the line through p and q.
  const Vec3f p{0.25f, 0.25f, 0.25f}, q{0.5f, 0.375f, 0.3125f};
  std::vector<std::uint32_t> degenerate;
  for (int i = 0; i < 50; ++i) {
    degenerate.push_back(static_cast<std::uint32_t>(tris.size()));
    // A point, a repeated vertex, three collinear points.
    const Vec3f r = i % 3 == 0 ? p : (i % 3 == 1 ? q : p + (q - p) * 2.0f);
    tris.push_back({p, i % 3 == 0 ? p : q, r});
  }
  // A degenerate triangle far outside must not widen the bounds either.
  degenerate.push_back(static_cast<std::uint32_t>(tris.size()));
  tris.push_back({{50.0f, 50.0f, 50.0f}, {60.0f, 60.0f, 60.0f}, {70.0f, 70.0f, 70.0f}});
  checkBoth(tris, "soup with degenerate triangles");
  for (const Builder& b : kBuilders) {
    BOOST_TEST_CONTEXT(b.name) {
      const KdTree tree = b.build(tris);
      BOOST_TEST(tree.stats.degenerate == degenerate.size());
      std::size_t referenced = 0;
      for (const std::uint32_t prim : tree.primIndices)
        referenced += std::count(degenerate.begin(), degenerate.end(), prim);
      BOOST_TEST(referenced == 0u);
      BOOST_TEST(tree.bounds.upper.x < 2.0f);
    }
  }
  // Only degenerate triangles: an empty tree.
  const Triangles only(degenerate.size(), TriangleVertices{p, q, q});
  for (const Builder& b : kBuilders) {
    BOOST_TEST_CONTEXT(b.name) {
      const KdTree tree = b.build(only);
      BOOST_TEST(tree.nodes.size() == 1u);
      BOOST_TEST(tree.stats.degenerate == only.size());
      BOOST_TEST(tree.primIndices.empty());
      BOOST_TEST(validateKdTree(tree, only) == "");
    }
  }
}

BOOST_AUTO_TEST_CASE(options_are_honoured) {
  const Triangles soup = randomSoup(5000, 31);
  for (const int depth : {1, 3, 10}) {
    SahKdTreeOptions sah;
    sah.maxDepth = depth;
    const KdTree a = buildSahKdTree(soup, sah);
    BOOST_TEST(validateKdTree(a, soup) == "");
    BOOST_TEST(a.stats.maxDepth <= static_cast<std::size_t>(depth));
    FastKdTreeOptions fast;
    fast.maxDepth = depth;
    const KdTree b = buildFastKdTree(soup, fast);
    BOOST_TEST(validateKdTree(b, soup) == "");
    BOOST_TEST(b.stats.maxDepth <= static_cast<std::size_t>(depth));
  }
  SahKdTreeOptions deep;
  deep.maxDepth = 1000;
  BOOST_TEST(buildSahKdTree(soup, deep).stats.maxDepth <= static_cast<std::size_t>(kKdMaxDepth));
  // A huge leaf tolerance makes the root a leaf.
  FastKdTreeOptions coarse;
  coarse.leafSize = 100000;
  BOOST_TEST(buildFastKdTree(soup, coarse).nodes.size() == 1u);
  // Expensive intersections make the SAH tree deeper than cheap ones.
  SahKdTreeOptions cheap, expensive;
  cheap.intersectionCost = 0.2f;
  expensive.intersectionCost = 20.0f;
  BOOST_TEST(buildSahKdTree(soup, cheap).stats.nodes < buildSahKdTree(soup, expensive).stats.nodes);
}

// The fast builder's leaves may grow by leafSizeGrowth per level: a larger growth stops earlier.
BOOST_AUTO_TEST_CASE(fast_tree_leaf_tolerance_grows_with_depth) {
  const Triangles soup = randomSoup(20000, 41, 0.01f);
  FastKdTreeOptions flat, growing;
  flat.leafSizeGrowth = 0.0f;
  growing.leafSizeGrowth = 1.0f;
  const KdTree a = buildFastKdTree(soup, flat), b = buildFastKdTree(soup, growing);
  BOOST_TEST(validateKdTree(a, soup) == "");
  BOOST_TEST(validateKdTree(b, soup) == "");
  BOOST_TEST(b.stats.nodes < a.stats.nodes);
  BOOST_TEST(a.stats.maxDepth <= static_cast<std::size_t>(2.0 * std::log2(20000.0) + 4.0));
  // Every leaf is within its depth's tolerance, at the depth limit, or could not be separated.
  std::size_t oversized = 0;
  std::vector<std::pair<std::uint32_t, int>> stack{{0u, 0}};
  while (!stack.empty()) {
    const auto [index, depth] = stack.back();
    stack.pop_back();
    const KdNode& n = b.nodes[index];
    if (!n.isLeaf()) {
      stack.push_back({index + 1, depth + 1});
      stack.push_back({n.aboveChild(), depth + 1});
    } else if (static_cast<float>(n.primCount()) > 2.0f + static_cast<float>(depth)) {
      ++oversized;
    }
  }
  BOOST_TEST(oversized < b.stats.leaves / 10);
}

BOOST_AUTO_TEST_CASE(sah_tree_needs_fewer_triangle_tests_than_fast_tree) {
  const Triangles soup = randomSoup(20000, 51);
  const KdTree sah = buildSahKdTree(soup), fast = buildFastKdTree(soup);
  BOOST_TEST(sahCost(sah) < sahCost(fast));
  const std::vector<TestRay> rays = randomRays(20000, 52);
  std::uint64_t tests[2] = {0, 0};
  const KdTree* trees[2] = {&sah, &fast};
  for (int i = 0; i < 2; ++i) {
    TraversalContext ctx;
    for (const TestRay& r : rays) {
      ObjectRay ray(r.origin, r.direction, 0.0f, kInfinity, 0, 0);
      Hit hit;
      intersectKdTree(*trees[i], soup, ray, hit, ctx);
    }
    tests[i] = ctx.triangleTests;
  }
  BOOST_TEST_MESSAGE("triangle tests: sah " << tests[0] << ", fast " << tests[1]
                                            << "; SAH cost: sah " << sahCost(sah) << ", fast "
                                            << sahCost(fast));
  BOOST_TEST(tests[0] < tests[1]);
}

BOOST_AUTO_TEST_CASE(builds_are_deterministic) {
  for (const Triangles& tris : {randomSoup(5000, 61), gridQuads(4), heightField(30, 62)}) {
    for (const Builder& b : kBuilders) {
      BOOST_TEST_CONTEXT(b.name) {
        const KdTree x = b.build(tris), y = b.build(tris);
        BOOST_REQUIRE(x.nodes.size() == y.nodes.size());
        bool same = true;
        for (std::size_t i = 0; i < x.nodes.size(); ++i)
          same = same && x.nodes[i].bits == y.nodes[i].bits && x.nodes[i].flags == y.nodes[i].flags;
        BOOST_TEST(same);
        BOOST_TEST(x.primIndices == y.primIndices);
        BOOST_TEST((x.bounds == y.bounds));
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(closest_hits_match_brute_force) {
  const Triangles soup = randomSoup(3000, 71, 0.08f);
  const Triangles field = heightField(24, 72);
  std::vector<Vec3f> vertices;
  for (const TriangleVertices& t : field) vertices.push_back(t.v0);
  Triangles grid = gridQuads(4);
  for (TriangleVertices& t : grid)
    for (Vec3f* v : {&t.v0, &t.v1, &t.v2}) *v = *v * 0.25f;
  std::vector<Vec3f> gridPoints;
  for (const TriangleVertices& t : grid) gridPoints.push_back((t.v0 + t.v2) * 0.5f);

  struct Case {
    const char* name;
    const Triangles* tris;
    const std::vector<Vec3f>* targets;
    std::size_t rays;
  };
  const std::vector<Vec3f> none;
  const Case cases[] = {{"soup", &soup, &none, 20000},
                        {"height field", &field, &vertices, 5000},
                        {"grid quads", &grid, &gridPoints, 5000}};
  for (const Case& c : cases) {
    const std::vector<TestRay> rays = randomRays(c.rays, 73, *c.targets);
    for (const Builder& b : kBuilders) {
      BOOST_TEST_CONTEXT(b.name << " builder, " << c.name) {
        const KdTree tree = b.build(*c.tris);
        std::string first;
        const std::size_t mismatches = countMismatches(tree, *c.tris, rays, first);
        BOOST_TEST(mismatches == 0u, "first mismatch: " << first);
      }
    }
  }
}

// Reports build times (not asserted: machines differ); useful when tuning the builders.
BOOST_AUTO_TEST_CASE(build_times) {
  for (const std::size_t n : {10000u, 100000u}) {
    const Triangles soup = randomSoup(n, 81, 0.02f);
    for (const Builder& b : kBuilders) {
      const auto start = std::chrono::steady_clock::now();
      const KdTree tree = b.build(soup);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      BOOST_TEST_MESSAGE(b.name << " build of " << n << " triangles: " << ms << " ms, "
                                << tree.stats.nodes << " nodes, " << tree.stats.primReferences
                                << " references, depth " << tree.stats.maxDepth);
      BOOST_TEST(tree.stats.primReferences >= n);
    }
  }
}

}  // namespace tg
