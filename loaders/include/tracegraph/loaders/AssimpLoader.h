/// @file AssimpLoader.h
/// Reads glTF 2.0 (.gltf/.glb), OBJ, PLY and the other formats Assimp knows into scene-graph
/// nodes.
#pragma once

#include <filesystem>
#include <string>

#include "tracegraph/loaders/LoadedScene.h"

namespace tg {

/// Options of the Assimp loader.
struct AssimpOptions {
  /// Animations repeat after their last key instead of holding it.
  bool loop = false;
};

/// Loads a file through Assimp.
///
/// Mapping: every Assimp node becomes a Separator holding its transform (a MatrixTransform, or
/// a tg::nodes::Transform with the node's translation/rotation/scale when an animation drives
/// it), its meshes, camera, light and children. A mesh is one Separator (Material, optional
/// Texture, Mesh) shared by every node that uses it, so a glTF mesh referenced by several
/// nodes is one backend object with several instances. Materials: base colour and
/// metallic/roughness become Phong terms (diffuse = base * (1 - metallic), specular =
/// mix(0.04, base, metallic), shininess = (2 / roughness^4 - 2) / 128 as X3D shininess),
/// emissive is kept, opacity below 1 becomes transmittance; the base colour (or diffuse)
/// texture is resolved next to the file. Cameras (perspective) and KHR_lights_punctual
/// lights become nodes under their Assimp node.
///
/// Animation: each animation clip gets a TimeSensor over its duration (all clips play from
/// time 0). Node translation/rotation/scale channels drive the node's Transform through
/// Position/OrientationInterpolators: LINEAR exactly, STEP exactly (held keys), CUBICSPLINE
/// through its key values with linear interpolation (Assimp drops the tangents; a warning
/// says so). Morph targets become a MorphDeformer whose weights follow the file's weight
/// animation; skins become a SkinDeformer whose joints are the nodes' transforms (the skinned
/// mesh sits at the root, since joint matrices are global). Morphed and skinned meshes are
/// deforming, animated nodes rigid, everything else static.
///
/// Rejected with tg::Error naming the file: files Assimp cannot read (malformed JSON, missing
/// or short buffers, accessors out of range, wrong types), glTF node indices out of range,
/// nodes that are their own ancestors or have two parents, a glTF scene without nodes, a file
/// without any triangle, NaN/Inf vertex positions or animation values, vertex indices out of
/// range. Dropped with a warning: missing or embedded texture images, orthographic cameras,
/// point and line primitives, bone weights naming unknown nodes.
LoadedScene loadAssimp(const std::filesystem::path& file, const AssimpOptions& options = {});

/// True when the installed Assimp reads files with this extension (".gltf", ".obj", ...; the
/// case does not matter).
bool assimpCanRead(const std::string& extension);

}  // namespace tg
