/// @file AffDocument.h
/// A parsed AFF (BART animated file format) or NFF file, described at the level of the format:
/// a tree of transform blocks holding geometry, a material table, view, lights and keyframe
/// tracks. Includes are already expanded in place (every inclusion is a separate instance that
/// inherits the transform stack); the document knows nothing about scene-graph nodes, which a
/// converter builds from it. See docs/aff-format.md for the format and its traps.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/TriangleMesh.h"
#include "tracegraph/backend/Vec3.h"
#include "tracegraph/loaders/KochanekBartels.h"

namespace tg {

/// Where something was read: an index into AffDocument::files and a 1-based line number.
struct AffSourceLocation {
  std::uint32_t file = 0;  ///< index into AffDocument::files
  std::uint32_t line = 0;  ///< 1-based line (LF counts lines; CR is plain whitespace)
};

/// One entry of the material table: an `fm` (or NFF `f`) state combined with the texture of the
/// primitive that used it. Identical combinations share one entry.
struct AffMaterial {
  Vec3f ambient{0, 0, 0};      ///< `fm` ambient; NFF `f` has none (0)
  Vec3f diffuse{1, 1, 1};      ///< `fm` diffuse; NFF `f`: Kd·rgb
  Vec3f specular{0, 0, 0};     ///< `fm` specular; NFF `f`: Ks in every channel
  float shine = 0.0f;          ///< Phong exponent on R·V
  float transmittance = 0.0f;  ///< T in [0, 1]; T > 0 makes the object two-sided and refractive
  float ior = 1.0f;            ///< index of refraction as written (robots has T > 0 with ior 0)
  std::string textureName;     ///< texture as written in the file; empty when untextured
  /// Resolved texture file: the including file's folder first, then its ../TextureFiles/.
  /// Empty when textureName is empty or the file was not found (a warning is recorded).
  std::filesystem::path texturePath;
  AffSourceLocation where;  ///< the `fm`/`f` command (line 0 for the built-in default)

  /// Index of refraction to render with: the reference treats 0 as 1.
  float refractiveIndex() const { return ior == 0.0f ? 1.0f : ior; }
};

/// The command a static geometry item came from.
enum class AffPrimitive : std::uint8_t {
  Mesh,              ///< `m`
  Polygon,           ///< `p` / `pp`, fan-triangulated
  TexturedTriangle,  ///< `tt` / `ttp`
  Cone,              ///< `c` (open cone or cylinder, tessellated)
  Sphere             ///< `s` (tessellated)
};

/// Analytic description of a cone or sphere, kept beside its tessellation.
struct AffShape {
  Vec3d base;               ///< cone base centre, or sphere centre
  double baseRadius = 0.0;  ///< cone base radius, or sphere radius
  Vec3d apex;               ///< cone apex centre (unused for spheres)
  double apexRadius = 0.0;  ///< cone apex radius (unused for spheres)
};

/// Static triangles in the frame of the enclosing block. Each triangle corner indexes the
/// attribute arrays separately (AFF allows different position, normal and texture-coordinate
/// counts); use toTriangleMesh() for a single-index mesh.
struct AffMesh {
  AffPrimitive primitive = AffPrimitive::Mesh;  ///< source command
  std::vector<Vec3f> positions;                 ///< vertex positions
  std::vector<Vec3f> normals;                   ///< empty → flat shading
  std::vector<Vec2f> uvs;                      ///< empty → untextured; v = 0 is the first PPM row
  std::vector<std::uint32_t> positionIndices;  ///< 3 per triangle, counter-clockwise = front
  std::vector<std::uint32_t> normalIndices;    ///< empty, or 3 per triangle into normals
  std::vector<std::uint32_t> uvIndices;        ///< empty, or 3 per triangle into uvs
  std::uint32_t material = 0;                  ///< index into AffDocument::materials
  std::optional<AffShape> shape;               ///< set for Cone and Sphere
  AffSourceLocation where;                     ///< the command that produced it

  /// Number of triangles.
  std::size_t triangleCount() const { return positionIndices.size() / 3; }
};

/// Converts to the engine's single-index mesh. When a corner's (position, normal, uv) index
/// triple differs from the position index alone, vertices are duplicated so that every
/// distinct triple becomes one vertex (corner order and triangle order are kept).
TriangleMesh toTriangleMesh(const AffMesh& mesh);

/// A `tpa` triangle: vertices and normals keyed in time, linearly interpolated.
struct AffAnimatedTriangle {
  /// One key of the animated triangle.
  struct Key {
    double time = 0.0;               ///< seconds, global animation time
    std::array<Vec3f, 3> positions;  ///< corners, counter-clockwise = front
    std::array<Vec3f, 3> normals;    ///< as written (often far from unit length)
  };
  std::vector<Key> keys;       ///< file order, at least one
  std::uint32_t material = 0;  ///< the `fm` current at the command; never textured
  AffSourceLocation where;     ///< the `tpa` command

  /// Corners and unit normals at time t: key 0 for t ≤ time0, the last key for t ≥ last time,
  /// otherwise the linear blend of the first keys k, k+1 (file order) with time_k ≤ t <
  /// time_k+1. Normals are renormalised (zero-length normals stay zero).
  void evaluate(double t, std::array<Vec3f, 3>& positions, std::array<Vec3f, 3>& normals) const;
};

/// A transform block of the file, or the implicit root.
struct AffBlock {
  /// What kind of transform the block applies.
  enum class Kind : std::uint8_t {
    Root,     ///< the whole file (identity)
    Static,   ///< `xs sx sy sz ax ay az deg tx ty tz {`
    Animated  ///< `x name {`: transform from the track `name` (identity if there is none)
  };
  Kind kind = Kind::Root;  ///< block kind
  std::string name;        ///< track name (Animated only)
  Vec3d scale{1, 1, 1};    ///< `xs` scale factors
  Vec3d axis{0, 1, 0};     ///< `xs` rotation axis as written
  double degrees = 0.0;    ///< `xs` rotation angle
  Vec3d translation;       ///< `xs` translation
  /// Static: M = T·R·S (column vectors; the axis normalised). Identity for the other kinds.
  Affine3d matrix;
  std::vector<AffBlock> children;                      ///< nested blocks in file order
  std::vector<AffMesh> meshes;                         ///< static geometry of this block
  std::vector<AffAnimatedTriangle> animatedTriangles;  ///< `tpa` of this block
  AffSourceLocation where;                             ///< the opening command
};

/// A point light (no attenuation). `la` lights follow a track's translation.
struct AffLight {
  Vec3d position;           ///< world position as written
  Vec3f colour{1, 1, 1};    ///< white unless given
  bool hasColour = false;   ///< whether the colour was written
  std::string track;        ///< `la` track name; empty for a static `l`
  AffSourceLocation where;  ///< the command
};

/// The `v` command.
struct AffView {
  bool present = false;     ///< whether the file has a `v`
  Vec3d from{0, 0, 0};      ///< eye
  Vec3d at{0, 0, -1};       ///< look-at point
  Vec3d up{0, 1, 0};        ///< up vector
  double angle = 45.0;      ///< vertical field of view in degrees
  double hither = 1.0;      ///< near distance as written
  int width = 0;            ///< resolution W
  int height = 0;           ///< resolution H
  AffSourceLocation where;  ///< the command

  /// Near distance to render with: the reference replaces hither < 1e-4 by 1.
  double effectiveHither() const { return hither < 1e-4 ? 1.0 : hither; }
};

/// The `a start end frames` command.
struct AffAnimation {
  bool present = false;     ///< whether the file has an `a`
  double start = 0.0;       ///< time of frame 0 (s)
  double end = 0.0;         ///< time of the last frame (s)
  int frames = 1;           ///< frame count N ≥ 1
  AffSourceLocation where;  ///< the command

  /// Time of frame f: start + f·(end − start)/(N − 1); `start` when N = 1.
  double frameTime(int frame) const;
};

/// A `k name { … }` block: up to four channels, each optional.
struct AffTrack {
  std::string name;                           ///< the name `x` blocks and `la` lights refer to
  std::optional<KbVectorSpline> translation;  ///< `transl`
  std::optional<KbRotationSpline> rotation;   ///< `rot`
  std::optional<KbVectorSpline> scale;        ///< `scale`
  std::vector<VisibilityKey> visibility;      ///< `visibility`; empty → always visible
  AffSourceLocation where;                    ///< the `k` command

  /// M(t) = T(t)·R(t)·S(t) in double; a missing channel contributes the identity.
  Affine3d evaluate(double t) const;
  /// Visibility of the blocks bound to this track at time t.
  bool visibleAt(double t) const { return evaluateVisibility(visibility, t); }
};

/// A camera pose at one time.
struct AffCamera {
  Vec3d eye;            ///< position
  Vec3d direction;      ///< unit view direction
  Vec3d up;             ///< up vector (unit unless the `v` up is not)
  double angle = 45.0;  ///< vertical field of view (degrees), from `v`
  double hither = 1.0;  ///< near distance after AffView::effectiveHither
  int width = 0;        ///< from `v`
  int height = 0;       ///< from `v`
};

/// Triangle counts of a document at its static state (cones and spheres as tessellated).
struct AffTriangleCounts {
  std::size_t meshes = 0;             ///< from `m`
  std::size_t polygons = 0;           ///< from `p`/`pp`
  std::size_t texturedTriangles = 0;  ///< from `tt`/`ttp`
  std::size_t cones = 0;              ///< from `c`
  std::size_t spheres = 0;            ///< from `s`
  std::size_t animated = 0;           ///< `tpa`
  std::size_t coneCount = 0;          ///< number of `c` primitives
  std::size_t sphereCount = 0;        ///< number of `s` primitives
  std::size_t meshCount = 0;          ///< number of AffMesh items of any primitive kind

  /// Triangles that never deform (everything but `tpa`).
  std::size_t staticTotal() const {
    return meshes + polygons + texturedTriangles + cones + spheres;
  }
  /// All triangles.
  std::size_t total() const { return staticTotal() + animated; }
};

/// A parsed AFF/NFF file with its includes expanded.
struct AffDocument {
  /// Every file read: [0] is the main file (or the name given to parseAffText), followed by
  /// included files in first-inclusion order. AffSourceLocation::file indexes this.
  std::vector<std::filesystem::path> files;
  AffBlock root;                       ///< the transform tree; kind Root
  std::vector<AffMaterial> materials;  ///< indexed by AffMesh::material
  AffView view;                        ///< last `v`
  Vec3f background{0, 0, 0};           ///< `b`, black by default
  Vec3f ambient{1, 1, 1};              ///< `am`, 1 1 1 by default
  std::vector<AffLight> lights;        ///< `l` and `la` in file order
  AffAnimation animation;              ///< `a`
  /// `k` blocks by name; a name parsed again replaces the earlier block.
  std::map<std::string, AffTrack, std::less<>> tracks;
  /// Non-fatal findings ("FILE:LINE: texture 'x' not found", duplicate tracks, …).
  std::vector<std::string> warnings;
  std::size_t includeCount = 0;  ///< `i` commands executed (skipped ones not counted)

  /// The track with this exact (case-sensitive) name, or null.
  const AffTrack* findTrack(std::string_view name) const;
  /// The camera track: exactly `camera` (robots also holds an unused `old_camera`).
  const AffTrack* cameraTrack() const { return findTrack("camera"); }
  /// Camera at time t: eye = transl(t), direction = R(t)·(0,0,−1), up = R(t)·(0,1,0); a missing
  /// channel (or track) falls back to the `v` from, at − from, and up.
  AffCamera camera(double t) const;
  /// Local transform of a block at time t (Static: its matrix; Animated: its track or identity).
  Affine3d blockMatrix(const AffBlock& block, double t) const;
  /// Whether an Animated block's track makes it visible at time t (other blocks: true).
  bool blockVisible(const AffBlock& block, double t) const;
  /// World position of a light at time t: the track's translation for `la` lights that have
  /// one, otherwise the written position.
  Vec3d lightPosition(const AffLight& light, double t) const;
  /// "FILE:LINE" for messages.
  std::string describe(const AffSourceLocation& where) const;
  /// Triangle counts over the whole tree.
  AffTriangleCounts countTriangles() const;
};

}  // namespace tg
