// example-deforming-mesh: drives a mesh with a deformer and prints, per frame, the deforming
// triangle count, what the sync rebuilt, and where a ray straight down meets the surface.
//
// A flag (a grid of quads) is moved by a KeyframeDeformer: a travelling wave in 8 keyframes
// over one second. A mesh whose points come from a deformer is deforming from its first frame:
// it is its own object, rebuilt with the fast builder whenever its points change, while the
// static pole beside it is built once and never again.
//
// Exits 1 when the flag is not deforming, the rebuilds include more than the flag, or the
// traced surface does not follow the wave.
#include <tracegraph/tracegraph.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <vector>

using namespace tg;

namespace {

constexpr int kCells = 32;  // the flag is kCells x kCells quads
constexpr std::size_t kFlagTriangles = 2 * kCells * kCells;
constexpr int kKeys = 8;
constexpr int kFrames = 12;

/// An axis-aligned box from lo to hi, 12 triangles facing outwards.
ref_ptr<nodes::Mesh> box(const Vec3f& lo, const Vec3f& hi) {
  std::vector<Vec3f> p;
  for (int i = 0; i < 8; ++i)
    p.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  return nodes::Mesh::create(std::move(p), {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                            2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5});
}

/// A kCells x kCells grid over [0, 2] x [0, 1] in the xy plane (facing +z); its rest points.
ref_ptr<nodes::Mesh> flag(std::vector<Vec3f>& rest) {
  std::vector<std::int32_t> indices;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i)
      rest.push_back({2.0f * static_cast<float>(i) / kCells, static_cast<float>(j) / kCells, 0.0f});
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const int a = j * (kCells + 1) + i, b = a + 1, c = a + kCells + 1, d = c + 1;
      indices.insert(indices.end(), {a, b, d, a, d, c});
    }
  return nodes::Mesh::create(rest, std::move(indices));
}

/// The wave's displacement along z at x for keyframe phase `phase`; zero at the pole (x = 0).
float wave(float x, float phase) {
  return 0.3f * x * std::sin(3.0f * x - phase);
}

}  // namespace

int main() {
  ref_ptr<nodes::Separator> root = nodes::Separator::create();

  // The pole: static, 12 triangles.
  root->addChild(box({-0.05f, -1.0f, -0.05f}, {0.0f, 1.0f, 0.05f}));

  // The flag and its deformer: keyframe k holds every point displaced by the wave at phase
  // 2 pi k / kKeys; the deformer blends the two keyframes around the clock time.
  std::vector<Vec3f> rest;
  ref_ptr<nodes::Mesh> cloth = flag(rest);
  ref_ptr<nodes::KeyframeDeformer> deformer = nodes::KeyframeDeformer::create();
  std::vector<float> times;
  std::vector<Vec3f> keyPoints;
  for (int k = 0; k <= kKeys; ++k) {
    const float phase = 2.0f * std::numbers::pi_v<float> * static_cast<float>(k) / kKeys;
    times.push_back(static_cast<float>(k) / kKeys);
    for (const Vec3f& p : rest) keyPoints.push_back({p.x, p.y, wave(p.x, phase)});
  }
  deformer->times = std::move(times);
  deformer->keyPoints = std::move(keyPoints);
  deformer->loop = true;
  deformer->drive(*cloth);
  root->addChild(cloth);

  SceneGraph graph;
  graph.setRoot(root);

  // A probe ray along -z through a point of the flag near its free end: its hit distance
  // follows the wave.
  Ray probe;
  probe.origin = {1.8f, 0.5f, 5.0f};
  probe.direction = {0.0f, 0.0f, -1.0f};

  std::printf(
      "frame  time   deforming  static  rebuilt(obj/tri)  rebuild_ms  toplevel_ms  "
      "probe_z\n");
  int failures = 0;
  auto expect = [&](bool ok, const std::string& what) {
    if (!ok) {
      std::cerr << "example-deforming-mesh: FAILED: " << what << "\n";
      ++failures;
    }
  };
  std::vector<float> probeZ;
  for (int f = 0; f < kFrames; ++f) {
    const double time = f / 24.0;
    graph.advanceTo(time);
    const FrameStats s = graph.sync();
    Hit hit;
    const bool hitFlag = graph.backendScene().intersect(probe, hit);
    const float z = hitFlag ? probe.origin.z - hit.t : std::nanf("");
    std::printf("%5d  %5.3f  %9zu  %6zu  %8zu/%-8zu  %10.3f  %11.3f  %7.4f\n", f + 1, time,
                s.triangles.deforming, s.triangles.statics, s.objectsRebuilt, s.trianglesRebuilt,
                s.rebuildMs, s.toplevelMs, static_cast<double>(z));
    probeZ.push_back(z);

    const std::string frame = "frame " + std::to_string(f + 1) + ": ";
    expect(s.triangles.deforming == kFlagTriangles, frame + "the whole flag is deforming");
    expect(hitFlag && graph.hitInfo(hit).shape == cloth.get(), frame + "the probe hits the flag");
    if (f > 0) {
      // Only the flag is rebuilt: its points changed, the pole's did not.
      expect(s.objectsRebuilt + s.objectsRefitted == 1,
             frame + "exactly one object (the flag) is rebuilt or refitted");
      expect(s.trianglesRebuilt == kFlagTriangles, frame + "only the flag's triangles rebuilt");
    }
  }
  // The probe follows the wave: the surface is where the deformer put it, frame by frame.
  for (int f = 0; f < kFrames; ++f) {
    const float phase = 2.0f * std::numbers::pi_v<float> * static_cast<float>(f) / 24.0f;
    const float z = wave(1.8f, phase);
    // Blending keyframes is linear in time, the wave is not: allow for the chord's sag.
    expect(std::abs(probeZ[static_cast<std::size_t>(f)] - z) < 0.05f,
           "frame " + std::to_string(f + 1) + ": the traced surface follows the wave");
  }
  if (failures == 0) std::cout << "OK: the flag deforms and only it is rebuilt\n";
  return failures == 0 ? 0 : 1;
}
