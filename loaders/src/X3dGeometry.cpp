// Polygon sets to meshes: validation of indices, triangulation, crease-angle normals and the
// split by colour (Mesh has no colour array: each colour becomes a mesh under its own
// Material).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>
#include <unordered_map>

#include "X3dImpl.h"

namespace tg::x3d {
namespace {

std::uint32_t bits(float f) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

bool inRange(std::int32_t i, std::size_t n) {
  return i >= 0 && static_cast<std::size_t>(i) < n;
}

/// Drops faces with bad coordinate indices and attributes with bad indices (warning once
/// each); returns the kept faces.
std::vector<std::uint32_t> validate(PolygonSet& s, const MeshContext& ctx) {
  std::vector<std::uint32_t> kept;
  std::size_t badIndex = 0, tooFew = 0;
  for (std::uint32_t f = 0; f < s.faceCount(); ++f) {
    const std::uint32_t b = s.faceStart[f], e = s.faceStart[f + 1];
    bool ok = true;
    for (std::uint32_t k = b; k < e && ok; ++k) ok = inRange(s.corners[k].coord, s.coords.size());
    if (!ok)
      ++badIndex;
    else if (e - b < 3)
      ++tooFew;
    else
      kept.push_back(f);
  }
  if (badIndex)
    ctx.warn(std::to_string(badIndex) + " face(s) with coordinate indices out of range dropped");
  if (tooFew) ctx.warn(std::to_string(tooFew) + " face(s) with fewer than 3 corners dropped");
  const auto check = [&](std::size_t n, auto&& index, const char* what) {
    if (n == 0) return true;
    for (const std::uint32_t f : kept)
      for (std::uint32_t k = s.faceStart[f]; k < s.faceStart[f + 1]; ++k)
        if (!inRange(index(f, k), n)) {
          ctx.warn(std::string(what) + " index out of range: " + what + "s ignored");
          return false;
        }
    return true;
  };
  const bool normalsOk =
      s.faceNormal.empty()
          ? check(
                s.normals.size(),
                [&](std::uint32_t, std::uint32_t k) { return s.corners[k].normal; }, "normal")
          : check(
                s.normals.size(), [&](std::uint32_t f, std::uint32_t) { return s.faceNormal[f]; },
                "normal");
  if (!normalsOk) s.normals.clear();
  if (!check(
          s.texCoords.size(), [&](std::uint32_t, std::uint32_t k) { return s.corners[k].tex; },
          "texture coordinate"))
    s.texCoords.clear();
  const bool colorsOk =
      s.faceColor.empty()
          ? check(
                s.colors.size(), [&](std::uint32_t, std::uint32_t k) { return s.corners[k].color; },
                "colour")
          : check(
                s.colors.size(), [&](std::uint32_t f, std::uint32_t) { return s.faceColor[f]; },
                "colour");
  if (!colorsOk) s.colors.clear();
  return kept;
}

/// Corner-level triangle: the face and three global corner indices.
struct Tri {
  std::uint32_t face;
  std::uint32_t c[3];
};

std::uint32_t quantise(const Color& c) {
  const auto q = [](float v) {
    return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
  };
  return q(c.r) << 16 | q(c.g) << 8 | q(c.b);
}

}  // namespace

std::vector<MeshPart> buildMeshes(PolygonSet s, const MeshContext& ctx) {
  const std::vector<std::uint32_t> kept = validate(s, ctx);
  if (kept.empty()) return {};

  // Faces in their final winding (reversed for ccw="false"), numbered densely.
  auto table = std::make_shared<FaceTable>();
  std::vector<Tri> tris;
  std::vector<Vec3f> pts;
  std::vector<std::uint32_t> local;
  std::size_t fanned = 0;
  for (std::uint32_t fi = 0; fi < kept.size(); ++fi) {
    const std::uint32_t f = kept[fi], b = s.faceStart[f], e = s.faceStart[f + 1];
    std::vector<std::uint32_t> order;
    for (std::uint32_t k = b; k < e; ++k) order.push_back(k);
    if (!s.ccw) std::reverse(order.begin(), order.end());
    pts.clear();
    for (const std::uint32_t k : order) {
      pts.push_back(s.coords[static_cast<std::size_t>(s.corners[k].coord)]);
      table->faceCoords.push_back(s.corners[k].coord);
    }
    table->faceStart.push_back(static_cast<std::uint32_t>(table->faceCoords.size()));
    local.clear();
    if (!triangulatePolygon(pts, ctx.options.maxEarClipCorners, local) && pts.size() > 3) ++fanned;
    for (std::size_t t = 0; t + 2 < local.size(); t += 3)
      tris.push_back({fi, {order[local[t]], order[local[t + 1]], order[local[t + 2]]}});
  }
  if (fanned)
    ctx.warn(std::to_string(fanned) + " polygon(s) could not be ear-clipped and were fanned");

  // Normals per corner: given (per vertex or per face) or computed with the crease angle.
  const std::vector<Vec3f> faceN = faceNormals(*table, s.coords);
  const bool given = !s.normals.empty();
  std::vector<Vec3f> cornerN(s.corners.size());
  std::vector<std::int32_t> cornerGiven(s.corners.size(), -1);
  std::vector<std::vector<std::uint32_t>> cornerSmooth;
  if (given) {
    for (std::uint32_t fi = 0; fi < kept.size(); ++fi)
      for (std::uint32_t k = s.faceStart[kept[fi]]; k < s.faceStart[kept[fi] + 1]; ++k) {
        const std::int32_t n = s.faceNormal.empty() ? s.corners[k].normal : s.faceNormal[kept[fi]];
        cornerGiven[k] = n;
        const Vec3f v = s.normals[static_cast<std::size_t>(n)];
        const float len = length(v);
        cornerN[k] = len > 0.0f ? v / len : Vec3f(0.0f, 1.0f, 0.0f);
      }
  } else {
    cornerSmooth.resize(s.corners.size());
    std::vector<std::vector<std::uint32_t>> coordFaces(s.coords.size());
    for (std::uint32_t fi = 0; fi < kept.size(); ++fi)
      for (std::uint32_t k = table->faceStart[fi]; k < table->faceStart[fi + 1]; ++k) {
        auto& list = coordFaces[static_cast<std::size_t>(table->faceCoords[k])];
        if (list.empty() || list.back() != fi) list.push_back(fi);
      }
    const double cosCrease = std::cos(static_cast<double>(std::clamp(s.creaseAngle, 0.0f, 3.2f)));
    for (std::uint32_t fi = 0; fi < kept.size(); ++fi) {
      const Vec3d nf(faceN[fi]);
      const double lf = length(nf);
      for (std::uint32_t k = s.faceStart[kept[fi]]; k < s.faceStart[kept[fi] + 1]; ++k) {
        std::vector<std::uint32_t>& set = cornerSmooth[k];
        if (s.creaseAngle <= 0.0f || lf == 0.0) {
          set.push_back(fi);
        } else {
          for (const std::uint32_t g : coordFaces[static_cast<std::size_t>(s.corners[k].coord)]) {
            const Vec3d ng(faceN[g]);
            const double lg = length(ng);
            if (g == fi || (lg > 0.0 && dot(nf, ng) >= cosCrease * lf * lg)) set.push_back(g);
          }
        }
        Vec3d sum;
        for (const std::uint32_t g : set) sum += Vec3d(faceN[g]);
        const double len = length(sum);
        cornerN[k] = len > 0.0 ? Vec3f(sum / len) : Vec3f(0.0f, 1.0f, 0.0f);
      }
    }
  }

  // Colour of each triangle, then the groups (one mesh each).
  std::vector<std::uint32_t> triGroup(tris.size(), 0);
  std::vector<Color> groupColor;
  if (!s.colors.empty()) {
    std::map<std::uint32_t, std::uint32_t> groups;
    std::vector<Color> triColor(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const std::uint32_t f = kept[tris[t].face];
      Color c;
      if (!s.faceColor.empty()) {
        c = s.colors[static_cast<std::size_t>(s.faceColor[f])];
      } else {
        for (const std::uint32_t k : tris[t].c) {
          const Color& ck = s.colors[static_cast<std::size_t>(s.corners[k].color)];
          c.r += ck.r / 3.0f, c.g += ck.g / 3.0f, c.b += ck.b / 3.0f;
        }
      }
      triColor[t] = c;
      const auto [it, added] =
          groups.emplace(quantise(c), static_cast<std::uint32_t>(groupColor.size()));
      if (added) groupColor.push_back(c);
      triGroup[t] = it->second;
    }
    if (groupColor.size() > ctx.options.maxColourGroups) {
      ctx.warn(std::to_string(groupColor.size()) + " distinct colours: the mean colour is used");
      Color mean;
      for (const Color& c : triColor) mean.r += c.r, mean.g += c.g, mean.b += c.b;
      const float n = static_cast<float>(triColor.size());
      groupColor = {Color{mean.r / n, mean.g / n, mean.b / n}};
      std::fill(triGroup.begin(), triGroup.end(), 0u);
    }
  }
  const std::size_t groupCount = std::max<std::size_t>(1, groupColor.size());

  std::vector<MeshPart> parts;
  const bool hasTex = !s.texCoords.empty();
  for (std::size_t g = 0; g < groupCount; ++g) {
    MeshPart part;
    part.faces = table;
    if (!groupColor.empty()) part.color = groupColor[g];
    using Key = std::tuple<std::int32_t, std::uint32_t, std::uint32_t, std::uint32_t, std::int32_t>;
    std::map<Key, std::int32_t> vertexOf;
    std::vector<Vec3f> points, normals;
    std::vector<Vec2f> uvs;
    std::vector<std::int32_t> indices;
    std::vector<std::vector<std::uint32_t>> smooth;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      if (triGroup[t] != g) continue;
      for (const std::uint32_t k : tris[t].c) {
        const Corner& c = s.corners[k];
        const Vec3f& n = cornerN[k];
        const Key key{c.coord, bits(n.x), bits(n.y), bits(n.z), hasTex ? c.tex : -1};
        const auto [it, added] = vertexOf.emplace(key, static_cast<std::int32_t>(points.size()));
        if (added) {
          points.push_back(s.coords[static_cast<std::size_t>(c.coord)]);
          normals.push_back(n);
          if (hasTex) uvs.push_back(s.texCoords[static_cast<std::size_t>(c.tex)]);
          part.vertexCoord.push_back(c.coord);
          if (given)
            part.vertexNormal.push_back(cornerGiven[k]);
          else
            smooth.push_back(cornerSmooth[k]);
        }
        indices.push_back(it->second);
      }
    }
    if (!given) {
      part.smoothStart.push_back(0);
      for (const auto& list : smooth) {
        part.smoothFaces.insert(part.smoothFaces.end(), list.begin(), list.end());
        part.smoothStart.push_back(static_cast<std::uint32_t>(part.smoothFaces.size()));
      }
    }
    part.mesh = nodes::Mesh::create(std::move(points), std::move(indices));
    part.mesh->normals = std::move(normals);
    if (hasTex) part.mesh->texCoords = std::move(uvs);
    parts.push_back(std::move(part));
  }
  return parts;
}

}  // namespace tg::x3d
