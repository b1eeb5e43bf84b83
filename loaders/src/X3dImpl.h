// Internals of the X3D loader shared by its source files: attribute parsing with file/line
// messages, the polygon-set representation every geometry node is reduced to, mesh building,
// and the animators that the nodes library does not provide.
#pragma once

#include <pugixml.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tracegraph/loaders/X3dLoader.h"
#include "tracegraph/nodes/Deformer.h"
#include "tracegraph/nodes/Material.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/TimeSensor.h"
#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/Color.h"
#include "tracegraph/scenegraph/MField.h"
#include "tracegraph/scenegraph/Rotation.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::x3d {

// ---------------------------------------------------------------------------------------------
// Source text and attribute values (X3dValues.cpp)

/// One parsed X3D file: its name for messages and the offsets of its lines.
class SourceText {
 public:
  SourceText(std::string name, std::filesystem::path dir, std::string_view text);
  const std::string& name() const { return name_; }
  /// Folder that relative urls resolve against.
  const std::filesystem::path& dir() const { return dir_; }
  /// 1-based line of a character offset.
  int lineAt(std::ptrdiff_t offset) const;
  /// 1-based line of an element.
  int line(const pugi::xml_node& node) const { return lineAt(node.offset_debug()); }
  /// "file:line: " prefix for messages.
  std::string where(int line) const;

 private:
  std::string name_;
  std::filesystem::path dir_;
  std::vector<std::size_t> lineStarts_;
};

/// Typed access to an element's attributes. Malformed values throw tg::Error naming the file,
/// line, element and attribute; absent attributes give the default.
class Attributes {
 public:
  Attributes(const SourceText& source, pugi::xml_node node) : src_(source), node_(node) {}
  bool has(const char* name) const;
  int line() const { return src_.line(node_); }
  std::string getString(const char* name, const std::string& def = {}) const;
  std::vector<std::string> getStrings(const char* name) const;
  bool getBool(const char* name, bool def) const;
  float getFloat(const char* name, float def) const;
  double getDouble(const char* name, double def) const;
  std::int32_t getInt(const char* name, std::int32_t def) const;
  Vec2f getVec2(const char* name, Vec2f def) const;
  Vec3f getVec3(const char* name, Vec3f def) const;
  Color getColor(const char* name, Color def) const;
  Rotation getRotation(const char* name, Rotation def) const;
  std::vector<float> getFloats(const char* name) const;
  std::vector<std::int32_t> getInts(const char* name) const;
  std::vector<Vec2f> getVec2s(const char* name) const;
  std::vector<Vec3f> getVec3s(const char* name) const;
  /// Colours with `components` (3 or 4, alpha dropped) values each.
  std::vector<Color> getColors(const char* name, int components = 3) const;
  std::vector<Rotation> getRotations(const char* name) const;
  /// Throws tg::Error "file:line: Element attr: what".
  [[noreturn]] void fail(const char* name, const std::string& what) const;

 private:
  std::vector<double> numbers(const char* name, std::size_t tuple) const;
  const SourceText& src_;
  pugi::xml_node node_;
};

// ---------------------------------------------------------------------------------------------
// Polygon sets and mesh building (X3dGeometry.cpp, X3dTriangulate.cpp)

/// A polygon corner: indices into the set's arrays (-1: none).
struct Corner {
  std::int32_t coord = -1;
  std::int32_t normal = -1;
  std::int32_t tex = -1;
  std::int32_t color = -1;
};

/// What every X3D geometry node is reduced to before meshing: polygons over shared arrays.
struct PolygonSet {
  std::vector<Vec3f> coords;
  std::vector<Vec3f> normals;  ///< given normals, or empty: computed with creaseAngle
  std::vector<Vec2f> texCoords;
  std::vector<Color> colors;
  std::vector<std::uint32_t> faceStart{0};  ///< face f has corners [faceStart[f], faceStart[f+1])
  std::vector<Corner> corners;
  std::vector<std::int32_t> faceNormal;  ///< per face when normals are per face, else empty
  std::vector<std::int32_t> faceColor;   ///< per face when colours are per face, else empty
  bool ccw = true;
  float creaseAngle = 0.0f;
  std::size_t faceCount() const { return faceStart.size() - 1; }
};

/// The faces of a polygon set as coordinate indices in their final winding, shared by all
/// meshes built from the set: what normal recomputation needs when coordinates move.
struct FaceTable {
  std::vector<std::uint32_t> faceStart{0};
  std::vector<std::int32_t> faceCoords;
};

/// One mesh built from a polygon set (one per colour when the set has colours).
struct MeshPart {
  ref_ptr<nodes::Mesh> mesh;
  std::optional<Color> color;  ///< diffuse colour replacing the material's, if coloured
  std::shared_ptr<const FaceTable> faces;
  std::vector<std::int32_t> vertexCoord;   ///< per mesh vertex: coordinate index
  std::vector<std::int32_t> vertexNormal;  ///< per mesh vertex: given normal index (or empty)
  std::vector<std::uint32_t> smoothStart;  ///< computed normals: per vertex, faces averaged
  std::vector<std::uint32_t> smoothFaces;
};

/// Limits and sinks used while meshing.
struct MeshContext {
  const X3dOptions& options;
  std::function<void(const std::string&)> warn;  ///< message without file/line prefix
};

/// Triangulates, computes normals and splits by colour. Faces with out-of-range coordinate
/// indices or fewer than three corners are dropped; attribute indices out of range drop that
/// attribute (both with a warning).
std::vector<MeshPart> buildMeshes(PolygonSet set, const MeshContext& ctx);

/// Triangulates one polygon (concave allowed) given its corner positions; appends triples of
/// local corner indices in the polygon's own winding. Returns false when it fell back to a fan.
bool triangulatePolygon(const std::vector<Vec3f>& points, std::size_t maxEarClip,
                        std::vector<std::uint32_t>& out);

/// Area-weighted (Newell) face normals of `faces` over `coords`.
std::vector<Vec3f> faceNormals(const FaceTable& faces, const std::vector<Vec3f>& coords);
/// Unit sums of the face normals listed per vertex (zero-length sums give +Y).
std::vector<Vec3f> smoothNormals(const std::vector<Vec3f>& faceN, const MeshPart& part);

/// Builds Box, Sphere, Cone, Cylinder as meshes with normals and X3D texture coordinates.
ref_ptr<nodes::Mesh> makeBox(Vec3f size);
ref_ptr<nodes::Mesh> makeSphere(float radius, std::uint32_t slices, std::uint32_t stacks);
ref_ptr<nodes::Mesh> makeCylinder(float radius, float height, bool bottom, bool side, bool top,
                                  std::uint32_t slices);
ref_ptr<nodes::Mesh> makeCone(float radius, float height, bool bottom, bool side,
                              std::uint32_t slices);

/// Extrusion fields.
struct ExtrusionSpec {
  std::vector<Vec2f> crossSection;
  std::vector<Vec3f> spine;
  std::vector<Vec2f> scale;
  std::vector<Rotation> orientation;
  bool beginCap = true, endCap = true, ccw = true;
  float creaseAngle = 0.0f;
};
/// Sweeps the cross-section along the spine (X3D's spine-aligned cross-section planes) into a
/// polygon set; empty when the spine or cross-section has fewer than two points.
PolygonSet extrusionPolygons(const ExtrusionSpec& spec);

// ---------------------------------------------------------------------------------------------
// Animators the nodes library lacks (X3dAnimation.cpp)

/// X3D TimeSensor: the nodes TimeSensor plus stopTime (outputs freeze at stopTime when it is
/// later than startTime).
class TimeSensor final : public nodes::TimeSensor {
 public:
  static ref_ptr<TimeSensor> create() { return ref_ptr<TimeSensor>(new TimeSensor()); }
  void evaluate(double time) override;
  /// Clock time at which the sensor stops (ignored unless later than startTime).
  SFTime stopTime{*this, "stopTime", ChangeKind::Parameter, 0.0};

 private:
  TimeSensor() = default;
};

/// X3D NormalInterpolator: key.size() lists of n unit vectors, spherically interpolated.
class NormalInterpolator final : public Animator {
 public:
  static ref_ptr<NormalInterpolator> create() {
    return ref_ptr<NormalInterpolator>(new NormalInterpolator());
  }
  std::string_view className() const override { return "NormalInterpolator"; }
  void evaluate(double time) override;
  SFFloat set_fraction{*this, "set_fraction", ChangeKind::Parameter, 0.0f};
  MFFloat key{*this, "key", ChangeKind::Parameter};
  MFVec3f keyValue{*this, "keyValue", ChangeKind::Parameter};
  MFVec3f value_changed{*this, "value_changed", ChangeKind::Parameter};

 private:
  NormalInterpolator() = default;
};

/// Maps a Coordinate's (and Normal's) values onto one built mesh: ROUTEs into Coordinate.point
/// connect `set_point`, ROUTEs into Normal.vector `set_vector`; the mesh's points (and normals,
/// recomputed with the mesh's crease groups unless routed) follow every evaluation.
class MeshDeformer final : public nodes::Deformer {
 public:
  /// A deformer for `part`, with `restCoords`/`restNormals` as values until routed; drives
  /// the part's mesh.
  static ref_ptr<MeshDeformer> create(const MeshPart& part, std::vector<Vec3f> restCoords,
                                      std::vector<Vec3f> restNormals);
  std::string_view className() const override { return "CoordinateDeformer"; }
  void evaluate(double time) override;
  MFVec3f set_point{*this, "set_point", ChangeKind::Parameter};
  MFVec3f set_vector{*this, "set_vector", ChangeKind::Parameter};

 protected:
  bool producesNormals() const override { return true; }

 private:
  MeshDeformer() = default;
  MeshPart part_;
};

}  // namespace tg::x3d
