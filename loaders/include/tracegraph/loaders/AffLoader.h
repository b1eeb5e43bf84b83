/// @file AffLoader.h
/// Turns an AFF (BART) or NFF file into a plain scene-graph node tree that a tg::SceneGraph
/// classifies and syncs: Separators and MatrixTransforms for the transform blocks, Mesh nodes
/// under shared Material (and Texture) nodes, a KeyframeDeformer per group of `tpa` triangles,
/// animators for the keyframe tracks, point lights and a camera.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "tracegraph/backend/Vec3.h"
#include "tracegraph/loaders/AffDocument.h"
#include "tracegraph/loaders/AffParser.h"
#include "tracegraph/nodes/Camera.h"
#include "tracegraph/nodes/PointLight.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/SceneRenderer.h"
#include "tracegraph/scenegraph/ref_ptr.h"

namespace tg {

/// Settings of loadAff().
struct AffLoadOptions {
  /// Parser settings (tessellation of cones and spheres, detail level, safety limits).
  AffParseOptions parse;
  /// Keep the parsed document in AffScene::document (tools and tests compare against it; it
  /// duplicates the geometry, so it is off by default).
  bool keepDocument = false;
};

/// A loaded AFF/NFF file: the node graph plus the file-level facts no node carries.
///
/// Put `root` into a SceneGraph, call advanceTo(frameTime(f)) and sync(). Everything that
/// moves is driven through field connections from the animators listed in `animators`, so
/// the SceneGraph finds and evaluates them by itself.
struct AffScene {
  /// The file as given to the loader (or the display name of in-memory text).
  std::string fileName;
  /// Root of the graph; never null after a successful load.
  ref_ptr<nodes::Separator> root;
  /// The camera node (also in the graph, first child of `root`), or null when the file has
  /// neither a `v` command nor a `camera` track.
  ref_ptr<nodes::Camera> camera;
  /// The point lights in file order (also in the graph, top level, world space).
  std::vector<ref_ptr<nodes::PointLight>> lights;
  /// Every animator created: one per keyframe track in use, the camera's, and one
  /// KeyframeDeformer per group of `tpa` triangles.
  std::vector<ref_ptr<Animator>> animators;
  /// Background colour (`b`, black by default).
  Vec3f background{0.0f, 0.0f, 0.0f};
  /// Global ambient light (`am`, 1 1 1 by default).
  Vec3f ambient{1.0f, 1.0f, 1.0f};
  /// The `a start end frames` range (present = false and one frame at time 0 without `a`).
  AffAnimation animation;
  /// Horizontal resolution of the `v` command; 0 when the file has none.
  int width = 0;
  /// Vertical resolution of the `v` command; 0 when the file has none.
  int height = 0;
  /// Folders where the file's texture names resolve: the file's folder, then
  /// ../TextureFiles/ (Texture nodes already hold resolved paths where the file was found).
  std::vector<std::filesystem::path> textureFolders;
  /// Triangle counts of the document (cones and spheres as tessellated).
  AffTriangleCounts triangles;
  /// Non-fatal findings of the parser and the conversion, "FILE:LINE: what" each.
  std::vector<std::string> warnings;
  /// The parsed document when AffLoadOptions::keepDocument was set, else null.
  std::shared_ptr<const AffDocument> document;

  /// Time of frame f (see AffAnimation::frameTime).
  double frameTime(int frame) const { return animation.frameTime(frame); }
  /// Number of frames (at least 1).
  int frameCount() const { return animation.frames; }
  /// Background and ambient light for a SceneRenderer.
  SceneLook look() const { return SceneLook{background, ambient}; }
};

/// Parses `file` with parseAffFile and converts it with buildAffScene.
///
/// Throws tg::Error with "FILE:LINE: what" when the file cannot be parsed or converted;
/// nothing of a failed load is returned or attached to any existing graph.
AffScene loadAff(const std::filesystem::path& file, const AffLoadOptions& options = {});

/// Parses AFF/NFF text held in memory (see parseAffText) and converts it.
AffScene loadAffText(std::string_view text, const std::filesystem::path& baseDir,
                     const AffLoadOptions& options = {}, std::string_view displayName = "<text>");

/// Converts a parsed document into a fresh node graph.
///
/// Mapping:
///  - the file → root Separator holding the Camera, the PointLights and the root block;
///  - `xs` block → Separator { MatrixTransform (T·R·S, static), content };
///  - `x name` block → Separator { MatrixTransform driven by the track's animator, content };
///    blocks naming the same track share its animator; a track with a visibility channel adds
///    a Switch around the content; a block without a track gets an identity (static) matrix;
///  - `m`, `p`, `pp`, `tt`, `c`, `s` → Mesh (no normals when the file gives none: flat);
///  - material: AFF's current material is global state, so every mesh is preceded, where the
///    traversal state differs, by the shared Material node of its material index; textured
///    meshes sit in their own Separator { Texture, Mesh } so that the texture cannot leak;
///  - `tpa` → one Mesh per block and (material, key times) group, driven by a
///    KeyframeDeformer (linear between keys, normals renormalised);
///  - `l` → PointLight (no attenuation), `la` → PointLight whose location follows its track;
///  - `v` and the `camera` track → Camera driven by an animator (eye = transl, view direction
///    R·(0,0,−1), up R·(0,1,0), fov = `v` angle in radians, aspect W/H, hither as
///    AffView::effectiveHither).
/// Material fields: ambient/diffuse/specular colours as written; shininess = the Phong
/// exponent when above 1, otherwise exponent/128 (SceneRenderer reads values up to 1 as
/// Inventor shininess, 128·s); transmittance = T; ior = AffMaterial::refractiveIndex().
///
/// Throws tg::Error naming the file and line of the offending command (e.g. a mesh whose
/// vertex count exceeds the node's 32-bit signed indices).
AffScene buildAffScene(AffDocument document, const AffLoadOptions& options = {});

}  // namespace tg
