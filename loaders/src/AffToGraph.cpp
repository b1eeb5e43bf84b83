// Conversion of a parsed AFF/NFF document into scene-graph nodes (see AffLoader.h for the
// mapping). The graph is built into fresh nodes only; nothing is attached anywhere until the
// whole conversion has succeeded, so a failure leaves no half-built state behind.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "AffAnimators.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AffLoader.h"
#include "tracegraph/nodes/Camera.h"
#include "tracegraph/nodes/KeyframeDeformer.h"
#include "tracegraph/nodes/Material.h"
#include "tracegraph/nodes/MatrixTransform.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/PointLight.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/nodes/Switch.h"
#include "tracegraph/nodes/Texture.h"

namespace tg {
namespace {

using aff::AffCameraAnimator;
using aff::AffTrackAnimator;

constexpr std::size_t kMaxNodeIndex =
    static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());

Color toColor(const Vec3f& c) {
  return Color{c.x, c.y, c.z};
}

/// Shininess field value for an AFF Phong exponent. SceneRenderer reads values up to 1 as
/// Inventor shininess (exponent 128·s) and larger ones as exponents, so exponents up to 1
/// (the data only has 0) are stored divided by 128 to come out unchanged.
float shininessOf(float exponent) {
  return exponent > 1.0f ? exponent : exponent / 128.0f;
}

/// `tpa` triangles of one block that can share a KeyframeDeformer: same material and the
/// same key times (museum5: all 1024 share keys 0…4).
struct TpaGroup {
  std::uint32_t material = 0;
  std::vector<double> times;                        ///< ascending
  std::vector<const AffAnimatedTriangle*> members;  ///< file order
  std::vector<std::vector<std::size_t>> keyOrder;   ///< per member: its keys by time
  AffSourceLocation where;                          ///< the first member
};

class GraphBuilder {
 public:
  GraphBuilder(const AffDocument& doc, AffScene& out)
      : doc_(doc), out_(out), start_(doc.animation.frameTime(0)) {}

  void build() {
    out_.root = nodes::Separator::create();
    addCamera(*out_.root);
    for (const AffLight& light : doc_.lights) addLight(*out_.root, light);
    addBlockContent(doc_.root, *out_.root, -1);
    if (cameraAnimator_) out_.animators.push_back(cameraAnimator_);
    for (const ref_ptr<AffTrackAnimator>& a : trackAnimatorsInOrder_) out_.animators.push_back(a);
    for (const ref_ptr<nodes::KeyframeDeformer>& d : deformers_) out_.animators.push_back(d);
  }

 private:
  /// Runs `f`, prefixing any tg::Error with the file and line of the command concerned.
  template <typename F>
  void at(const AffSourceLocation& where, F&& f) {
    try {
      std::forward<F>(f)();
    } catch (const Error& e) {
      throw Error(doc_.describe(where) + ": " + e.what());
    }
  }

  void warn(const AffSourceLocation& where, const std::string& what) {
    out_.warnings.push_back(doc_.describe(where) + ": " + what);
  }

  /// The animator of a track, created on first use; every block and light naming the track
  /// shares it (kitchen instances `rotating_wheel_*` twice).
  AffTrackAnimator& trackAnimator(const AffTrack& track) {
    auto it = trackAnimators_.find(track.name);
    if (it == trackAnimators_.end()) {
      ref_ptr<AffTrackAnimator> a =
          AffTrackAnimator::create(std::make_shared<const AffTrack>(track), start_);
      trackAnimatorsInOrder_.push_back(a);
      it = trackAnimators_.emplace(track.name, std::move(a)).first;
    }
    return *it->second;
  }

  void addCamera(Group& parent) {
    const AffTrack* track = doc_.cameraTrack();
    const AffView& view = doc_.view;
    if (!view.present && !track) return;
    ref_ptr<nodes::Camera> cam = nodes::Camera::create();
    cam->setName("camera");
    at(view.where, [&] {
      double degrees = view.angle;
      if (!(degrees > 0.0 && degrees < 180.0)) {
        warn(view.where, "view angle " + std::to_string(degrees) + " outside (0, 180): 45 used");
        degrees = 45.0;
      }
      cam->fov = static_cast<float>(degrees * std::numbers::pi / 180.0);
      cam->hither = static_cast<float>(view.effectiveHither());
      cam->aspect = view.width > 0 && view.height > 0
                        ? static_cast<float>(view.width) / static_cast<float>(view.height)
                        : 1.0f;
      const bool animated = track && (track->translation || track->rotation);
      ref_ptr<AffCameraAnimator> a = AffCameraAnimator::create(
          animated ? std::make_shared<const AffTrack>(*track) : nullptr, view, start_);
      cam->position = a->position_changed.value();
      cam->orientation = a->orientation_changed.value();
      if (animated) {
        cam->position.connectFrom(a->position_changed);
        cam->orientation.connectFrom(a->orientation_changed);
        cameraAnimator_ = a;
      }
    });
    out_.camera = cam;
    parent.addChild(cam);
  }

  void addLight(Group& parent, const AffLight& light) {
    ref_ptr<nodes::PointLight> node = nodes::PointLight::create();
    at(light.where, [&] {
      node->location = Vec3f(light.position);
      node->color = toColor(light.colour);
      // AFF lights have no attenuation: the node's default (1, 0, 0) is exactly that.
      if (!light.track.empty()) {
        node->setName(light.track);
        const AffTrack* track = doc_.findTrack(light.track);
        if (!track) {
          warn(light.where, "light track '" + light.track + "' has no k block: light fixed");
        } else if (track->translation) {
          AffTrackAnimator& a = trackAnimator(*track);
          node->location = a.translation_changed.value();
          node->location.connectFrom(a.translation_changed);
        }
      }
    });
    out_.lights.push_back(node);
    parent.addChild(node);
  }

  /// The shared Material node of material `index`.
  nodes::Material& material(std::uint32_t index) {
    if (materials_.size() <= index) materials_.resize(index + std::size_t{1});
    ref_ptr<nodes::Material>& slot = materials_[index];
    if (!slot) {
      const AffMaterial& m = doc_.materials.at(index);
      slot = nodes::Material::create();
      at(m.where, [&] {
        slot->ambientColor = toColor(m.ambient);
        slot->diffuseColor = toColor(m.diffuse);
        slot->specularColor = toColor(m.specular);
        slot->emissiveColor = Color{};
        slot->shininess = shininessOf(m.shine);
        slot->transmittance = m.transmittance;
        slot->ior = m.refractiveIndex();
      });
    }
    return *slot;
  }

  /// The shared Texture node of a material's image, or null when it has none.
  ref_ptr<nodes::Texture> texture(std::uint32_t index) {
    const AffMaterial& m = doc_.materials.at(index);
    if (m.textureName.empty()) return {};
    // The resolved path when the parser found the file; otherwise the name as written, which
    // the renderer looks up in AffScene::textureFolders and reports when missing.
    const std::string file = m.texturePath.empty() ? m.textureName : m.texturePath.string();
    ref_ptr<nodes::Texture>& slot = textures_[file];
    if (!slot) {
      slot = nodes::Texture::create(file);
      slot->setName(m.textureName);
    }
    return slot;
  }

  /// Makes material `index` current in `container` unless the traversal state already has it.
  void useMaterial(Group& container, std::uint32_t index, std::int64_t& state) {
    if (state == static_cast<std::int64_t>(index)) return;
    if (index >= doc_.materials.size())
      throw Error("material index " + std::to_string(index) + " out of range");
    container.addChild(ref_ptr<Node>(&material(index)));
    state = index;
  }

  static ref_ptr<nodes::Mesh> meshNode(const AffMesh& m) {
    TriangleMesh tm = toTriangleMesh(m);
    if (tm.positions.size() > kMaxNodeIndex)
      throw Error("mesh has " + std::to_string(tm.positions.size()) +
                  " vertices, more than a Mesh node can index");
    std::vector<std::int32_t> indices(tm.indices.size());
    std::transform(tm.indices.begin(), tm.indices.end(), indices.begin(),
                   [](std::uint32_t i) { return static_cast<std::int32_t>(i); });
    ref_ptr<nodes::Mesh> node = nodes::Mesh::create(std::move(tm.positions), std::move(indices));
    // No normals in the file means flat shading: the mesh stays without normals.
    if (!tm.normals.empty()) node->normals = std::move(tm.normals);
    if (!tm.uvs.empty()) node->texCoords = std::move(tm.uvs);
    return node;
  }

  void addMesh(Group& container, const AffMesh& m, std::int64_t& state) {
    if (m.triangleCount() == 0) return;
    at(m.where, [&] {
      useMaterial(container, m.material, state);
      ref_ptr<nodes::Mesh> node = meshNode(m);
      if (ref_ptr<nodes::Texture> tex = texture(m.material)) {
        // Texture state would otherwise leak to the untextured meshes that follow in the
        // same block; a Separator of its own keeps it to this mesh.
        ref_ptr<nodes::Separator> s = nodes::Separator::create();
        s->addChild(tex);
        s->addChild(node);
        container.addChild(s);
      } else {
        container.addChild(node);
      }
    });
  }

  std::vector<TpaGroup> groupTpa(const AffBlock& block) {
    std::vector<TpaGroup> groups;
    for (const AffAnimatedTriangle& tri : block.animatedTriangles) {
      if (tri.keys.empty()) continue;
      std::vector<std::size_t> order(tri.keys.size());
      std::iota(order.begin(), order.end(), std::size_t{0});
      if (!std::is_sorted(tri.keys.begin(), tri.keys.end(),
                          [](const auto& a, const auto& b) { return a.time < b.time; })) {
        // The deformer needs ascending keys; the data never has others.
        warn(tri.where, "tpa key times decrease: keys sorted by time");
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
          return tri.keys[a].time < tri.keys[b].time;
        });
      }
      std::vector<double> times(order.size());
      for (std::size_t k = 0; k < order.size(); ++k) times[k] = tri.keys[order[k]].time;
      auto it = std::find_if(groups.begin(), groups.end(), [&](const TpaGroup& g) {
        return g.material == tri.material && g.times == times;
      });
      if (it == groups.end()) {
        groups.push_back({tri.material, std::move(times), {}, {}, tri.where});
        it = std::prev(groups.end());
      }
      it->members.push_back(&tri);
      it->keyOrder.push_back(std::move(order));
    }
    return groups;
  }

  void addTpaGroup(Group& container, const TpaGroup& g, std::int64_t& state) {
    at(g.where, [&] {
      useMaterial(container, g.material, state);
      const std::size_t n = g.members.size() * 3;
      if (n > kMaxNodeIndex) throw Error("too many animated triangles for one Mesh node");
      std::vector<Vec3f> keyPoints, keyNormals;
      keyPoints.reserve(n * g.times.size());
      keyNormals.reserve(n * g.times.size());
      for (std::size_t k = 0; k < g.times.size(); ++k) {
        for (std::size_t i = 0; i < g.members.size(); ++i) {
          const AffAnimatedTriangle::Key& key = g.members[i]->keys[g.keyOrder[i][k]];
          keyPoints.insert(keyPoints.end(), key.positions.begin(), key.positions.end());
          keyNormals.insert(keyNormals.end(), key.normals.begin(), key.normals.end());
        }
      }
      std::vector<float> times(g.times.size());
      std::transform(g.times.begin(), g.times.end(), times.begin(),
                     [](double t) { return static_cast<float>(t); });

      ref_ptr<nodes::KeyframeDeformer> deformer = nodes::KeyframeDeformer::create();
      deformer->times = std::move(times);
      deformer->keyPoints = std::move(keyPoints);
      deformer->keyNormals = std::move(keyNormals);

      // The rest state is the pose at the first frame, so that a graph that is never
      // advanced still shows the scene as the file starts it.
      std::vector<Vec3f> points(n), normals(n);
      std::vector<std::int32_t> indices(n);
      std::iota(indices.begin(), indices.end(), 0);
      for (std::size_t i = 0; i < g.members.size(); ++i) {
        std::array<Vec3f, 3> p, nrm;
        g.members[i]->evaluate(start_, p, nrm);
        std::copy(p.begin(), p.end(), points.begin() + static_cast<std::ptrdiff_t>(3 * i));
        std::copy(nrm.begin(), nrm.end(), normals.begin() + static_cast<std::ptrdiff_t>(3 * i));
      }
      ref_ptr<nodes::Mesh> mesh = nodes::Mesh::create(std::move(points), std::move(indices));
      mesh->normals = std::move(normals);
      mesh->setName("tpa");
      deformer->drive(*mesh);
      deformers_.push_back(deformer);
      container.addChild(mesh);
    });
  }

  /// Adds a block below `parent`: its own Separator (except for the root, whose content goes
  /// straight into the root Separator) with its transform, geometry and nested blocks.
  /// `materialState` is the material index current in the traversal where the block starts
  /// (−1: none yet); AFF's material is global, so each mesh re-establishes its own.
  void addBlockContent(const AffBlock& block, Group& parent, std::int64_t materialState) {
    Group* container = &parent;
    if (block.kind != AffBlock::Kind::Root) {
      ref_ptr<nodes::Separator> sep = nodes::Separator::create();
      at(block.where, [&] { container = &addTransform(block, *sep); });
      parent.addChild(sep);
    }
    std::int64_t state = materialState;
    for (const AffMesh& m : block.meshes) addMesh(*container, m, state);
    for (const TpaGroup& g : groupTpa(block)) addTpaGroup(*container, g, state);
    for (const AffBlock& child : block.children) addBlockContent(child, *container, state);
  }

  /// Adds the block's transform to `sep` and returns the group its content goes into.
  Group& addTransform(const AffBlock& block, nodes::Separator& sep) {
    if (block.kind == AffBlock::Kind::Static) {
      sep.addChild(nodes::MatrixTransform::create(block.matrix));
      return sep;
    }
    const AffTrack* track = doc_.findTrack(block.name);
    ref_ptr<nodes::MatrixTransform> xf = nodes::MatrixTransform::create();
    xf->setName(block.name);
    sep.addChild(xf);
    if (!track) {
      // An `x` without `k` is the identity (5 robots blocks): nothing drives it.
      warn(block.where, "x block '" + block.name + "' has no k block: identity transform");
      return sep;
    }
    AffTrackAnimator& a = trackAnimator(*track);
    xf->matrix = a.matrix_changed.value();
    xf->matrix.connectFrom(a.matrix_changed);
    if (track->visibility.empty()) return sep;
    ref_ptr<nodes::Switch> sw = nodes::Switch::create();
    sw->setName(block.name);
    sw->whichChild = a.whichChild_changed.value();
    sw->whichChild.connectFrom(a.whichChild_changed);
    sep.addChild(sw);
    return *sw;
  }

  const AffDocument& doc_;
  AffScene& out_;
  double start_;  ///< time of frame 0: initial values of every driven field
  std::vector<ref_ptr<nodes::Material>> materials_;
  std::map<std::string, ref_ptr<nodes::Texture>> textures_;
  std::map<std::string, ref_ptr<AffTrackAnimator>, std::less<>> trackAnimators_;
  std::vector<ref_ptr<AffTrackAnimator>> trackAnimatorsInOrder_;
  ref_ptr<AffCameraAnimator> cameraAnimator_;
  std::vector<ref_ptr<nodes::KeyframeDeformer>> deformers_;
};

}  // namespace

AffScene buildAffScene(AffDocument document, const AffLoadOptions& options) {
  AffScene scene;
  scene.fileName = document.files.empty() ? std::string() : document.files.front().string();
  scene.warnings = document.warnings;
  GraphBuilder(document, scene).build();
  scene.background = document.background;
  scene.ambient = document.ambient;
  scene.animation = document.animation;
  if (document.view.present) {
    scene.width = document.view.width;
    scene.height = document.view.height;
  }
  if (!document.files.empty()) {
    const std::filesystem::path dir = document.files.front().parent_path();
    scene.textureFolders = {dir, dir / ".." / "TextureFiles"};
  }
  scene.triangles = document.countTriangles();
  if (options.keepDocument)
    scene.document = std::make_shared<const AffDocument>(std::move(document));
  return scene;
}

AffScene loadAff(const std::filesystem::path& file, const AffLoadOptions& options) {
  AffScene scene = buildAffScene(parseAffFile(file, options.parse), options);
  scene.fileName = file.string();
  return scene;
}

AffScene loadAffText(std::string_view text, const std::filesystem::path& baseDir,
                     const AffLoadOptions& options, std::string_view displayName) {
  return buildAffScene(parseAffText(text, baseDir, options.parse, displayName), options);
}

}  // namespace tg
