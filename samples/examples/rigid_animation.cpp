// example-rigid-animation: animates transforms and prints, frame by frame, how the scene graph
// classifies the triangles below them (FrameStats by class).
//
// Two parts sit on a static floor:
// - a propeller turned by a TimeSensor -> OrientationInterpolator -> Transform.rotation chain:
//   driven by an animator, it is rigid from the first frame and stays rigid;
// - a crate that the application itself moves in frames 4 to 10 by setting
//   Transform.translation: nothing declares it dynamic, the classifier sees the transform change
//   and promotes the crate from static to rigid, then returns it to static once it has rested
//   for SyncOptions::restFrames frames.
// A rigid part costs one instance matrix per frame, not a rebuild: frames in which only rigid
// parts move rebuild no object.
//
// Exits 1 when the classes or rebuilds are not what is described above.
#include <tracegraph/tracegraph.h>

#include <cstdio>
#include <iostream>
#include <numbers>
#include <vector>

using namespace tg;

namespace {

/// An axis-aligned box from lo to hi, 12 triangles facing outwards.
ref_ptr<nodes::Mesh> box(const Vec3f& lo, const Vec3f& hi) {
  std::vector<Vec3f> p;
  for (int i = 0; i < 8; ++i)
    p.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  return nodes::Mesh::create(std::move(p), {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                            2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5});
}

constexpr int kFrames = 24;
constexpr int kMoveFirst = 4, kMoveLast = 10;  // frames in which the application moves the crate
constexpr std::size_t kBoxTriangles = 12;

}  // namespace

int main() {
  ref_ptr<nodes::Separator> root = nodes::Separator::create();
  root->addChild(box({-5.0f, -0.1f, -5.0f}, {5.0f, 0.0f, 5.0f}));  // floor

  // Propeller: two blades (one mesh each) below one animated rotation, so the classifier
  // groups them into one rigid object with one instance.
  ref_ptr<nodes::TimeSensor> clock = nodes::TimeSensor::create();
  clock->cycleInterval = 1.0;
  clock->loop = true;
  ref_ptr<nodes::OrientationInterpolator> spin = nodes::OrientationInterpolator::create();
  spin->key = std::vector<float>{0.0f, 0.5f, 1.0f};
  const float pi = std::numbers::pi_v<float>;
  spin->keyValue = std::vector<Rotation>{
      {{0.0f, 1.0f, 0.0f}, 0.0f}, {{0.0f, 1.0f, 0.0f}, pi}, {{0.0f, 1.0f, 0.0f}, 2.0f * pi}};
  spin->set_fraction.connectFrom(clock->fraction_changed);
  ref_ptr<nodes::Separator> propeller = nodes::Separator::create();
  ref_ptr<nodes::Transform> hub = nodes::Transform::create();
  hub->translation = Vec3f{2.0f, 1.0f, 0.0f};
  propeller->addChild(hub);
  ref_ptr<nodes::Transform> turn = nodes::Transform::create();
  turn->rotation.connectFrom(spin->value_changed);
  propeller->addChild(turn);
  propeller->addChild(box({-1.0f, -0.05f, -0.1f}, {1.0f, 0.05f, 0.1f}));
  propeller->addChild(box({-0.1f, -0.05f, -1.0f}, {0.1f, 0.05f, 1.0f}));
  root->addChild(propeller);

  // Crate: an ordinary Transform that the application edits now and then.
  ref_ptr<nodes::Separator> crate = nodes::Separator::create();
  ref_ptr<nodes::Transform> place = nodes::Transform::create();
  place->translation = Vec3f{-2.0f, 0.0f, 0.0f};
  crate->addChild(place);
  crate->addChild(box({-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}));
  root->addChild(crate);

  // A short rest period so that the return to static shows within a few frames.
  SyncOptions options;
  options.restFrames = 5;
  SceneGraph graph(options);
  graph.setRoot(root);

  std::printf(
      "frame   static  rigid  deforming  instances  rebuilt(obj/tri)  reclassified  "
      "sync_ms\n");
  std::vector<FrameStats> frames;
  for (int f = 1; f <= kFrames; ++f) {
    if (f >= kMoveFirst && f <= kMoveLast)
      place->translation = Vec3f{-2.0f, 0.0f, 0.25f * static_cast<float>(f - kMoveFirst + 1)};
    graph.advanceTo(f / 30.0);
    const FrameStats s = graph.sync();
    std::printf("%5d  %7zu  %5zu  %9zu  %9zu  %8zu/%-8zu  %12zu  %7.3f\n", f, s.triangles.statics,
                s.triangles.rigid, s.triangles.deforming, s.instances, s.objectsRebuilt,
                s.trianglesRebuilt, s.reclassified, s.syncMs);
    frames.push_back(s);
  }

  int failures = 0;
  auto expect = [&](bool ok, const std::string& what) {
    if (!ok) {
      std::cerr << "example-rigid-animation: FAILED: " << what << "\n";
      ++failures;
    }
  };
  auto at = [&](int f) -> const FrameStats& { return frames[static_cast<std::size_t>(f - 1)]; };
  // Frame 1: the propeller (2 boxes) is rigid at once; floor and crate are static.
  expect(at(1).triangles.rigid == 2 * kBoxTriangles, "the driven propeller is rigid in frame 1");
  expect(at(1).triangles.statics == 2 * kBoxTriangles, "floor and crate start static");
  // While the crate moves it is rigid too, and its motion rebuilds nothing after the frame
  // that promoted it (only its instance matrix changes).
  expect(at(kMoveLast).triangles.rigid == 3 * kBoxTriangles, "the moving crate became rigid");
  for (int f = kMoveFirst + 2; f <= kMoveLast; ++f)
    expect(at(f).objectsRebuilt == 0,
           "frame " + std::to_string(f) + ": rigid motion rebuilds no object");
  // Some frames after it stopped, the crate is static again; the propeller never returns.
  const FrameStats& last = frames.back();
  expect(last.triangles.rigid == 2 * kBoxTriangles, "the crate came to rest, the propeller not");
  expect(last.triangles.statics == 2 * kBoxTriangles, "the crate is static again");
  std::size_t reclassified = 0;
  for (const FrameStats& s : frames) reclassified += s.reclassified;
  expect(reclassified >= 2, "the crate was reclassified twice (static -> rigid -> static)");
  if (failures == 0) std::cout << "OK: static -> rigid -> static, without rebuilds while moving\n";
  return failures == 0 ? 0 : 1;
}
