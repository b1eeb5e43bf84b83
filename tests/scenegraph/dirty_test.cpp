// The sync visits only what changed: its work for one edit does not grow with the graph.
#define BOOST_TEST_MODULE dirty
#include <boost/test/unit_test.hpp>

#include "GraphTestUtil.h"
#include "tracegraph/nodes/PositionInterpolator.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {

/// `n` static boxes in their own Separators, plus one driven transform over a box and one
/// leaf Separator to edit.
struct Scenario {
  ref_ptr<Separator> root = Separator::create();
  ref_ptr<Transform> moving = Transform::create();
  ref_ptr<PositionInterpolator> driver = PositionInterpolator::create();
  ref_ptr<Material> material = Material::create();
  ref_ptr<Separator> leaf = Separator::create();
  SceneGraph sg;

  explicit Scenario(int n) {
    for (int i = 0; i < n; ++i)
      root->addChild(sep(translate({float(i % 32) * 2.0f, float(i / 32) * 2.0f, 0.0f}), unitBox()));
    driver->key.setValues({0.0f, 1.0f});
    driver->keyValue.setValues({{0, 0, 5}, {1, 0, 5}});
    moving->translation.connectFrom(driver->value_changed);
    root->addChild(sep(material, moving, unitBox()));
    leaf->addChild(unitBox());
    root->addChild(sep(translate({0, 0, -5}), leaf));
    sg.setRoot(root);
    sg.sync();
  }
};

}  // namespace

BOOST_AUTO_TEST_CASE(one_transform_edit_costs_the_same_in_small_and_large_graphs) {
  std::vector<SyncDebugStats> stats;
  for (int n : {10, 1000}) {
    Scenario s(n);
    // The interpolator's fraction is set by hand (no time sensor); advanceTo evaluates it
    // and its output moves the transform.
    s.driver->set_fraction.setValue(0.5f);
    s.sg.advanceTo(0.0);
    const FrameStats f = s.sg.sync();
    BOOST_TEST(f.objectsRebuilt == 0u);
    BOOST_TEST(s.sg.debugStats().regionsRetraversed == 0u);
    BOOST_TEST(s.sg.debugStats().framesUpdated == 1u);
    stats.push_back(s.sg.debugStats());
  }
  BOOST_TEST(stats[0].dirtyNodes == 1u);
  BOOST_TEST(stats[0].nodesVisited == stats[1].nodesVisited);
  BOOST_TEST(stats[1].nodesVisited <= 2u);
}

BOOST_AUTO_TEST_CASE(nothing_changed_visits_nothing) {
  Scenario s(1000);
  s.sg.sync();
  BOOST_TEST(s.sg.debugStats().nodesVisited == 0u);
  BOOST_TEST(s.sg.debugStats().framesUpdated == 0u);
}

BOOST_AUTO_TEST_CASE(material_edit_needs_no_backend_work) {
  Scenario s(100);
  s.material->diffuseColor.setValue({1, 0, 0});
  const FrameStats f = s.sg.sync();
  BOOST_TEST(s.sg.debugStats().nodesVisited == 1u);
  BOOST_TEST(f.objectsRebuilt == 0u);
  BOOST_TEST(s.sg.debugStats().instancesCreated == 0u);
  BOOST_TEST(s.sg.debugStats().regionsRetraversed == 0u);
}

BOOST_AUTO_TEST_CASE(structure_edit_walks_only_the_enclosing_separator) {
  std::vector<std::size_t> visited;
  for (int n : {10, 1000}) {
    Scenario s(n);
    s.leaf->addChild(makeBox({3, 3, 3}, {4, 4, 4}));
    const FrameStats f = s.sg.sync();
    BOOST_TEST(s.sg.debugStats().regionsRetraversed == 1u);
    BOOST_TEST(s.sg.debugStats().chunksRebuilt <= 2u);
    BOOST_TEST(f.objectsRebuilt <= 2u);
    visited.push_back(s.sg.debugStats().nodesVisited);
    BOOST_TEST(traceMapped(s.sg, rayTo({3.5f, 3.5f, 10}, {3.5f, 3.5f, 0})).hit);
  }
  BOOST_TEST(visited[0] == visited[1]);
  BOOST_TEST(visited[1] <= 4u);
}
