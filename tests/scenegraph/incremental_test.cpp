// Hard case 20: for every frame of an animation with random edits, the hits of the
// incrementally synced scene equal those of a scene built from scratch on the same graph
// state (classification changes speed, never pixels).
#define BOOST_TEST_MODULE incremental
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cstdlib>

#include "GraphTestUtil.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/nodes/KeyframeDeformer.h"
#include "tracegraph/nodes/MorphDeformer.h"
#include "tracegraph/nodes/OrientationInterpolator.h"
#include "tracegraph/nodes/PositionInterpolator.h"
#include "tracegraph/nodes/Switch.h"
#include "tracegraph/nodes/TimeSensor.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {

/// A random graph with animated, edited, shared and deforming parts, and the handles needed
/// to edit it.
struct RandomGraph {
  std::mt19937 rng;
  ref_ptr<Separator> root = Separator::create();
  ref_ptr<TimeSensor> clock = TimeSensor::create();
  std::vector<ref_ptr<Group>> groups;  // every group (Separators, Groups, Switches)
  std::vector<ref_ptr<Switch>> switches;
  std::vector<ref_ptr<Transform>> freeTransforms;  // not driven: edited by hand
  std::vector<ref_ptr<Mesh>> freeMeshes;           // not driven: edited by hand
  std::vector<ref_ptr<Material>> materials;
  std::vector<ref_ptr<Node>> keep;  // keeps removed nodes alive for reuse

  explicit RandomGraph(unsigned seed) : rng(seed) {
    clock->loop.setValue(true);
    clock->cycleInterval.setValue(2.0);
    groups.push_back(root);
    for (int i = 0; i < 6; ++i) root->addChild(makeSubtree(0));
  }

  float uni(float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); }
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); }
  Vec3f randomPoint(float s) { return {uni(-s, s), uni(-s, s), uni(-s, s)}; }

  ref_ptr<Mesh> makeMesh() {
    const Vec3f c = randomPoint(1.0f);
    const Vec3f h(uni(0.2f, 0.8f), uni(0.2f, 0.8f), uni(0.2f, 0.8f));
    ref_ptr<Mesh> m = makeBox(c - h, c + h);
    keep.push_back(m);
    return m;
  }

  ref_ptr<Transform> makeTransform(int depth) {
    auto t = Transform::create();
    t->translation.setValue(randomPoint(4.0f / float(depth + 1)));
    t->rotation.setValue(Rotation{randomPoint(1.0f), uni(-3.0f, 3.0f)});
    t->scale.setValue({uni(0.6f, 1.4f), uni(0.6f, 1.4f), uni(0.6f, 1.4f)});
    keep.push_back(t);
    const int kind = pick(3);
    if (kind == 0) {
      auto p = PositionInterpolator::create();
      p->key.setValues({0.0f, 0.5f, 1.0f});
      const Vec3f a = t->translation.getValue();
      p->keyValue.setValues({a, a + randomPoint(1.0f), a});
      p->set_fraction.connectFrom(clock->fraction_changed);
      t->translation.connectFrom(p->value_changed);
    } else if (kind == 1) {
      auto o = OrientationInterpolator::create();
      o->key.setValues({0.0f, 1.0f});
      o->keyValue.setValues({Rotation{{0, 1, 0}, 0.0f}, Rotation{randomPoint(1.0f), 3.0f}});
      o->set_fraction.connectFrom(clock->fraction_changed);
      t->rotation.connectFrom(o->value_changed);
    } else {
      freeTransforms.push_back(t);
    }
    return t;
  }

  ref_ptr<Node> makeSubtree(int depth) {
    const int kind = depth >= 3 ? pick(3) : pick(7);
    switch (kind) {
      case 0: {
        ref_ptr<Mesh> m = makeMesh();
        const int d = pick(6);
        if (d == 0) {
          auto k = KeyframeDeformer::create();
          std::vector<Vec3f> keys = m->points.getValues();
          for (const Vec3f& p : m->points.getValues()) keys.push_back(p * 1.3f + Vec3f(0, 0.2f, 0));
          k->times.setValues({0.0f, 1.0f});
          k->keyPoints.setValues(keys);
          k->loop.setValue(true);
          k->drive(*m);
        } else if (d == 1) {
          auto morph = MorphDeformer::create();
          morph->basePoints.setValues(m->points.getValues());
          std::vector<Vec3f> target;
          for (const Vec3f& p : m->points.getValues()) target.push_back(p + randomPoint(0.3f));
          morph->targets.setValues(target);
          morph->weights.setValues({0.5f});
          morph->drive(*m);
        } else {
          freeMeshes.push_back(m);
        }
        return m;
      }
      case 1:
        return makeTransform(depth);
      case 2: {
        auto mat = Material::create();
        mat->diffuseColor.setValue({uni(0, 1), uni(0, 1), uni(0, 1)});
        materials.push_back(mat);
        keep.push_back(mat);
        return mat;
      }
      case 3:
      case 4: {
        ref_ptr<Group> g = kind == 3 ? ref_ptr<Group>(Separator::create()) : Group::create();
        const int n = 2 + pick(4);
        for (int i = 0; i < n; ++i) g->addChild(makeSubtree(depth + 1));
        groups.push_back(g);
        keep.push_back(g);
        return g;
      }
      case 5: {
        auto s = Switch::create();
        for (int i = 0; i < 3; ++i) s->addChild(makeSubtree(depth + 1));
        s->whichChild.setValue(pick(4) - 1);
        switches.push_back(s);
        groups.push_back(s);
        keep.push_back(s);
        return s;
      }
      default: {
        // DEF/USE: reuse an existing group or mesh if one is there.
        if (groups.size() > 1 && pick(2) == 0) return groups[1 + pick(int(groups.size()) - 1)];
        if (!freeMeshes.empty()) return freeMeshes[pick(int(freeMeshes.size()))];
        return makeMesh();
      }
    }
  }

  /// A few random edits of every kind the sync distinguishes.
  void edit() {
    const int edits = pick(4);
    for (int e = 0; e < edits; ++e) {
      switch (pick(9)) {
        case 0:
        case 1:
          if (!freeTransforms.empty()) {
            Transform& t = *freeTransforms[pick(int(freeTransforms.size()))];
            t.translation.setValue(t.translation.getValue() + randomPoint(0.3f));
          }
          break;
        case 2:
          if (!switches.empty())
            switches[pick(int(switches.size()))]->whichChild.setValue(pick(5) - 2);
          break;
        case 3:
          if (!materials.empty())
            materials[pick(int(materials.size()))]->diffuseColor.setValue({uni(0, 1), 0.5f, 0.5f});
          break;
        case 4: {  // move a child elsewhere (may be rejected as a cycle)
          Group& from = *groups[pick(int(groups.size()))];
          if (from.numChildren() < 2) break;
          const std::size_t i = std::size_t(pick(int(from.numChildren())));
          ref_ptr<Node> child(from.child(i));
          Group& to = *groups[pick(int(groups.size()))];
          try {
            to.addChild(child);
            from.removeChild(i);
          } catch (const Error&) {
          }
          break;
        }
        case 5:
          if (!freeMeshes.empty()) {
            Mesh& m = *freeMeshes[pick(int(freeMeshes.size()))];
            m.points.edit([this](std::vector<Vec3f>& p) { p[0] += randomPoint(0.2f); });
          }
          break;
        case 6:
          if (!freeMeshes.empty()) {  // topology: drop or restore the last triangle
            Mesh& m = *freeMeshes[pick(int(freeMeshes.size()))];
            std::vector<std::int32_t> idx = m.indices.getValues();
            if (idx.size() == 36)
              idx.resize(33);
            else
              idx = makeBox({0, 0, 0}, {1, 1, 1})->indices.getValues();
            m.indices.setValues(idx);
          }
          break;
        case 7: {  // new subtree
          Group& g = *groups[pick(int(groups.size()))];
          try {  // the new subtree may reuse an ancestor of g: rejected as a cycle
            g.insertChild(std::size_t(pick(int(g.numChildren()) + 1)), makeSubtree(2));
          } catch (const Error&) {
          }
          break;
        }
        default: {  // share an existing group somewhere else (DEF/USE), or unshare it
          Group& g = *groups[pick(int(groups.size()))];
          ref_ptr<Group> shared = groups[pick(int(groups.size()))];
          try {
            if (shared->parents().size() > 1 && pick(2) == 0)
              shared->parents()[0]->removeChild(shared.get());
            else
              g.addChild(shared);
          } catch (const Error&) {
          }
          break;
        }
      }
    }
  }
};

/// Materials of every occurrence of triangle `triangle` of `shape` in the synced scene.
std::vector<const MaterialNode*> occurrences(const SceneGraph& sg, const ShapeNode* shape,
                                             std::uint32_t triangle) {
  std::vector<const MaterialNode*> out;
  const Scene& scene = sg.backendScene();
  for (InstanceId id : sg.instancesOf(*shape)) {
    Hit h;
    h.instanceId = id;
    const std::size_t n = scene.objectMesh(scene.instanceObject(id)).triangleCount();
    for (std::uint32_t k = 0; k < n; ++k) {
      h.primId = k;
      const HitInfo info = sg.hitInfo(h);
      if (info.shape == shape && info.triangle == triangle) out.push_back(info.material);
    }
  }
  return out;
}

/// True when both scenes hold the hit triangle several times (the same mesh used twice at the
/// same place, DEF/USE without a transform between) and each answer is one of the copies.
bool coincidentCopies(const SceneGraph& a, const MappedHit& ha, const SceneGraph& b,
                      const MappedHit& hb) {
  const auto ca = occurrences(a, ha.shape, ha.triangle);
  const auto cb = occurrences(b, hb.shape, hb.triangle);
  auto has = [](const auto& v, const MaterialNode* m) {
    return std::find(v.begin(), v.end(), m) != v.end();
  };
  return ca.size() >= 2 && cb.size() >= 2 && has(ca, hb.material) && has(cb, ha.material);
}

bool nearEdge(const MappedHit& h) {
  const float w = 1.0f - h.u - h.v;
  return std::min({h.u, h.v, w}) < 1e-4f;
}

}  // namespace

/// Seeds to run: 1..3 by default; TG_SEEDS=n runs 1..n, TG_SEED=s replays one seed.
std::vector<unsigned> seeds() {
  if (const char* one = std::getenv("TG_SEED")) return {unsigned(std::strtoul(one, nullptr, 10))};
  unsigned n = 3;
  if (const char* count = std::getenv("TG_SEEDS")) n = unsigned(std::strtoul(count, nullptr, 10));
  std::vector<unsigned> out;
  for (unsigned s = 1; s <= n; ++s) out.push_back(s);
  return out;
}

BOOST_AUTO_TEST_CASE(incremental_sync_equals_scratch_over_100_frames) {
  for (unsigned seed : seeds()) {
    RandomGraph g(seed);
    SceneGraph sg;
    sg.setRoot(g.root);
    std::mt19937 rayRng(seed * 7919u);
    std::size_t hits = 0, compared = 0, ambiguous = 0, coincident = 0, reclassified = 0,
                deforming = 0;
    for (int frame = 0; frame < 100; ++frame) {
      if (frame > 0) g.edit();
      sg.advanceTo(0.037 * frame);
      const FrameStats stats = sg.sync();
      reclassified += stats.reclassified;
      deforming += stats.triangles.deforming > 0 ? 1 : 0;

      SceneGraph scratch;
      scratch.setRoot(g.root);
      scratch.sync();
      BOOST_TEST_REQUIRE(sg.backendScene().instancedTriangleCount() ==
                         scratch.backendScene().instancedTriangleCount());

      const Box3f b = scratch.backendScene().bounds();
      const Vec3f center = b.empty() ? Vec3f{} : b.center();
      const float size = b.empty() ? 1.0f : maxComponent(b.extent());
      for (const Ray& ray : randomRays(rayRng, center, size * 1.5f, size * 0.5f, 2000)) {
        const MappedHit a = traceMapped(sg, ray);
        const MappedHit s = traceMapped(scratch, ray);
        ++compared;
        const bool sameT = a.hit && s.hit && std::abs(a.t - s.t) <= 1e-5f * std::abs(s.t);
        const bool same =
            a.hit == s.hit && (!a.hit || (sameT && a.shape == s.shape && a.triangle == s.triangle &&
                                          a.material == s.material));
        hits += a.hit ? 1 : 0;
        if (same) continue;
        // A ray through an edge or a silhouette may go either way by rounding when one side
        // is baked and the other instanced; anything else is a real difference.
        if ((a.hit && nearEdge(a)) || (s.hit && nearEdge(s))) {
          ++ambiguous;
          continue;
        }
        // The same mesh used twice at the same place with different materials (DEF/USE
        // without a transform between) is a true tie: the backend breaks it by instance id,
        // and ids differ between the two scenes.
        if (sameT && a.shape == s.shape && a.triangle == s.triangle &&
            coincidentCopies(sg, a, scratch, s)) {
          ++coincident;
          continue;
        }
        BOOST_ERROR("seed " << seed << " frame " << frame << ": hit " << a.hit << "/" << s.hit
                            << " t " << a.t << "/" << s.t << " shape " << a.shape << "/" << s.shape
                            << " triangle " << a.triangle << "/" << s.triangle);
        return;
      }
    }
    BOOST_TEST_MESSAGE("seed " << seed << ": " << compared << " rays, " << hits << " hits, "
                               << ambiguous << " edge cases, " << coincident
                               << " coincident copies, " << reclassified << " reclassifications, "
                               << deforming << " frames deforming");
    BOOST_TEST(hits > compared / 20);  // the rays must mostly test something
    BOOST_TEST(ambiguous <= compared / 10000);
    BOOST_TEST(reclassified > 0u);
    BOOST_TEST(deforming > 0u);
  }
}
