// Geometry commands of the AFF/NFF parser: m, p/pp, tt/ttp, c, s, tpa, and the material table.
#include <cmath>
#include <system_error>
#include <utility>

#include "AffParserImpl.h"
#include "AffTessellate.h"

namespace tg::aff_detail {
namespace {

bool allFinite(const std::vector<Vec3f>& v) {
  for (const Vec3f& p : v)
    if (!isFinite(p)) return false;
  return true;
}

}  // namespace

void AffParserImpl::parseMesh(Source& s, const AffToken& cmd) {
  AffMesh mesh;
  mesh.primitive = AffPrimitive::Mesh;
  mesh.where = where(s, cmd.line);
  expectKeyword(s, "vertices", "after 'm'");
  const std::uint32_t nv = readCount(s, "mesh vertex count", 3);
  mesh.positions.resize(nv);
  for (Vec3f& p : mesh.positions) p = readVec3f(s, "mesh vertex coordinate");

  const char* sectionWanted = "'normals', 'texturecoords' or 'triangles'";
  AffToken section = expectToken(s, sectionWanted);
  // A section that is present adds its three indices to every triangle row, even when empty.
  bool normalSection = false, uvSection = false;
  if (section.text == "normals") {
    normalSection = true;
    const std::uint32_t nn = readCount(s, "mesh normal count", 3);
    mesh.normals.resize(nn);
    for (Vec3f& n : mesh.normals) n = readVec3f(s, "mesh normal coordinate");
    section = expectToken(s, "'texturecoords' or 'triangles'");
  }
  std::string_view texture;
  if (section.text == "texturecoords") {
    uvSection = true;
    const std::uint32_t nt = readCount(s, "mesh texture coordinate count", 2);
    texture = readName(s, "mesh texture name");
    mesh.uvs.resize(nt);
    for (Vec2f& t : mesh.uvs) {
      t.u = readFloat(s, "mesh texture coordinate");
      t.v = readFloat(s, "mesh texture coordinate");
    }
    section = expectToken(s, "'triangles'");
  }
  if (section.text != "triangles") {
    fail(s, section.line,
         "expected " + std::string(sectionWanted) + " in the mesh started at line " +
             std::to_string(cmd.line) + ", found " + quoteToken(section.text));
  }
  const std::uint32_t columns = 3 * (1 + (normalSection ? 1 : 0) + (uvSection ? 1 : 0));
  const std::uint32_t nt = readCount(s, "mesh triangle count", columns);
  addTriangles(s, cmd.line, nt);
  mesh.positionIndices.resize(std::size_t{3} * nt);
  if (normalSection) mesh.normalIndices.resize(std::size_t{3} * nt);
  if (uvSection) mesh.uvIndices.resize(std::size_t{3} * nt);
  const auto nn = static_cast<std::uint32_t>(mesh.normals.size());
  const auto nuv = static_cast<std::uint32_t>(mesh.uvs.size());
  for (std::size_t t = 0; t < nt; ++t) {
    for (std::size_t c = 0; c < 3; ++c)
      mesh.positionIndices[3 * t + c] = readIndex(s, nv, "mesh vertex index");
    if (normalSection) {
      for (std::size_t c = 0; c < 3; ++c)
        mesh.normalIndices[3 * t + c] = readIndex(s, nn, "mesh normal index");
    }
    if (uvSection) {
      for (std::size_t c = 0; c < 3; ++c)
        mesh.uvIndices[3 * t + c] = readIndex(s, nuv, "mesh texture coordinate index");
    }
  }
  mesh.material = materialFor(s, cmd.line, texture, false);
  block().meshes.push_back(std::move(mesh));
}

void AffParserImpl::parsePolygon(Source& s, const AffToken& cmd, bool withNormals) {
  AffMesh mesh;
  mesh.primitive = AffPrimitive::Polygon;
  mesh.where = where(s, cmd.line);
  const std::uint32_t n = readCount(s, "polygon vertex count", withNormals ? 6 : 3);
  if (n < 3) fail(s, cmd.line, "a polygon needs at least 3 vertices, got " + std::to_string(n));
  addTriangles(s, cmd.line, n - 2);
  mesh.positions.resize(n);
  if (withNormals) mesh.normals.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    mesh.positions[i] = readVec3f(s, "polygon vertex coordinate");
    if (withNormals) mesh.normals[i] = readVec3f(s, "polygon normal coordinate");
  }
  // Planar convex polygons, counter-clockwise from the front: a fan keeps that orientation.
  mesh.positionIndices.reserve(3 * std::size_t{n - 2});
  for (std::uint32_t i = 1; i + 1 < n; ++i)
    mesh.positionIndices.insert(mesh.positionIndices.end(), {0, i, i + 1});
  if (withNormals) mesh.normalIndices = mesh.positionIndices;
  mesh.material = materialFor(s, cmd.line, {}, false);
  block().meshes.push_back(std::move(mesh));
}

void AffParserImpl::parseTexturedTriangle(Source& s, const AffToken& cmd, bool withNormals) {
  AffMesh mesh;
  mesh.primitive = AffPrimitive::TexturedTriangle;
  mesh.where = where(s, cmd.line);
  const std::string_view texture = readName(s, "texture name");
  addTriangles(s, cmd.line, 1);
  mesh.positions.resize(3);
  mesh.uvs.resize(3);
  if (withNormals) mesh.normals.resize(3);
  for (std::size_t i = 0; i < 3; ++i) {
    mesh.positions[i] = readVec3f(s, "textured triangle vertex coordinate");
    if (withNormals) mesh.normals[i] = readVec3f(s, "textured triangle normal coordinate");
    mesh.uvs[i].u = readFloat(s, "textured triangle texture coordinate");
    mesh.uvs[i].v = readFloat(s, "textured triangle texture coordinate");
  }
  mesh.positionIndices = {0, 1, 2};
  mesh.uvIndices = {0, 1, 2};
  if (withNormals) mesh.normalIndices = {0, 1, 2};
  mesh.material = materialFor(s, cmd.line, texture, false);
  block().meshes.push_back(std::move(mesh));
}

void AffParserImpl::parseCone(Source& s, const AffToken& cmd) {
  AffShape shape;
  shape.base = Vec3d(readVec3f(s, "cone base centre"));
  shape.baseRadius = static_cast<double>(readFloat(s, "cone base radius"));
  shape.apex = Vec3d(readVec3f(s, "cone apex centre"));
  shape.apexRadius = static_cast<double>(readFloat(s, "cone apex radius"));
  if (shape.baseRadius < 0.0 || shape.apexRadius < 0.0) fail(s, cmd.line, "negative cone radius");
  AffMesh mesh = tessellateCone(shape, opt_.coneSegments);
  if (!allFinite(mesh.positions)) fail(s, cmd.line, "cone too large for single precision");
  addTriangles(s, cmd.line, mesh.triangleCount());
  mesh.where = where(s, cmd.line);
  mesh.material = materialFor(s, cmd.line, {}, false);
  block().meshes.push_back(std::move(mesh));
}

void AffParserImpl::parseSphere(Source& s, const AffToken& cmd) {
  AffShape shape;
  shape.base = Vec3d(readVec3f(s, "sphere centre"));
  shape.baseRadius = static_cast<double>(readFloat(s, "sphere radius"));
  if (shape.baseRadius < 0.0) fail(s, cmd.line, "negative sphere radius");
  AffMesh mesh = tessellateSphere(shape, opt_.sphereSegments);
  if (!allFinite(mesh.positions)) fail(s, cmd.line, "sphere too large for single precision");
  addTriangles(s, cmd.line, mesh.triangleCount());
  mesh.where = where(s, cmd.line);
  mesh.material = materialFor(s, cmd.line, {}, false);
  block().meshes.push_back(std::move(mesh));
}

void AffParserImpl::parseAnimatedTriangle(Source& s, const AffToken& cmd) {
  AffAnimatedTriangle tri;
  tri.where = where(s, cmd.line);
  // Each key: a time and three rows of x y z nx ny nz.
  const std::uint32_t n = readCount(s, "'tpa' key count", 19);
  if (n < 1) fail(s, cmd.line, "'tpa' needs at least one key");
  addTriangles(s, cmd.line, 1);
  tri.keys.resize(n);
  for (AffAnimatedTriangle::Key& k : tri.keys) {
    k.time = readDouble(s, "'tpa' key time");
    for (std::size_t c = 0; c < 3; ++c) {
      k.positions[c] = readVec3f(s, "'tpa' vertex coordinate");
      k.normals[c] = readVec3f(s, "'tpa' normal coordinate");
    }
  }
  tri.material = materialFor(s, cmd.line, {}, true);
  block().animatedTriangles.push_back(std::move(tri));
}

std::uint32_t AffParserImpl::materialFor(const Source& s, std::uint32_t line,
                                         std::string_view texture, bool untextured) {
  // An NFF `f` may name a texture for the primitives after it; `tpa` is never textured.
  if (texture.empty() && !untextured) texture = nffTexture_;
  if (texture.empty() && plainMaterialIndex_ >= 0)
    return static_cast<std::uint32_t>(plainMaterialIndex_);
  AffMaterial m = material_;
  if (!texture.empty()) {
    m.textureName = std::string(texture);
    m.texturePath = resolveTexture(s, line, texture);
  }
  const MaterialKey key{
      {m.ambient.x, m.ambient.y, m.ambient.z, m.diffuse.x, m.diffuse.y, m.diffuse.z, m.specular.x,
       m.specular.y, m.specular.z, m.shine, m.transmittance, m.ior},
      m.textureName + '\n' + m.texturePath.string()};
  const auto [it, inserted] =
      materialIndex_.try_emplace(key, static_cast<std::uint32_t>(doc_.materials.size()));
  if (inserted) doc_.materials.push_back(std::move(m));
  if (texture.empty()) plainMaterialIndex_ = it->second;
  return it->second;
}

std::filesystem::path AffParserImpl::resolveTexture(const Source& s, std::uint32_t line,
                                                    std::string_view texture) {
  std::string cacheKey = s.dir.string();
  cacheKey += '\n';
  cacheKey += texture;
  const auto it = textureCache_.find(cacheKey);
  if (it != textureCache_.end()) return it->second;
  // BART keeps textures in ../TextureFiles relative to the aff folder; NFF samples keep them
  // beside the scene. Look beside the naming file first.
  const std::filesystem::path name{std::string(texture)};
  std::filesystem::path found;
  for (const std::filesystem::path& candidate :
       {s.dir / name, s.dir / ".." / "TextureFiles" / name}) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec)) {
      found = candidate.lexically_normal();
      break;
    }
  }
  if (found.empty()) {
    doc_.warnings.push_back(doc_.describe(where(s, line)) + ": texture " + quoteToken(texture) +
                            " not found beside the file or in ../TextureFiles/");
  }
  textureCache_.emplace(std::move(cacheKey), found);
  return found;
}

}  // namespace tg::aff_detail
