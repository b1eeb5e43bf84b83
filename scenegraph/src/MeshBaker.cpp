#include "MeshBaker.h"

namespace tg::sync {

TriangleMesh bakeMesh(std::span<const ContentItem> items, std::vector<std::uint32_t>& primBegin) {
  TriangleMesh out;
  primBegin.clear();
  bool anyNormals = false, anyUvs = false;
  std::size_t points = 0, indices = 0;
  for (const ContentItem& item : items) {
    const ShapeGeometry g = item.shape->geometry();
    anyNormals |= !g.normals.empty();
    anyUvs |= !g.uvs.empty();
    points += g.points.size();
    indices += g.indices.size();
  }
  out.positions.reserve(points);
  out.indices.reserve(indices);
  if (anyNormals) out.normals.reserve(points);
  if (anyUvs) out.uvs.reserve(points);

  for (const ContentItem& item : items) {
    const ShapeGeometry g = item.shape->geometry();
    primBegin.push_back(static_cast<std::uint32_t>(out.indices.size() / 3));
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    const bool identity = item.bake == Affine3d::identity();
    for (const Vec3f& p : g.points)
      out.positions.push_back(identity ? p : Vec3f(item.bake.transformPoint(Vec3d(p))));
    for (std::int32_t i : g.indices) out.indices.push_back(base + static_cast<std::uint32_t>(i));
    if (anyNormals) {
      if (g.normals.empty()) {
        out.normals.resize(out.positions.size(), Vec3f{});
      } else if (identity) {
        out.normals.insert(out.normals.end(), g.normals.begin(), g.normals.end());
      } else {
        // Normals follow the inverse transpose so they stay perpendicular under non-uniform
        // scale; a singular bake (zero scale) flattens the shape, whose normals are then moot.
        const std::optional<Affine3d> inv = item.bake.inverse();
        for (const Vec3f& n : g.normals) {
          Vec3d w = inv ? inv->transformTransposed(Vec3d(n)) : Vec3d{};
          const double len = length(w);
          out.normals.push_back(len > 0.0 ? Vec3f(w / len) : Vec3f{});
        }
      }
    }
    if (anyUvs) {
      if (g.uvs.empty())
        out.uvs.resize(out.positions.size(), Vec2f{});
      else
        out.uvs.insert(out.uvs.end(), g.uvs.begin(), g.uvs.end());
    }
  }
  return out;
}

Box3d bakedBounds(const ShapeNode& shape, const Affine3d& bake) {
  const Box3f b = shape.localBounds();
  if (b.empty()) return {};
  return bake.transformBox(Box3d(Vec3d(b.lower), Vec3d(b.upper)));
}

}  // namespace tg::sync
