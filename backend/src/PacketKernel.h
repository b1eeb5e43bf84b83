// The packet traversal kernel of the BVH4 (object and top level): its ray layout, its leaf
// callback and one entry point per instruction set. Internal header: not installed.
//
// The kernel translation units are compiled with their own instruction-set flags. They must not
// emit out-of-line copies of inline functions shared with the rest of the library (the linker
// could keep an AVX copy for baseline callers), so this header holds only plain data and
// function-pointer types, and the kernels call back into baseline code for triangle tests.
#pragma once

#include <cstdint>

#include "Bvh4.h"
#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/Ray.h"

namespace tg::detail {

/// Rays per packet.
inline constexpr unsigned kPacketLanes = 8;
/// Mask with every lane set.
inline constexpr unsigned kAllLanes = (1u << kPacketLanes) - 1u;

/// A packet of up to kPacketLanes rays in structure-of-arrays layout, as the node test reads
/// them. All lanes share the signs of their direction components (signs), which is
/// what lets one box plane serve as entry plane for every lane.
struct alignas(64) PacketBoxRays {
  /// Origin per axis and lane.
  float origin[3][kPacketLanes];
  /// 1/direction per axis and lane; +inf for a zero (+0 or -0) component, as in Bvh4Ray.
  float reciprocal[3][kPacketLanes];
  /// Smallest t per lane.
  float tnear[kPacketLanes];
  /// Largest t per lane; leaf callbacks lower it as they find closer hits.
  float tfar[kPacketLanes];
  /// The lanes' shared direction signs: bit a set when component a is negative (-0 and NaN
  /// count as positive, as in directionSigns). They fix the Bvh4Node::bounds rows of the planes
  /// entered first and left last (OctantRows in PacketTraversalImpl.h).
  unsigned signs;
};

/// Tests primitives [first, first + count) of a leaf against the lanes in `lanes`. Closest-hit
/// callbacks lower rays.tfar of the lanes that found a closer hit; any-hit callbacks return the
/// lanes that hit something (the kernel stops tracing them).
using PacketLeafFn = unsigned (*)(void* user, std::uint32_t first, std::uint32_t count,
                                  unsigned lanes, PacketBoxRays& rays);

/// Walks the subtree rooted at inner node `child` with lane `lane` alone, as the single-ray
/// walk does (traverseBvh4From); closest-hit callbacks lower rays.tfar[lane], any-hit
/// callbacks return non-zero when the lane is occluded. The packet walk hands a subtree over
/// when only one lane still enters it: the shared walk would cost more than it saves.
using PacketSingleFn = unsigned (*)(void* user, std::uint32_t child, unsigned lane,
                                    PacketBoxRays& rays);

/// Walks the subtree (rootChild, rootCount) of a BVH4 with the lanes in `lanes`: inner node
/// rootChild when rootCount is 0, else the leaf of rootCount primitives at rootChild; (0, 0) is
/// the whole tree, whose root is nodes[0]. Closest hit (anyHit false): returns 0; the answer is
/// what the leaf callbacks recorded. Any hit: returns the lanes found occluded, visiting the
/// children hit highest slot first (the order of any-hit walks, Bvh4.h). Every lane visits
/// exactly the leaves whose widened box interval meets [tnear, tfar] at the time, with the
/// single-ray box test's arithmetic, so a lane finds what the single-ray walk finds.
using PacketTraverseFn = unsigned (*)(const Bvh4Node* nodes, std::uint32_t rootChild,
                                      std::uint32_t rootCount, PacketBoxRays& rays, unsigned lanes,
                                      bool anyHit, PacketLeafFn leaf, PacketSingleFn single,
                                      void* user, std::uint64_t& nodeVisits);

/// Lanes of a pair of packets walked as one (PairTraverseFn): lane 8h + l is lane l of half h.
inline constexpr unsigned kPairLanes = 2 * kPacketLanes;

/// The closest-hit leaf callback of a pair walk: tests primitives [first, first + count) of a
/// leaf against the lanes `lanes` (pair lanes, see kPairLanes) of the two halves' rays, and lowers
/// rays[h]->tfar of the lanes that found a closer hit.
using PairLeafFn = void (*)(void* user, std::uint32_t first, std::uint32_t count, unsigned lanes,
                            PacketBoxRays* const (&rays)[2]);

/// Walks the subtree rooted at inner node `child` with pair lane `lane` alone (PacketSingleFn for
/// a pair): closest hits lower its half's tfar.
using PairSingleFn = void (*)(void* user, std::uint32_t child, unsigned lane,
                              PacketBoxRays* const (&rays)[2]);

/// The closest-hit walk (PacketTraverseFn, anyHit false) of two packets as one of kPairLanes
/// lanes: each node's boxes are tested against the lanes of both halves at once, so a node
/// both halves enter is fetched, ordered and pushed once. The halves must share their direction
/// signs (PacketBoxRays::signs). Every lane visits exactly the leaves its own packet walk would
/// visit, so it finds what the single-ray walk finds.
using PairTraverseFn = void (*)(const Bvh4Node* nodes, std::uint32_t rootChild,
                                std::uint32_t rootCount, PacketBoxRays* const (&rays)[2],
                                unsigned lanes, PairLeafFn leaf, PairSingleFn single, void* user,
                                std::uint64_t& nodeVisits);

/// The any-hit leaf callback of a pair walk: returns the pair lanes of `lanes` that the leaf's
/// primitives occlude (the walk stops tracing them).
using PairOccludedLeafFn = unsigned (*)(void* user, std::uint32_t first, std::uint32_t count,
                                        unsigned lanes, PacketBoxRays* const (&rays)[2]);

/// Walks the subtree rooted at inner node `child` with pair lane `lane` alone for any hit:
/// non-zero when the lane is occluded.
using PairOccludedSingleFn = unsigned (*)(void* user, std::uint32_t child, unsigned lane,
                                          PacketBoxRays* const (&rays)[2]);

/// The any-hit walk (PacketTraverseFn, anyHit true) of two packets as one: returns the pair
/// lanes found occluded. The halves must share their direction signs.
using PairOccludedFn = unsigned (*)(const Bvh4Node* nodes, std::uint32_t rootChild,
                                    std::uint32_t rootCount, PacketBoxRays* const (&rays)[2],
                                    unsigned lanes, PairOccludedLeafFn leaf,
                                    PairOccludedSingleFn single, void* user,
                                    std::uint64_t& nodeVisits);

/// The lanes of a packet (kLanes of them: kPacketLanes, or kPairLanes for a pair) as the
/// watertight triangle test sees them, for lanes that share the axis permutation (kx, ky, kz)
/// of WatertightRay.
template <unsigned kLanes>
struct alignas(64) TriangleRaysOf {
  /// WatertightRay::origin per axis and lane.
  float origin[3][kLanes];
  /// WatertightRay::sx per lane.
  float sx[kLanes];
  /// WatertightRay::sy per lane.
  float sy[kLanes];
  /// WatertightRay::tnear per lane.
  float tnear[kLanes];
  /// WatertightRay::originD per axis and lane: the double ray on which t is refined.
  double originD[3][kLanes];
  /// WatertightRay::directionD per axis and lane.
  double directionD[3][kLanes];
  ///@{
  /// The shared axis permutation.
  int kx = 0, ky = 1, kz = 2;
  ///@}
};

/// The triangle-test rays of one packet.
using PacketTriangleRays = TriangleRaysOf<kPacketLanes>;
/// The triangle-test rays of a pair of packets (lane 8h + l is lane l of half h).
using PairTriangleRays = TriangleRaysOf<kPairLanes>;

/// Triangles one call of the packet triangle test takes at most.
inline constexpr std::uint32_t kTriangleBatch = 8;

/// What one call of the triangle test found for kLanes lanes, per triangle i of the batch.
template <unsigned kLanes>
struct alignas(64) TriangleHitsOf {
  /// Lanes that hit triangle i within [tnear, tfar] (tfar as lowered by the batch's earlier
  /// hits), with t, u and v below.
  unsigned hit[kTriangleBatch];
  /// Lanes whose inside test met an edge function exactly zero in float: the scalar test
  /// decides them (in double). Never also in hit[i].
  unsigned exact[kTriangleBatch];
  /// Distance of the hit per lane (valid in hit[i]).
  float t[kTriangleBatch][kLanes];
  ///@{
  /// Barycentrics per lane (valid in hit[i]).
  float u[kTriangleBatch][kLanes], v[kTriangleBatch][kLanes];
  ///@}
  /// cross(v1 - v0, v2 - v0) in double (TriangleHit::normal), valid when hit[i] is not empty.
  double normal[kTriangleBatch][3];
};

/// What the triangle test found for one packet.
using PacketTriangleHits = TriangleHitsOf<kPacketLanes>;
/// What the triangle test found for a pair of packets.
using PairTriangleHits = TriangleHitsOf<kPairLanes>;

/// Where a run of triangles keeps its vertices: component a of vertex v of triangle i is
/// at[(3 * v + a) * componentStride + i * triangleStride]. Packed triangles (9 floats each: v0,
/// v1, v2) have strides 1 and 9; a leaf's rows (LeafRows.h) the leaf's size and 1.
struct TriangleFloats {
  const float* at = nullptr;
  std::uint32_t componentStride = 1;
  std::uint32_t triangleStride = 9;
};

/// The watertight test (intersectWatertight) of the lanes in `lanes` against up to
/// kTriangleBatch triangles (`vertices`) in order, with the scalar test's exact
/// arithmetic in float and in double. A lane that hits lowers its own tfar (copied from `tfar`)
/// for the triangles after; with `anyHit` it leaves the batch instead. The call stops after the
/// first triangle with lanes in exact[i], which need the scalar test before the rest of the
/// batch, or when no lane is left; it returns how many triangles it wrote in `out`.
using TriangleTestFn = std::uint32_t (*)(const TriangleFloats& vertices, std::uint32_t count,
                                         const PacketTriangleRays& rays, const float* tfar,
                                         unsigned lanes, bool anyHit, PacketTriangleHits& out);

/// TriangleTestFn for the closest hits of a pair's lanes (kPairLanes), whose halves share their
/// axis permutation.
using PairTriangleTestFn = std::uint32_t (*)(const TriangleFloats& vertices, std::uint32_t count,
                                             const PairTriangleRays& rays, const float* tfar,
                                             unsigned lanes, PairTriangleHits& out);

/// Loads rays[0..kPacketLanes) (all of them are read) for a packet walk: leaves in `lanes` only
/// its lanes whose rays are traceable (isTraceable), writes into `out` the box rays of those
/// whose direction signs match the first one's (tfar lowered to hits[l].t unless `hits` is
/// null; every other lane a copy of the first, so that full-width arithmetic sees ordinary
/// numbers) and returns them: exactly what the single-ray box test computes per lane (Bvh4Ray).
/// Returns 0 when no lane is traceable.
using BoxRayLoadFn = unsigned (*)(const Ray* rays, const Hit* hits, unsigned& lanes,
                                  PacketBoxRays& out);

/// What a packet's row load (TransformedRowsFn, IdentityRowsFn) found of its lanes (see
/// BvhPacketRays).
struct LoadedLanes {
  /// The lanes loaded with the first one's object-space direction signs: the box rows'.
  unsigned coherent = 0;
  /// The lanes of `coherent` with the first one's axis permutation: the triangle rows'.
  unsigned filtered = 0;
  /// The first lane's dominant axis (WatertightRay::kz) and whether its component there is
  /// negative, from which WatertightRay::shearAxes gives kx and ky.
  int kz = 2;
  bool kzNegative = false;
};

/// Loads the rows of the lanes `lanes` (not empty) of rays[0..kPacketLanes) (all are read)
/// entering an instance whose world-to-object matrix is `worldToObject`, lane l limited to
/// tfar[l] (read for `lanes` only), as mapping each lane (objectRayFor) and loading the object
/// rays (BvhAccel::loadPacket) would give them: `box` whole, and the rows of `triangles` (kx, ky
/// and kz are left to the caller, from the answer's kz). Lanes outside the answer's sets hold the
/// first lane's numbers.
using TransformedRowsFn = LoadedLanes (*)(const Ray* rays, const Affine3d& worldToObject,
                                          unsigned lanes, const float* tfar, PacketBoxRays& box,
                                          PacketTriangleRays& triangles);

/// Loads the triangle rows of the lanes `lanes` (not empty) of rays[0..kPacketLanes) (all are
/// read) entering identity instances, whose object rays are the world rays: the rows of
/// `triangles` as mapIdentityPacket writes them (kx, ky and kz left to the caller, as for
/// TransformedRowsFn). The answer's `coherent` is `lanes`: the box rows are the world's.
using IdentityRowsFn = LoadedLanes (*)(const Ray* rays, unsigned lanes,
                                       PacketTriangleRays& triangles);

/// The lanes of `lanes` whose rays meet the box in slot 0 of `node` (a Bvh4Node with one
/// used slot) within [tnear, tfar], with the walks' box arithmetic.
using PacketOneBoxFn = unsigned (*)(const Bvh4Node& node, const PacketBoxRays& rays,
                                    unsigned lanes);

/// The kernels of one instruction set.
struct PacketKernels {
  /// The packet load of the top-level walk.
  BoxRayLoadFn loadBoxRays = nullptr;
  /// The BVH4 packet walk.
  PacketTraverseFn traverse = nullptr;
  /// The triangle test.
  TriangleTestFn testTriangles = nullptr;
  /// The rows of a packet entering a transformed instance.
  TransformedRowsFn loadTransformedRows = nullptr;
  /// The triangle rows of a packet entering identity instances.
  IdentityRowsFn loadIdentityRows = nullptr;
  /// The test of one box, before the walk (the top level's box for packets from outside it).
  PacketOneBoxFn meetsOneBox = nullptr;
  /// The closest-hit walk of two packets as one: the AVX-512 kernels only, where one register
  /// holds a pair's sixteen lanes. With AVX2's two registers per slot it measured no faster than
  /// each packet alone (tg-bench trace, rows tracegraph-bvh-packets against -packets8 in one
  /// process, one thread, 640x480, from the BART cameras on a Zen 5 with TG_SIMD=avx2: kitchen
  /// 22.14 against 21.83 ms, robots 22.08 against 22.02), where AVX-512 pairs took 18.98
  /// against 22.42 and 18.46 against 22.86.
  PairTraverseFn traversePair = nullptr;
  /// The any-hit walk of two packets as one; null for the portable kernels. Shadow packets from
  /// the BART cameras (same runs as traversePair) took 4-5% less time with it, AVX2 and
  /// AVX-512 alike.
  PairOccludedFn occludedPair = nullptr;
  /// The triangle test of a pair's lanes; null where no register holds a pair's sixteen floats
  /// (the pair's leaves then test half by half).
  PairTriangleTestFn testTrianglesPair = nullptr;
};

/// The portable kernels (SSE on x86-64).
PacketKernels packetKernelsPortable();
/// The AVX2 kernels; null members when the build has none.
PacketKernels packetKernelsAvx2();
/// The AVX-512 kernels; null members when the build has none.
PacketKernels packetKernelsAvx512();

/// The kernels of the active instruction set (tg::activeSimdIsa).
const PacketKernels& activePacketKernels();

}  // namespace tg::detail
