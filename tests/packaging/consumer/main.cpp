// Builds a node graph with one mesh, syncs it into the backend and traces one ray at it.
// Prints OK and exits 0 when the ray hits the mesh where expected.
#include <tracegraph/tracegraph.h>

#include <cmath>
#include <iostream>

int main() {
  using namespace tg;
  ref_ptr<nodes::Separator> root = nodes::Separator::create();
  ref_ptr<nodes::Transform> lift = nodes::Transform::create();
  lift->translation = Vec3f{0.0f, 0.0f, 2.0f};
  root->addChild(lift);
  root->addChild(nodes::Mesh::create(
      {{-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}, {0, 1, 2}));

  SceneGraph graph;
  graph.setRoot(root);
  const FrameStats stats = graph.sync();

  Ray ray;
  ray.origin = {0.0f, 0.0f, 10.0f};
  ray.direction = {0.0f, 0.0f, -1.0f};
  Hit hit;
  const bool hitMesh = graph.backendScene().intersect(ray, hit);
  if (!hitMesh || std::abs(hit.t - 8.0f) > 1e-5f || !graph.hitInfo(hit).valid() ||
      stats.triangles.statics != 1) {
    std::cerr << "consumer: unexpected result (hit " << hitMesh << ", t " << hit.t << ")\n";
    return 1;
  }
  std::cout << "OK: hit at t = " << hit.t << "\n";
  return 0;
}
