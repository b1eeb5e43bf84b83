#include "tracegraph/loaders/DemoScene.h"

#include <cmath>
#include <numbers>

#include "tracegraph/nodes/Camera.h"
#include "tracegraph/nodes/KeyframeDeformer.h"
#include "tracegraph/nodes/Material.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/OrientationInterpolator.h"
#include "tracegraph/nodes/PointLight.h"
#include "tracegraph/nodes/PositionInterpolator.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/nodes/TimeSensor.h"
#include "tracegraph/nodes/Transform.h"

namespace tg {
namespace {

using namespace tg::nodes;

constexpr float kPi = std::numbers::pi_v<float>;

ref_ptr<Mesh> box(const Vec3f& lo, const Vec3f& hi) {
  std::vector<Vec3f> p;
  for (int i = 0; i < 8; ++i)
    p.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  const std::vector<std::int32_t> idx = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                         2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return Mesh::create(std::move(p), idx);
}

/// A quad grid in the xz plane, n x n cells, centred at the origin, facing +y.
ref_ptr<Mesh> grid(float size, int n, std::vector<Vec3f>* restPoints = nullptr) {
  std::vector<Vec3f> p;
  std::vector<std::int32_t> idx;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      p.push_back({size * (static_cast<float>(i) / static_cast<float>(n) - 0.5f), 0.0f,
                   size * (static_cast<float>(j) / static_cast<float>(n) - 0.5f)});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      idx.insert(idx.end(), {a, c, d, a, d, b});
    }
  if (restPoints) *restPoints = p;
  return Mesh::create(std::move(p), std::move(idx));
}

/// Icosahedron subdivided `level` times and projected onto a sphere of `radius`.
ref_ptr<Mesh> sphere(float radius, int level) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<Vec3f> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::int32_t> f = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                                 4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                                 6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (int l = 0; l < level; ++l) {
    std::vector<std::int32_t> next;
    for (std::size_t i = 0; i < f.size(); i += 3) {
      const std::int32_t a = f[i], b = f[i + 1], c = f[i + 2];
      auto mid = [&](std::int32_t x, std::int32_t y) {
        v.push_back((v[static_cast<std::size_t>(x)] + v[static_cast<std::size_t>(y)]) * 0.5f);
        return static_cast<std::int32_t>(v.size() - 1);
      };
      const std::int32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = std::move(next);
  }
  std::vector<Vec3f> normals;
  for (Vec3f& p : v) {
    p = normalize(p);
    normals.push_back(p);
    p = p * radius;
  }
  ref_ptr<Mesh> m = Mesh::create(std::move(v), std::move(f));
  m->normals = std::move(normals);
  return m;
}

ref_ptr<nodes::Material> material(Color diffuse, Color specular = {}, float shine = 30.0f,
                           float transmittance = 0.0f, float ior = 1.0f) {
  ref_ptr<nodes::Material> m = nodes::Material::create();
  m->ambientColor = Color{diffuse.r * 0.3f, diffuse.g * 0.3f, diffuse.b * 0.3f};
  m->diffuseColor = diffuse;
  m->specularColor = specular;
  m->shininess = shine;
  m->transmittance = transmittance;
  m->ior = ior;
  return m;
}

/// A Separator holding a material and a mesh, optionally under a static transform.
ref_ptr<Separator> shape(ref_ptr<nodes::Material> mat, ref_ptr<Mesh> mesh, std::size_t& counter,
                         ref_ptr<Transform> xf = {}) {
  ref_ptr<Separator> s = Separator::create();
  if (xf) s->addChild(xf);
  s->addChild(mat);
  counter += mesh->indices.size() / 3;
  s->addChild(mesh);
  return s;
}

ref_ptr<Transform> translate(const Vec3f& t) {
  ref_ptr<Transform> x = Transform::create();
  x->translation = t;
  return x;
}

/// An OrientationInterpolator swinging about `axis` between -amplitude and +amplitude.
ref_ptr<OrientationInterpolator> swing(TimeSensor& clock, const Vec3f& axis, float amplitude,
                                       int keys) {
  ref_ptr<OrientationInterpolator> o = OrientationInterpolator::create();
  std::vector<float> k;
  std::vector<Rotation> r;
  for (int i = 0; i <= keys; ++i) {
    const float f = static_cast<float>(i) / static_cast<float>(keys);
    k.push_back(f);
    r.push_back({axis, amplitude * std::sin(2.0f * kPi * f)});
  }
  o->key = std::move(k);
  o->keyValue = std::move(r);
  o->set_fraction.connectFrom(clock.fraction_changed);
  return o;
}

}  // namespace

DemoScene makeDemoScene() {
  DemoScene demo;
  demo.look.background = {0.35f, 0.45f, 0.65f};
  demo.look.ambient = {0.35f, 0.35f, 0.35f};
  ref_ptr<Separator> root = Separator::create();
  ref_ptr<TimeSensor> clock = TimeSensor::create();
  clock->cycleInterval = demo.duration;
  clock->loop = true;

  // Camera swinging around the room on a circle, looking at its centre.
  ref_ptr<nodes::Camera> camera = nodes::Camera::create();
  camera->fov = 0.8f;
  ref_ptr<PositionInterpolator> camPos = PositionInterpolator::create();
  ref_ptr<OrientationInterpolator> camRot = OrientationInterpolator::create();
  {
    std::vector<float> k;
    std::vector<Vec3f> pos;
    std::vector<Rotation> rot;
    for (int i = 0; i <= 16; ++i) {
      const float f = static_cast<float>(i) / 16.0f;
      const float yaw = 0.45f * std::sin(2.0f * kPi * f);
      k.push_back(f);
      pos.push_back({9.0f * std::sin(yaw), 2.2f, 9.0f * std::cos(yaw)});
      rot.push_back({{0.0f, 1.0f, 0.0f}, yaw});
    }
    camPos->key = k;
    camPos->keyValue = std::move(pos);
    camRot->key = std::move(k);
    camRot->keyValue = std::move(rot);
  }
  camPos->set_fraction.connectFrom(clock->fraction_changed);
  camRot->set_fraction.connectFrom(clock->fraction_changed);
  camera->position.connectFrom(camPos->value_changed);
  camera->orientation.connectFrom(camRot->value_changed);
  root->addChild(camera);

  ref_ptr<nodes::PointLight> key = nodes::PointLight::create();
  key->location = Vec3f{4.0f, 7.0f, 6.0f};
  key->color = Color{0.75f, 0.72f, 0.65f};
  ref_ptr<nodes::PointLight> fill = nodes::PointLight::create();
  fill->location = Vec3f{-6.0f, 5.0f, 3.0f};
  fill->color = Color{0.3f, 0.33f, 0.4f};
  root->addChild(key);
  root->addChild(fill);

  // Static room: floor, back and left walls, a mirror on the back wall, a pedestal with a
  // glass sphere.
  std::size_t& st = demo.staticTriangles;
  root->addChild(shape(material({0.7f, 0.68f, 0.62f}), grid(16.0f, 8), st));
  ref_ptr<Transform> back = translate({0.0f, 4.0f, -5.0f});
  back->rotation = Rotation{{1.0f, 0.0f, 0.0f}, 0.5f * kPi};
  root->addChild(shape(material({0.55f, 0.6f, 0.7f}), grid(16.0f, 4), st, back));
  ref_ptr<Transform> left = translate({-6.0f, 4.0f, 0.0f});
  left->rotation = Rotation{{0.0f, 0.0f, 1.0f}, -0.5f * kPi};
  root->addChild(shape(material({0.7f, 0.5f, 0.45f}), grid(16.0f, 4), st, left));
  root->addChild(shape(material({0.05f, 0.05f, 0.05f}, {0.85f, 0.85f, 0.85f}, 200.0f),
                       box({-2.5f, 0.8f, -4.95f}, {1.5f, 3.6f, -4.85f}), st));
  root->addChild(shape(material({0.3f, 0.3f, 0.32f}, {0.2f, 0.2f, 0.2f}),
                       box({2.2f, 0.0f, -0.8f}, {3.8f, 1.0f, 0.8f}), st));
  root->addChild(shape(material({0.02f, 0.02f, 0.02f}, {0.15f, 0.15f, 0.15f}, 300.0f, 0.9f, 1.5f),
                       sphere(0.8f, 3), st, translate({3.0f, 1.8f, 0.0f})));

  // Rigid: a robot arm. Shoulder (animated) -> upper arm -> elbow (animated) -> static offset
  // -> forearm. The static offset sits below the last dynamic transform, so it is baked.
  std::size_t& rt = demo.rigidTriangles;
  ref_ptr<Separator> arm = Separator::create();
  arm->addChild(translate({-2.5f, 0.0f, 0.5f}));
  ref_ptr<Transform> shoulder = Transform::create();
  shoulder->rotation.connectFrom(swing(*clock, {0.0f, 1.0f, 0.0f}, 1.2f, 16)->value_changed);
  arm->addChild(shoulder);
  arm->addChild(shape(material({0.85f, 0.55f, 0.1f}, {0.3f, 0.3f, 0.3f}),
                      box({-0.3f, 0.0f, -0.3f}, {0.3f, 2.0f, 0.3f}), rt));
  ref_ptr<Separator> forearm = Separator::create();
  ref_ptr<Transform> elbow = translate({0.0f, 2.0f, 0.0f});
  elbow->rotation.connectFrom(swing(*clock, {0.0f, 0.0f, 1.0f}, 0.9f, 16)->value_changed);
  forearm->addChild(elbow);
  forearm->addChild(translate({0.0f, 0.1f, 0.0f}));  // static offset below a dynamic transform
  forearm->addChild(shape(material({0.2f, 0.5f, 0.85f}, {0.3f, 0.3f, 0.3f}),
                          box({-0.2f, 0.0f, -0.2f}, {0.2f, 1.6f, 0.2f}), rt));
  arm->addChild(forearm);
  root->addChild(arm);

  // Deforming: a wave surface, 12 keyframes of a travelling sine, looping.
  std::vector<Vec3f> rest;
  ref_ptr<Mesh> wave = grid(4.0f, 24, &rest);
  ref_ptr<KeyframeDeformer> deformer = KeyframeDeformer::create();
  {
    std::vector<float> times;
    std::vector<Vec3f> keyPoints;
    constexpr int kKeys = 12;
    for (int k = 0; k <= kKeys; ++k) {
      const float phase = 2.0f * kPi * static_cast<float>(k) / kKeys;
      times.push_back(static_cast<float>(demo.duration) * static_cast<float>(k) / kKeys);
      for (const Vec3f& p : rest)
        keyPoints.push_back({p.x, 0.25f * std::sin(2.0f * p.x + phase) * std::cos(1.5f * p.z), p.z});
    }
    deformer->times = std::move(times);
    deformer->keyPoints = std::move(keyPoints);
    deformer->loop = true;
  }
  deformer->drive(*wave);
  ref_ptr<Separator> waveSep = Separator::create();
  waveSep->addChild(translate({0.0f, 0.5f, 1.2f}));
  waveSep->addChild(material({0.2f, 0.6f, 0.35f}, {0.25f, 0.25f, 0.25f}, 60.0f));
  demo.deformingTriangles = wave->indices.size() / 3;
  waveSep->addChild(wave);
  root->addChild(waveSep);

  demo.root = root;
  return demo;
}

}  // namespace tg
