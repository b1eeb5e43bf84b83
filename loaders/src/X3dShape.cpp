// Shape, Appearance and geometry nodes: every polygonal geometry is reduced to a PolygonSet
// and meshed by buildMeshes; the parametric shapes are tessellated directly.
#include <algorithm>
#include <cmath>

#include "X3dReader.h"
#include "tracegraph/backend/Error.h"

namespace tg::x3d {
namespace {

bool isPolygonal(std::string_view n) {
  return n == "IndexedFaceSet" || n == "IndexedTriangleSet" || n == "TriangleSet" ||
         n == "IndexedTriangleFanSet" || n == "IndexedTriangleStripSet" || n == "TriangleFanSet" ||
         n == "TriangleStripSet";
}

bool isGeometry(std::string_view n) {
  return isPolygonal(n) || n == "Box" || n == "Sphere" || n == "Cone" || n == "Cylinder" ||
         n == "Extrusion";
}

void addFace(PolygonSet& s, std::initializer_list<std::int32_t> coords) {
  for (const std::int32_t c : coords) s.corners.push_back({c, c, c, c});
  s.faceStart.push_back(static_cast<std::uint32_t>(s.corners.size()));
}

/// X3D's default texture coordinates: S along the longest bounding-box side, T along the
/// second longest, both scaled by the longest side.
void defaultTexCoords(PolygonSet& s) {
  Box3f box;
  for (const Vec3f& p : s.coords) box.extend(p);
  if (box.empty()) return;
  const Vec3f e = box.extent();
  int a = maxDimension(e);
  int b = (a + 1) % 3, c = (a + 2) % 3;
  if (e[static_cast<std::size_t>(c)] > e[static_cast<std::size_t>(b)]) std::swap(b, c);
  const float size = e[static_cast<std::size_t>(a)] > 0.0f ? e[static_cast<std::size_t>(a)] : 1.0f;
  s.texCoords.clear();
  for (const Vec3f& p : s.coords) {
    const Vec3f d = p - box.lower;
    s.texCoords.push_back(
        {d[static_cast<std::size_t>(a)] / size, d[static_cast<std::size_t>(b)] / size});
  }
  for (Corner& k : s.corners) k.tex = k.coord;
}

Vec2f transformUv(const Affine3d& m, const Vec2f& uv) {
  const Vec3d p = m.transformPoint({uv.u, uv.v, 0.0});
  return {static_cast<float>(p.x), static_cast<float>(p.y)};
}

}  // namespace

ref_ptr<Node> FileReader::readShape(pugi::xml_node el, std::size_t depth) {
  ref_ptr<nodes::Separator> sep = nodes::Separator::create();
  DefEntry* e = define(el, graphEntry(sep, sep.get()));
  std::shared_ptr<AppearanceData> look;
  pugi::xml_node geometryEl;
  for (pugi::xml_node c = el.first_child(); c; c = c.next_sibling()) {
    if (c.type() != pugi::node_element) continue;
    const std::string_view n = c.name();
    if (depth + 1 > s_.options.maxNesting) fail(c, "elements nested too deeply");
    if (n == "Appearance") {
      look = readAppearance(c);
    } else if (isGeometry(n) || n == "Text" || n == "ElevationGrid" || n == "PointSet" ||
               n == "IndexedLineSet" || n == "LineSet") {
      if (geometryEl) warn(c, "Shape with two geometry nodes: the last one is used");
      geometryEl = c;
    } else if (!n.starts_with("Metadata")) {
      warn(c, "unsupported node " + std::string(n) + " in Shape skipped");
    }
  }
  if (!look) look = std::make_shared<AppearanceData>();
  if (look->texture) sep->addChild(look->texture);
  ref_ptr<nodes::Material> material = look->material;
  if (!material) material = nodes::Material::create();  // X3D's unlit white, approximated
  sep->addChild(material);
  if (geometryEl) {
    if (const std::shared_ptr<GeometryData> g = readGeometry(geometryEl, *look)) {
      for (const MeshPart& part : g->parts) {
        if (part.color) {
          // Colour nodes replace the diffuse colour; the rest of the material is kept.
          ref_ptr<nodes::Material> m = nodes::Material::create();
          m->ambientColor = material->ambientColor.getValue();
          m->diffuseColor = *part.color;
          m->specularColor = material->specularColor.getValue();
          m->emissiveColor = material->emissiveColor.getValue();
          m->shininess = material->shininess.getValue();
          m->transmittance = material->transmittance.getValue();
          sep->addChild(m);
        }
        sep->addChild(part.mesh);
      }
    }
  }
  if (e) e->complete = true;
  return sep;
}

std::shared_ptr<AppearanceData> FileReader::readAppearance(pugi::xml_node el) {
  if (!el.attribute("USE").empty()) {
    const DefEntry* e = use(el);
    return e ? e->appearance : nullptr;
  }
  auto look = std::make_shared<AppearanceData>();
  for (pugi::xml_node c = el.first_child(); c; c = c.next_sibling()) {
    if (c.type() != pugi::node_element) continue;
    const std::string_view n = c.name();
    if (n == "Material") {
      look->material = readMaterial(c);
    } else if (n == "ImageTexture") {
      if (!c.attribute("USE").empty()) {
        const DefEntry* e = use(c);
        if (e)
          look->texture = ref_ptr<nodes::Texture>(dynamic_cast<nodes::Texture*>(e->node.get()));
        continue;
      }
      std::filesystem::path found;
      const std::vector<std::string> urls = attrs(c).getStrings("url");
      for (const std::string& url : urls) {
        if (url.empty() || url.find("://") != std::string::npos) continue;
        std::error_code ec;
        if (std::filesystem::is_regular_file(src_.dir() / url, ec)) {
          found = (src_.dir() / url).lexically_normal();
          break;
        }
      }
      if (found.empty()) {
        warn(c, "ImageTexture: no url names an existing local image ('" +
                    (urls.empty() ? std::string() : urls[0]) + "'), texture dropped");
        continue;
      }
      look->texture = nodes::Texture::create(found.string());
      if (DefEntry* e = define(c, graphEntry(look->texture, nullptr))) e->complete = true;
    } else if (n == "TextureTransform") {
      const Attributes a = attrs(c);
      const Vec2f center = a.getVec2("center", {}), scale = a.getVec2("scale", {1.0f, 1.0f});
      const Vec2f translation = a.getVec2("translation", {});
      const double rot = a.getDouble("rotation", 0.0);
      // X3D: tc' = -C * S * R * C * T * tc.
      look->textureTransform = Affine3d::translation({-center.u, -center.v, 0.0}) *
                               Affine3d::scaling({scale.u, scale.v, 1.0}) *
                               rotationMatrix({{0.0f, 0.0f, 1.0f}, static_cast<float>(rot)}) *
                               Affine3d::translation({center.u, center.v, 0.0}) *
                               Affine3d::translation({translation.u, translation.v, 0.0});
      look->hasTextureTransform = true;
    } else if (!n.starts_with("Metadata")) {
      warn(c, "unsupported node " + std::string(n) + " in Appearance skipped");
    }
  }
  if (DefEntry* e = define(el, appearanceEntry(look))) e->complete = true;
  return look;
}

ref_ptr<nodes::Material> FileReader::readMaterial(pugi::xml_node el) {
  if (!el.attribute("USE").empty()) {
    const DefEntry* e = use(el);
    return e ? ref_ptr<nodes::Material>(dynamic_cast<nodes::Material*>(e->node.get())) : nullptr;
  }
  const Attributes a = attrs(el);
  ref_ptr<nodes::Material> m = nodes::Material::create();
  const Color diffuse = a.getColor("diffuseColor", {0.8f, 0.8f, 0.8f});
  const float ambient = std::clamp(a.getFloat("ambientIntensity", 0.2f), 0.0f, 1.0f);
  m->diffuseColor = diffuse;
  m->ambientColor = Color{diffuse.r * ambient, diffuse.g * ambient, diffuse.b * ambient};
  m->specularColor = a.getColor("specularColor", {});
  m->emissiveColor = a.getColor("emissiveColor", {});
  m->shininess = std::clamp(a.getFloat("shininess", 0.2f), 0.0f, 1.0f);
  m->transmittance = std::clamp(a.getFloat("transparency", 0.0f), 0.0f, 1.0f);
  if (DefEntry* e = define(el, graphEntry(m, m.get()))) e->complete = true;
  return m;
}

std::shared_ptr<AttributeData> FileReader::readAttribute(pugi::xml_node el) {
  if (!el.attribute("USE").empty()) {
    const DefEntry* e = use(el);
    return e ? e->attribute : nullptr;
  }
  const Attributes a = attrs(el);
  const std::string_view n = el.name();
  auto data = std::make_shared<AttributeData>();
  if (n == "Coordinate" || n == "CoordinateDouble")
    data->v3 = a.getVec3s("point");
  else if (n == "Normal")
    data->v3 = a.getVec3s("vector");
  else if (n == "TextureCoordinate")
    data->v2 = a.getVec2s("point");
  else if (n == "Color")
    data->colors = a.getColors("color", 3);
  else
    data->colors = a.getColors("color", 4);  // ColorRGBA: alpha has no Mesh counterpart
  if (DefEntry* e = define(el, attributeEntry(data))) e->complete = true;
  return data;
}

PolygonSet FileReader::readPolygons(pugi::xml_node el, std::shared_ptr<GeometryData>& geometry) {
  const Attributes a = attrs(el);
  const std::string_view type = el.name();
  PolygonSet s;
  std::shared_ptr<AttributeData> coord, normal, tex, color;
  for (pugi::xml_node c = el.first_child(); c; c = c.next_sibling()) {
    if (c.type() != pugi::node_element) continue;
    const std::string_view n = c.name();
    if (n == "Coordinate" || n == "CoordinateDouble")
      coord = readAttribute(c);
    else if (n == "Normal")
      normal = readAttribute(c);
    else if (n == "TextureCoordinate")
      tex = readAttribute(c);
    else if (n == "Color" || n == "ColorRGBA")
      color = readAttribute(c);
    else if (!n.starts_with("Metadata"))
      warn(c, "unsupported node " + std::string(n) + " in " + std::string(type) + " skipped");
  }
  if (coord || normal) routable_.push_back(geometry);
  if (coord) {
    s.coords = coord->v3;
    coord->users.push_back(geometry);
    geometry->coord = coord;
  }
  if (normal) {
    s.normals = normal->v3;
    normal->users.push_back(geometry);
    geometry->normal = normal;
  }
  if (tex) s.texCoords = tex->v2;
  if (color) s.colors = color->colors;
  s.ccw = a.getBool("ccw", true);
  const bool normalPerVertex = a.getBool("normalPerVertex", true);
  const bool colorPerVertex = a.getBool("colorPerVertex", true);

  if (type == "IndexedFaceSet") {
    s.creaseAngle = a.getFloat("creaseAngle", 0.0f);
    const std::vector<std::int32_t> ci = a.getInts("coordIndex"), ni = a.getInts("normalIndex"),
                                    ti = a.getInts("texCoordIndex"), ki = a.getInts("colorIndex");
    // Per-vertex attribute index lists parallel coordIndex; empty lists reuse coordIndex.
    const auto at = [](const std::vector<std::int32_t>& v, std::size_t p, std::int32_t dflt) {
      return v.empty() ? dflt : (p < v.size() ? v[p] : -1);
    };
    std::int32_t face = 0;
    for (std::size_t p = 0; p <= ci.size(); ++p) {
      if (p == ci.size() || ci[p] < 0) {
        if (s.corners.size() == s.faceStart.back()) continue;  // empty face ("-1 -1")
        s.faceStart.push_back(static_cast<std::uint32_t>(s.corners.size()));
        if (!normalPerVertex) s.faceNormal.push_back(at(ni, static_cast<std::size_t>(face), face));
        if (!colorPerVertex) s.faceColor.push_back(at(ki, static_cast<std::size_t>(face), face));
        ++face;
        continue;
      }
      s.corners.push_back({ci[p], normalPerVertex ? at(ni, p, ci[p]) : -1, at(ti, p, ci[p]),
                           colorPerVertex ? at(ki, p, ci[p]) : -1});
    }
    return s;
  }
  // The triangle sets: no creaseAngle field; generated normals are smooth or flat per
  // normalPerVertex.
  s.creaseAngle = normalPerVertex ? 3.2f : 0.0f;
  const std::vector<std::int32_t> index = a.getInts("index");
  const auto n = static_cast<std::int32_t>(s.coords.size());
  if (type == "IndexedTriangleSet") {
    for (std::size_t i = 0; i + 2 < index.size(); i += 3)
      addFace(s, {index[i], index[i + 1], index[i + 2]});
  } else if (type == "TriangleSet") {
    for (std::int32_t i = 0; i + 2 < n; i += 3) addFace(s, {i, i + 1, i + 2});
  } else {
    // Fans and strips, either as -1 separated index runs or as counts over the coordinates.
    std::vector<std::vector<std::int32_t>> runs(1);
    if (type.starts_with("Indexed")) {
      for (const std::int32_t i : index)
        if (i < 0)
          runs.emplace_back();
        else
          runs.back().push_back(i);
    } else {
      const std::vector<std::int32_t> counts =
          a.getInts(type == "TriangleFanSet" ? "fanCount" : "stripCount");
      std::int32_t next = 0;
      for (const std::int32_t c : counts) {
        std::vector<std::int32_t>& r = runs.back();
        for (std::int32_t k = 0; k < c && next < n; ++k) r.push_back(next++);
        runs.emplace_back();
      }
    }
    const bool fanType = type.find("Fan") != std::string_view::npos;
    for (const std::vector<std::int32_t>& r : runs)
      for (std::size_t k = 2; k < r.size(); ++k) {
        if (fanType)
          addFace(s, {r[0], r[k - 1], r[k]});
        else if (k % 2 == 0)
          addFace(s, {r[k - 2], r[k - 1], r[k]});
        else
          addFace(s, {r[k - 1], r[k - 2], r[k]});
      }
  }
  if (!normalPerVertex)
    for (std::size_t f = 0; f < s.faceCount(); ++f)
      s.faceNormal.push_back(static_cast<std::int32_t>(f));
  if (!colorPerVertex)
    for (std::size_t f = 0; f < s.faceCount(); ++f)
      s.faceColor.push_back(static_cast<std::int32_t>(f));
  return s;
}

std::shared_ptr<GeometryData> FileReader::readGeometry(pugi::xml_node el,
                                                       const AppearanceData& look) {
  const std::string_view type = el.name();
  if (!isGeometry(type)) {
    warn(el, "unsupported geometry " + std::string(type) + " skipped");
    return nullptr;
  }
  if (!el.attribute("USE").empty()) {
    const DefEntry* e = use(el);
    return e ? e->geometry : nullptr;
  }
  auto g = std::make_shared<GeometryData>();
  DefEntry* e = define(el, geometryEntry(g));
  const Attributes a = attrs(el);
  const MeshContext ctx{s_.options,
                        [&](const std::string& w) { warn(el, std::string(type) + ": " + w); }};
  const auto finishSet = [&](PolygonSet set) {
    if (look.texture && set.texCoords.empty()) defaultTexCoords(set);
    if (look.hasTextureTransform)
      for (Vec2f& uv : set.texCoords) uv = transformUv(look.textureTransform, uv);
    std::size_t corners = set.corners.size();
    countTriangles(el, corners);  // an upper bound until triangulated
    g->parts = buildMeshes(std::move(set), ctx);
    s_.triangles -= corners;
    for (const MeshPart& p : g->parts) countTriangles(el, p.mesh->triangleCount());
  };
  if (isPolygonal(type)) {
    finishSet(readPolygons(el, g));
  } else if (type == "Extrusion") {
    ExtrusionSpec spec;
    spec.spine = a.has("spine") ? a.getVec3s("spine")
                                : std::vector<Vec3f>{{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
    spec.crossSection = a.has("crossSection")
                            ? a.getVec2s("crossSection")
                            : std::vector<Vec2f>{{1, 1}, {1, -1}, {-1, -1}, {-1, 1}, {1, 1}};
    spec.scale = a.getVec2s("scale");
    spec.orientation = a.getRotations("orientation");
    spec.beginCap = a.getBool("beginCap", true);
    spec.endCap = a.getBool("endCap", true);
    spec.ccw = a.getBool("ccw", true);
    spec.creaseAngle = a.getFloat("creaseAngle", 0.0f);
    // Bound the sweep before building it: its size is the product of two lists.
    countTriangles(el, 2 * spec.spine.size() * spec.crossSection.size());
    s_.triangles -= 2 * spec.spine.size() * spec.crossSection.size();
    PolygonSet set = extrusionPolygons(spec);
    if (set.faceCount() == 0) warn(el, "Extrusion with fewer than 2 spine or cross-section points");
    finishSet(std::move(set));
  } else {
    ref_ptr<nodes::Mesh> m;
    const std::uint32_t slices = s_.options.cylinderSlices;
    if (type == "Box") {
      m = makeBox(a.getVec3("size", {2.0f, 2.0f, 2.0f}));
    } else if (type == "Sphere") {
      m = makeSphere(a.getFloat("radius", 1.0f), s_.options.sphereSlices, s_.options.sphereStacks);
    } else if (type == "Cylinder") {
      m = makeCylinder(a.getFloat("radius", 1.0f), a.getFloat("height", 2.0f),
                       a.getBool("bottom", true), a.getBool("side", true), a.getBool("top", true),
                       slices);
    } else {
      m = makeCone(a.getFloat("bottomRadius", 1.0f), a.getFloat("height", 2.0f),
                   a.getBool("bottom", true), a.getBool("side", true), slices);
    }
    if (look.hasTextureTransform)
      m->texCoords.edit([&](std::vector<Vec2f>& uvs) {
        for (Vec2f& uv : uvs) uv = transformUv(look.textureTransform, uv);
      });
    countTriangles(el, m->triangleCount());
    MeshPart part;
    part.mesh = m;
    g->parts.push_back(std::move(part));
  }
  if (e) e->complete = true;
  return g;
}

}  // namespace tg::x3d
