/// @file X3dLoader.h
/// Reads X3D XML files (.x3d) into scene-graph nodes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "tracegraph/loaders/LoadedScene.h"

namespace tg {

/// Tessellation and safety limits of the X3D loader.
struct X3dOptions {
  std::uint32_t sphereSlices = 32;    ///< Sphere: segments around the Y axis
  std::uint32_t sphereStacks = 16;    ///< Sphere: segments from pole to pole
  std::uint32_t cylinderSlices = 32;  ///< Cone and Cylinder: segments around the Y axis
  /// Inline files nested deeper than this are rejected (cycles are rejected at any depth).
  std::size_t maxInlineDepth = 16;
  /// XML elements nested deeper than this are rejected (keeps the recursive walk bounded).
  std::size_t maxNesting = 256;
  /// Files producing more triangles than this (over all Inlines) are rejected.
  std::size_t maxTriangles = 50'000'000;
  /// Polygons with more corners than this are fanned instead of ear-clipped (ear clipping is
  /// quadratic), with a warning.
  std::size_t maxEarClipCorners = 2048;
  /// Per-face or per-vertex colours split a mesh into one mesh per distinct colour, each under
  /// its own Material; beyond this many colours the mesh keeps one mean colour (warning).
  std::size_t maxColourGroups = 64;
};

/// Loads an X3D XML file.
///
/// Mapping: Scene, Group, StaticGroup (and Collision, Anchor, Billboard, LOD level 0) become
/// Separators; `Transform { children }` becomes a Separator holding a tg::nodes::Transform and
/// the children; Shape becomes a Separator holding a Material, an optional Texture and one
/// Mesh per colour; Switch becomes tg::nodes::Switch. IndexedFaceSet (concave polygons by ear
/// clipping, ccw, creaseAngle, per-vertex/per-face normals and colours, TextureTransform
/// applied to the coordinates), IndexedTriangleSet, TriangleSet, the fan and strip sets, Box,
/// Sphere, Cone, Cylinder and Extrusion become Meshes. Mesh has no colour array: colours
/// replace the diffuse colour of the Shape's material per triangle (per-vertex colours are
/// averaged over each triangle) and triangles of equal colour share a mesh. Viewpoint,
/// PointLight, DirectionalLight and SpotLight become their nodes (lights are global, unlike
/// X3D's scoped DirectionalLight). Background sets LoadedScene::background, WorldInfo the
/// title. A node written once with DEF and again with USE is the same node object under every
/// parent (one backend object, several instances). A Shape without Material gets the default
/// Material (X3D's unlit white is not modelled).
///
/// Animation: TimeSensor (cycleInterval, loop, startTime, stopTime, enabled on the scene
/// clock, whose time 0 is the load), Position-, Orientation-, Scalar-, Coordinate- and
/// NormalInterpolator, and ROUTEs between them and node fields (`set_x`/`x_changed` names
/// accepted; Material transparency drives transmittance, Viewpoint fieldOfView the camera's
/// fov). A ROUTE into a Coordinate or Normal makes the meshes built from it deforming.
/// Inline loads the first url that exists, relative to the including file, with its own DEF
/// names; a file inlined twice is loaded once and shared.
///
/// Bad input, rejected with tg::Error naming the file and line: malformed XML, a file that is
/// not X3D (no X3D or Scene element), attribute values of the wrong type or count (`0 1` for
/// an SFVec3f, `abc` for a number), NaN/Inf numbers or numbers beyond 1e18, a node that USEs itself
/// or an ancestor, Inline cycles, nesting beyond the limits, more than maxTriangles triangles.
/// Dropped with a warning naming the file and line, the rest still loads: unknown or
/// unsupported nodes (with their subtree), USE of an unknown name or of a node of another
/// kind, faces with out-of-range or too few coordinate indices, normal/texture/colour
/// indices out of range (that attribute is dropped), interpolators with decreasing keys,
/// ROUTEs naming unknown nodes or fields, of mismatched types, from a non-animator or closing
/// a cycle, missing Inline files and missing texture images.
LoadedScene loadX3d(const std::filesystem::path& file, const X3dOptions& options = {});

/// Loads X3D text held in memory; relative urls (Inline, ImageTexture) resolve against
/// `baseDir`, and messages name `name`. Same mapping and error policy as loadX3d.
LoadedScene loadX3dString(std::string_view text, const std::filesystem::path& baseDir,
                          const std::string& name = "memory.x3d", const X3dOptions& options = {});

}  // namespace tg
