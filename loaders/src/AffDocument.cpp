#include "tracegraph/loaders/AffDocument.h"

#include <cmath>
#include <string>
#include <unordered_map>

#include "tracegraph/backend/Error.h"

namespace tg {
namespace {

/// A corner's attribute indices; vertices are shared between corners with equal triples.
struct CornerKey {
  std::uint32_t p, n, t;
  bool operator==(const CornerKey&) const = default;
};

struct CornerKeyHash {
  std::size_t operator()(const CornerKey& k) const {
    std::uint64_t h = (std::uint64_t{k.p} << 32) ^ (std::uint64_t{k.n} * 0x9E3779B97F4A7C15ull);
    h ^= std::uint64_t{k.t} * 0xC2B2AE3D27D4EB4Full;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

Vec3f unitOrZero(const Vec3d& v) {
  const double len = length(v);
  return len > 0.0 && std::isfinite(len) ? Vec3f(v / len) : Vec3f{0, 0, 0};
}

}  // namespace

TriangleMesh toTriangleMesh(const AffMesh& mesh) {
  const std::size_t corners = mesh.positionIndices.size();
  const bool hasNormals = !mesh.normalIndices.empty();
  const bool hasUvs = !mesh.uvIndices.empty();
  if (corners % 3 != 0 || (hasNormals && mesh.normalIndices.size() != corners) ||
      (hasUvs && mesh.uvIndices.size() != corners)) {
    throw Error("toTriangleMesh: index arrays must hold 3 entries per triangle");
  }
  TriangleMesh out;
  // Common case (all BART meshes without separate indices): one index already names a vertex.
  const bool sameNormals = !hasNormals || (mesh.normalIndices == mesh.positionIndices &&
                                           mesh.normals.size() == mesh.positions.size());
  const bool sameUvs = !hasUvs || (mesh.uvIndices == mesh.positionIndices &&
                                   mesh.uvs.size() == mesh.positions.size());
  if (sameNormals && sameUvs) {
    for (const std::uint32_t i : mesh.positionIndices) {
      if (i >= mesh.positions.size()) throw Error("toTriangleMesh: position index out of range");
    }
    out.positions = mesh.positions;
    out.indices = mesh.positionIndices;
    if (hasNormals) out.normals = mesh.normals;
    if (hasUvs) out.uvs = mesh.uvs;
    return out;
  }
  std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> vertexOf;
  vertexOf.reserve(corners);
  out.indices.reserve(corners);
  for (std::size_t c = 0; c < corners; ++c) {
    const CornerKey key{mesh.positionIndices[c], hasNormals ? mesh.normalIndices[c] : 0,
                        hasUvs ? mesh.uvIndices[c] : 0};
    if (key.p >= mesh.positions.size() || (hasNormals && key.n >= mesh.normals.size()) ||
        (hasUvs && key.t >= mesh.uvs.size())) {
      throw Error("toTriangleMesh: index out of range");
    }
    const auto [it, inserted] =
        vertexOf.try_emplace(key, static_cast<std::uint32_t>(out.positions.size()));
    if (inserted) {
      out.positions.push_back(mesh.positions[key.p]);
      if (hasNormals) out.normals.push_back(mesh.normals[key.n]);
      if (hasUvs) out.uvs.push_back(mesh.uvs[key.t]);
    }
    out.indices.push_back(it->second);
  }
  return out;
}

void AffAnimatedTriangle::evaluate(double t, std::array<Vec3f, 3>& positions,
                                   std::array<Vec3f, 3>& normals) const {
  if (keys.empty()) {
    positions = {};
    normals = {};
    return;
  }
  const Key* a = &keys.back();
  const Key* b = a;
  double w = 0.0;
  if (!(t > keys.front().time)) {
    a = b = &keys.front();
  } else if (!(t >= keys.back().time)) {
    for (std::size_t k = 0; k + 1 < keys.size(); ++k) {
      if (keys[k].time <= t && t < keys[k + 1].time) {
        a = &keys[k];
        b = &keys[k + 1];
        w = (t - a->time) / (b->time - a->time);
        break;
      }
    }
  }
  for (std::size_t c = 0; c < 3; ++c) {
    const Vec3d pa(a->positions[c]), pb(b->positions[c]);
    const Vec3d na(a->normals[c]), nb(b->normals[c]);
    positions[c] = Vec3f(pa + (pb - pa) * w);
    normals[c] = unitOrZero(na + (nb - na) * w);
  }
}

double AffAnimation::frameTime(int frame) const {
  if (frames <= 1) return start;
  return start + frame * (end - start) / (frames - 1);
}

Affine3d AffTrack::evaluate(double t) const {
  Affine3d m = rotation ? rotation->matrix(t) : Affine3d::identity();
  if (scale) {
    const Vec3d s = scale->evaluate(t);
    for (int r = 0; r < 3; ++r) {
      m.m[r][0] *= s.x;
      m.m[r][1] *= s.y;
      m.m[r][2] *= s.z;
    }
  }
  if (translation) {
    const Vec3d p = translation->evaluate(t);
    m.m[0][3] = p.x;
    m.m[1][3] = p.y;
    m.m[2][3] = p.z;
  }
  return m;
}

const AffTrack* AffDocument::findTrack(std::string_view name) const {
  const auto it = tracks.find(name);
  return it == tracks.end() ? nullptr : &it->second;
}

AffCamera AffDocument::camera(double t) const {
  AffCamera c;
  c.angle = view.angle;
  c.hither = view.effectiveHither();
  c.width = view.width;
  c.height = view.height;
  const AffTrack* track = cameraTrack();
  c.eye = track && track->translation ? track->translation->evaluate(t) : view.from;
  if (track && track->rotation) {
    const Affine3d r = track->rotation->matrix(t);
    c.direction = r.transformVector({0, 0, -1});
    c.up = r.transformVector({0, 1, 0});
  } else {
    const Vec3d d = view.at - view.from;
    c.direction = length(d) > 0.0 ? normalize(d) : Vec3d{0, 0, -1};
    c.up = view.up;
  }
  return c;
}

Affine3d AffDocument::blockMatrix(const AffBlock& block, double t) const {
  switch (block.kind) {
    case AffBlock::Kind::Static:
      return block.matrix;
    case AffBlock::Kind::Animated: {
      const AffTrack* track = findTrack(block.name);
      return track ? track->evaluate(t) : Affine3d::identity();
    }
    case AffBlock::Kind::Root:
      break;
  }
  return Affine3d::identity();
}

bool AffDocument::blockVisible(const AffBlock& block, double t) const {
  if (block.kind != AffBlock::Kind::Animated) return true;
  const AffTrack* track = findTrack(block.name);
  return !track || track->visibleAt(t);
}

Vec3d AffDocument::lightPosition(const AffLight& light, double t) const {
  if (light.track.empty()) return light.position;
  const AffTrack* track = findTrack(light.track);
  return track && track->translation ? track->translation->evaluate(t) : light.position;
}

std::string AffDocument::describe(const AffSourceLocation& where) const {
  const std::string file = where.file < files.size() ? files[where.file].string() : "?";
  return file + ":" + std::to_string(where.line);
}

AffTriangleCounts AffDocument::countTriangles() const {
  AffTriangleCounts n;
  // Explicit stack: documents built by hand may nest deeper than the parser allows.
  std::vector<const AffBlock*> todo{&root};
  while (!todo.empty()) {
    const AffBlock* b = todo.back();
    todo.pop_back();
    for (const AffBlock& child : b->children) todo.push_back(&child);
    n.animated += b->animatedTriangles.size();
    for (const AffMesh& m : b->meshes) {
      ++n.meshCount;
      const std::size_t tris = m.triangleCount();
      switch (m.primitive) {
        case AffPrimitive::Mesh:
          n.meshes += tris;
          break;
        case AffPrimitive::Polygon:
          n.polygons += tris;
          break;
        case AffPrimitive::TexturedTriangle:
          n.texturedTriangles += tris;
          break;
        case AffPrimitive::Cone:
          n.cones += tris;
          ++n.coneCount;
          break;
        case AffPrimitive::Sphere:
          n.spheres += tris;
          ++n.sphereCount;
          break;
      }
    }
  }
  return n;
}

}  // namespace tg
