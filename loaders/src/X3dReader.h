// The X3D element walk: one FileReader per file (each file has its own DEF names, as X3D
// Inline scoping requires), sharing a Session with the limits, the Inline cache and the result.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "X3dImpl.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/nodes/Texture.h"
#include "tracegraph/scenegraph/Group.h"

namespace tg::x3d {

/// State shared by every file of one load.
struct Session {
  Session(const X3dOptions& o, LoadedScene& result) : options(o), out(result) {}
  const X3dOptions& options;
  LoadedScene& out;
  std::size_t triangles = 0;
  std::vector<std::filesystem::path> inlineStack;  ///< canonical paths being read
  std::map<std::filesystem::path, ref_ptr<nodes::Separator>> inlineCache;
  std::vector<ref_ptr<TimeSensor>> timeSensors;
};

/// Appearance: the material, texture and texture transform of a Shape.
struct AppearanceData {
  ref_ptr<nodes::Material> material;  ///< null: the default material
  ref_ptr<nodes::Texture> texture;
  bool hasTextureTransform = false;
  Affine3d textureTransform;  ///< acts on (s, t, 0)
};

struct GeometryData;

/// Coordinate, Normal, TextureCoordinate, Color values, and the geometry built from them (for
/// ROUTEs into Coordinate.point and Normal.vector).
struct AttributeData {
  std::vector<Vec3f> v3;
  std::vector<Vec2f> v2;
  std::vector<Color> colors;
  std::vector<std::weak_ptr<GeometryData>> users;
};

/// A geometry node's meshes, shared by every Shape that USEs it.
struct GeometryData {
  std::vector<MeshPart> parts;
  std::vector<ref_ptr<MeshDeformer>> deformers;  ///< per part, created by the first ROUTE
  std::shared_ptr<AttributeData> coord, normal;
};

/// A DEF name: what USE inserts and what ROUTEs address.
struct DefEntry {
  std::string type;  ///< element name
  int line = 0;
  bool complete = false;   ///< false while the element is read: a USE then is recursive
  ref_ptr<Node> node;      ///< the graph node inserted by USE (or the animator)
  Node* target = nullptr;  ///< the node whose fields ROUTEs address
  std::shared_ptr<AppearanceData> appearance;
  std::shared_ptr<GeometryData> geometry;
  std::shared_ptr<AttributeData> attribute;
};

/// DEF entry of a node in the graph (or an animator) whose fields ROUTEs address at `target`.
inline DefEntry graphEntry(ref_ptr<Node> node, Node* target) {
  DefEntry e;
  e.node = std::move(node);
  e.target = target;
  return e;
}
/// DEF entry of an Appearance.
inline DefEntry appearanceEntry(std::shared_ptr<AppearanceData> data) {
  DefEntry e;
  e.appearance = std::move(data);
  return e;
}
/// DEF entry of a geometry node.
inline DefEntry geometryEntry(std::shared_ptr<GeometryData> data) {
  DefEntry e;
  e.geometry = std::move(data);
  return e;
}
/// DEF entry of a Coordinate, Normal, TextureCoordinate or Color.
inline DefEntry attributeEntry(std::shared_ptr<AttributeData> data) {
  DefEntry e;
  e.attribute = std::move(data);
  return e;
}

/// A ROUTE, resolved once the whole file is read.
struct RouteSpec {
  std::string fromNode, fromField, toNode, toField;
  int line = 0;
};

/// Reads one file's Scene into a Separator.
class FileReader {
 public:
  FileReader(Session& session, const SourceText& source, std::size_t inlineDepth)
      : s_(session), src_(source), inlineDepth_(inlineDepth) {}
  /// Reads the children of `scene` and resolves the ROUTEs.
  ref_ptr<nodes::Separator> readScene(pugi::xml_node scene);

 private:
  // X3dReader.cpp
  ref_ptr<Node> readNode(pugi::xml_node el, std::size_t depth);
  void readChildren(pugi::xml_node el, Group& into, std::size_t depth, bool keepIndices);
  ref_ptr<Node> readGrouping(pugi::xml_node el, std::size_t depth);
  ref_ptr<Node> readTransform(pugi::xml_node el, std::size_t depth);
  ref_ptr<Node> readSwitch(pugi::xml_node el, std::size_t depth);
  ref_ptr<Node> readViewpoint(pugi::xml_node el);
  ref_ptr<Node> readLight(pugi::xml_node el);
  ref_ptr<Node> readInline(pugi::xml_node el);
  void readBackground(pugi::xml_node el);
  // X3dShape.cpp
  ref_ptr<Node> readShape(pugi::xml_node el, std::size_t depth);
  std::shared_ptr<AppearanceData> readAppearance(pugi::xml_node el);
  ref_ptr<nodes::Material> readMaterial(pugi::xml_node el);
  std::shared_ptr<GeometryData> readGeometry(pugi::xml_node el, const AppearanceData& look);
  std::shared_ptr<AttributeData> readAttribute(pugi::xml_node el);
  PolygonSet readPolygons(pugi::xml_node el, std::shared_ptr<GeometryData>& geometry);
  // X3dRoutes.cpp
  void readAnimator(pugi::xml_node el);
  void readRoute(pugi::xml_node el);
  void resolveRoutes();
  void connectInto(const RouteSpec& r, Field& from, DefEntry& to);

  /// Looks up `USE` of `el`: null with a warning for unknown names, tg::Error for a node
  /// still being read (it would contain itself).
  DefEntry* use(pugi::xml_node el);
  /// Registers the element's DEF (incomplete until finish()).
  DefEntry* define(pugi::xml_node el, DefEntry entry);
  void warn(pugi::xml_node el, const std::string& what);
  void warnAt(int line, const std::string& what);
  [[noreturn]] void fail(pugi::xml_node el, const std::string& what) const;
  void countTriangles(pugi::xml_node el, std::size_t triangles);
  Attributes attrs(pugi::xml_node el) const { return Attributes(src_, el); }

  Session& s_;
  const SourceText& src_;
  std::size_t inlineDepth_;
  std::map<std::string, DefEntry, std::less<>> defs_;
  std::vector<RouteSpec> routes_;
  /// Geometry built from Coordinate/Normal nodes, kept until the ROUTEs are resolved.
  std::vector<std::shared_ptr<GeometryData>> routable_;
};

/// Parses and reads one file (or text) with its own DEF scope.
ref_ptr<nodes::Separator> readX3dText(Session& session, std::string_view text,
                                      const std::string& name, const std::filesystem::path& dir,
                                      std::size_t inlineDepth);

}  // namespace tg::x3d
