#include "tracegraph/nodes/Mesh.h"

#include <string>

namespace tg::nodes {

ref_ptr<Mesh> Mesh::create(std::vector<Vec3f> points, std::vector<std::int32_t> indices) {
  ref_ptr<Mesh> m = create();
  m->points.setValues(std::move(points));
  m->indices.setValues(std::move(indices));
  return m;
}

ShapeGeometry Mesh::geometry() const {
  return {points.getValues(), indices.getValues(), normals.getValues(), texCoords.getValues()};
}

Box3f Mesh::localBounds() const {
  if (!boundsValid_) {
    bounds_ = Box3f{};
    for (const Vec3f& p : points.getValues()) bounds_.extend(p);
    boundsValid_ = true;
  }
  return bounds_;
}

std::string Mesh::validate() const {
  const std::size_t n = points.size();
  if (indices.size() % 3 != 0)
    return label() + ": index count " + std::to_string(indices.size()) + " is not a multiple of 3";
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const std::int32_t k = indices[i];
    if (k < 0 || static_cast<std::size_t>(k) >= n)
      return label() + ": index " + std::to_string(k) + " (at " + std::to_string(i) +
             ") is out of range for " + std::to_string(n) + " points";
  }
  if (!normals.empty() && normals.size() != n)
    return label() + ": " + std::to_string(normals.size()) + " normals for " + std::to_string(n) +
           " points";
  if (!texCoords.empty() && texCoords.size() != n)
    return label() + ": " + std::to_string(texCoords.size()) + " texture coordinates for " +
           std::to_string(n) + " points";
  return {};
}

void Mesh::fieldChanged(const Field&) {
  // Every field of a mesh is geometry: one version counter tells the sync what is stale.
  ++version_;
  boundsValid_ = false;
}

}  // namespace tg::nodes
