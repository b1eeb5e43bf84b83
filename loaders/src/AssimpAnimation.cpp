// Animation from Assimp scenes: clips become TimeSensors driving interpolators into node
// Transforms, morph targets a MorphDeformer with interpolated weights, skins a SkinDeformer
// over the node transforms.
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>

#include "AssimpImpl.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/nodes/KeyInterval.h"
#include "tracegraph/nodes/OrientationInterpolator.h"
#include "tracegraph/nodes/PositionInterpolator.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/nodes/SkinDeformer.h"
#include "tracegraph/nodes/Transform.h"

namespace tg::assimp {
namespace {

/// Keys as fractions of the clip, values, and the interpolation, ready for an interpolator.
template <typename T>
struct Track {
  std::vector<float> keys;
  std::vector<T> values;
};

/// Converts Assimp keys (times in ticks) to clip fractions; STEP holds each value until the
/// next key by repeating it at the next key's time.
template <typename T, typename Key, typename Conv>
Track<T> track(const Key* k, unsigned n, double tps, double duration, Interpolation mode,
               Conv&& conv) {
  Track<T> t;
  for (unsigned i = 0; i < n; ++i) {
    const auto f = static_cast<float>(k[i].mTime / tps / duration);
    if (!std::isfinite(f)) throw Error("animation key time is NaN or infinite");
    t.keys.push_back(f);
    t.values.push_back(conv(k[i].mValue));
    if (mode == Interpolation::Step && i + 1 < n) {
      t.keys.push_back(static_cast<float>(k[i + 1].mTime / tps / duration));
      t.values.push_back(conv(k[i].mValue));
    }
  }
  if (!std::is_sorted(t.keys.begin(), t.keys.end())) throw Error("animation key times decrease");
  return t;
}

Vec3f vec(const aiVector3D& v) {
  return {v.x, v.y, v.z};
}

Rotation rot(const aiQuaternion& q) {
  return toRotation(Quaternion{q.w, q.x, q.y, q.z});
}

}  // namespace

void WeightsInterpolator::evaluate(double) {
  const std::vector<float>& keys = key.getValues();
  const std::vector<float>& values = keyValue.getValues();
  if (keys.empty() || values.size() < keys.size()) return;
  const std::size_t n = values.size() / keys.size();
  const nodes::KeyInterval s = nodes::findKeyInterval(keys, set_fraction.getValue());
  const std::size_t a = s.index * n;
  std::vector<float> out(values.begin() + static_cast<std::ptrdiff_t>(a),
                         values.begin() + static_cast<std::ptrdiff_t>(a + n));
  if (s.weight != 0.0f)
    for (std::size_t i = 0; i < n; ++i) out[i] += (values[a + n + i] - out[i]) * s.weight;
  value_changed.setValues(std::move(out));
}

void SceneBuilder::findAnimatedNodes() {
  std::map<std::string, int> count;
  std::vector<const aiNode*> todo{scene_.mRootNode};
  while (!todo.empty()) {
    const aiNode* n = todo.back();
    todo.pop_back();
    ++count[n->mName.C_Str()];
    for (unsigned i = 0; i < n->mNumChildren; ++i) todo.push_back(n->mChildren[i]);
  }
  for (unsigned a = 0; a < scene_.mNumAnimations; ++a)
    for (unsigned c = 0; c < scene_.mAnimations[a]->mNumChannels; ++c) {
      const std::string name = scene_.mAnimations[a]->mChannels[c]->mNodeName.C_Str();
      animatedNodes_[name] = count[name];
      if (count[name] != 1)
        warn("animation channel for '" + name + "' names " + std::to_string(count[name]) +
             " nodes: ignored");
    }
}

void SceneBuilder::buildAnimations() {
  bool cubicWarned = false;
  for (unsigned a = 0; a < scene_.mNumAnimations; ++a) {
    const aiAnimation& anim = *scene_.mAnimations[a];
    const double tps = anim.mTicksPerSecond > 0.0 ? anim.mTicksPerSecond : 25.0;
    const double duration = anim.mDuration / tps;
    const auto modeOf = [&](const std::string& node, const char* path) {
      if (!gltf_ || a >= gltf_->interpolation.size()) return Interpolation::Linear;
      const auto it = gltf_->interpolation[a].find({node, path});
      const Interpolation m =
          it == gltf_->interpolation[a].end() ? Interpolation::Linear : it->second;
      if (m == Interpolation::CubicSpline && !cubicWarned) {
        warn("CUBICSPLINE animation interpolated linearly through its keys (tangents dropped)");
        cubicWarned = true;
      }
      return m;
    };
    if (!std::isfinite(duration)) throw Error("animation duration is NaN or infinite");
    ref_ptr<nodes::TimeSensor> clock = nodes::TimeSensor::create();
    clock->cycleInterval = duration > 0.0 ? duration : 1.0;
    clock->loop = options_.loop;
    clock->setName(anim.mName.C_Str());
    bool used = false;
    for (unsigned c = 0; c < anim.mNumChannels; ++c) {
      const aiNodeAnim& ch = *anim.mChannels[c];
      const std::string name = ch.mNodeName.C_Str();
      const auto it = byName_.find(name);
      if (animatedNodes_[name] != 1 || it == byName_.end()) continue;
      auto* t = dynamic_cast<nodes::Transform*>(transforms_[it->second]);
      if (!t) continue;
      // A single key is a constant; two or more are interpolated over the clip.
      const auto drive = [&](auto&& interpolator, auto& tr, auto& field) {
        if (tr.values.size() == 1 || duration <= 0.0) {
          field = tr.values.front();
          return;
        }
        interpolator->key = tr.keys;
        interpolator->keyValue = tr.values;
        interpolator->set_fraction.connectFrom(clock->fraction_changed);
        field.connectFrom(interpolator->value_changed);
        out_.animators.push_back(interpolator);
        used = true;
      };
      const double span = duration > 0.0 ? duration : 1.0;
      if (ch.mNumPositionKeys > 0) {
        auto tr = track<Vec3f>(ch.mPositionKeys, ch.mNumPositionKeys, tps, span,
                               modeOf(name, "translation"), vec);
        drive(nodes::PositionInterpolator::create(), tr, t->translation);
      }
      if (ch.mNumRotationKeys > 0) {
        auto tr = track<Rotation>(ch.mRotationKeys, ch.mNumRotationKeys, tps, span,
                                  modeOf(name, "rotation"), rot);
        drive(nodes::OrientationInterpolator::create(), tr, t->rotation);
      }
      if (ch.mNumScalingKeys > 0) {
        auto tr = track<Vec3f>(ch.mScalingKeys, ch.mNumScalingKeys, tps, span,
                               modeOf(name, "scale"), vec);
        drive(nodes::PositionInterpolator::create(), tr, t->scale);
      }
    }
    for (unsigned c = 0; c < anim.mNumMorphMeshChannels; ++c) {
      const aiMeshMorphAnim& ch = *anim.mMorphMeshChannels[c];
      const auto it = morphs_.find(ch.mName.C_Str());
      if (it == morphs_.end() || ch.mNumKeys == 0) {
        warn(std::string("morph animation for '") + ch.mName.C_Str() +
             "' without morph targets: ignored");
        continue;
      }
      std::size_t n = 0;
      for (const ref_ptr<nodes::MorphDeformer>& d : it->second) n = std::max(n, d->weights.size());
      const Interpolation mode = modeOf(ch.mName.C_Str(), "weights");
      ref_ptr<WeightsInterpolator> w = WeightsInterpolator::create();
      std::vector<float> keys, values;
      for (unsigned k = 0; k < ch.mNumKeys; ++k) {
        std::vector<float> v(n, 0.0f);
        for (unsigned j = 0; j < ch.mKeys[k].mNumValuesAndWeights; ++j)
          if (ch.mKeys[k].mValues[j] < n)
            v[ch.mKeys[k].mValues[j]] = static_cast<float>(ch.mKeys[k].mWeights[j]);
        const int copies = mode == Interpolation::Step && k + 1 < ch.mNumKeys ? 2 : 1;
        for (int r = 0; r < copies; ++r) {
          const double time = ch.mKeys[k + static_cast<unsigned>(r)].mTime;
          keys.push_back(static_cast<float>(time / tps / (duration > 0.0 ? duration : 1.0)));
          values.insert(values.end(), v.begin(), v.end());
        }
      }
      if (!std::is_sorted(keys.begin(), keys.end())) throw Error("morph key times decrease");
      w->key = keys;
      w->keyValue = values;
      w->set_fraction.connectFrom(clock->fraction_changed);
      for (const ref_ptr<nodes::MorphDeformer>& d : it->second)
        d->weights.connectFrom(w->value_changed);
      out_.animators.push_back(w);
      used = true;
    }
    if (used) {
      out_.animators.push_back(clock);
      out_.animationDuration = std::max(out_.animationDuration, duration);
    }
  }
}

ref_ptr<nodes::Separator> SceneBuilder::morphSeparator(const aiNode& n, unsigned index) {
  const aiMesh& m = *scene_.mMeshes[index];
  ref_ptr<nodes::Mesh> mesh = convertMesh(m);
  // The deformer moves points only: shading falls back to the geometric normal.
  mesh->normals = std::vector<Vec3f>{};
  ref_ptr<nodes::MorphDeformer> d = nodes::MorphDeformer::create();
  std::vector<Vec3f> targets;
  std::vector<float> weights;
  for (unsigned a = 0; a < m.mNumAnimMeshes; ++a) {
    const aiAnimMesh& am = *m.mAnimMeshes[a];
    if (am.mNumVertices != m.mNumVertices || !am.mVertices) {
      warn("morph target of mesh '" + std::string(m.mName.C_Str()) +
           "' without positions: ignored");
      continue;
    }
    for (unsigned i = 0; i < am.mNumVertices; ++i) targets.push_back(vec(am.mVertices[i]));
    weights.push_back(am.mWeight);
  }
  d->basePoints = mesh->points.getValues();
  d->targets = std::move(targets);
  d->weights = std::move(weights);
  d->setName(n.mName.C_Str());
  d->drive(*mesh);
  morphs_[n.mName.C_Str()].push_back(d);
  out_.animators.push_back(d);
  ref_ptr<nodes::Separator> sep = nodes::Separator::create();
  if (ref_ptr<nodes::Texture> t = texture(m.mMaterialIndex)) sep->addChild(t);
  sep->addChild(material(m.mMaterialIndex));
  sep->addChild(mesh);
  return sep;
}

void SceneBuilder::buildSkins() {
  for (const auto& [owner, index] : skinned_) {
    const aiMesh& m = *scene_.mMeshes[index];
    ref_ptr<nodes::Mesh> mesh = convertMesh(m);
    // Joints: every bone's node and all its ancestors, parents first, so that the deformer's
    // global joint matrices are world matrices (the mesh then sits at the root).
    std::vector<const aiNode*> joints;
    std::map<const aiNode*, int> depth;
    for (unsigned b = 0; b < m.mNumBones; ++b) {
      const auto it = byName_.find(m.mBones[b]->mName.C_Str());
      if (it == byName_.end()) continue;
      for (const aiNode* p = it->second; p && !depth.count(p); p = p->mParent) {
        int d = 0;
        for (const aiNode* q = p->mParent; q; q = q->mParent) ++d;
        depth[p] = d;
        joints.push_back(p);
      }
    }
    std::stable_sort(joints.begin(), joints.end(),
                     [&](const aiNode* x, const aiNode* y) { return depth[x] < depth[y]; });
    std::map<const aiNode*, std::int32_t> slot;
    for (std::size_t j = 0; j < joints.size(); ++j) slot[joints[j]] = static_cast<std::int32_t>(j);
    std::vector<ref_ptr<TransformNode>> transforms;
    std::vector<std::int32_t> parents;
    std::vector<Affine3d> bind(joints.size());
    for (const aiNode* j : joints) {
      transforms.emplace_back(transforms_[j]);
      parents.push_back(j->mParent && slot.count(j->mParent) ? slot[j->mParent] : -1);
    }
    // Up to four influences per vertex, the largest kept.
    std::vector<std::vector<std::pair<float, std::int32_t>>> influence(m.mNumVertices);
    for (unsigned b = 0; b < m.mNumBones; ++b) {
      const aiBone& bone = *m.mBones[b];
      const auto it = byName_.find(bone.mName.C_Str());
      if (it == byName_.end()) {
        warn("bone '" + std::string(bone.mName.C_Str()) +
             "' names no node: its weights are ignored");
        continue;
      }
      const std::int32_t j = slot[it->second];
      const aiMatrix4x4& o = bone.mOffsetMatrix;
      const double rows[12] = {o.a1, o.a2, o.a3, o.a4, o.b1, o.b2,
                               o.b3, o.b4, o.c1, o.c2, o.c3, o.c4};
      bind[static_cast<std::size_t>(j)] = Affine3d::fromRows(rows);
      for (unsigned w = 0; w < bone.mNumWeights; ++w)
        if (bone.mWeights[w].mVertexId < m.mNumVertices && bone.mWeights[w].mWeight > 0.0f)
          influence[bone.mWeights[w].mVertexId].emplace_back(bone.mWeights[w].mWeight, j);
    }
    std::vector<std::int32_t> jointIndices;
    std::vector<float> jointWeights;
    for (auto& inf : influence) {
      std::sort(inf.begin(), inf.end(),
                [](const auto& x, const auto& y) { return x.first > y.first; });
      for (std::size_t k = 0; k < 4; ++k) {
        jointIndices.push_back(k < inf.size() ? inf[k].second : 0);
        jointWeights.push_back(k < inf.size() ? inf[k].first : 0.0f);
      }
    }
    ref_ptr<nodes::SkinDeformer> skin = nodes::SkinDeformer::create();
    skin->setJoints(std::move(transforms));
    skin->jointParents = parents;
    skin->inverseBindMatrices = bind;
    skin->jointIndices = jointIndices;
    skin->jointWeights = jointWeights;
    skin->restPoints = mesh->points.getValues();
    skin->restNormals = mesh->normals.getValues();
    skin->setName(owner->mName.C_Str());
    if (m.mNumAnimMeshes > 0) {
      // Morph first, then skin the morphed points.
      ref_ptr<nodes::Separator> morphed = morphSeparator(*owner, index);
      skin->restPoints.connectFrom(morphs_[owner->mName.C_Str()].back()->points_changed);
      skin->restNormals = std::vector<Vec3f>{};
      mesh = ref_ptr<nodes::Mesh>(dynamic_cast<nodes::Mesh*>(morphed->children().back().get()));
      mesh->points.disconnect();
      skin->drive(*mesh);
      out_.root->addChild(morphed);
    } else {
      skin->drive(*mesh);
      ref_ptr<nodes::Separator> sep = nodes::Separator::create();
      if (ref_ptr<nodes::Texture> t = texture(m.mMaterialIndex)) sep->addChild(t);
      sep->addChild(material(m.mMaterialIndex));
      sep->addChild(mesh);
      out_.root->addChild(sep);
    }
    out_.animators.push_back(skin);
  }
}

}  // namespace tg::assimp
