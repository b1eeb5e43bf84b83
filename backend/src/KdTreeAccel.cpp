#include "tracegraph/backend/KdTreeAccel.h"

#include <chrono>

#include "BvhAccel.h"

namespace tg {

std::string_view accelKindName(AccelKind kind) {
  switch (kind) {
    case AccelKind::SahKdTree:
      return "sah-kd";
    case AccelKind::FastKdTree:
      return "fast-kd";
    case AccelKind::Bvh:
      return "bvh";
    case AccelKind::BvhFast:
      return "bvh-fast";
  }
  return "unknown";
}

std::unique_ptr<ObjectAccel> createObjectAccel(AccelKind kind) {
  switch (kind) {
    case AccelKind::SahKdTree:
    case AccelKind::FastKdTree:
      return std::make_unique<KdTreeAccel>(kind);
    case AccelKind::Bvh:
    case AccelKind::BvhFast:
      return std::make_unique<detail::BvhAccel>(kind);
  }
  return nullptr;
}

void KdTreeAccel::build(const TriangleMesh& mesh) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = mesh.triangleCount();
  triangles_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    triangles_[i] = {mesh.positions[mesh.indices[3 * i]], mesh.positions[mesh.indices[3 * i + 1]],
                     mesh.positions[mesh.indices[3 * i + 2]]};
  }
  tree_ = kind_ == AccelKind::SahKdTree ? buildSahKdTree(triangles_) : buildFastKdTree(triangles_);
  tree_.stats.triangles = n;
  tree_.stats.bytes = tree_.nodes.capacity() * sizeof(KdNode) +
                      tree_.primIndices.capacity() * sizeof(std::uint32_t) +
                      triangles_.capacity() * sizeof(TriangleVertices);
  tree_.stats.buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace tg
