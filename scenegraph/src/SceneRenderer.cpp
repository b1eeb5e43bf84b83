#include "tracegraph/scenegraph/SceneRenderer.h"

#include <algorithm>
#include <chrono>

#include "tracegraph/backend/Error.h"

namespace tg {
namespace {

Vec3f toVec(const Color& c) {
  return {c.r, c.g, c.b};
}

/// Inventor/X3D shininess lies in [0, 1] and means exponent 128 s (OpenGL's convention); AFF and
/// NFF write the exponent itself, always well above 1 in practice.
float phongExponent(float shininess) {
  return shininess <= 1.0f ? 128.0f * shininess : shininess;
}

}  // namespace

SceneRenderer::SceneRenderer(SceneGraph& graph, const RenderSettings& settings)
    : graph_(graph), renderer_(settings) {}

void SceneRenderer::setTextureSearchPath(std::vector<std::filesystem::path> folders) {
  searchPath_ = std::move(folders);
}

std::uint32_t SceneRenderer::textureIndex(const std::string& fileName) {
  const auto it = textureIds_.find(fileName);
  if (it != textureIds_.end()) return it->second;
  std::uint32_t id = kInvalidId;
  std::vector<std::filesystem::path> candidates{fileName};
  for (const auto& folder : searchPath_) candidates.push_back(folder / fileName);
  std::string reason = "not found";
  for (const auto& path : candidates) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) continue;
    try {
      scene_.textures.push_back(std::make_shared<const Texture>(Texture::load(path.string())));
      id = static_cast<std::uint32_t>(scene_.textures.size() - 1);
    } catch (const Error& e) {
      reason = e.what();
    }
    break;
  }
  if (id == kInvalidId) warnings_.push_back("texture '" + fileName + "': " + reason);
  textureIds_.emplace(fileName, id);
  return id;
}

std::uint32_t SceneRenderer::materialIndex(const MaterialNode* material,
                                           const TextureNode* texture) {
  const auto key = std::make_pair(material, texture);
  const auto it = materialIds_.find(key);
  if (it != materialIds_.end()) return it->second;
  Material m;
  if (material) {
    const MaterialData d = material->materialData();
    // Emission has no term of its own in the Phong model: it is light the surface adds
    // whatever the lights, which is what the ambient term does under unit ambient light.
    m.ambient = toVec(d.ambient) + toVec(d.emissive);
    m.diffuse = toVec(d.diffuse);
    m.specular = toVec(d.specular);
    m.shine = phongExponent(d.shininess);
    m.transmittance = std::clamp(d.transmittance, 0.0f, 1.0f);
    m.ior = d.ior;
  } else {
    m.ambient = {0.2f, 0.2f, 0.2f};
  }
  if (texture && !texture->fileName().empty()) m.texture = textureIndex(texture->fileName());
  // Bad values from an application edit must not stop the frame: fall back to the default.
  if (!m.validate().empty()) m = Material{};
  scene_.materials.push_back(m);
  const auto id = static_cast<std::uint32_t>(scene_.materials.size() - 1);
  materialIds_.emplace(key, id);
  return id;
}

void SceneRenderer::update() {
  scene_.scene = &graph_.backendScene();
  scene_.background = look_.background;
  scene_.ambient = look_.ambient;

  scene_.pointLights.clear();
  scene_.directionalLights.clear();
  scene_.spotLights.clear();
  for (const WorldLight& wl : graph_.lights()) {
    const LightData& l = wl.data;
    if (!l.on) continue;
    const Vec3f color = toVec(l.color) * l.intensity;
    const LightAttenuation att{l.attenuation.x, l.attenuation.y, l.attenuation.z};
    switch (l.kind) {
      case LightKind::Point:
        scene_.pointLights.push_back({l.position, color, att});
        break;
      case LightKind::Directional:
        scene_.directionalLights.push_back({l.direction, color});
        break;
      case LightKind::Spot:
        scene_.spotLights.push_back(
            {l.position, l.direction, color, l.cutOffAngle, l.beamWidth, att});
        break;
    }
  }

  // Material values may have been edited since the last frame: rebuild the (small) table.
  scene_.materials.clear();
  materialIds_.clear();
  const std::vector<InstanceId> ids = graph_.instanceIds();
  const std::size_t limit = ids.empty() ? 0 : ids.back() + 1;
  scene_.instanceMaterialRanges.assign(limit, {});
  scene_.instanceClasses.assign(limit, DynamicsClass::Static);
  for (InstanceId id : ids) {
    auto& ranges = scene_.instanceMaterialRanges[id];
    for (const MeshSegment& s : graph_.segments(id))
      ranges.push_back({s.primBegin, materialIndex(s.material, s.texture)});
    scene_.instanceClasses[id] = graph_.instanceClass(id);
  }
}

CameraParams cameraParamsOf(const WorldCamera& c, std::uint32_t width, std::uint32_t height) {
  CameraParams p;
  p.eye = c.position;
  p.viewDirection = c.direction;
  p.up = c.up;
  p.fovYDegrees = c.fov * 57.29577951308232f;
  p.hither = c.hither;
  p.width = width;
  p.height = height;
  return p;
}

Camera SceneRenderer::camera(std::uint32_t width, std::uint32_t height) const {
  if (const std::optional<WorldCamera> c = graph_.camera())
    return Camera(cameraParamsOf(*c, width, height));
  Box3f b = graph_.backendScene().bounds();
  if (b.empty()) b = Box3f({-1, -1, -1}, {1, 1, 1});
  const Vec3f centre = b.center();
  const float radius = std::max(0.5f * length(b.extent()), 1e-3f);
  // Distance at which a sphere of that radius fills a 45-degree vertical field of view.
  const float distance = radius / std::sin(0.5f * 0.785398f);
  const Vec3f eye = centre + normalize(Vec3f{0.6f, 0.45f, 1.0f}) * distance;
  return Camera::lookAt(eye, centre, {0.0f, 1.0f, 0.0f}, 45.0f, width, height, distance * 1e-4f);
}

RenderStats SceneRenderer::render(const Camera& camera, Frame& frame, FrameStats* stats) {
  RenderingScope scope(graph_);
  // The headlight follows the camera of this render, so it is added here, not in update().
  const bool headlight = look_.headlight && scene_.pointLights.empty() &&
                         scene_.directionalLights.empty() && scene_.spotLights.empty();
  if (headlight) scene_.directionalLights.push_back({camera.params().viewDirection, {1, 1, 1}});
  RenderStats r;
  try {
    r = renderer_.render(scene_, camera, frame);
  } catch (...) {
    if (headlight) scene_.directionalLights.pop_back();
    throw;
  }
  if (headlight) scene_.directionalLights.pop_back();
  if (stats) {
    stats->renderMs = r.traceShadeMs;
    stats->rays = r.traced;
  }
  return r;
}

}  // namespace tg
