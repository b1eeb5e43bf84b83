// X3D's parametric geometry: Box, Sphere, Cone, Cylinder tessellated with normals and the
// standard texture mapping, and Extrusion swept into a polygon set.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "X3dImpl.h"

namespace tg::x3d {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Collects vertices and triangles (counter-clockwise seen from outside).
struct Builder {
  std::vector<Vec3f> p, n;
  std::vector<Vec2f> uv;
  std::vector<std::int32_t> idx;
  std::int32_t add(const Vec3d& pos, const Vec3d& nrm, double u, double v) {
    p.push_back(Vec3f(pos));
    n.push_back(Vec3f(nrm));
    uv.push_back({static_cast<float>(u), static_cast<float>(v)});
    return static_cast<std::int32_t>(p.size() - 1);
  }
  void tri(std::int32_t a, std::int32_t b, std::int32_t c) { idx.insert(idx.end(), {a, b, c}); }
  ref_ptr<nodes::Mesh> mesh() {
    ref_ptr<nodes::Mesh> m = nodes::Mesh::create(std::move(p), std::move(idx));
    m->normals = std::move(n);
    m->texCoords = std::move(uv);
    return m;
  }
};

/// Point on the unit circle at fraction u of a turn, starting at the back (-Z) and running
/// counter-clockwise seen from +Y, as X3D's texture mapping of round shapes requires.
Vec3d around(double u) {
  const double a = u * kTwoPi;
  return {-std::sin(a), 0.0, -std::cos(a)};
}

/// A disc cap at height y facing `up` (+1 top, -1 bottom) with a centre vertex.
void cap(Builder& b, double radius, double y, double up, std::uint32_t slices) {
  const std::int32_t centre = b.add({0.0, y, 0.0}, {0.0, up, 0.0}, 0.5, 0.5);
  std::vector<std::int32_t> ring;
  for (std::uint32_t i = 0; i <= slices; ++i) {
    const Vec3d d = around(static_cast<double>(i) / slices);
    // Texture: the cap as seen from outside, +X to the right.
    ring.push_back(b.add({d.x * radius, y, d.z * radius}, {0.0, up, 0.0}, 0.5 + 0.5 * d.x,
                         0.5 - 0.5 * d.z * up));
  }
  for (std::uint32_t i = 0; i < slices; ++i) {
    if (up > 0)
      b.tri(centre, ring[i], ring[i + 1]);
    else
      b.tri(centre, ring[i + 1], ring[i]);
  }
}

}  // namespace

ref_ptr<nodes::Mesh> makeBox(Vec3f size) {
  Builder b;
  const Vec3d h = Vec3d(size) * 0.5;
  // Each face: normal, and the axes (right, up) of its texture as seen from outside.
  const Vec3d faces[6][3] = {
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}};
  for (const auto& f : faces) {
    std::int32_t v[4];
    for (int k = 0; k < 4; ++k) {
      const double s = (k == 1 || k == 2) ? 1.0 : -1.0, t = k >= 2 ? 1.0 : -1.0;
      const Vec3d d = f[0] + f[1] * s + f[2] * t;
      v[k] = b.add(d * h, f[0], 0.5 * (s + 1.0), 0.5 * (t + 1.0));
    }
    b.tri(v[0], v[1], v[2]);
    b.tri(v[0], v[2], v[3]);
  }
  return b.mesh();
}

ref_ptr<nodes::Mesh> makeSphere(float radius, std::uint32_t slices, std::uint32_t stacks) {
  slices = std::max(slices, 3u);
  stacks = std::max(stacks, 2u);
  Builder b;
  const double r = radius;
  for (std::uint32_t j = 0; j <= stacks; ++j) {
    const double v = 1.0 - static_cast<double>(j) / stacks;  // 1 at the north pole
    const double phi = (1.0 - v) * std::numbers::pi;
    for (std::uint32_t i = 0; i <= slices; ++i) {
      const double u = static_cast<double>(i) / slices;
      const Vec3d d = around(u) * std::sin(phi) + Vec3d(0.0, std::cos(phi), 0.0);
      b.add(d * r, d, u, v);
    }
  }
  const auto at = [&](std::uint32_t j, std::uint32_t i) {
    return static_cast<std::int32_t>(j * (slices + 1) + i);
  };
  for (std::uint32_t j = 0; j < stacks; ++j)
    for (std::uint32_t i = 0; i < slices; ++i) {
      // Pole rows collapse to one triangle per slice.
      if (j != 0) b.tri(at(j, i), at(j + 1, i), at(j, i + 1));
      if (j + 1 != stacks) b.tri(at(j, i + 1), at(j + 1, i), at(j + 1, i + 1));
    }
  return b.mesh();
}

ref_ptr<nodes::Mesh> makeCylinder(float radius, float height, bool bottom, bool side, bool top,
                                  std::uint32_t slices) {
  slices = std::max(slices, 3u);
  Builder b;
  const double r = radius, h = 0.5 * static_cast<double>(height);
  if (side) {
    std::vector<std::int32_t> lo, hi;
    for (std::uint32_t i = 0; i <= slices; ++i) {
      const double u = static_cast<double>(i) / slices;
      const Vec3d d = around(u);
      lo.push_back(b.add({d.x * r, -h, d.z * r}, d, u, 0.0));
      hi.push_back(b.add({d.x * r, h, d.z * r}, d, u, 1.0));
    }
    for (std::uint32_t i = 0; i < slices; ++i) {
      b.tri(lo[i], lo[i + 1], hi[i + 1]);
      b.tri(lo[i], hi[i + 1], hi[i]);
    }
  }
  if (top) cap(b, r, h, 1.0, slices);
  if (bottom) cap(b, r, -h, -1.0, slices);
  return b.mesh();
}

ref_ptr<nodes::Mesh> makeCone(float radius, float height, bool bottom, bool side,
                              std::uint32_t slices) {
  slices = std::max(slices, 3u);
  Builder b;
  const double r = radius, h = 0.5 * static_cast<double>(height);
  if (side) {
    const double slant = std::sqrt(r * r + 4.0 * h * h);
    const double ny = slant > 0.0 ? r / slant : 0.0, nr = slant > 0.0 ? 2.0 * h / slant : 1.0;
    for (std::uint32_t i = 0; i < slices; ++i) {
      const double u0 = static_cast<double>(i) / slices, u1 = static_cast<double>(i + 1) / slices;
      const Vec3d d0 = around(u0), d1 = around(u1), dm = around(0.5 * (u0 + u1));
      const std::int32_t a = b.add({d0.x * r, -h, d0.z * r}, d0 * nr + Vec3d(0, ny, 0), u0, 0.0);
      const std::int32_t c = b.add({d1.x * r, -h, d1.z * r}, d1 * nr + Vec3d(0, ny, 0), u1, 0.0);
      const std::int32_t apex =
          b.add({0.0, h, 0.0}, dm * nr + Vec3d(0, ny, 0), 0.5 * (u0 + u1), 1.0);
      b.tri(a, c, apex);
    }
  }
  if (bottom) cap(b, r, -h, -1.0, slices);
  return b.mesh();
}

PolygonSet extrusionPolygons(const ExtrusionSpec& spec) {
  PolygonSet s;
  s.ccw = spec.ccw;
  s.creaseAngle = spec.creaseAngle;
  const std::vector<Vec3f>& sp = spec.spine;
  const std::vector<Vec2f>& cs = spec.crossSection;
  const std::size_t n = sp.size(), m = cs.size();
  if (n < 2 || m < 2) return s;
  const bool closedSpine = sp.front() == sp.back();
  const bool closedCs = cs.front() == cs.back();
  // Spine-aligned cross-section planes (X3D 13.3.5): Y along the spine, Z from the bend.
  std::vector<Vec3d> ys(n), zs(n);
  const auto d = [&](std::size_t a, std::size_t b) { return Vec3d(sp[a]) - Vec3d(sp[b]); };
  for (std::size_t i = 0; i < n; ++i) {
    if (i == 0)
      ys[i] = closedSpine && n > 2 ? d(1, n - 2) : d(1, 0);
    else if (i == n - 1)
      ys[i] = closedSpine && n > 2 ? d(1, n - 2) : d(n - 1, n - 2);
    else
      ys[i] = d(i + 1, i - 1);
    if (i > 0 && i < n - 1)
      zs[i] = cross(d(i + 1, i), d(i - 1, i));
    else if (closedSpine && n > 2)
      zs[i] = cross(d(1, 0), d(n - 2, 0));
  }
  if (!closedSpine) {
    zs[0] = n > 2 ? zs[1] : Vec3d();
    zs[n - 1] = n > 2 ? zs[n - 2] : Vec3d();
  }
  Vec3d firstY, firstZ;
  for (std::size_t i = 0; i < n; ++i) {
    if (length(ys[i]) > 0.0 && length(firstY) == 0.0) firstY = ys[i];
    if (length(zs[i]) > 0.0 && length(firstZ) == 0.0) firstZ = zs[i];
  }
  if (length(firstY) == 0.0) firstY = {0.0, 1.0, 0.0};
  firstY = normalize(firstY);
  if (length(firstZ) == 0.0 || length(cross(firstZ, firstY)) == 0.0) {
    // Straight spine: the rotation taking +Y to the spine direction, applied to +Z.
    const Vec3d axis = cross(Vec3d(0.0, 1.0, 0.0), firstY);
    const double angle = std::acos(std::clamp(firstY.y, -1.0, 1.0));
    firstZ = length(axis) > 1e-12
                 ? rotate(toQuaternion({Vec3f(normalize(axis)), static_cast<float>(angle)}),
                          Vec3d(0.0, 0.0, 1.0))
                 : Vec3d(0.0, 0.0, firstY.y >= 0.0 ? 1.0 : -1.0);
  }
  Vec3d prevY = firstY, prevZ = normalize(firstZ);
  std::size_t ring = closedCs ? m - 1 : m;
  const std::size_t rings = closedSpine ? n - 1 : n;
  for (std::size_t i = 0; i < n; ++i) {
    Vec3d y = length(ys[i]) > 0.0 ? normalize(ys[i]) : prevY;
    Vec3d z = length(zs[i]) > 0.0 ? normalize(zs[i]) : prevZ;
    if (dot(z, prevZ) < 0.0) z = -z;
    prevY = y, prevZ = z;
    const Vec3d x = cross(y, z);
    if (i >= rings) break;
    const Vec2f sc =
        spec.scale.empty() ? Vec2f{1.0f, 1.0f} : spec.scale[std::min(i, spec.scale.size() - 1)];
    const Quaternion q =
        spec.orientation.empty()
            ? Quaternion{}
            : toQuaternion(spec.orientation[std::min(i, spec.orientation.size() - 1)]);
    for (std::size_t j = 0; j < ring; ++j) {
      const Vec3d local = rotate(q, Vec3d(cs[j].u * sc.u, 0.0, cs[j].v * sc.v));
      s.coords.push_back(Vec3f(Vec3d(sp[i]) + x * local.x + y * local.y + z * local.z));
    }
  }
  const auto coord = [&](std::size_t i, std::size_t j) {
    return static_cast<std::int32_t>((i % rings) * ring + (j % ring));
  };
  // Side texture: u along the cross-section, v along the spine (both by length).
  std::vector<double> us(m, 0.0), vs(n, 0.0);
  for (std::size_t j = 1; j < m; ++j)
    us[j] =
        us[j - 1] + static_cast<double>(std::hypot(cs[j].u - cs[j - 1].u, cs[j].v - cs[j - 1].v));
  for (std::size_t i = 1; i < n; ++i) vs[i] = vs[i - 1] + length(d(i, i - 1));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < m; ++j)
      s.texCoords.push_back({static_cast<float>(us.back() > 0 ? us[j] / us.back() : 0.0),
                             static_cast<float>(vs.back() > 0 ? vs[i] / vs.back() : 0.0)});
  const auto addFace = [&](std::initializer_list<std::pair<std::int32_t, std::int32_t>> cs2) {
    for (const auto& [c, t] : cs2) s.corners.push_back({c, -1, t, -1});
    s.faceStart.push_back(static_cast<std::uint32_t>(s.corners.size()));
  };
  const auto tex = [&](std::size_t i, std::size_t j) {
    return static_cast<std::int32_t>(i * m + j);
  };
  for (std::size_t i = 0; i + 1 < n; ++i)
    for (std::size_t j = 0; j + 1 < m; ++j)
      addFace({{coord(i, j), tex(i, j)},
               {coord(i, j + 1), tex(i, j + 1)},
               {coord(i + 1, j + 1), tex(i + 1, j + 1)},
               {coord(i + 1, j), tex(i + 1, j)}});
  // Caps (never on a closed spine): the cross-section polygon, textured by its bounds.
  if (!closedSpine && ring >= 3 && (spec.beginCap || spec.endCap)) {
    float lo[2] = {cs[0].u, cs[0].v}, hi[2] = {cs[0].u, cs[0].v};
    for (const Vec2f& c : cs) {
      lo[0] = std::min(lo[0], c.u), lo[1] = std::min(lo[1], c.v);
      hi[0] = std::max(hi[0], c.u), hi[1] = std::max(hi[1], c.v);
    }
    const float size = std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-30f});
    const auto capTex = static_cast<std::int32_t>(s.texCoords.size());
    for (std::size_t j = 0; j < ring; ++j)
      s.texCoords.push_back({(cs[j].u - lo[0]) / size, (cs[j].v - lo[1]) / size});
    if (spec.beginCap) {
      for (std::size_t j = ring; j-- > 0;)
        s.corners.push_back({coord(0, j), -1, capTex + static_cast<std::int32_t>(j), -1});
      s.faceStart.push_back(static_cast<std::uint32_t>(s.corners.size()));
    }
    if (spec.endCap) {
      for (std::size_t j = 0; j < ring; ++j)
        s.corners.push_back({coord(n - 1, j), -1, capTex + static_cast<std::int32_t>(j), -1});
      s.faceStart.push_back(static_cast<std::uint32_t>(s.corners.size()));
    }
  }
  return s;
}

}  // namespace tg::x3d
