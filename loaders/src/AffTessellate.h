/// @file AffTessellate.h
/// Triangle approximations of the analytic AFF/NFF primitives (private to the loaders library).
#pragma once

#include "tracegraph/loaders/AffDocument.h"

namespace tg::aff_detail {

/// Open cone or cylinder (no end caps) between `shape.base` (radius baseRadius) and
/// `shape.apex` (radius apexRadius): `segments` quads of 2 triangles each, or one triangle per
/// segment when a radius is zero. Smooth normals (perpendicular to the slanted surface) get
/// their own index triples; triangles are counter-clockwise seen from outside.
AffMesh tessellateCone(const AffShape& shape, int segments);

/// Sphere about `shape.base` with radius `shape.baseRadius`: `segments` around and
/// segments/2 rings (at least 2), giving 2·segments·(rings − 1) triangles, counter-clockwise
/// seen from outside, with unit normals.
AffMesh tessellateSphere(const AffShape& shape, int segments);

}  // namespace tg::aff_detail
