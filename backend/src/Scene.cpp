#include "tracegraph/backend/Scene.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "NormalizePair.h"
#include "PacketRays.h"
#include "tracegraph/backend/Error.h"

namespace tg {
namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

/// The next float above `x` (std::nextafter(x, +inf)), inline: commit() takes six per instance,
/// and as library calls they were a visible share of a large top-level rebuild.
inline float nextUp(float x) {
  if (!(x < kInfinity)) return x;  // +inf and NaN stay
  if (x == 0.0f) return std::numeric_limits<float>::denorm_min();
  // One step up in magnitude when positive, down when negative: no branch on the sign, which
  // is as random as the instances' positions.
  const auto bits = std::bit_cast<std::uint32_t>(x);
  return std::bit_cast<float>(bits + 1u - ((bits >> 31) << 1));
}
/// The next float below `x` (std::nextafter(x, -inf)).
inline float nextDown(float x) {
  return -nextUp(-x);
}

/// Rounds a double box outwards to float and pads it by a few float ulps of its magnitude, so
/// that a ray which the float matrices send onto the object's silhouette is not culled by the
/// top level.
Box3f conservativeFloatBox(const Box3d& b) {
  if (b.empty()) return {};
  Box3f out;
  for (int a = 0; a < 3; ++a) {
    const double magnitude = std::max({std::abs(b.lower[a]), std::abs(b.upper[a]), 1e-30});
    const double pad = magnitude * 1e-6;
    out.lower[a] = nextDown(static_cast<float>(b.lower[a] - pad));
    out.upper[a] = nextUp(static_cast<float>(b.upper[a] + pad));
  }
  return out;
}

/// Instance counts from which commit() makes the instance records in parallel.
constexpr std::size_t kParallelRecords = 4096;

}  // namespace

struct Scene::Impl {
  struct Object {
    TriangleMesh committed;
    std::optional<TriangleMesh> pending;
    ObjectUsage usage = ObjectUsage::Static;
    std::unique_ptr<ObjectAccel> accel;
    /// Per triangle of `committed`: texture-coordinate area per object-space area (empty
    /// without texture coordinates); see uvAreaPerWorldArea.
    std::vector<float> uvPerArea;
    std::size_t instanceRefs = 0;
    bool alive = true;
    bool dirty = true;
    bool built = false;  ///< accel holds a full build of some earlier mesh (refit candidate)
  };
  struct Instance {
    ObjectId object = kInvalidId;
    Affine3d objectToWorld;
    Affine3d worldToObject;
    bool alive = true;
  };

  SceneOptions options;
  std::vector<Object> objects;
  std::vector<Instance> instances;
  std::vector<InstanceRecord> records;
  /// Record index of each instance id when records has gaps closed (some instance dead or of
  /// an empty object); empty when record k is instance k's.
  std::vector<std::uint32_t> recordOfInstance;
  std::unique_ptr<TopLevelAccel> topLevel;
  bool instancesDirty = true;
  std::size_t pendingInstanceUpdates = 0;

  Object& object(ObjectId id, const char* call) {
    if (id >= objects.size() || !objects[id].alive)
      throw Error(std::string(call) + ": unknown object id " + std::to_string(id));
    return objects[id];
  }
  Instance& instance(InstanceId id, const char* call) {
    if (id >= instances.size() || !instances[id].alive)
      throw Error(std::string(call) + ": unknown instance id " + std::to_string(id));
    return instances[id];
  }
  /// World to object of instance `id` as last committed (the queries' state: the instance's
  /// own matrices may already hold an uncommitted edit). `id` must be of a committed record,
  /// as the instance id of a hit is.
  const Affine3d& committedWorldToObject(std::uint32_t id) const {
    return committedRecord(id).worldToObjectD;
  }
  /// committedWorldToObject(id) for mapping hit normals, or nullptr for an identity instance,
  /// whose matrix is then exactly the identity (commit()).
  const Affine3d* committedNormalMap(std::uint32_t id) const {
    const InstanceRecord& r = committedRecord(id);
    return r.identity ? nullptr : &r.worldToObjectD;
  }
  /// The committed record of instance `id` (see committedWorldToObject).
  const InstanceRecord& committedRecord(std::uint32_t id) const {
    return records[recordOfInstance.empty() ? id : recordOfInstance[id]];
  }
  /// Fills obj.uvPerArea from obj.committed. In float: it only chooses mip levels, and it
  /// runs at every commit of a textured mesh.
  static void fillUvPerArea(Object& obj) {
    const TriangleMesh& mesh = obj.committed;
    obj.uvPerArea.clear();
    if (mesh.uvs.empty()) return;
    obj.uvPerArea.resize(mesh.triangleCount());
    for (std::size_t t = 0; t < obj.uvPerArea.size(); ++t) {
      const std::uint32_t i0 = mesh.indices[3 * t], i1 = mesh.indices[3 * t + 1],
                          i2 = mesh.indices[3 * t + 2];
      const Vec2f &t0 = mesh.uvs[i0], &t1 = mesh.uvs[i1], &t2 = mesh.uvs[i2];
      const float uvArea = std::abs((t1.u - t0.u) * (t2.v - t0.v) - (t2.u - t0.u) * (t1.v - t0.v));
      const Vec3f& p0 = mesh.positions[i0];
      const float area = length(cross(mesh.positions[i1] - p0, mesh.positions[i2] - p0));
      const float ratio = uvArea / area;
      obj.uvPerArea[t] = std::isfinite(ratio) && area > 0.0f ? ratio : 0.0f;
    }
  }
  static void checkMesh(const TriangleMesh& mesh, const char* call) {
    const std::string problem = mesh.validate();
    if (!problem.empty()) throw Error(std::string(call) + ": invalid mesh: " + problem);
  }
  static void setMatrices(Instance& inst, const Affine3d& m, const char* call) {
    if (!m.isFinite()) throw Error(std::string(call) + ": matrix has NaN or infinite entries");
    const std::optional<Affine3d> inverse = m.inverse();
    if (!inverse) throw Error(std::string(call) + ": matrix is singular (zero scale?)");
    // Rays and boxes cross between the spaces in float: a matrix that float cannot hold would
    // send them to infinities.
    const Affine3f toWorldF(m), toObjectF(*inverse);
    if (!toWorldF.isFinite() || !toObjectF.isFinite())
      throw Error(std::string(call) + ": matrix or its inverse exceeds the float range");
    inst.objectToWorld = m;
    inst.worldToObject = *inverse;
  }
};

SceneOptions sceneOptionsFor(Engine engine) {
  SceneOptions o;
  switch (engine) {
    case Engine::KdTree:
      o.topLevel = TopLevelKind::KdTree;
      o.staticAccel = AccelKind::SahKdTree;
      o.deformingAccel = AccelKind::FastKdTree;
      break;
    case Engine::Bvh:
      o.topLevel = TopLevelKind::Bvh;
      o.staticAccel = AccelKind::Bvh;
      o.deformingAccel = AccelKind::BvhFast;
      break;
  }
  return o;
}

bool parseEngine(std::string_view name, Engine& engine) {
  if (name == "kd") {
    engine = Engine::KdTree;
    return true;
  }
  if (name == "bvh") {
    engine = Engine::Bvh;
    return true;
  }
  return false;
}

Scene::Scene(const SceneOptions& options) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->topLevel = createTopLevelAccel(options.topLevel);
}

Scene::~Scene() = default;

ObjectId Scene::createObject(TriangleMesh mesh, ObjectUsage usage) {
  Impl::checkMesh(mesh, "Scene::createObject");
  Impl::Object obj;
  obj.committed = std::move(mesh);
  obj.usage = usage;
  impl_->objects.push_back(std::move(obj));
  return static_cast<ObjectId>(impl_->objects.size() - 1);
}

void Scene::setObjectMesh(ObjectId object, TriangleMesh mesh) {
  Impl::Object& obj = impl_->object(object, "Scene::setObjectMesh");
  Impl::checkMesh(mesh, "Scene::setObjectMesh");
  obj.pending = std::move(mesh);
  obj.dirty = true;
}

void Scene::setObjectPositions(ObjectId object, std::span<const Vec3f> positions) {
  Impl::Object& obj = impl_->object(object, "Scene::setObjectPositions");
  const TriangleMesh& current = obj.pending ? *obj.pending : obj.committed;
  if (positions.size() != current.positions.size())
    throw Error("Scene::setObjectPositions: " + std::to_string(positions.size()) +
                " positions for an object with " + std::to_string(current.positions.size()));
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!isFinite(positions[i]))
      throw Error("Scene::setObjectPositions: position " + std::to_string(i) +
                  " is NaN or infinite");
  if (!obj.pending) obj.pending = obj.committed;
  obj.pending->positions.assign(positions.begin(), positions.end());
  obj.dirty = true;
}

void Scene::destroyObject(ObjectId object) {
  Impl::Object& obj = impl_->object(object, "Scene::destroyObject");
  if (obj.instanceRefs != 0)
    throw Error("Scene::destroyObject: object " + std::to_string(object) + " still has " +
                std::to_string(obj.instanceRefs) + " instances");
  obj = Impl::Object{};
  obj.alive = false;
  obj.dirty = false;
}

const TriangleMesh& Scene::objectMesh(ObjectId object) const {
  return impl_->object(object, "Scene::objectMesh").committed;
}

ObjectUsage Scene::objectUsage(ObjectId object) const {
  return impl_->object(object, "Scene::objectUsage").usage;
}

const ObjectAccel* Scene::objectAccel(ObjectId object) const {
  return impl_->object(object, "Scene::objectAccel").accel.get();
}

InstanceId Scene::createInstance(ObjectId object, const Affine3d& objectToWorld) {
  Impl::Object& obj = impl_->object(object, "Scene::createInstance");
  Impl::Instance inst;
  inst.object = object;
  Impl::setMatrices(inst, objectToWorld, "Scene::createInstance");
  ++obj.instanceRefs;
  impl_->instances.push_back(inst);
  impl_->instancesDirty = true;
  ++impl_->pendingInstanceUpdates;
  return static_cast<InstanceId>(impl_->instances.size() - 1);
}

void Scene::setInstanceTransform(InstanceId instance, const Affine3d& objectToWorld) {
  Impl::Instance& inst = impl_->instance(instance, "Scene::setInstanceTransform");
  Impl::Instance updated = inst;
  Impl::setMatrices(updated, objectToWorld, "Scene::setInstanceTransform");
  inst = updated;
  impl_->instancesDirty = true;
  ++impl_->pendingInstanceUpdates;
}

const Affine3d& Scene::instanceTransform(InstanceId instance) const {
  return impl_->instance(instance, "Scene::instanceTransform").objectToWorld;
}

ObjectId Scene::instanceObject(InstanceId instance) const {
  return impl_->instance(instance, "Scene::instanceObject").object;
}

void Scene::destroyInstance(InstanceId instance) {
  Impl::Instance& inst = impl_->instance(instance, "Scene::destroyInstance");
  --impl_->objects[inst.object].instanceRefs;
  inst.alive = false;
  impl_->instancesDirty = true;
  ++impl_->pendingInstanceUpdates;
}

bool Scene::hasPendingChanges() const {
  if (impl_->instancesDirty) return true;
  for (const Impl::Object& obj : impl_->objects)
    if (obj.alive && obj.dirty) return true;
  return false;
}

CommitStats Scene::commit() {
  CommitStats stats;
  Impl& s = *impl_;
  std::vector<ObjectId> dirty;
  for (ObjectId id = 0; id < s.objects.size(); ++id) {
    Impl::Object& obj = s.objects[id];
    if (!obj.alive || !obj.dirty) continue;
    if (obj.pending) {
      obj.committed = std::move(*obj.pending);
      obj.pending.reset();
    }
    const AccelKind kind =
        obj.usage == ObjectUsage::Deforming ? s.options.deformingAccel : s.options.staticAccel;
    if (!obj.accel || obj.accel->kind() != kind) {
      obj.accel = createObjectAccel(kind);
      obj.built = false;
    }
    dirty.push_back(id);
    stats.trianglesRebuilt += obj.committed.triangleCount();
  }
  auto start = std::chrono::steady_clock::now();
  std::vector<char> refitted(dirty.size(), 0);
  tbb::parallel_for(std::size_t(0), dirty.size(), [&](std::size_t k) {
    Impl::Object& obj = s.objects[dirty[k]];
    obj.dirty = false;
    Impl::fillUvPerArea(obj);
    // A deforming object keeps its tree while only its points moved and the refitted boxes are
    // still nearly as good as a fresh build's; refit() itself refuses a changed topology.
    if (obj.usage == ObjectUsage::Deforming && obj.built && obj.accel->refit(obj.committed)) {
      const BuildStats& st = obj.accel->stats();
      if (st.sahCost <= s.options.maxRefitCostRatio * st.buildSahCost) {
        refitted[k] = 1;
        return;
      }
    }
    obj.accel->build(obj.committed);
    obj.built = true;
  });
  stats.rebuildMs = millisecondsSince(start);
  for (const char r : refitted) stats.objectsRefitted += r != 0 ? 1 : 0;
  stats.objectsRebuilt = dirty.size() - stats.objectsRefitted;

  // Any rebuilt object may have new bounds, so its instances' world bounds change too.
  if (s.instancesDirty || !dirty.empty()) {
    start = std::chrono::steady_clock::now();
    // One record per live instance of a non-empty object, in instance order. Large scenes fill
    // them in parallel at their instance's index and close the gaps afterwards, if any.
    const std::size_t count = s.instances.size();
    s.records.resize(count);
    const auto fill = [&](std::size_t begin, std::size_t end) {
      std::size_t kept = 0;
      for (std::size_t id = begin; id < end; ++id) {
        const Impl::Instance& inst = s.instances[id];
        InstanceRecord& r = s.records[id];
        r.accel = nullptr;  // marks a gap
        if (!inst.alive) continue;
        const Impl::Object& obj = s.objects[inst.object];
        const Box3f objectBounds = obj.accel->bounds();
        if (objectBounds.empty()) continue;  // nothing to hit
        r.accel = obj.accel.get();
        r.identity = inst.objectToWorld == Affine3d::identity();
        // An identity given with -0 entries (equal to the identity) could invert to -0 entries;
        // identity records hold the exact identity, whose products mapNormals shortcuts.
        r.worldToObjectD = r.identity ? Affine3d::identity() : inst.worldToObject;
        r.worldBounds = r.identity ? objectBounds
                                   : conservativeFloatBox(inst.objectToWorld.transformBox(Box3d(
                                         Vec3d(objectBounds.lower), Vec3d(objectBounds.upper))));
        r.instanceId = static_cast<std::uint32_t>(id);
        r.objectId = inst.object;
        ++kept;
      }
      return kept;
    };
    std::size_t kept = 0;
    if (count >= kParallelRecords) {
      std::atomic<std::size_t> total{0};
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1024),
                        [&](const tbb::blocked_range<std::size_t>& block) {
                          total.fetch_add(fill(block.begin(), block.end()),
                                          std::memory_order_relaxed);
                        });
      kept = total.load(std::memory_order_relaxed);
    } else {
      kept = fill(0, count);
    }
    s.recordOfInstance.clear();
    if (kept != count) {
      std::erase_if(s.records, [](const InstanceRecord& r) { return r.accel == nullptr; });
      s.recordOfInstance.assign(count, kInvalidId);
      for (std::size_t k = 0; k < s.records.size(); ++k)
        s.recordOfInstance[s.records[k].instanceId] = static_cast<std::uint32_t>(k);
    }
    s.topLevel->build(s.records);
    stats.topLevelRebuilt = true;
    stats.topLevelMs = millisecondsSince(start);
    stats.instancesUpdated = s.pendingInstanceUpdates;
    s.instancesDirty = false;
    s.pendingInstanceUpdates = 0;
  }
  return stats;
}

bool Scene::intersect(const Ray& ray, Hit& hit) const {
  TraversalContext ctx;
  return intersect(ray, hit, ctx);
}

bool Scene::intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const {
  hit = Hit{};
  if (!isTraceable(ray)) return false;
  impl_->topLevel->intersect(ray, hit, ctx);
  if (!hit.valid()) return false;
  fillGeometricNormal(hit);
  return true;
}

namespace {

/// transformTransposed(n) of a matrix whose linear part is the identity, bit for bit: each
/// component is n's own plus two zeros, zero times the other two components, added in
/// transformTransposed's order. Only a zero component can change, and only its sign (a zero
/// times a negative component is -0); NaN and infinities propagate as through the matrix.
/// Nine loads of matrix entries and six multiplications fewer per hit: static geometry, all of
/// it in identity instances, takes most hits in BART scenes.
Vec3d identityTransposed(const Vec3d& n) {
  const Vec3d zero = n * 0.0;
  return {(n.x + zero.y) + zero.z, (zero.x + n.y) + zero.z, (zero.x + zero.y) + n.z};
}

/// The world normal of one hit (see mapNormals), in scalars: a single ray's hit, or the last of
/// an odd count.
void mapNormal(const Affine3d* worldToObject, Hit& hit) {
  const Vec3d n(hit.geometricNormal);
  const Vec3d world =
      worldToObject != nullptr ? worldToObject->transformTransposed(n) : identityTransposed(n);
  hit.geometricNormal = Vec3f(normalize(world));
}

/// The world normals of `count` hits from the object-space normals the leaf tests left (see
/// Scene::fillGeometricNormal), each by the inverse transpose of its instance (worldToObject
/// transposed; nullptr for an instance whose matrix has the identity as its linear part, see
/// committedNormalMap), in double, then normalised and rounded to float. Single rays and
/// packets both come here, so they give the same bits by construction.
///
/// On x86-64 two hits per SSE2 instruction: the operations of transformTransposed and normalize
/// in their order (this baseline translation unit has no fused multiply-add to contract into;
/// square root, division and the rounding to float are correctly rounded in vectors as in
/// scalars). Three divisions per hit made the normals 7% of a packet's trace; in pairs, primary
/// packets of the BART kitchen and robots traced 2-5% faster (interleaved runs, both cameras).
/// A single hit takes the scalar operations: a pair made of one hit twice cost twice the
/// instructions for the same latency.
void mapNormals(const Affine3d* const* worldToObject, Hit* const* hits, std::size_t count) {
  std::size_t i = 0;
#if defined(__SSE2__)
  static constexpr Affine3d kIdentity = Affine3d::identity();
  for (; i + 1 < count; i += 2) {
    const Vec3f& na = hits[i]->geometricNormal;
    const Vec3f& nb = hits[i + 1]->geometricNormal;
    const __m128d nx = _mm_set_pd(nb.x, na.x), ny = _mm_set_pd(nb.y, na.y),
                  nz = _mm_set_pd(nb.z, na.z);
    Vec3f normals[2];
    if (worldToObject[i] == nullptr && worldToObject[i + 1] == nullptr) {
      // identityTransposed in pairs. The matrix path below gives the same bits, but through it
      // the kitchen's primary packets took 1.7% more instructions (Callgrind, 320x240).
      const __m128d zero = _mm_setzero_pd();
      const __m128d zx = _mm_mul_pd(nx, zero), zy = _mm_mul_pd(ny, zero), zz = _mm_mul_pd(nz, zero);
      detail::normalizePair(_mm_add_pd(_mm_add_pd(nx, zy), zz), _mm_add_pd(_mm_add_pd(zx, ny), zz),
                            _mm_add_pd(_mm_add_pd(zx, zy), nz), normals);
    } else {
      // The exact identity's ones and zeros give identityTransposed's bits.
      const Affine3d& a = worldToObject[i] != nullptr ? *worldToObject[i] : kIdentity;
      const Affine3d& b = worldToObject[i + 1] != nullptr ? *worldToObject[i + 1] : kIdentity;
      // transformTransposed: column c of the 3x3 part dotted with n, summed left to right.
      const auto column = [&](int c) {
        const __m128d m0 = _mm_set_pd(b.m[0][c], a.m[0][c]), m1 = _mm_set_pd(b.m[1][c], a.m[1][c]),
                      m2 = _mm_set_pd(b.m[2][c], a.m[2][c]);
        return _mm_add_pd(_mm_add_pd(_mm_mul_pd(m0, nx), _mm_mul_pd(m1, ny)), _mm_mul_pd(m2, nz));
      };
      detail::normalizePair(column(0), column(1), column(2), normals);
    }
    hits[i]->geometricNormal = normals[0];
    hits[i + 1]->geometricNormal = normals[1];
  }
#endif
  for (; i < count; ++i) mapNormal(worldToObject[i], *hits[i]);
}

}  // namespace

void Scene::fillGeometricNormal(Hit& hit) const {
  // The leaf test left the object-space normal, cross(v1 - v0, v2 - v0) from the double t
  // refinement, scaled into float's range (objectNormalForHit): reading the triangle again from
  // the mesh here would cost cache misses on every hit. Mapped in double: the inverse transpose
  // keeps it perpendicular under non-uniform scale and points it to the same side of the
  // surface after a mirroring (negative determinant) transform.
  mapNormal(impl_->committedNormalMap(hit.instanceId), hit);
}

namespace {

/// A packet's hits before its walk.
alignas(16) constexpr Hit kNoHits[kRayPacketSize] = {};

#if defined(__SSE2__)
/// Copies kNoHits as its 16-byte blocks, loaded and stored one by one. A memcpy of its fixed
/// size became `rep movsq` in this baseline translation unit, whose start-up was more than half
/// of Scene::intersect's own time in perf profiles of primary packets.
template <std::size_t... Block>
void copyNoHitBlocks(Hit* out, std::index_sequence<Block...>) {
  const auto* from = reinterpret_cast<const __m128i*>(kNoHits);
  auto* to = reinterpret_cast<__m128i*>(out);
  (_mm_storeu_si128(to + Block, _mm_load_si128(from + Block)), ...);
}
#endif

/// Writes kNoHits into a full packet's hits.
void copyNoHits(Hit* out) {
#if defined(__SSE2__)
  static_assert(sizeof(kNoHits) % 16 == 0, "the packet's hits fill whole 16-byte blocks");
  copyNoHitBlocks(out, std::make_index_sequence<sizeof(kNoHits) / 16>{});
#else
  std::memcpy(static_cast<void*>(out), kNoHits, sizeof(kNoHits));
#endif
}

}  // namespace

void Scene::intersect(std::span<const Ray> rays, std::span<Hit> hits, TraversalContext& ctx) const {
  if (rays.size() != hits.size())
    throw Error("Scene::intersect: " + std::to_string(rays.size()) + " rays but " +
                std::to_string(hits.size()) + " hits");
  // Where the kernels walk two packets as one, full pairs of packets go together.
  const bool pairs = ctx.pairPackets && detail::activePacketKernels().traversePair != nullptr;
  for (std::size_t base = 0; base < rays.size();) {
    const std::size_t left = rays.size() - base;
    const std::size_t n = pairs && left >= 2 * kRayPacketSize
                              ? 2 * kRayPacketSize
                              : std::min<std::size_t>(kRayPacketSize, left);
    const Ray* packet = rays.data() + base;
    Hit* packetHits = hits.data() + base;
    // The stream is read once, front to back: ask for the packet after next while this one is
    // traced (its cache lines).
    if (base + 3 * n <= rays.size())
      for (std::size_t line = 0; line < sizeof(Ray) * n; line += 64)
        __builtin_prefetch(reinterpret_cast<const char*>(packet + 2 * n) + line);
    // Default hits in one block copy: assigning Hit{} lane by lane stored field by field.
    if (n >= kRayPacketSize) {
      for (std::size_t h = 0; h < n; h += kRayPacketSize) copyNoHits(packetHits + h);
    } else {
      std::memcpy(static_cast<void*>(packetHits), kNoHits, n * sizeof(Hit));
    }
    if (n == 2 * kRayPacketSize) {
      impl_->topLevel->intersectPacketPair(packet, (1u << n) - 1u, packetHits, ctx);
    } else if (n < kRayPacketSize) {
      // The packet walk reads kRayPacketSize rays; a short tail goes through a full-size copy.
      Ray tail[kRayPacketSize];
      Hit tailHits[kRayPacketSize];
      std::copy(packet, packet + n, tail);
      impl_->topLevel->intersectPacket(tail, (1u << n) - 1u, tailHits, ctx);
      std::copy(tailHits, tailHits + n, packetHits);
    } else {
      // The top level leaves out the rays that are not traceable, from the rows it loads.
      impl_->topLevel->intersectPacket(packet, detail::kAllLanes, packetHits, ctx);
    }
    // Each packet's normals in one call, which maps them two at a time (mapNormals).
    for (std::size_t h = 0; h < n; h += kRayPacketSize) {
      const Affine3d* worldToObject[kRayPacketSize];
      Hit* hit[kRayPacketSize];
      std::size_t count = 0;
      for (std::size_t l = h; l < std::min(n, h + kRayPacketSize); ++l)
        if (packetHits[l].valid()) {
          worldToObject[count] = impl_->committedNormalMap(packetHits[l].instanceId);
          hit[count++] = &packetHits[l];
        }
      mapNormals(worldToObject, hit, count);
    }
    base += n;
  }
}

void Scene::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                     TraversalContext& ctx) const {
  if (rays.size() != occluded.size())
    throw Error("Scene::occluded: " + std::to_string(rays.size()) + " rays but " +
                std::to_string(occluded.size()) + " results");
  // Where the kernels walk two packets as one, full pairs of packets go together.
  const bool pairs = ctx.pairPackets && detail::activePacketKernels().occludedPair != nullptr;
  for (std::size_t base = 0; base < rays.size();) {
    if (pairs && rays.size() - base >= 2 * kRayPacketSize) {
      const unsigned blocked = impl_->topLevel->occludedPacketPair(
          rays.data() + base, (1u << (2 * kRayPacketSize)) - 1u, ctx);
      for (std::size_t l = 0; l < 2 * kRayPacketSize; ++l) occluded[base + l] = (blocked >> l) & 1u;
      base += 2 * kRayPacketSize;
      continue;
    }
    const std::size_t n = std::min<std::size_t>(kRayPacketSize, rays.size() - base);
    Ray packet[kRayPacketSize];
    std::copy(rays.data() + base, rays.data() + base + n, packet);
    const unsigned blocked = impl_->topLevel->occludedPacket(packet, (1u << n) - 1u, ctx);
    for (std::size_t l = 0; l < n; ++l) occluded[base + l] = (blocked >> l) & 1u;
    base += n;
  }
}

bool Scene::occluded(const Ray& ray) const {
  TraversalContext ctx;
  return occluded(ray, ctx);
}

bool Scene::occluded(const Ray& ray, TraversalContext& ctx) const {
  if (!isTraceable(ray)) return false;
  return impl_->topLevel->occluded(ray, ctx);
}

Box3f Scene::bounds() const {
  Box3f b;
  for (const InstanceRecord& r : impl_->records) b.extend(r.worldBounds);
  return b;
}

std::size_t Scene::objectCount() const {
  std::size_t n = 0;
  for (const Impl::Object& obj : impl_->objects) n += obj.alive ? 1 : 0;
  return n;
}

std::size_t Scene::instanceCount() const {
  std::size_t n = 0;
  for (const Impl::Instance& inst : impl_->instances) n += inst.alive ? 1 : 0;
  return n;
}

std::size_t Scene::instancedTriangleCount() const {
  std::size_t n = 0;
  for (const Impl::Instance& inst : impl_->instances)
    if (inst.alive) n += impl_->objects[inst.object].committed.triangleCount();
  return n;
}

const TopLevelAccel& Scene::topLevel() const {
  return *impl_->topLevel;
}

const SceneOptions& Scene::options() const {
  return impl_->options;
}

Scene::SurfaceData Scene::surfaceAt(const Ray& ray, const Hit& hit) const {
  SurfaceData sd;
  sd.position = ray.origin + ray.direction * hit.t;
  sd.geometricNormal = hit.geometricNormal;
  sd.shadingNormal = hit.geometricNormal;
  sd.uv = {hit.u, hit.v};
  if (!hit.valid()) return sd;
  const TriangleMesh& mesh = impl_->objects[hit.objectId].committed;
  const std::uint32_t i0 = mesh.indices[3 * hit.primId], i1 = mesh.indices[3 * hit.primId + 1],
                      i2 = mesh.indices[3 * hit.primId + 2];
  const float w = 1.0f - hit.u - hit.v;
  if (!mesh.normals.empty()) {
    const Vec3f n = mesh.normals[i0] * w + mesh.normals[i1] * hit.u + mesh.normals[i2] * hit.v;
    const Vec3d world = impl_->committedWorldToObject(hit.instanceId).transformTransposed(Vec3d(n));
    const double len = length(world);
    if (len > 0.0) {
      sd.shadingNormal = Vec3f(world / len);
      // Interpolated normals may point to the other side of the surface than the geometric
      // one (bad input or sharp silhouettes); keep them on the geometric normal's side.
      if (dot(sd.shadingNormal, sd.geometricNormal) < 0.0f) sd.shadingNormal = -sd.shadingNormal;
    }
  }
  if (!mesh.uvs.empty()) {
    const Vec2f &t0 = mesh.uvs[i0], &t1 = mesh.uvs[i1], &t2 = mesh.uvs[i2];
    sd.uv = {t0.u * w + t1.u * hit.u + t2.u * hit.v, t0.v * w + t1.v * hit.u + t2.v * hit.v};
    sd.hasUv = true;
  }
  return sd;
}

float Scene::uvAreaPerWorldArea(const Hit& hit) const {
  if (!hit.valid()) return 0.0f;
  const std::vector<float>& perTriangle = impl_->objects[hit.objectId].uvPerArea;
  if (perTriangle.empty()) return 0.0f;
  const float objectRatio = perTriangle[hit.primId];
  // Areas grow from object to world space by |det L|^(2/3) for L = M^-1, exactly so for rigid
  // motions and uniform scales (and as a mean over directions for non-uniform ones).
  const double det = impl_->committedWorldToObject(hit.instanceId).determinant();
  if (det == 1.0) return objectRatio;
  return static_cast<float>(static_cast<double>(objectRatio) * std::cbrt(det * det));
}

}  // namespace tg
