/// @file ReferenceIntersector.h
/// The judge of every accelerator: brute force over all triangles, in double precision.
///
/// It reads a committed Scene's meshes and double-precision instance matrices (never its
/// accelerators or float matrices), flattens every instance into world space in double, and
/// answers closest-hit and any-hit queries by testing every triangle. Besides the answer it
/// reports whether the answer is *ambiguous* in float: a hit within a relative 4e-6 (of the
/// coordinates' magnitude, measured perpendicular to the ray) of a triangle edge or of the
/// ray's ends, or two triangles at nearly the same t. Differential tests
/// compare exactly where the reference is unambiguous and accept either answer where it is not.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/Scene.h"

namespace tg {

/// A reference answer.
struct ReferenceHit {
  /// True when a triangle is hit.
  bool hit = false;
  /// Distance of the closest hit, in double.
  double t = 0.0;
  /// Instance of the closest hit.
  std::uint32_t instanceId = kInvalidId;
  /// Triangle of the closest hit.
  std::uint32_t primId = kInvalidId;
  /// Hit/miss could flip under float rounding (grazing an edge, or t at tnear/tfar).
  bool hitAmbiguous = false;
  /// Another triangle is hit within the t tolerance, so either may be reported.
  bool primAmbiguous = false;
};

/// Brute-force double-precision ray queries over a flattened copy of a scene.
class ReferenceIntersector {
 public:
  /// Flattens the committed state of `scene` (every live instance of every object).
  explicit ReferenceIntersector(const Scene& scene);

  /// Closest hit in [tnear, tfar], with its ambiguity flags.
  ReferenceHit intersect(const Ray& ray) const;
  /// Any hit in [tnear, tfar]; `ambiguous` (optional) is set when the answer could flip.
  bool occluded(const Ray& ray, bool* ambiguous = nullptr) const;
  /// t of the ray against one instanced triangle, if it hits (edges inclusive, no tolerance).
  std::optional<double> intersectTriangle(const Ray& ray, std::uint32_t instanceId,
                                          std::uint32_t primId) const;
  /// Tolerance in t units for comparisons and ambiguity: 4e-6 of the magnitude of the origin
  /// and hit point, divided by the direction's length.
  static double tolerance(const Ray& ray, double t);

  /// Triangles of the flattened scene.
  std::size_t triangleCount() const { return triangles_.size(); }

 private:
  struct Triangle {
    Vec3d v0, v1, v2;
    std::uint32_t instanceId, primId;
  };
  std::vector<Triangle> triangles_;
  std::vector<std::vector<std::size_t>> index_;  ///< [instance][prim] -> triangles_ slot
};

}  // namespace tg
