// The accuracy suite: every hard case of ../shared/docs/hard-cases.md that can be measured,
// as a measurement rather than a pass/fail test. Each row names a case and an implementation
// variant, times the rays it traced, and carries the error those rays showed against the
// double-precision brute-force reference (or against an analytic answer where the case has
// one). The pass/fail versions live in tests/backend; here the figures are reported even when
// they are bad (the Moller-Trumbore and epsilon variants exist to show what goes wrong).
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "AccuracyGeometry.h"
#include "BenchSceneLoader.h"
#include "BenchTiming.h"
#include "FlattenedScene.h"
#include "ImageJudge.h"
#include "ReferenceJudge.h"
#include "SceneGenerators.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "TraceParallel.h"
#include "TriangleTests.h"
#include "Variants.h"
#include "tracegraph/backend/ReferenceIntersector.h"
#include "tracegraph/backend/render/Optics.h"
#include "tracegraph/backend/render/RayOffset.h"
#include "tracegraph/loaders/SceneSource.h"
#include "tracegraph/scenegraph/SceneGraph.h"
#include "tracegraph/scenegraph/SceneRenderer.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {
namespace {

/// Sizes of one run: --quick shrinks everything so that the suite fits a CI budget.
struct Sizes {
  int reps = 3;
  int icosphereLevel = 5;    ///< 20,480 triangles, as the case demands
  std::size_t tRays = 2000;  ///< rays per translation of the t-error case
  std::vector<double> translations = {1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7};
  std::size_t acneRays = 20000;
  std::vector<double> acneTranslations = {1.0, 1e2, 1e4, 1e6};
  std::size_t contactSamples = 2000;
  std::size_t glassRays = 4000;
  ImageSize renderSize{160, 120};
  ImageSize bartSize{320, 240};
  std::size_t bartJudged = 1024;  ///< BART rays judged by the (brute-force) reference
};

Sizes sizesFor(bool quick) {
  Sizes s;
  if (!quick) return s;
  s.reps = 1;
  s.icosphereLevel = 4;
  s.tRays = 300;
  s.translations = {1.0, 1e2, 1e4, 1e6, 1e7};
  s.acneRays = 2000;
  s.acneTranslations = {1.0, 1e4, 1e6};
  s.contactSamples = 400;
  s.glassRays = 400;
  s.renderSize = {48, 32};
  s.bartSize = {64, 48};
  s.bartJudged = 96;
#ifdef TG_BENCH_SANITIZED
  // Under the sanitizers everything runs several times slower; the quick run stays a smoke
  // test of every case.
  s.icosphereLevel = 3;
  s.tRays = 100;
  s.translations = {1.0, 1e6};
  s.acneRays = 500;
  s.contactSamples = 100;
  s.glassRays = 100;
  s.bartSize = {32, 24};
  s.bartJudged = 32;
#endif
  return s;
}

std::string sci(double v) {
  if (v == 0.0) return "0";
  const int e = static_cast<int>(std::lround(std::log10(std::abs(v))));
  if (std::abs(v - std::pow(10.0, e)) < 1e-9 * std::abs(v)) return "1e" + std::to_string(e);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

double per1e7(std::size_t count, std::size_t rays) {
  return rays == 0 ? 0.0 : 1e7 * static_cast<double>(count) / static_cast<double>(rays);
}
double percent(std::size_t count, std::size_t total) {
  return total == 0 ? 0.0 : 100.0 * static_cast<double>(count) / static_cast<double>(total);
}

void addJudgement(BenchRow& row, const Judgement& j) {
  row.extra.push_back(intField("mismatches", static_cast<std::int64_t>(j.mismatches)));
  row.extra.push_back(intField("ambiguous", static_cast<std::int64_t>(j.ambiguous)));
  row.extra.push_back(intField("judged", static_cast<std::int64_t>(j.rays)));
}

BenchScene singleMesh(const TriangleMesh& mesh, const std::string& name) {
  BenchScene s;
  s.name = name;
  s.meshes.push_back(mesh);
  s.instances.push_back({0, Affine3d{}});
  return s;
}

// -------------------------------------------------------------------------------------------
// Case 1: closed-mesh leaks, rays aimed exactly at vertices and edges.

void leakCase(BenchReport& report, const CommonOptions& common, const Sizes& sizes,
              tbb::task_arena& arena) {
  struct Closed {
    std::string name;
    TriangleMesh mesh;
    Vec3f origin;
  };
  std::vector<Closed> meshes;
  TriangleMesh sphere = makeIcosphereMesh(sizes.icosphereLevel);
  meshes.push_back({"icosphere " + std::to_string(sphere.triangleCount()) + " tris",
                    std::move(sphere),
                    {0.01f, -0.02f, 0.03f}});
  meshes.push_back({"cube 12 tris", makeClosedBox({-1, -1, -1}, {1, 1, 1}), {0.1f, 0.2f, -0.3f}});
  meshes.push_back({"torus 2304 tris", makeTorusMesh(2.0, 0.7, 48, 24), {2.0f, 0.0f, 0.1f}});

  for (const Closed& c : meshes) {
    const std::string caseName = "leaks: " + c.name;
    progress("accuracy: " + caseName);
    const std::vector<AimedRay> aimed = makeAimedRays(c.mesh, c.origin);
    std::vector<Ray> rays;
    for (const AimedRay& a : aimed) rays.push_back(a.ray);
    const auto addLeaks = [&](BenchRow& row, std::size_t leaks) {
      setRays(row, rays.size());
      row.extra.push_back(intField("leaks", static_cast<std::int64_t>(leaks)));
      row.extra.push_back(realField("leaks_per_1e7", per1e7(leaks, rays.size())));
    };

    // Whole scenes: a ray that finds no triangle at all has leaked. `trace` fills one outcome
    // per ray; the row gets its time and the rays that found nothing.
    const auto leakRow = [&](const std::string& impl, const auto& trace) {
      std::vector<RayOutcome> out(rays.size());
      const TimingSummary t = measureRepeated(
          sizes.reps, [&](int) { return timeMs([&] { arena.execute([&] { trace(out); }); }); });
      const auto leaks = static_cast<std::size_t>(
          std::count_if(out.begin(), out.end(), [](const RayOutcome& o) { return !o.hit(); }));
      addLeaks(addRow(report, caseName, impl, t), leaks);
    };
    for (const AccelVariant& v : accelVariants()) {
      Scene scene(v.options);
      scene.createInstance(scene.createObject(c.mesh));
      arena.execute([&] { scene.commit(); });
      leakRow("tracegraph-" + v.name,
              [&](std::vector<RayOutcome>& out) { out = traceOutcomes(scene, rays); });
      // Packets through the same BVH: the aimed rays leave one origin towards neighbouring
      // vertices and edges, so consecutive rays make coherent packets.
      if (v.name == "bvh")
        leakRow("tracegraph-bvh-packets",
                [&](std::vector<RayOutcome>& out) { out = traceOutcomesInPackets(scene, rays); });
    }
#ifdef TG_HAVE_EMBREE
    {
      EmbreeDevice device(common.threads, common.embreeConfig);
      EmbreeBenchScene peer(device, singleMesh(c.mesh, c.name), EmbreeQuality::High);
      arena.execute([&] { peer.commit(); });
      leakRow("embree-intersect1",
              [&](std::vector<RayOutcome>& out) { peer.intersect1(rays, out); });
    }
#else
    (void)common;
#endif

    // The triangle test alone: a ray through a vertex or edge must hit one of the triangles
    // around it (the fan), whatever else it would hit later.
    for (const TriangleTestVariant& test : triangleTestVariants()) {
      std::vector<std::uint8_t> leaked(aimed.size());
      const TimingSummary t = measureRepeated(sizes.reps, [&](int) {
        return timeMs([&] {
          arena.execute([&] {
            parallelOverRays(aimed.size(), [&](std::size_t begin, std::size_t end) {
              for (std::size_t i = begin; i < end; ++i) {
                const PreparedRay r(aimed[i].ray);
                bool hit = false;
                for (const std::uint32_t tri : aimed[i].fan) {
                  float tHit = 0.0f;
                  hit |= test.test(r, c.mesh.positions[c.mesh.indices[3 * tri]],
                                   c.mesh.positions[c.mesh.indices[3 * tri + 1]],
                                   c.mesh.positions[c.mesh.indices[3 * tri + 2]], kInfinity, tHit);
                }
                leaked[i] = hit ? 0 : 1;
              }
            });
          });
        });
      });
      addLeaks(addRow(report, caseName, "fan-" + test.name, t),
               static_cast<std::size_t>(std::count(leaked.begin(), leaked.end(), 1)));
    }
  }
}

// -------------------------------------------------------------------------------------------
// Cases 6 and 7: t error in ulps through instances at growing translations, against the same
// geometry flattened into float world coordinates and against a float brute force.

void translationCase(BenchReport& report, const CommonOptions& common, const Sizes& sizes,
                     tbb::task_arena& arena) {
  const TriangleMesh mesh = makeIcosphereMesh(3);
  for (const double translation : sizes.translations) {
    const std::string caseName = "t error: translation " + sci(translation);
    progress("accuracy: " + caseName);
    const Affine3d m = Affine3d::translation({translation, -translation, translation}) *
                       Affine3d::rotation({1, 2, 3}, 30.0);
    BenchScene instanced;
    instanced.name = "icosphere instanced";
    instanced.meshes.push_back(mesh);
    instanced.instances.push_back({0, m});
    const Flattened flat = flatten(instanced);

    // Rays from a few radii around the object towards points near its centre, in float world
    // coordinates (what an application at that translation would produce).
    BenchRandom random(77);
    const Vec3d centre(translation, -translation, translation);
    std::vector<Ray> rays(sizes.tRays);
    for (Ray& r : rays) {
      const Vec3d from =
          centre + Vec3d(random.uniform(-4, 4), random.uniform(-4, 4), random.uniform(-4, 4));
      const Vec3d to = centre + Vec3d(random.uniform(-0.5, 0.5), random.uniform(-0.5, 0.5),
                                      random.uniform(-0.5, 0.5));
      r.origin = Vec3f(from);
      r.direction = Vec3f(to - Vec3d(r.origin));
    }

    Scene judgeScene;
    populateScene(instanced, judgeScene);
    judgeScene.commit();
    const ReferenceIntersector reference(judgeScene);
    std::vector<ReferenceHit> expected;
    arena.execute([&] { expected = referenceHits(reference, rays); });

    // t of each ray as traced by an implementation, with its outcome in the instanced ids.
    const auto judgeT = [&](BenchRow& row, const std::vector<float>& t,
                            const std::vector<RayOutcome>& out) {
      setRays(row, rays.size());
      std::vector<double> ulps;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const ReferenceHit& e = expected[i];
        // t is compared wherever both found the same triangle, even where the reference calls
        // the choice of triangle ambiguous: t on a given triangle is well defined.
        if (!e.hit || !out[i].hit() || out[i].prim != e.primId || out[i].instance != e.instanceId)
          continue;
        ulps.push_back(ulpError(t[i], e.t));
      }
      std::sort(ulps.begin(), ulps.end());
      row.extra.push_back(realField("ulp_max", ulps.empty() ? 0.0 : ulps.back()));
      row.extra.push_back(realField("ulp_median", ulps.empty() ? 0.0 : ulps[ulps.size() / 2]));
      row.extra.push_back(intField("t_compared", static_cast<std::int64_t>(ulps.size())));
      addJudgement(row, judgeOutcomes(expected, out));
    };

    const auto traceScene = [&](const BenchScene& bench, const SceneOptions& options,
                                const std::string& impl, const Flattened* mapBack, bool packets) {
      Scene scene(options);
      populateScene(bench, scene);
      arena.execute([&] { scene.commit(); });
      std::vector<float> t(rays.size(), kInfinity);
      std::vector<RayOutcome> out(rays.size());
      const TimingSummary timing = measureRepeated(sizes.reps, [&](int) {
        return timeMs([&] {
          arena.execute([&] {
            parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
              TraversalContext ctx;
              std::vector<Hit> hits(end - begin);
              if (packets) {
                scene.intersect(std::span<const Ray>(rays).subspan(begin, end - begin),
                                std::span<Hit>(hits), ctx);
              } else {
                for (std::size_t i = begin; i < end; ++i)
                  scene.intersect(rays[i], hits[i - begin], ctx);
              }
              for (std::size_t i = begin; i < end; ++i) {
                const Hit& hit = hits[i - begin];
                out[i] = hit.valid() ? RayOutcome{hit.instanceId, hit.primId} : RayOutcome{};
                if (hit.valid()) t[i] = hit.t;
              }
            });
          });
        });
      });
      if (mapBack) unflatten(*mapBack, out);
      judgeT(addRow(report, caseName, impl, timing), t, out);
    };
    for (const AccelVariant& v : accelVariants()) {
      traceScene(instanced, v.options, "tracegraph-" + v.name + " instanced", nullptr, false);
      traceScene(flat.scene, v.options, "tracegraph-" + v.name + " flattened", &flat, false);
    }
    traceScene(instanced, SceneOptions{}, "tracegraph-bvh-packets instanced", nullptr, true);

    // A float brute force over the flattened triangles: what a single-precision judge would
    // report (the "float reference").
    for (const TriangleTestVariant& test : triangleTestVariants()) {
      const TriangleMesh& fm = flat.scene.meshes[0];
      std::vector<float> t(rays.size(), kInfinity);
      std::vector<RayOutcome> out(rays.size());
      const TimingSummary timing = measureRepeated(sizes.reps, [&](int) {
        return timeMs([&] {
          arena.execute([&] {
            parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
              for (std::size_t i = begin; i < end; ++i) {
                const PreparedRay r(rays[i]);
                float best = kInfinity;
                std::uint32_t bestPrim = kInvalidId;
                for (std::size_t k = 0; k < fm.triangleCount(); ++k) {
                  float tHit = 0.0f;
                  if (test.test(r, fm.positions[fm.indices[3 * k]],
                                fm.positions[fm.indices[3 * k + 1]],
                                fm.positions[fm.indices[3 * k + 2]], best, tHit) &&
                      tHit < best) {
                    best = tHit;
                    bestPrim = static_cast<std::uint32_t>(k);
                  }
                }
                t[i] = best;
                out[i] = bestPrim == kInvalidId ? RayOutcome{} : RayOutcome{0, bestPrim};
              }
            });
          });
        });
      });
      unflatten(flat, out);
      judgeT(addRow(report, caseName, "bruteforce-" + test.name + " flattened", timing), t, out);
    }

#ifdef TG_HAVE_EMBREE
    EmbreeDevice device(common.threads, common.embreeConfig);
    for (const auto& [bench, name, mapBack] :
         {std::tuple<const BenchScene*, const char*, const Flattened*>{&instanced, "instanced",
                                                                       nullptr},
          std::tuple<const BenchScene*, const char*, const Flattened*>{&flat.scene, "flattened",
                                                                       &flat}}) {
      EmbreeBenchScene peer(device, *bench, EmbreeQuality::High);
      arena.execute([&] { peer.commit(); });
      std::vector<RayOutcome> out(rays.size());
      const TimingSummary timing = measureRepeated(sizes.reps, [&](int) {
        return timeMs([&] { arena.execute([&] { peer.intersect1(rays, out); }); });
      });
      if (mapBack) unflatten(*mapBack, out);
      BenchRow& row = addRow(report, caseName, std::string("embree-intersect1 ") + name, timing);
      setRays(row, rays.size());
      addJudgement(row, judgeOutcomes(expected, out));  // the peer's API gives no t to compare
    }
#else
    (void)common;
#endif
  }
}

// -------------------------------------------------------------------------------------------
// Secondary-ray origins (cases 13-15).

/// The origin of a ray leaving the hit `hit` of `ray` in direction `w`, by offset variant.
Ray secondaryRay(const Scene& scene, const Ray& ray, const Hit& hit, const Vec3f& w,
                 OffsetKind kind) {
  if (kind == OffsetKind::Scaled) return spawnRay(refineHitPoint(scene, ray, hit), w);
  Ray r;
  r.origin = ray.origin + ray.direction * hit.t;
  r.direction = w;
  if (kind == OffsetKind::Epsilon) {
    const Vec3f n =
        dot(hit.geometricNormal, w) >= 0.0f ? hit.geometricNormal : -hit.geometricNormal;
    r.origin += n * kFixedEpsilon;
  }
  return r;
}

TriangleMesh quadMesh(const Vec3f& corner, const Vec3f& e1, const Vec3f& e2) {
  TriangleMesh m;
  m.positions = {corner, corner + e1, corner + e1 + e2, corner + e2};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

/// Case 13: a large tilted plane alone, lit at a grazing 3 degrees: every shadow ray must
/// escape, so any occluded one is acne.
void acneCase(BenchReport& report, const Sizes& sizes, tbb::task_arena& arena) {
  for (const double translation : sizes.acneTranslations) {
    const std::string caseName = "acne: plane at " + sci(translation) + ", light at 3 deg";
    progress("accuracy: " + caseName);
    const Vec3f c(Vec3d(translation, -translation, 0.5 * translation));
    const Vec3f e1 = normalize(Vec3f{1.0f, 0.3f, -0.2f}) * 400.0f;
    const Vec3f e2 = normalize(cross(Vec3f{0.2f, 0.4f, 1.0f}, e1)) * 300.0f;
    Scene scene;
    scene.createInstance(scene.createObject(quadMesh(c - e1 * 0.5f - e2 * 0.5f, e1, e2)));
    scene.commit();
    const Vec3f n = normalize(cross(e1, e2));
    const Vec3f tangent = normalize(e1);
    const double elevation = 3.0 * std::numbers::pi / 180.0;
    const Vec3f toLight = normalize(tangent * static_cast<float>(std::cos(elevation)) +
                                    n * static_cast<float>(std::sin(elevation)));
    BenchRandom random(13);
    std::vector<Ray> primary;
    std::vector<Hit> hits;
    while (primary.size() < sizes.acneRays) {
      const Vec3f local = e1 * static_cast<float>(random.uniform(-0.45, 0.45)) +
                          e2 * static_cast<float>(random.uniform(-0.45, 0.45));
      Ray r;
      r.origin = c + local + n * 300.0f +
                 Vec3f(Vec3d(random.uniform(-100, 100), random.uniform(-100, 100), 0.0));
      r.direction = c + local - r.origin;
      Hit hit;
      if (!scene.intersect(r, hit)) continue;
      primary.push_back(r);
      hits.push_back(hit);
    }
    for (const OffsetVariant& v : offsetVariants()) {
      std::vector<Ray> shadow(primary.size());
      for (std::size_t i = 0; i < primary.size(); ++i)
        shadow[i] = secondaryRay(scene, primary[i], hits[i], toLight, v.kind);
      std::vector<std::uint8_t> occluded(shadow.size());
      const TimingSummary t = measureRepeated(sizes.reps, [&](int) {
        return timeMs([&] {
          arena.execute([&] {
            parallelOverRays(shadow.size(), [&](std::size_t begin, std::size_t end) {
              TraversalContext ctx;
              for (std::size_t i = begin; i < end; ++i)
                occluded[i] = scene.occluded(shadow[i], ctx) ? 1 : 0;
            });
          });
        });
      });
      BenchRow& row = addRow(report, caseName, v.name, t);
      setRays(row, shadow.size());
      const auto acne = static_cast<std::size_t>(std::count(occluded.begin(), occluded.end(), 1));
      row.extra.push_back(intField("acne", static_cast<std::int64_t>(acne)));
      row.extra.push_back(realField("acne_pct", percent(acne, shadow.size())));
    }
  }
}

/// Case 14: a unit box floating a gap g above a floor, lit from the side at 45 degrees. A floor
/// point under the box at distance d from its edge sees the light exactly when d < g. Reports,
/// per offset variant, the wrongly lit or shadowed share per gap, the smallest gap with at most
/// 1% wrong, and the light leaking at contact (g = 0: everything under the box is dark).
void contactCase(BenchReport& report, const Sizes& sizes, tbb::task_arena& arena) {
  const std::string caseName = "contact shadows: unit box over a floor, gaps 1e-1 .. 1e-6";
  progress("accuracy: " + caseName);
  const std::vector<double> gaps = {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 0.0};
  const Vec3f toLight(1.0f, 1.0f, 0.0f);  // exactly 45 degrees; t in units of this vector
  for (const OffsetVariant& v : offsetVariants()) {
    double totalMs = 0.0;
    std::size_t totalRays = 0;
    double smallestCorrect = 0.0;
    bool allCorrect = true;
    std::vector<ExtraField> fields;
    double contactLeakPct = 0.0;
    for (const double gap : gaps) {
      const auto g = static_cast<float>(gap);
      Scene scene;
      scene.createInstance(scene.createObject(quadMesh({-2, 0, 2}, {4, 0, 0}, {0, 0, -4})));
      scene.createInstance(
          scene.createObject(makeClosedBox({-0.5f, g, -0.5f}, {0.5f, g + 1.0f, 0.5f})));
      scene.commit();
      BenchRandom random(14);
      const double band = gap > 0.0 ? 2.0 * gap : 0.1;
      std::vector<Ray> shadow;
      std::vector<std::uint8_t> expectLit, ambiguous;
      while (shadow.size() < sizes.contactSamples) {
        const auto target =
            Vec3f(Vec3d(0.5 - random.uniform(0.0, band), 0.0, random.uniform(-0.4, 0.4)));
        Ray r;
        // From below the (two-sided) floor, so that the box never hides the target; what
        // matters is the rounding of the computed hit point, not the side it is seen from.
        r.origin = target + Vec3f(-0.3f, -3.0f, 0.2f);
        r.direction = target - r.origin;
        Hit hit;
        if (!scene.intersect(r, hit) || hit.instanceId != 0) continue;
        // Expected from the point actually hit, in double: d = 0.5 - x, lit when d < g.
        const Vec3d p = Vec3d(r.origin) + Vec3d(r.direction) * static_cast<double>(hit.t);
        const double d = 0.5 - p.x;
        shadow.push_back(secondaryRay(scene, r, hit, toLight, v.kind));
        expectLit.push_back(d < static_cast<double>(g) ? 1 : 0);
        // Within a few ulps of the boundary either answer is acceptable.
        ambiguous.push_back(std::abs(d - static_cast<double>(g)) < 4.0 * 6e-8 ? 1 : 0);
      }
      std::vector<std::uint8_t> occluded(shadow.size());
      const double ms = timeMs([&] {
        arena.execute([&] {
          parallelOverRays(shadow.size(), [&](std::size_t begin, std::size_t end) {
            TraversalContext ctx;
            for (std::size_t i = begin; i < end; ++i)
              occluded[i] = scene.occluded(shadow[i], ctx) ? 1 : 0;
          });
        });
      });
      totalMs += ms;
      totalRays += shadow.size();
      std::size_t wrong = 0, judged = 0;
      for (std::size_t i = 0; i < shadow.size(); ++i) {
        if (ambiguous[i]) continue;
        ++judged;
        if ((occluded[i] == 0) != (expectLit[i] != 0)) ++wrong;
      }
      const double pct = percent(wrong, judged);
      if (gap > 0.0) {
        fields.push_back(realField("wrong_pct_gap_" + sci(gap), pct));
        if (allCorrect && pct <= 1.0) smallestCorrect = gap;
        if (pct > 1.0) allCorrect = false;
      } else {
        contactLeakPct = pct;
      }
    }
    TimingSummary t;
    t.medianMs = t.minMs = t.maxMs = totalMs;
    t.reps = 1;
    BenchRow& row = addRow(report, caseName, v.name, t);
    setRays(row, totalRays);
    row.extra.push_back(realField("smallest_correct_gap", smallestCorrect));
    row.extra.push_back(realField("contact_leak_pct", contactLeakPct));
    for (ExtraField& f : fields) row.extra.push_back(std::move(f));
  }
}

/// Case 15: a refractive slab (index 1.5) of thickness h, entered from above: the refracted ray
/// must hit the slab's far face, and the ray leaving it must not hit the slab again.
void thinGlassCase(BenchReport& report, const Sizes& sizes, tbb::task_arena& arena) {
  for (const double thickness : {1e-2, 1e-4, 1e-5}) {
    const std::string caseName = "thin glass: slab " + sci(thickness) + " thick";
    progress("accuracy: " + caseName);
    for (const OffsetVariant& v : offsetVariants()) {
      std::size_t failures = 0, rays = 0;
      double ms = 0.0;
      for (const double translation : {0.0, 10.0}) {
        const auto T = static_cast<float>(translation);
        const auto h = static_cast<float>(thickness);
        Scene scene;
        scene.createInstance(scene.createObject(
            makeClosedBox({T - 1.0f, T - h, T - 1.0f}, {T + 1.0f, T, T + 1.0f})));
        scene.commit();
        BenchRandom random(15);
        std::vector<Ray> entering(sizes.glassRays);
        for (Ray& r : entering) {
          const Vec3f dir =
              normalize(Vec3f(Vec3d(random.uniform(-1, 1), -1.0, random.uniform(-1, 1))));
          r.origin = Vec3f(Vec3d(translation + random.uniform(-0.5, 0.5), translation,
                                 translation + random.uniform(-0.5, 0.5))) -
                     dir * 3.0f;
          r.direction = dir;
        }
        std::vector<std::uint8_t> failed(entering.size(), 0);
        ms += timeMs([&] {
          arena.execute([&] {
            parallelOverRays(entering.size(), [&](std::size_t begin, std::size_t end) {
              for (std::size_t i = begin; i < end; ++i) {
                const Ray& r = entering[i];
                Hit top;
                if (!scene.intersect(r, top)) {
                  failed[i] = 1;
                  continue;
                }
                const Vec3f n1 = dot(top.geometricNormal, r.direction) < 0.0f
                                     ? top.geometricNormal
                                     : -top.geometricNormal;
                const FresnelSplit in = fresnelRefract(r.direction, n1, 1.0f, 1.5f);
                const Ray inside = secondaryRay(scene, r, top, in.refracted, v.kind);
                Hit bottom;
                // The far face is the bottom (y = T - h), whose normal is -y.
                if (!scene.intersect(inside, bottom) || std::abs(bottom.geometricNormal.y) < 0.5f ||
                    inside.origin.y + inside.direction.y * bottom.t > T - 0.5f * h) {
                  failed[i] = 1;
                  continue;
                }
                const Vec3f n2 = dot(bottom.geometricNormal, inside.direction) < 0.0f
                                     ? bottom.geometricNormal
                                     : -bottom.geometricNormal;
                const FresnelSplit out = fresnelRefract(inside.direction, n2, 1.5f, 1.0f);
                if (out.totalInternalReflection) continue;
                Hit again;
                if (scene.intersect(secondaryRay(scene, inside, bottom, out.refracted, v.kind),
                                    again))
                  failed[i] = 1;
              }
            });
          });
        });
        failures += static_cast<std::size_t>(std::count(failed.begin(), failed.end(), 1));
        rays += entering.size();
      }
      TimingSummary t;
      t.medianMs = t.minMs = t.maxMs = ms;
      t.reps = 1;
      BenchRow& row = addRow(report, caseName, v.name, t);
      setRays(row, 3 * rays);  // entering, inside and leaving rays
      row.extra.push_back(intField("failures", static_cast<std::int64_t>(failures)));
      row.extra.push_back(realField("exit_fail_pct", percent(failures, rays)));
    }
  }
}

// -------------------------------------------------------------------------------------------
// Cases 2 and 21: determinism over runs and thread counts.

void determinismCase(BenchReport& report, const CommonOptions& common, const Sizes& sizes) {
  progress("accuracy: determinism");
  const int threadCounts[] = {1, std::max(2, common.threads)};
  {
    const std::string caseName = "determinism: shared-edge rays, 1 and N threads, twice";
    const TriangleMesh mesh = makeIcosphereMesh(3);
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
      const Vec3f a = mesh.positions[mesh.indices[i]], b = mesh.positions[mesh.indices[i + 1]];
      rays.push_back({{0.0f, 0.0f, 0.0f}, 0.0f, (a + b) * 0.5f, kInfinity});
    }
    for (const AccelVariant& v : accelVariants()) {
      Scene scene(v.options);
      scene.createInstance(scene.createObject(mesh));
      scene.commit();
      std::vector<RayOutcome> first;
      std::size_t differing = 0;
      std::vector<double> samples;
      for (int run = 0; run < 2; ++run)
        for (const int threads : threadCounts) {
          tbb::task_arena arena(threads);
          std::vector<RayOutcome> out;
          samples.push_back(
              timeMs([&] { arena.execute([&] { out = traceOutcomes(scene, rays); }); }));
          if (first.empty()) {
            first = out;
            continue;
          }
          for (std::size_t i = 0; i < out.size(); ++i)
            differing += out[i].prim != first[i].prim || out[i].instance != first[i].instance;
        }
      BenchRow& row = addRow(report, caseName, "tracegraph-" + v.name, summarize(samples));
      setRays(row, rays.size());
      row.extra.push_back(intField("differing", static_cast<std::int64_t>(differing)));
      row.extra.push_back(intField(
          "misses",
          std::count_if(first.begin(), first.end(), [](const RayOutcome& o) { return !o.hit(); })));
    }
  }
  {
    const std::string caseName =
        "determinism: demo scene, Whitted, " + std::to_string(sizes.renderSize.width) + "x" +
        std::to_string(sizes.renderSize.height) + ", 1 and N threads, twice";
    const SceneSource source = loadSceneSource(std::nullopt, 30.0);
    SceneGraph graph;
    graph.setRoot(source.root);
    RenderSettings settings;
    settings.mode = RenderMode::Whitted;
    SceneRenderer renderer(graph, settings);
    renderer.setLook(source.look);
    graph.advanceTo(source.timing.timeOf(source.timing.frames / 2));
    graph.sync();
    renderer.update();
    const Camera camera = renderer.camera(static_cast<std::uint32_t>(sizes.renderSize.width),
                                          static_cast<std::uint32_t>(sizes.renderSize.height));
    Frame first;
    std::size_t differing = 0;
    std::vector<double> samples;
    RenderStats stats;
    for (int run = 0; run < 2; ++run)
      for (const int threads : threadCounts) {
        tbb::task_arena arena(threads);
        Frame frame;
        samples.push_back(
            timeMs([&] { arena.execute([&] { stats = renderer.render(camera, frame); }); }));
        if (first.beauty.empty()) {
          first = std::move(frame);
          continue;
        }
        const std::vector<float>& a = first.beauty.data();
        const std::vector<float>& b = frame.beauty.data();
        for (std::size_t i = 0; i < a.size(); ++i)
          differing += std::memcmp(&a[i], &b[i], sizeof(float)) != 0;
        if (!(first.primId == frame.primId) || !first.depth.bitwiseEqual(frame.depth)) ++differing;
      }
    BenchRow& row = addRow(report, caseName, "tracegraph-whitted", summarize(samples));
    setRays(row, stats.traced.total());
    row.extra.push_back(intField("differing", static_cast<std::int64_t>(differing)));
  }
}

// -------------------------------------------------------------------------------------------
// Primitive ids on the BART scenes: ours (each accelerator, instanced and flattened) against
// Embree single rays and packets, all judged by the reference on a subsample of the rays.

void bartCase(BenchReport& report, const CommonOptions& common, const AccuracyOptions& options,
              const Sizes& sizes, tbb::task_arena& arena) {
  const std::array<std::pair<const char*, const char*>, 3> scenes = {
      {{"kitchen", "bart/kitchen/aff/kitchen.aff"},
       {"robots", "bart/robots/aff/Robot.aff"},
       {"museum", "bart/museum/aff/museum5.aff"}}};
  for (const auto& [name, relative] : scenes) {
    const std::filesystem::path path = std::filesystem::path(options.dataDir) / relative;
    if (options.dataDir.empty() || !std::filesystem::exists(path)) {
      progress(std::string("accuracy: ") + name + " not found; its rows are skipped");
      continue;
    }
    const ImageSize size = sizes.bartSize;
    const std::string caseName = std::string("BART ids: ") + name + " primary " +
                                 std::to_string(size.width) + "x" + std::to_string(size.height);
    progress("accuracy: " + caseName);
    const BenchScene bench = loadBenchScene(path.string());
    const Flattened flat = flatten(bench);
    Scene judgeScene;
    populateScene(bench, judgeScene);
    arena.execute([&] { judgeScene.commit(); });
    const std::vector<Ray> rays = makePrimaryRays(frameBounds(judgeScene.bounds(), size), size);
    const std::vector<Ray> judged = subsampleRays(rays, sizes.bartJudged);
    std::vector<ReferenceHit> expected;
    std::optional<ReferenceImage> image;  // for the perceptual (FLIP) error
    {
      const ReferenceIntersector reference(judgeScene);
      arena.execute([&] {
        expected = referenceHits(reference, judged);
        image.emplace(judgeScene, reference, rays, size, sizes.bartJudged);
      });
    }
    std::vector<RayOutcome> ours;
    const auto finish = [&](BenchRow& row, const std::vector<RayOutcome>& out) {
      setRays(row, rays.size());
      if (ours.empty()) ours = out;
      const MismatchCounts vsOurs = compareOutcomes(ours, out);
      row.extra.push_back(intField("prim_mismatches", static_cast<std::int64_t>(vsOurs.prim)));
      row.extra.push_back(intField("hit_mismatches", static_cast<std::int64_t>(vsOurs.hitMiss)));
      const std::vector<RayOutcome> sub = subsampleOutcomes(out, sizes.bartJudged);
      row.extra.push_back(realField("ref_mismatches",
                                    static_cast<double>(judgeOutcomes(expected, sub).mismatches)));
      row.extra.push_back(intField("judged", static_cast<std::int64_t>(judged.size())));
      row.extra.push_back(realField("psnr_db", eyeLightPsnr(judgeScene, judged, expected, sub)));
      row.extra.push_back(realField("flip_mean", image->flipMean(out)));
    };
    const auto traceOurs = [&](const BenchScene& b, const SceneOptions& o, const std::string& impl,
                               const Flattened* mapBack) {
      Scene scene(o);
      populateScene(b, scene);
      arena.execute([&] { scene.commit(); });
      std::vector<RayOutcome> out;
      const TimingSummary t = measureRepeated(sizes.reps, [&](int) {
        return timeMs([&] { arena.execute([&] { out = traceOutcomes(scene, rays); }); });
      });
      if (mapBack) unflatten(*mapBack, out);
      finish(addRow(report, caseName, impl, t), out);
    };
    const std::vector<AccelVariant> variants = accelVariants();
    for (const AccelVariant& v : variants)
      traceOurs(bench, v.options, "tracegraph-" + v.name, nullptr);
    traceOurs(flat.scene, variants.front().options,
              "tracegraph-" + variants.front().name + " flattened", &flat);
#ifdef TG_HAVE_EMBREE
    EmbreeDevice device(common.threads, common.embreeConfig);
    EmbreeBenchScene peer(device, bench, EmbreeQuality::High);
    arena.execute([&] { peer.commit(); });
    std::vector<RayOutcome> out(rays.size());
    TimingSummary t = measureRepeated(sizes.reps, [&](int) {
      return timeMs([&] { arena.execute([&] { peer.intersect1(rays, out); }); });
    });
    finish(addRow(report, caseName, "embree-intersect1", t), out);
    std::fill(out.begin(), out.end(), RayOutcome{});
    t = measureRepeated(sizes.reps, [&](int) {
      return timeMs([&] { arena.execute([&] { peer.intersect8(rays, size, out); }); });
    });
    finish(addRow(report, caseName, "embree-intersect8", t), out);
#else
    (void)common;
#endif
  }
}

}  // namespace

BenchReport runAccuracySuite(const CommonOptions& common, const AccuracyOptions& options) {
  const Sizes sizes = sizesFor(options.quick);
  BenchReport report = startReport("accuracy", common);
  report.extra.push_back(
      textField("reference", "double-precision brute force (ReferenceIntersector)"));
  tbb::task_arena arena(common.threads);
  leakCase(report, common, sizes, arena);
  translationCase(report, common, sizes, arena);
  acneCase(report, sizes, arena);
  contactCase(report, sizes, arena);
  thinGlassCase(report, sizes, arena);
  determinismCase(report, common, sizes);
  bartCase(report, common, options, sizes, arena);
  return report;
}

}  // namespace tg::bench
