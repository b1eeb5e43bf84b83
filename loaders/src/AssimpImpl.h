// Internals of the Assimp loader: the glTF pre-check (a small JSON reader that looks at what
// Assimp drops or would crash on) and the animators the nodes library lacks.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

struct aiMesh;
struct aiNode;
struct aiScene;

#include "tracegraph/loaders/AssimpLoader.h"
#include "tracegraph/nodes/Material.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/MorphDeformer.h"
#include "tracegraph/nodes/Texture.h"
#include "tracegraph/nodes/TimeSensor.h"
#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/Group.h"
#include "tracegraph/scenegraph/MField.h"
#include "tracegraph/scenegraph/SField.h"
#include "tracegraph/scenegraph/TransformNode.h"

namespace tg::assimp {

/// How a glTF animation sampler interpolates.
enum class Interpolation { Linear, Step, CubicSpline };

/// Facts about a glTF file read from its JSON before Assimp sees it.
struct GltfInfo {
  /// Per node index: the name Assimp gives the node (its name, or "nodes[i]").
  std::vector<std::string> nodeNames;
  /// Per animation index: (Assimp node name, "translation"/"rotation"/"scale"/"weights") to
  /// the sampler's interpolation. Names shared by several nodes are left out.
  std::vector<std::map<std::pair<std::string, std::string>, Interpolation>> interpolation;
  /// Perspective cameras by the Assimp name of the node holding them: vertical field of view
  /// and aspect ratio (0 when the file leaves it to the viewport).
  struct Camera {
    bool perspective = true;
    double yfov = 0.8, aspect = 0.0, znear = 0.01;
  };
  std::map<std::string, Camera> cameras;
};

/// Reads the JSON of a .gltf or .glb file and rejects, with tg::Error naming `file`, what
/// Assimp would crash or hang on or silently accept: malformed JSON or GLB framing, node,
/// mesh, camera or scene indices out of range, nodes that are their own ancestors or have two
/// parents, and a scene without nodes.
GltfInfo readGltfInfo(const std::filesystem::path& file);

/// Interpolates lists of morph weights: `keyValue` holds key.size() lists of n weights.
class WeightsInterpolator final : public Animator {
 public:
  static ref_ptr<WeightsInterpolator> create() {
    return ref_ptr<WeightsInterpolator>(new WeightsInterpolator());
  }
  std::string_view className() const override { return "WeightsInterpolator"; }
  void evaluate(double time) override;
  SFFloat set_fraction{*this, "set_fraction", ChangeKind::Parameter, 0.0f};
  MFFloat key{*this, "key", ChangeKind::Parameter};
  MFFloat keyValue{*this, "keyValue", ChangeKind::Parameter};
  MFFloat value_changed{*this, "value_changed", ChangeKind::Parameter};

 private:
  WeightsInterpolator() = default;
};

/// Turns an imported aiScene into nodes (AssimpLoader.cpp: hierarchy, meshes, materials,
/// cameras, lights; AssimpAnimation.cpp: clips, morph targets, skins).
class SceneBuilder {
 public:
  SceneBuilder(const aiScene& scene, const std::filesystem::path& file, const GltfInfo* gltf,
               const AssimpOptions& options, LoadedScene& out)
      : scene_(scene), file_(file), gltf_(gltf), options_(options), out_(out) {}
  /// Fills out.root, cameras, animators, duration and warnings.
  void build();

 private:
  ref_ptr<nodes::Separator> node(const aiNode& n, int depth);
  ref_ptr<nodes::Separator> meshSeparator(unsigned index);
  ref_ptr<nodes::Mesh> convertMesh(const aiMesh& m) const;
  ref_ptr<nodes::Material> material(unsigned index);
  ref_ptr<nodes::Texture> texture(unsigned materialIndex);
  void addCamera(const aiNode& n, Group& into);
  void addLight(const aiNode& n, Group& into);
  void warn(const std::string& what) { out_.warnings.push_back(file_.string() + ": " + what); }

  void findAnimatedNodes();
  void buildAnimations();
  ref_ptr<nodes::Separator> morphSeparator(const aiNode& n, unsigned index);
  void buildSkins();

  const aiScene& scene_;
  std::filesystem::path file_;
  const GltfInfo* gltf_;
  const AssimpOptions& options_;
  LoadedScene& out_;
  std::map<std::string, int> animatedNodes_;  ///< node name -> number of nodes with it
  std::map<const aiNode*, TransformNode*> transforms_;
  std::map<std::string, const aiNode*> byName_;
  std::map<unsigned, ref_ptr<nodes::Separator>> meshes_;
  std::map<unsigned, ref_ptr<nodes::Material>> materials_;
  std::map<std::string, ref_ptr<nodes::Texture>> textures_;
  std::map<std::string, std::vector<ref_ptr<nodes::MorphDeformer>>> morphs_;  ///< by node name
  std::vector<std::pair<const aiNode*, unsigned>> skinned_;
};

}  // namespace tg::assimp
