// Assimp scenes to nodes: import with validation, node hierarchy, shared meshes, PBR materials
// mapped onto Phong, textures, cameras and lights.
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "AssimpImpl.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AssimpLoader.h"
#include "tracegraph/nodes/Camera.h"
#include "tracegraph/nodes/DirectionalLight.h"
#include "tracegraph/nodes/MatrixTransform.h"
#include "tracegraph/nodes/PointLight.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/nodes/SpotLight.h"
#include "tracegraph/nodes/Transform.h"

namespace tg::assimp {
namespace {

Affine3d toAffine(const aiMatrix4x4& m) {
  const double rows[12] = {m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4};
  return Affine3d::fromRows(rows);
}

Vec3f toVec(const aiVector3D& v) {
  return {v.x, v.y, v.z};
}

Color toColor(const aiColor4D& c) {
  return {c.r, c.g, c.b};
}

float channelMax(const aiColor3D& c) {
  return std::max({c.r, c.g, c.b});
}

}  // namespace

void SceneBuilder::build() {
  std::vector<const aiNode*> todo{scene_.mRootNode};
  while (!todo.empty()) {
    const aiNode* n = todo.back();
    todo.pop_back();
    byName_.emplace(n->mName.C_Str(), n);
    for (unsigned i = 0; i < n->mNumChildren; ++i) todo.push_back(n->mChildren[i]);
  }
  findAnimatedNodes();
  out_.root = nodes::Separator::create();
  out_.root->addChild(node(*scene_.mRootNode, 0));
  buildSkins();
  buildAnimations();
}

ref_ptr<nodes::Separator> SceneBuilder::node(const aiNode& n, int depth) {
  if (depth > 1000) throw Error("node hierarchy deeper than 1000");
  ref_ptr<nodes::Separator> sep = nodes::Separator::create();
  sep->setName(n.mName.C_Str());
  const Affine3d m = toAffine(n.mTransformation);
  if (!m.isFinite()) throw Error("node '" + std::string(n.mName.C_Str()) + "' has a NaN matrix");
  const auto animated = animatedNodes_.find(n.mName.C_Str());
  if (animated != animatedNodes_.end() && animated->second == 1) {
    // Animated: decomposed so that the channels can drive translation, rotation and scale.
    aiVector3D s, p;
    aiQuaternion q;
    n.mTransformation.Decompose(s, q, p);
    ref_ptr<nodes::Transform> t = nodes::Transform::create();
    t->translation = toVec(p);
    t->scale = toVec(s);
    t->rotation = toRotation(Quaternion{q.w, q.x, q.y, q.z});
    t->setName(n.mName.C_Str());
    transforms_[&n] = t.get();
    sep->addChild(t);
  } else {
    ref_ptr<nodes::MatrixTransform> t = nodes::MatrixTransform::create(m);
    t->setName(n.mName.C_Str());
    transforms_[&n] = t.get();
    sep->addChild(t);
  }
  for (unsigned k = 0; k < n.mNumMeshes; ++k) {
    const unsigned idx = n.mMeshes[k];
    if (idx >= scene_.mNumMeshes) throw Error("node mesh index out of range");
    const aiMesh& mesh = *scene_.mMeshes[idx];
    if (mesh.mNumBones > 0)
      skinned_.emplace_back(&n, idx);  // placed at the root once all joints exist
    else if (mesh.mNumAnimMeshes > 0)
      sep->addChild(morphSeparator(n, idx));
    else
      sep->addChild(meshSeparator(idx));
  }
  addCamera(n, *sep);
  addLight(n, *sep);
  for (unsigned i = 0; i < n.mNumChildren; ++i) sep->addChild(node(*n.mChildren[i], depth + 1));
  return sep;
}

ref_ptr<nodes::Mesh> SceneBuilder::convertMesh(const aiMesh& m) const {
  const std::string name = std::string("mesh '") + m.mName.C_Str() + "'";
  std::vector<Vec3f> points(m.mNumVertices);
  for (unsigned i = 0; i < m.mNumVertices; ++i) {
    points[i] = toVec(m.mVertices[i]);
    if (!isFinite(points[i])) throw Error(name + " has a NaN or infinite vertex position");
  }
  std::vector<std::int32_t> indices;
  indices.reserve(3u * m.mNumFaces);
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const aiFace& face = m.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines carry no surface
    for (unsigned k = 0; k < 3; ++k) {
      if (face.mIndices[k] >= m.mNumVertices)
        throw Error(name + " has a vertex index out of range");
      indices.push_back(static_cast<std::int32_t>(face.mIndices[k]));
    }
  }
  ref_ptr<nodes::Mesh> mesh = nodes::Mesh::create(std::move(points), std::move(indices));
  mesh->setName(m.mName.C_Str());
  if (m.HasNormals()) {
    std::vector<Vec3f> n(m.mNumVertices);
    for (unsigned i = 0; i < m.mNumVertices; ++i) {
      n[i] = toVec(m.mNormals[i]);
      if (!isFinite(n[i])) n[i] = {0.0f, 1.0f, 0.0f};  // a bad normal only affects shading
    }
    mesh->normals = std::move(n);
  }
  if (m.HasTextureCoords(0)) {
    std::vector<Vec2f> uv(m.mNumVertices);
    for (unsigned i = 0; i < m.mNumVertices; ++i) {
      uv[i] = {m.mTextureCoords[0][i].x, m.mTextureCoords[0][i].y};
      if (!std::isfinite(uv[i].u) || !std::isfinite(uv[i].v)) uv[i] = {};
    }
    mesh->texCoords = std::move(uv);
  }
  return mesh;
}

ref_ptr<nodes::Separator> SceneBuilder::meshSeparator(unsigned index) {
  if (const auto it = meshes_.find(index); it != meshes_.end()) return it->second;
  const aiMesh& m = *scene_.mMeshes[index];
  ref_ptr<nodes::Separator> sep = nodes::Separator::create();
  if (ref_ptr<nodes::Texture> t = texture(m.mMaterialIndex)) sep->addChild(t);
  sep->addChild(material(m.mMaterialIndex));
  sep->addChild(convertMesh(m));
  meshes_.emplace(index, sep);
  return sep;
}

ref_ptr<nodes::Material> SceneBuilder::material(unsigned index) {
  if (const auto it = materials_.find(index); it != materials_.end()) return it->second;
  ref_ptr<nodes::Material> out = nodes::Material::create();
  materials_.emplace(index, out);
  if (index >= scene_.mNumMaterials) return out;
  const aiMaterial& m = *scene_.mMaterials[index];
  aiColor4D base(0.8f, 0.8f, 0.8f, 1.0f);
  if (m.Get(AI_MATKEY_BASE_COLOR, base) != AI_SUCCESS) m.Get(AI_MATKEY_COLOR_DIFFUSE, base);
  float metallic = 0.0f, roughness = 1.0f, opacity = 1.0f;
  const bool pbr = m.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS;
  m.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness);
  m.Get(AI_MATKEY_OPACITY, opacity);
  metallic = std::clamp(std::isfinite(metallic) ? metallic : 0.0f, 0.0f, 1.0f);
  roughness = std::clamp(std::isfinite(roughness) ? roughness : 1.0f, 0.0f, 1.0f);
  const Color b = toColor(base);
  if (!FieldTraits<Color>::finite(b)) throw Error("material with a NaN colour");
  if (pbr) {
    // Metals reflect their base colour and have no diffuse part; dielectrics reflect 4%.
    const auto mix = [&](float c) { return 0.04f + (c - 0.04f) * metallic; };
    out->diffuseColor =
        Color{b.r * (1.0f - metallic), b.g * (1.0f - metallic), b.b * (1.0f - metallic)};
    out->specularColor = Color{mix(b.r), mix(b.g), mix(b.b)};
    // Blinn-Phong exponent matching GGX roughness (alpha = roughness^2): 2 / alpha^2 - 2,
    // written as X3D shininess (exponent / 128), which the renderer reads for values <= 1.
    const double r4 = std::pow(static_cast<double>(roughness), 4.0);
    const double exponent = r4 > 0.0 ? 2.0 / r4 - 2.0 : 128.0;
    out->shininess = static_cast<float>(std::clamp(exponent / 128.0, 0.0, 1.0));
  } else {
    out->diffuseColor = b;
    aiColor4D spec(0.0f, 0.0f, 0.0f, 1.0f);
    if (m.Get(AI_MATKEY_COLOR_SPECULAR, spec) == AI_SUCCESS &&
        FieldTraits<Color>::finite(toColor(spec)))
      out->specularColor = toColor(spec);
    float shininess = 0.0f;
    if (m.Get(AI_MATKEY_SHININESS, shininess) == AI_SUCCESS && std::isfinite(shininess) &&
        shininess > 0.0f)
      out->shininess = shininess;  // a Phong exponent (OBJ Ns), read as such when > 1
  }
  aiColor4D emissive(0.0f, 0.0f, 0.0f, 1.0f);
  if (m.Get(AI_MATKEY_COLOR_EMISSIVE, emissive) == AI_SUCCESS &&
      FieldTraits<Color>::finite(toColor(emissive)))
    out->emissiveColor = toColor(emissive);
  const float alpha =
      std::min(std::isfinite(opacity) ? opacity : 1.0f, std::isfinite(base.a) ? base.a : 1.0f);
  if (alpha < 1.0f) out->transmittance = std::clamp(1.0f - alpha, 0.0f, 1.0f);
  out->setName(m.GetName().C_Str());
  return out;
}

ref_ptr<nodes::Texture> SceneBuilder::texture(unsigned materialIndex) {
  if (materialIndex >= scene_.mNumMaterials) return nullptr;
  const aiMaterial& m = *scene_.mMaterials[materialIndex];
  aiString path;
  if (m.GetTexture(aiTextureType_BASE_COLOR, 0, &path) != AI_SUCCESS &&
      m.GetTexture(aiTextureType_DIFFUSE, 0, &path) != AI_SUCCESS)
    return nullptr;
  const std::string p = path.C_Str();
  if (const auto it = textures_.find(p); it != textures_.end()) return it->second;
  ref_ptr<nodes::Texture> tex;
  if (p.empty() || p[0] == '*' || scene_.GetEmbeddedTexture(p.c_str())) {
    warn("embedded texture '" + p + "' is not supported (only image files): dropped");
  } else {
    const std::filesystem::path full = (file_.parent_path() / p).lexically_normal();
    std::error_code ec;
    if (std::filesystem::is_regular_file(full, ec))
      tex = nodes::Texture::create(full.string());
    else
      warn("texture image '" + p + "' not found: dropped");
  }
  textures_.emplace(p, tex);
  return tex;
}

void SceneBuilder::addCamera(const aiNode& n, Group& into) {
  for (unsigned i = 0; i < scene_.mNumCameras; ++i) {
    const aiCamera& c = *scene_.mCameras[i];
    if (c.mName != n.mName) continue;
    ref_ptr<nodes::Camera> cam = nodes::Camera::create();
    if (gltf_) {
      // glTF cameras sit at their node's origin looking down -Z (Assimp's copy of the node
      // translation into mPosition would apply it twice).
      const auto it = gltf_->cameras.find(n.mName.C_Str());
      const GltfInfo::Camera info = it != gltf_->cameras.end() ? it->second : GltfInfo::Camera{};
      if (!info.perspective) {
        warn("orthographic camera '" + std::string(n.mName.C_Str()) +
             "' is not supported: dropped");
        continue;
      }
      cam->position = Vec3f{};
      if (info.yfov > 0.0 && info.yfov < 3.14) cam->fov = static_cast<float>(info.yfov);
      if (info.aspect > 0.0 && info.aspect < 1e6) cam->aspect = static_cast<float>(info.aspect);
      if (info.znear > 0.0 && info.znear < 1e6) cam->hither = static_cast<float>(info.znear);
    } else {
      const float aspect = c.mAspect > 0.0f && std::isfinite(c.mAspect) ? c.mAspect : 1.0f;
      cam->lookAt(toVec(c.mPosition), toVec(c.mPosition + c.mLookAt), toVec(c.mUp));
      // mHorizontalFOV is half the horizontal angle.
      const double v = 2.0 * std::atan(std::tan(static_cast<double>(c.mHorizontalFOV)) /
                                       static_cast<double>(aspect));
      if (v > 0.0 && v < 3.14) cam->fov = static_cast<float>(v);
      cam->aspect = aspect;
    }
    cam->setName(n.mName.C_Str());
    out_.cameras.push_back(cam);
    into.addChild(cam);
  }
}

void SceneBuilder::addLight(const aiNode& n, Group& into) {
  for (unsigned i = 0; i < scene_.mNumLights; ++i) {
    const aiLight& l = *scene_.mLights[i];
    if (l.mName != n.mName) continue;
    const float peak = channelMax(l.mColorDiffuse);
    const Color color =
        peak > 0.0f && std::isfinite(peak)
            ? Color{l.mColorDiffuse.r / peak, l.mColorDiffuse.g / peak, l.mColorDiffuse.b / peak}
            : Color{1.0f, 1.0f, 1.0f};
    const float intensity = peak > 0.0f && std::isfinite(peak) ? peak : 1.0f;
    Vec3f att(l.mAttenuationConstant, l.mAttenuationLinear, l.mAttenuationQuadratic);
    if (!isFinite(att) || (att.x <= 0.0f && att.y <= 0.0f && att.z <= 0.0f))
      att = {1.0f, 0.0f, 0.0f};
    const Vec3f pos = isFinite(toVec(l.mPosition)) ? toVec(l.mPosition) : Vec3f{};
    Vec3f dir = toVec(l.mDirection);
    if (!isFinite(dir) || length(dir) == 0.0f) dir = {0.0f, 0.0f, -1.0f};
    ref_ptr<Node> node;
    if (l.mType == aiLightSource_DIRECTIONAL) {
      ref_ptr<nodes::DirectionalLight> d = nodes::DirectionalLight::create();
      d->color = color, d->intensity = intensity, d->direction = dir;
      node = d;
    } else if (l.mType == aiLightSource_SPOT) {
      ref_ptr<nodes::SpotLight> s = nodes::SpotLight::create();
      s->color = color, s->intensity = intensity, s->location = pos, s->direction = dir;
      s->attenuation = att;
      if (std::isfinite(l.mAngleOuterCone) && l.mAngleOuterCone > 0.0f)
        s->cutOffAngle = l.mAngleOuterCone;
      if (std::isfinite(l.mAngleInnerCone) && l.mAngleInnerCone > 0.0f)
        s->beamWidth = l.mAngleInnerCone;
      node = s;
    } else if (l.mType == aiLightSource_POINT) {
      ref_ptr<nodes::PointLight> p = nodes::PointLight::create();
      p->color = color, p->intensity = intensity, p->location = pos, p->attenuation = att;
      node = p;
    } else {
      warn("light '" + std::string(l.mName.C_Str()) + "' of an unsupported kind: dropped");
      continue;
    }
    node->setName(n.mName.C_Str());
    into.addChild(node);
  }
}

}  // namespace tg::assimp

namespace tg {

LoadedScene loadAssimp(const std::filesystem::path& file, const AssimpOptions& options) {
  const std::string name = file.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw Error(name + ": no such file");
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const bool gltf = ext == ".gltf" || ext == ".glb";
  assimp::GltfInfo info;
  if (gltf) info = assimp::readGltfInfo(file);

  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  unsigned flags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure;
  // glTF is indexed already (and merging could break morph target correspondence).
  if (!gltf) flags |= aiProcess_JoinIdenticalVertices;
  const aiScene* scene = importer.ReadFile(name, flags);
  if (!scene) throw Error(name + ": " + importer.GetErrorString());
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
    throw Error(name + ": incomplete scene");
  if (scene->mNumMeshes == 0) throw Error(name + ": no triangles in the file");

  LoadedScene out;
  out.fileName = name;
  out.textureFolders.push_back(file.parent_path());
  try {
    assimp::SceneBuilder(*scene, file, gltf ? &info : nullptr, options, out).build();
  } catch (const Error& e) {
    const std::string what = e.what();
    throw Error(what.starts_with(name) ? what : name + ": " + what);
  }
  return out;
}

}  // namespace tg

namespace tg {

bool assimpCanRead(const std::string& extension) {
  std::string lower = extension;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  // The AFF reader owns .nff (Assimp's NFF reader does not know BART's extensions).
  if (lower == ".aff" || lower == ".nff" || lower == ".x3d") return false;
  return Assimp::Importer().IsExtensionSupported(lower);
}

}  // namespace tg
