// Polygon triangulation by ear clipping (concave polygons of IndexedFaceSet and Extrusion
// caps) and the face/vertex normal computations shared by the mesh builder and the
// coordinate deformer.
#include <cmath>

#include "X3dImpl.h"

namespace tg::x3d {
namespace {

struct P2 {
  double x = 0.0, y = 0.0;
};

double cross2(const P2& o, const P2& a, const P2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/// True when p lies inside or on triangle abc (counter-clockwise).
bool inTriangle(const P2& p, const P2& a, const P2& b, const P2& c) {
  return cross2(a, b, p) >= 0.0 && cross2(b, c, p) >= 0.0 && cross2(c, a, p) >= 0.0;
}

Vec3d newell(const std::vector<Vec3f>& pts) {
  Vec3d n;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec3d a(pts[i]), b(pts[(i + 1) % pts.size()]);
    n.x += (a.y - b.y) * (a.z + b.z);
    n.y += (a.z - b.z) * (a.x + b.x);
    n.z += (a.x - b.x) * (a.y + b.y);
  }
  return n;
}

void fan(std::size_t first, const std::vector<std::uint32_t>& ring,
         std::vector<std::uint32_t>& out) {
  for (std::size_t i = first + 1; i + 1 < ring.size(); ++i)
    out.insert(out.end(), {ring[first], ring[i], ring[i + 1]});
}

}  // namespace

bool triangulatePolygon(const std::vector<Vec3f>& points, std::size_t maxEarClip,
                        std::vector<std::uint32_t>& out) {
  const std::size_t n = points.size();
  std::vector<std::uint32_t> ring(n);
  for (std::size_t i = 0; i < n; ++i) ring[i] = static_cast<std::uint32_t>(i);
  if (n < 3) return true;
  if (n == 3) {
    out.insert(out.end(), {0u, 1u, 2u});
    return true;
  }
  if (n > maxEarClip) {
    fan(0, ring, out);
    return false;
  }
  // Project onto the plane of the Newell normal, keeping the polygon's winding
  // counter-clockwise in 2D, so convexity is a sign test.
  const Vec3d nn = newell(points);
  const int axis = maxDimension(abs(nn));
  if (nn[static_cast<std::size_t>(axis)] == 0.0) {
    fan(0, ring, out);  // degenerate (collinear or zero-area) polygon
    return true;
  }
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const bool flip = nn[static_cast<std::size_t>(axis)] < 0.0;
  std::vector<P2> p(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3d q(points[i]);
    p[i] = {q[static_cast<std::size_t>(u)], q[static_cast<std::size_t>(v)]};
    if (flip) p[i].x = -p[i].x;
  }
  // Ear clipping: repeatedly cut a convex corner whose triangle holds no other corner.
  std::size_t guard = 0;
  std::size_t i = 0;
  while (ring.size() > 3) {
    const std::size_t m = ring.size();
    const std::uint32_t a = ring[(i + m - 1) % m], b = ring[i % m], c = ring[(i + 1) % m];
    bool ear = cross2(p[a], p[b], p[c]) > 0.0;
    for (std::size_t k = 0; ear && k < m; ++k) {
      const std::uint32_t q = ring[k];
      if (q == a || q == b || q == c) continue;
      const P2& pq = p[q];
      // Corners coinciding with the ear's own do not block it (duplicate points).
      if ((pq.x == p[a].x && pq.y == p[a].y) || (pq.x == p[b].x && pq.y == p[b].y) ||
          (pq.x == p[c].x && pq.y == p[c].y))
        continue;
      if (inTriangle(pq, p[a], p[b], p[c])) ear = false;
    }
    if (ear) {
      out.insert(out.end(), {a, b, c});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i % m));
      guard = 0;
      if (i >= ring.size()) i = 0;
      continue;
    }
    i = (i + 1) % m;
    if (++guard > m) {
      // No ear left (self-intersecting or numerically degenerate): fan the rest.
      fan(0, ring, out);
      return false;
    }
  }
  out.insert(out.end(), {ring[0], ring[1], ring[2]});
  return true;
}

std::vector<Vec3f> faceNormals(const FaceTable& faces, const std::vector<Vec3f>& coords) {
  const std::size_t nf = faces.faceStart.size() - 1;
  std::vector<Vec3f> out(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    Vec3d n;
    const std::uint32_t b = faces.faceStart[f], e = faces.faceStart[f + 1];
    for (std::uint32_t k = b; k < e; ++k) {
      const auto ia = static_cast<std::size_t>(faces.faceCoords[k]);
      const auto ib = static_cast<std::size_t>(faces.faceCoords[k + 1 < e ? k + 1 : b]);
      if (ia >= coords.size() || ib >= coords.size()) continue;
      const Vec3d a(coords[ia]), c(coords[ib]);
      n.x += (a.y - c.y) * (a.z + c.z);
      n.y += (a.z - c.z) * (a.x + c.x);
      n.z += (a.x - c.x) * (a.y + c.y);
    }
    out[f] = Vec3f(n * 0.5);  // half the Newell vector: the polygon's area vector
  }
  return out;
}

std::vector<Vec3f> smoothNormals(const std::vector<Vec3f>& faceN, const MeshPart& part) {
  const std::size_t nv = part.smoothStart.size() - 1;
  std::vector<Vec3f> out(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    Vec3d s;
    for (std::uint32_t k = part.smoothStart[v]; k < part.smoothStart[v + 1]; ++k)
      s += Vec3d(faceN[part.smoothFaces[k]]);
    const double len = length(s);
    out[v] = len > 0.0 && std::isfinite(len) ? Vec3f(s / len) : Vec3f(0.0f, 1.0f, 0.0f);
  }
  return out;
}

}  // namespace tg::x3d
