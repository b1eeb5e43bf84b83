/// @file SceneRenderer.h
/// Renders a SceneGraph's current frame: the one place where graph materials, lights and
/// cameras become the renderer's RenderScene and Camera.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tracegraph/backend/render/Renderer.h"
#include "tracegraph/scenegraph/FrameStats.h"
#include "tracegraph/scenegraph/SceneGraph.h"

namespace tg {

/// Scene-wide look that no node carries (loaders set it from the file).
struct SceneLook {
  Vec3f background{0.0f, 0.0f, 0.0f};  ///< colour of rays that hit nothing
  Vec3f ambient{0.2f, 0.2f, 0.2f};     ///< ambient light (AFF `am`)
  /// A scene without any light that is on is lit by a white directional light along the
  /// camera's view (X3D's NavigationInfo headlight, on by default; glTF viewers do the same).
  bool headlight = true;
};

/// The renderer's camera parameters for the graph camera `c` and a width x height image.
CameraParams cameraParamsOf(const WorldCamera& c, std::uint32_t width, std::uint32_t height);

/// Keeps a RenderScene in step with a synced SceneGraph and renders frames of it.
///
/// Per frame (after SceneGraph::sync), update() rebuilds the light list, the material table
/// and each instance's material ranges from the graph's mesh segments: this is O(segments),
/// not O(triangles), so it costs microseconds even for the BART kitchen. Textures are loaded
/// once per file and kept.
///
/// Shininess: MaterialData::shininess at most 1 is read as Inventor/X3D shininess (Phong
/// exponent 128 * s); larger values are Phong exponents as AFF/NFF files write them.
class SceneRenderer {
 public:
  /// Renders `graph` (which must outlive the renderer) with `settings`.
  explicit SceneRenderer(SceneGraph& graph, const RenderSettings& settings = {});

  /// Replaces the render settings (shading mode, depth, ...).
  void setSettings(const RenderSettings& settings) { renderer_.setSettings(settings); }
  /// The render settings.
  const RenderSettings& settings() const { return renderer_.settings(); }
  /// Sets background and ambient light.
  void setLook(const SceneLook& look) { look_ = look; }
  /// Background and ambient light.
  const SceneLook& look() const { return look_; }
  /// Folders searched, in order, for texture files not found as named.
  void setTextureSearchPath(std::vector<std::filesystem::path> folders);

  /// Refreshes lights, materials, textures and classes from the graph (call after sync()).
  void update();
  /// The camera for a width x height frame: the graph's camera when it has one, otherwise a
  /// view from the front-upper-right that frames the scene's bounds.
  Camera camera(std::uint32_t width, std::uint32_t height) const;
  /// Renders the current state under a RenderingScope (graph edits throw meanwhile) and fills
  /// `stats->renderMs` and `stats->rays` when given.
  RenderStats render(const Camera& camera, Frame& frame, FrameStats* stats = nullptr);

  /// The renderer-side scene as of the last update().
  const RenderScene& renderScene() const { return scene_; }
  /// Texture files that could not be loaded (each reported once), with the reason.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  std::uint32_t materialIndex(const MaterialNode* material, const TextureNode* texture);
  std::uint32_t textureIndex(const std::string& fileName);

  SceneGraph& graph_;
  Renderer renderer_;
  SceneLook look_;
  RenderScene scene_;
  std::vector<std::filesystem::path> searchPath_;
  std::map<std::pair<const MaterialNode*, const TextureNode*>, std::uint32_t> materialIds_;
  std::map<std::string, std::uint32_t> textureIds_;  ///< kInvalidId: failed to load
  std::vector<std::string> warnings_;
};

}  // namespace tg
