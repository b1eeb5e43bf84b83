// Keyframe, morph and skin deformers.
#include <cmath>

#include "tracegraph/nodes/KeyInterval.h"
#include "tracegraph/nodes/KeyframeDeformer.h"
#include "tracegraph/nodes/MorphDeformer.h"
#include "tracegraph/nodes/SkinDeformer.h"
#include "tracegraph/scenegraph/Field.h"

namespace tg::nodes {
namespace {

Vec3f lerp(const Vec3f& a, const Vec3f& b, float w) {
  return a + (b - a) * w;
}

Vec3f unit(const Vec3d& v) {
  const double len = length(v);
  return len > 0.0 ? Vec3f(v / len) : Vec3f{};
}

}  // namespace

void Deformer::drive(Mesh& mesh) {
  mesh.points.connectFrom(points_changed);
  if (producesNormals()) mesh.normals.connectFrom(normals_changed);
}

void KeyframeDeformer::evaluate(double time) {
  const auto& keys = times.getValues();
  const auto& pts = keyPoints.getValues();
  if (keys.empty() || pts.size() < keys.size()) return;
  const std::size_t n = pts.size() / keys.size();
  double t = time;
  const double first = static_cast<double>(keys.front());
  const double span = static_cast<double>(keys.back()) - first;
  if (loop.getValue() && span > 0.0 && t > first) t = first + std::fmod(t - first, span);
  const KeyInterval s = findKeyInterval(keys, static_cast<float>(t));
  const std::size_t a = s.index * n;
  const std::size_t b = s.weight != 0.0f ? a + n : a;
  std::vector<Vec3f> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = lerp(pts[a + i], pts[b + i], s.weight);
  const auto& nrm = keyNormals.getValues();
  if (nrm.size() == pts.size()) {
    std::vector<Vec3f> out(n);
    for (std::size_t i = 0; i < n; ++i)
      out[i] = unit(Vec3d(lerp(nrm[a + i], nrm[b + i], s.weight)));
    normals_changed.setValues(std::move(out));
  }
  points_changed.setValues(std::move(p));
}

void MorphDeformer::evaluate(double) {
  const auto& base = basePoints.getValues();
  const auto& tgt = targets.getValues();
  const auto& w = weights.getValues();
  const std::size_t n = base.size();
  // Accumulate in double: many small weighted offsets would otherwise round differently
  // depending on the number of targets.
  std::vector<Vec3d> acc(base.begin(), base.end());
  for (std::size_t j = 0; j < w.size() && (j + 1) * n <= tgt.size(); ++j) {
    const double wj = static_cast<double>(w[j]);
    if (wj == 0.0) continue;
    for (std::size_t i = 0; i < n; ++i) acc[i] += (Vec3d(tgt[j * n + i]) - Vec3d(base[i])) * wj;
  }
  std::vector<Vec3f> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = Vec3f(acc[i]);
  points_changed.setValues(std::move(p));
}

void SkinDeformer::setJoints(std::vector<ref_ptr<TransformNode>> joints) {
  checkEditable("SkinDeformer::setJoints");
  joints_ = std::move(joints);
  Field::noteDependencyChange();
}

void SkinDeformer::dependencies(std::vector<Node*>& out) const {
  for (const ref_ptr<TransformNode>& j : joints_) out.push_back(j.get());
}

void SkinDeformer::evaluate(double) {
  const std::size_t joints = joints_.size();
  const auto& parents = jointParents.getValues();
  const auto& bind = inverseBindMatrices.getValues();
  std::vector<Affine3d> skin(joints);
  std::vector<Affine3d> global(joints);
  for (std::size_t j = 0; j < joints; ++j) {
    const std::int32_t p = j < parents.size() ? parents[j] : -1;
    const Affine3d local = joints_[j] ? joints_[j]->localMatrix() : Affine3d{};
    // Parents must come first; a bad parent index is treated as a root joint.
    global[j] = p >= 0 && static_cast<std::size_t>(p) < j
                    ? global[static_cast<std::size_t>(p)] * local
                    : local;
    skin[j] = j < bind.size() ? global[j] * bind[j] : global[j];
  }
  const auto& rest = restPoints.getValues();
  const auto& restN = restNormals.getValues();
  const auto& idx = jointIndices.getValues();
  const auto& wts = jointWeights.getValues();
  const std::size_t n = rest.size();
  std::vector<Vec3f> p(n);
  std::vector<Vec3f> nrm(restN.size() == n ? n : 0);
  for (std::size_t i = 0; i < n; ++i) {
    Vec3d acc, accN;
    double total = 0.0;
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t slot = 4 * i + k;
      if (slot >= idx.size() || slot >= wts.size()) break;
      const std::int32_t j = idx[slot];
      const double w = static_cast<double>(wts[slot]);
      if (w == 0.0 || j < 0 || static_cast<std::size_t>(j) >= joints) continue;
      const Affine3d& m = skin[static_cast<std::size_t>(j)];
      acc += m.transformPoint(Vec3d(rest[i])) * w;
      if (!nrm.empty()) accN += m.transformVector(Vec3d(restN[i])) * w;
      total += w;
    }
    // Unweighted points stay at rest; weights not summing to one are normalised.
    p[i] = total > 0.0 ? Vec3f(acc / total) : rest[i];
    if (!nrm.empty()) nrm[i] = total > 0.0 ? unit(accN) : restN[i];
  }
  if (!nrm.empty()) normals_changed.setValues(std::move(nrm));
  points_changed.setValues(std::move(p));
}

}  // namespace tg::nodes
