// Each classification rule on a small graph: static, rigid (with nested dynamic chains and
// baked static transforms), deforming, DEF/USE sharing, static chunks.
#define BOOST_TEST_MODULE classification
#include <boost/test/unit_test.hpp>

#include "GraphTestUtil.h"
#include "tracegraph/nodes/KeyframeDeformer.h"
#include "tracegraph/nodes/MatrixTransform.h"
#include "tracegraph/nodes/PositionInterpolator.h"
#include "tracegraph/nodes/TimeSensor.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {

/// Drives `t.translation` from a position interpolator running from `a` to `b` over 1 s.
ref_ptr<PositionInterpolator> drive(Transform& t, const Vec3f& a, const Vec3f& b) {
  auto clock = TimeSensor::create();
  auto interp = PositionInterpolator::create();
  interp->key.setValues({0.0f, 1.0f});
  interp->keyValue.setValues({a, b});
  interp->set_fraction.connectFrom(clock->fraction_changed);
  t.translation.connectFrom(interp->value_changed);
  return interp;
}

bool near(const Affine3d& a, const Affine3d& b, double tol = 1e-12) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      if (std::abs(a.m[r][c] - b.m[r][c]) > tol) return false;
  return true;
}

}  // namespace

BOOST_AUTO_TEST_CASE(static_mesh_is_merged_in_world_space) {
  auto box = unitBox();
  auto root = sep(translate({3, 0, 0}), box);
  SceneGraph sg;
  sg.setRoot(root);
  const FrameStats s = sg.sync();
  const Scene& scene = sg.backendScene();
  BOOST_TEST(scene.instanceCount() == 1u);
  BOOST_TEST(s.triangles.statics == 12u);
  BOOST_TEST(s.triangles.rigid == 0u);
  const std::vector<InstanceId> inst = sg.instancesOf(*box);
  BOOST_REQUIRE(inst.size() == 1u);
  BOOST_TEST(sg.instanceClass(inst[0]) == DynamicsClass::Static);
  BOOST_TEST(scene.instanceTransform(inst[0]) == Affine3d::identity());
  // The static transform is baked into world-space vertices.
  const Box3f b = scene.objectMesh(scene.instanceObject(inst[0])).bounds();
  BOOST_TEST(b.lower.x == 2.5f);
  BOOST_TEST(b.upper.x == 3.5f);
  const MappedHit h = traceMapped(sg, rayTo({3, 0, 10}, {3, 0, 0}));
  BOOST_TEST(h.hit);
  BOOST_TEST(h.shape == box.get());
  BOOST_TEST(h.t == 0.95f, boost::test_tools::tolerance(1e-6f));
  BOOST_TEST(!sg.isDynamic(*box));
}

BOOST_AUTO_TEST_CASE(animated_transform_is_rigid_and_moves_by_matrix_only) {
  auto box = unitBox();
  auto other = makeBox({5, 5, 5}, {6, 6, 6});
  auto t = Transform::create();
  drive(*t, {0, 0, 0}, {10, 0, 0});
  auto root = sep(sep(t, box), sep(other));
  SceneGraph sg;
  sg.setRoot(root);
  sg.advanceTo(0.0);
  FrameStats s = sg.sync();
  BOOST_TEST(sg.isDynamic(*t));
  BOOST_TEST(s.triangles.rigid == 12u);
  BOOST_TEST(s.triangles.statics == 12u);
  const std::vector<InstanceId> inst = sg.instancesOf(*box);
  BOOST_REQUIRE(inst.size() == 1u);
  BOOST_TEST(sg.instanceClass(inst[0]) == DynamicsClass::Rigid);
  BOOST_TEST(sg.backendScene().objectUsage(sg.backendScene().instanceObject(inst[0])) ==
             ObjectUsage::Rigid);

  sg.advanceTo(0.5);
  s = sg.sync();
  BOOST_TEST(s.objectsRebuilt == 0u);
  BOOST_TEST(s.reclassified == 0u);
  BOOST_TEST(sg.debugStats().framesUpdated == 1u);
  BOOST_TEST(near(sg.backendScene().instanceTransform(inst[0]), t->localMatrix()));
  const MappedHit h = traceMapped(sg, rayTo({5, 0, 10}, {5, 0, 0}));
  BOOST_TEST(h.hit);
  BOOST_TEST(h.shape == box.get());
}

BOOST_AUTO_TEST_CASE(robot_arm_gives_one_rigid_group_per_dynamic_chain) {
  auto base = unitBox(), upper = unitBox(), hand = unitBox();
  auto tBase = Transform::create(), tUpper = Transform::create(), tHand = Transform::create();
  drive(*tBase, {0, 0, 0}, {0, 1, 0});
  drive(*tUpper, {0, 2, 0}, {0, 2, 1});
  drive(*tHand, {0, 2, 0}, {1, 2, 0});
  auto bend = Transform::create();  // static joint offset between base and upper arm
  bend->rotation.setValue(Rotation{{0, 0, 1}, 0.3f});
  auto root = sep(sep(tBase, base, sep(bend, tUpper, upper, sep(tHand, hand))));
  SceneGraph sg;
  sg.setRoot(root);
  sg.advanceTo(0.25);
  sg.sync();
  const Scene& scene = sg.backendScene();
  BOOST_TEST(scene.objectCount() == 3u);
  const InstanceId iBase = sg.instancesOf(*base).at(0);
  const InstanceId iUpper = sg.instancesOf(*upper).at(0);
  const InstanceId iHand = sg.instancesOf(*hand).at(0);
  const Affine3d mBase = tBase->localMatrix();
  const Affine3d mUpper = mBase * bend->localMatrix() * tUpper->localMatrix();
  const Affine3d mHand = mUpper * tHand->localMatrix();
  BOOST_TEST(near(scene.instanceTransform(iBase), mBase));
  BOOST_TEST(near(scene.instanceTransform(iUpper), mUpper));
  BOOST_TEST(near(scene.instanceTransform(iHand), mHand));
  for (InstanceId i : {iBase, iUpper, iHand})
    BOOST_TEST(sg.instanceClass(i) == DynamicsClass::Rigid);

  // Moving only the hand updates only the hand's instance (a connected field may also be set
  // directly; the next advanceTo overwrites it).
  tHand->translation.setValue({0.7f, 2.0f, 0.0f});
  FrameStats s = sg.sync();
  BOOST_TEST(s.objectsRebuilt == 0u);
  BOOST_TEST(s.reclassified == 0u);
  BOOST_TEST(sg.debugStats().framesUpdated == 1u);
  BOOST_TEST(sg.debugStats().regionsRetraversed == 0u);
  // Moving the base updates all three.
  tBase->translation.setValue({0.0f, 0.5f, 0.0f});
  s = sg.sync();
  BOOST_TEST(s.objectsRebuilt == 0u);
  BOOST_TEST(sg.debugStats().framesUpdated == 3u);
  const Affine3d mHand2 =
      tBase->localMatrix() * bend->localMatrix() * tUpper->localMatrix() * tHand->localMatrix();
  BOOST_TEST(near(sg.backendScene().instanceTransform(sg.instancesOf(*hand).at(0)), mHand2));
  const MappedHit h = traceMapped(
      sg, rayTo(Vec3f(mHand2.transformPoint({0, 0, 10})), Vec3f(mHand2.transformPoint({0, 0, 0}))));
  BOOST_TEST(h.shape == hand.get());
}

BOOST_AUTO_TEST_CASE(static_transform_below_a_dynamic_one_is_baked) {
  auto box = unitBox();
  auto tDyn = Transform::create();
  drive(*tDyn, {0, 0, 0}, {0, 0, 5});
  auto tStatic = Transform::create();
  tStatic->translation.setValue({4, 0, 0});
  tStatic->scale.setValue({2, 2, 2});
  auto root = sep(tDyn, tStatic, box);
  SceneGraph sg;
  sg.setRoot(root);
  sg.advanceTo(0.5);
  sg.sync();
  const Scene& scene = sg.backendScene();
  const InstanceId i = sg.instancesOf(*box).at(0);
  BOOST_TEST(near(scene.instanceTransform(i), tDyn->localMatrix()));
  const Box3f b = scene.objectMesh(scene.instanceObject(i)).bounds();
  BOOST_TEST(b.lower.x == 3.0f);  // 4 - 2 * 0.5
  BOOST_TEST(b.upper.x == 5.0f);
  BOOST_TEST(b.upper.y == 1.0f);
  BOOST_TEST(!sg.isDynamic(*tStatic));
}

BOOST_AUTO_TEST_CASE(mesh_driven_by_a_deformer_is_deforming) {
  auto mesh = unitBox();
  auto deformer = KeyframeDeformer::create();
  std::vector<Vec3f> keys = mesh->points.getValues();
  for (const Vec3f& p : mesh->points.getValues()) keys.push_back(p * 2.0f);
  deformer->times.setValues({0.0f, 1.0f});
  deformer->keyPoints.setValues(keys);
  deformer->drive(*mesh);
  auto root = sep(translate({0, 0, -1}), mesh, sep(makeBox({5, 5, 5}, {6, 6, 6})));
  SceneGraph sg;
  sg.setRoot(root);
  sg.advanceTo(0.0);
  FrameStats s = sg.sync();
  BOOST_TEST(s.triangles.deforming == 12u);
  const InstanceId i = sg.instancesOf(*mesh).at(0);
  BOOST_TEST(sg.instanceClass(i) == DynamicsClass::Deforming);
  BOOST_TEST(sg.backendScene().objectUsage(sg.backendScene().instanceObject(i)) ==
             ObjectUsage::Deforming);
  // The transform above stays on the instance; the object holds the mesh's own points.
  BOOST_TEST(near(sg.backendScene().instanceTransform(i), translate({0, 0, -1})->localMatrix()));

  sg.advanceTo(1.0);
  s = sg.sync();
  BOOST_TEST(s.objectsRebuilt + s.objectsRefitted == 1u);
  BOOST_TEST(s.trianglesRebuilt == 12u);
  const MappedHit h = traceMapped(sg, rayTo({0, 0, 10}, {0, 0, 0}));
  BOOST_TEST(h.hit);
  BOOST_TEST(h.shape == mesh.get());
  BOOST_TEST(h.t == 1.0f, boost::test_tools::tolerance(1e-6f));  // top face now at z = 0
  // No change, no rebuild.
  sg.advanceTo(1.5);
  s = sg.sync();
  BOOST_TEST(s.objectsRebuilt == 0u);
}

BOOST_AUTO_TEST_CASE(shared_separator_is_one_object_with_several_instances) {
  auto box = unitBox();
  auto material = Material::create();
  auto shared = sep(material, box);
  auto root = sep(sep(translate({0, 0, 0}), shared), sep(translate({3, 0, 0}), shared),
                  sep(translate({6, 0, 0}), shared));
  SceneGraph sg;
  sg.setRoot(root);
  const FrameStats s = sg.sync();
  const Scene& scene = sg.backendScene();
  BOOST_TEST(scene.objectCount() == 1u);
  BOOST_TEST(scene.instanceCount() == 3u);
  BOOST_TEST(s.triangles.statics == 36u);
  for (float x : {0.0f, 3.0f, 6.0f}) {
    const MappedHit h = traceMapped(sg, rayTo({x, 0, 10}, {x, 0, 0}));
    BOOST_TEST(h.hit);
    BOOST_TEST(h.shape == box.get());
    BOOST_TEST(h.material == material.get());
    BOOST_TEST(h.t == 0.95f, boost::test_tools::tolerance(1e-6f));
  }
}

BOOST_AUTO_TEST_CASE(shared_mesh_is_one_object_with_several_instances) {
  auto box = unitBox();
  auto red = Material::create(), blue = Material::create();
  auto root = sep(sep(red, translate({0, 0, 0}), box), sep(blue, translate({3, 0, 0}), box));
  SceneGraph sg;
  sg.setRoot(root);
  sg.sync();
  BOOST_TEST(sg.backendScene().objectCount() == 1u);
  BOOST_TEST(sg.backendScene().instanceCount() == 2u);
  // One object, but each instance keeps the material of its own path.
  BOOST_TEST(traceMapped(sg, rayTo({0, 0, 10}, {0, 0, 0})).material == red.get());
  BOOST_TEST(traceMapped(sg, rayTo({3, 0, 10}, {3, 0, 0})).material == blue.get());
  // The same per instance through the segment tables renderers fill once per sync.
  std::vector<const MaterialNode*> materials;
  for (InstanceId id : sg.instanceIds()) {
    const std::vector<MeshSegment> segs = sg.segments(id);
    BOOST_REQUIRE(segs.size() == 1u);
    BOOST_TEST(segs[0].primBegin == 0u);
    BOOST_TEST(segs[0].primEnd == 12u);
    BOOST_TEST(segs[0].shape == box.get());
    materials.push_back(segs[0].material);
  }
  BOOST_TEST(materials.size() == 2u);
  BOOST_TEST(materials[0] != materials[1]);
}

BOOST_AUTO_TEST_CASE(replacing_the_root_rebuilds_everything) {
  auto a = unitBox(), b = makeBox({4, 0, 0}, {5, 1, 1});
  SceneGraph sg;
  sg.setRoot(sep(a));
  sg.sync();
  BOOST_TEST(traceMapped(sg, rayTo({0, 0, 10}, {0, 0, 0})).shape == a.get());
  sg.setRoot(sep(b));
  sg.sync();
  BOOST_TEST(!traceMapped(sg, rayTo({0, 0, 10}, {0, 0, 0})).hit);
  BOOST_TEST(traceMapped(sg, rayTo({4.5f, 0.5f, 10}, {4.5f, 0.5f, 0})).shape == b.get());
  BOOST_TEST(sg.backendScene().objectCount() == 1u);
  sg.setRoot(nullptr);
  const FrameStats s = sg.sync();
  BOOST_TEST(s.instances == 0u);
  BOOST_TEST(sg.backendScene().objectCount() == 0u);
}

BOOST_AUTO_TEST_CASE(invalid_mesh_is_skipped_until_fixed) {
  auto m = unitBox();
  auto root = sep(m, sep(translate({3, 0, 0}), unitBox()));
  SceneGraph sg;
  sg.setRoot(root);
  sg.sync();
  m->indices.set1Value(0, 99);  // out of range: not drawn, the rest of the scene is
  sg.sync();
  BOOST_TEST(sg.debugStats().invalidShapes == 1u);
  BOOST_TEST(sg.instancesOf(*m).empty());
  BOOST_TEST(traceMapped(sg, rayTo({3, 0, 10}, {3, 0, 0})).hit);
  m->indices.set1Value(0, 0);
  sg.sync();
  BOOST_TEST(traceMapped(sg, rayTo({0, 0, 10}, {0, 0, 0})).shape == m.get());
}

BOOST_AUTO_TEST_CASE(static_geometry_is_split_into_chunks) {
  auto root = Separator::create();
  std::vector<ref_ptr<Mesh>> boxes;
  std::vector<ref_ptr<Transform>> transforms;
  for (int x = 0; x < 8; ++x)
    for (int y = 0; y < 8; ++y) {
      auto t = translate({float(x) * 4.0f, float(y) * 4.0f, 0.0f});
      auto b = unitBox();
      root->addChild(sep(t, b));
      boxes.push_back(b);
      transforms.push_back(t);
    }
  SceneGraph sg;
  sg.setRoot(root);
  sg.sync();
  const std::size_t chunks = sg.backendScene().objectCount();
  BOOST_TEST(chunks > 1u);
  BOOST_TEST(chunks <= 64u);
  // A static box that starts moving leaves its chunk: one chunk rebuilt, one rigid object.
  transforms[9]->translation.setValue({4.5f, 4.0f, 0.0f});
  const FrameStats s = sg.sync();
  BOOST_TEST(s.reclassified == 1u);
  BOOST_TEST(sg.debugStats().chunksRebuilt == 1u);
  BOOST_TEST(s.objectsRebuilt == 2u);
  BOOST_TEST(sg.instanceClass(sg.instancesOf(*boxes[9]).at(0)) == DynamicsClass::Rigid);
  BOOST_TEST(traceMapped(sg, rayTo({4.5f, 4, 10}, {4.5f, 4, 0})).shape == boxes[9].get());
}

BOOST_AUTO_TEST_CASE(overflowing_baked_points_are_dropped_not_fatal) {
  // Each matrix is finite, but their product takes the points beyond float range.
  auto huge = MatrixTransform::create(Affine3d::scaling({1e20, 1e20, 1e20}));
  auto huger = MatrixTransform::create(Affine3d::scaling({1e20, 1e20, 1e20}));
  auto lost = unitBox();
  auto fine = makeBox({3, 0, 0}, {4, 1, 1});
  SceneGraph sg;
  sg.setRoot(sep(sep(huge, huger, lost), fine));
  BOOST_CHECK_NO_THROW(sg.sync());
  BOOST_TEST(sg.instancesOf(*lost).empty());
  BOOST_TEST(traceMapped(sg, rayTo({3.5f, 0.5f, 10}, {3.5f, 0.5f, 0})).shape == fine.get());
}
