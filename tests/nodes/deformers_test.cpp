// Keyframe (BART tpa), morph and skin deformers, alone and driving meshes in the graph.
#define BOOST_TEST_MODULE deformers
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "../scenegraph/GraphTestUtil.h"
#include "tracegraph/nodes/KeyframeDeformer.h"
#include "tracegraph/nodes/MorphDeformer.h"
#include "tracegraph/nodes/OrientationInterpolator.h"
#include "tracegraph/nodes/SkinDeformer.h"
#include "tracegraph/nodes/TimeSensor.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {
constexpr float kPi = 3.14159265f;

bool near(const Vec3f& a, const Vec3f& b, float tol = 1e-5f) {
  return length(a - b) <= tol;
}
}  // namespace

BOOST_AUTO_TEST_CASE(keyframes_interpolate_clamp_and_loop) {
  auto k = KeyframeDeformer::create();
  k->times.setValues({1.0f, 3.0f});
  k->keyPoints.setValues({{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {1, 2, 0}});
  k->keyNormals.setValues({{0, 0, 1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}});
  k->evaluate(0.0);
  BOOST_TEST(k->points_changed[1] == Vec3f(1, 0, 0));
  k->evaluate(2.0);
  BOOST_TEST(k->points_changed[0] == Vec3f(0, 1, 0));
  BOOST_TEST(near(k->normals_changed[0], Vec3f(0, std::sqrt(0.5f), std::sqrt(0.5f))));
  k->evaluate(5.0);
  BOOST_TEST(k->points_changed[1] == Vec3f(1, 2, 0));
  k->loop.setValue(true);
  k->evaluate(4.0);  // 1 + (3 mod 2) = 2: halfway
  BOOST_TEST(k->points_changed[0] == Vec3f(0, 1, 0));
}

BOOST_AUTO_TEST_CASE(morph_blends_targets_by_weight) {
  auto m = MorphDeformer::create();
  m->basePoints.setValues({{0, 0, 0}, {1, 0, 0}});
  m->targets.setValues({{0, 1, 0}, {1, 1, 0}, {0, 0, 2}, {1, 0, 2}});
  m->weights.setValues({0.5f, 0.25f});
  m->evaluate(0.0);
  BOOST_TEST(m->points_changed[0] == Vec3f(0, 0.5f, 0.5f));
  BOOST_TEST(m->points_changed[1] == Vec3f(1, 0.5f, 0.5f));
}

BOOST_AUTO_TEST_CASE(skin_follows_joint_hierarchy) {
  auto root = Transform::create();
  auto elbow = Transform::create();
  elbow->translation.setValue({1, 0, 0});  // elbow at x = 1 relative to the root joint
  auto skin = SkinDeformer::create();
  skin->setJoints({root, elbow});
  skin->jointParents.setValues({-1, 0});
  // Bind pose: root at the origin, elbow at x = 1.
  skin->inverseBindMatrices.setValues({Affine3d{}, Affine3d::translation({-1, 0, 0})});
  skin->restPoints.setValues({{0.5f, 0, 0}, {2, 0, 0}, {1, 0, 0}});
  skin->jointIndices.setValues({0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});
  skin->jointWeights.setValues({1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0});
  skin->evaluate(0.0);
  BOOST_TEST(near(skin->points_changed[1], Vec3f(2, 0, 0)));  // bind pose: unchanged
  elbow->rotation.setValue(Rotation{{0, 0, 1}, kPi / 2});
  skin->evaluate(0.0);
  BOOST_TEST(near(skin->points_changed[0], Vec3f(0.5f, 0, 0)));  // on the root joint
  BOOST_TEST(near(skin->points_changed[1], Vec3f(1, 1, 0)));     // bent up at the elbow
  BOOST_TEST(near(skin->points_changed[2], Vec3f(1, 0, 0)));     // at the elbow: both agree
  root->translation.setValue({0, 0, 3});
  skin->evaluate(0.0);
  BOOST_TEST(near(skin->points_changed[1], Vec3f(1, 1, 3)));
}

BOOST_AUTO_TEST_CASE(skinned_mesh_in_the_graph_deforms_every_frame) {
  // An arm of two boxes: the upper arm (x in [0, 1]) on the root joint, the forearm
  // (x in [1, 2]) on the elbow.
  auto upperArm = makeBox({0, -0.1f, -0.1f}, {1, 0.1f, 0.1f});
  auto foreArm = makeBox({1, -0.1f, -0.1f}, {2, 0.1f, 0.1f});
  std::vector<Vec3f> pts = upperArm->points.getValues();
  pts.insert(pts.end(), foreArm->points.getValues().begin(), foreArm->points.getValues().end());
  std::vector<std::int32_t> tris = upperArm->indices.getValues();
  for (std::int32_t i : foreArm->indices.getValues()) tris.push_back(i + 8);
  auto mesh = Mesh::create(pts, tris);
  auto root = Transform::create();
  auto elbow = Transform::create();
  elbow->translation.setValue({1, 0, 0});
  auto skin = SkinDeformer::create();
  skin->setJoints({root, elbow});
  skin->jointParents.setValues({-1, 0});
  skin->inverseBindMatrices.setValues({Affine3d{}, Affine3d::translation({-1, 0, 0})});
  skin->restPoints.setValues(mesh->points.getValues());
  std::vector<std::int32_t> idx;
  std::vector<float> w;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    idx.insert(idx.end(), {i >= 8 ? 1 : 0, 0, 0, 0});
    w.insert(w.end(), {1, 0, 0, 0});
  }
  skin->jointIndices.setValues(idx);
  skin->jointWeights.setValues(w);
  skin->drive(*mesh);
  // The elbow is animated by an interpolator; the skin reads it, so it is evaluated after.
  auto ts = TimeSensor::create();
  auto bend = OrientationInterpolator::create();
  bend->key.setValues({0.0f, 1.0f});
  bend->keyValue.setValues({Rotation{{0, 0, 1}, 0.0f}, Rotation{{0, 0, 1}, kPi / 2}});
  bend->set_fraction.connectFrom(ts->fraction_changed);
  elbow->rotation.connectFrom(bend->value_changed);

  SceneGraph sg;
  sg.setRoot(sep(mesh));
  sg.advanceTo(0.0);
  FrameStats s = sg.sync();
  BOOST_TEST(s.triangles.deforming == 24u);
  BOOST_TEST(traceMapped(sg, rayTo({1.8f, 0, 10}, {1.8f, 0, 0})).shape == mesh.get());
  sg.advanceTo(1.0);  // fully bent: the forearm points up along +y from x = 1
  s = sg.sync();
  BOOST_TEST(s.objectsRebuilt + s.objectsRefitted == 1u);
  BOOST_TEST(!traceMapped(sg, rayTo({1.8f, 0, 10}, {1.8f, 0, 0})).hit);
  const MappedHit up = traceMapped(sg, rayTo({1, 0.8f, 10}, {1, 0.8f, 0}));
  BOOST_TEST(up.shape == mesh.get());
  BOOST_TEST(up.t == 0.99f, boost::test_tools::tolerance(1e-5f));
}
