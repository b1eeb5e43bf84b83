// Tests of the AFF/NFF parser and the keyframe mathematics against the BART scenes (facts from
// docs/aff-format.md and data/README.md) and against small hand-written and malformed files.
#define BOOST_TEST_MODULE loaders_aff
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "SharedData.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AffParser.h"
#include "tracegraph/loaders/KochanekBartels.h"

// Printers for Boost.Test messages.
namespace tg {
template <typename T>
std::ostream& operator<<(std::ostream& os, const Vec3<T>& v) {
  return os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
}
std::ostream& operator<<(std::ostream& os, const Vec2f& v) {
  return os << '(' << v.u << ", " << v.v << ')';
}
std::ostream& operator<<(std::ostream& os, AffBlock::Kind k) {
  return os << static_cast<int>(k);
}
}  // namespace tg

namespace fs = std::filesystem;
namespace utf = boost::unit_test;

namespace {

const fs::path kData = TG_DATA_DIR;
const fs::path kKitchen = kData / "bart/kitchen/aff/kitchen.aff";
const fs::path kRobots = kData / "bart/robots/aff/Robot.aff";
const fs::path kMuseum = kData / "bart/museum/aff/museum5.aff";
constexpr double kDeg = std::numbers::pi / 180.0;

/// Skips a test (with the reason) when the shared BART scenes are not installed.
tg::test::FilesAvailable BartAvailable() {
  return {"BART scenes", kData, {kKitchen, kRobots, kMuseum}};
}

/// Each scene is parsed once and shared by the tests.
const tg::AffDocument& scene(const fs::path& file) {
  static std::map<fs::path, tg::AffDocument> cache;
  auto it = cache.find(file);
  if (it == cache.end()) it = cache.emplace(file, tg::parseAffFile(file)).first;
  return it->second;
}

double maxDiff(const tg::Affine3d& a, const tg::Affine3d& b) {
  double d = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(a.m[r][c] - b.m[r][c]));
  return d;
}

double maxDiff(const tg::Vec3d& a, const tg::Vec3d& b) {
  return std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
}

/// A fresh folder for small test files, removed afterwards.
struct TempDir {
  fs::path dir;
  TempDir() {
    static int counter = 0;
    dir = fs::temp_directory_path() / ("tg_aff_test_" + std::to_string(std::random_device{}()) +
                                       "_" + std::to_string(counter++));
    fs::create_directories(dir);
    dir = fs::canonical(dir);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = dir / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
};

/// Parses `file` and returns the tg::Error message (empty if it parsed).
std::string errorOf(const fs::path& file, const tg::AffParseOptions& options = {}) {
  try {
    tg::parseAffFile(file, options);
  } catch (const tg::Error& e) {
    return e.what();
  }
  return {};
}

/// Checks that parsing `text` (as file `name` in a temp folder) fails with a message starting
/// with "…name:line: " and containing `what`.
void expectError(const std::string& text, int line, const std::string& what) {
  TempDir tmp;
  const fs::path file = tmp.write("bad.aff", text);
  const std::string msg = errorOf(file);
  BOOST_TEST_INFO("message: " << msg);
  BOOST_TEST(msg.find(file.string() + ":" + std::to_string(line) + ": ") == 0u);
  BOOST_TEST(msg.find(what) != std::string::npos);
}

tg::AffDocument parseText(const std::string& text, const tg::AffParseOptions& options = {}) {
  return tg::parseAffText(text, fs::temp_directory_path(), options, "inline.aff");
}

/// Second-order one-sided finite-difference derivatives of f at t, from the left and right.
template <typename F>
std::pair<tg::Vec3d, tg::Vec3d> sideDerivatives(F f, double t, double eps) {
  const tg::Vec3d left = (f(t) * 3.0 - f(t - eps) * 4.0 + f(t - 2 * eps)) / (2 * eps);
  const tg::Vec3d right = (f(t + eps) * 4.0 - f(t) * 3.0 - f(t + 2 * eps)) / (2 * eps);
  return {left, right};
}

/// Left/right mismatch of the quaternion's time derivative at t: {absolute, relative to size}.
/// The spline is compared as quaternions: the matrix conversion (angle = 2·acos w, as the
/// reference does) quantises angles near the identity to ~3e-8 rad, which finite differences
/// would amplify.
std::pair<double, double> quaternionKink(const tg::KbRotationSpline& spline, double t, double eps) {
  const auto vec = [&](double x) { return spline.evaluate(x).vec(); };
  const auto scalar = [&](double x) { return tg::Vec3d{spline.evaluate(x).w, 0, 0}; };
  const auto [lv, rv] = sideDerivatives(vec, t, eps);
  const auto [lw, rw] = sideDerivatives(scalar, t, eps);
  const double kink = std::max(maxDiff(lv, rv), maxDiff(lw, rw));
  return {kink, kink / (1.0 + tg::length(lv) + std::abs(lw.x))};
}

/// Key k of a file-ordered key list is met exactly by the reference segment search at t_k:
/// it is held (k = 1 or k = n-2) or starts the segment chosen at t_k.
template <typename Key>
bool keyIsReached(const std::vector<Key>& keys, std::size_t k) {
  const std::size_t n = keys.size();
  if (k == 1 || k == n - 2) return true;
  const double t = keys[k].time;
  if (!(t > keys[1].time) || !(t < keys[n - 2].time) || !(keys[k + 1].time > t)) return false;
  for (std::size_t s = 2; s < k; ++s)
    if (keys[s].time > t) return false;
  return true;
}

/// Key k is an interior key with strictly increasing, reachable neighbours on both sides.
template <typename Key>
bool keyIsInterior(const std::vector<Key>& keys, std::size_t k) {
  const std::size_t n = keys.size();
  if (k < 2 || k + 3 > n) return false;
  return keyIsReached(keys, k) && keyIsReached(keys, k - 1) && keys[k - 1].time < keys[k].time &&
         keys[k].time < keys[k + 1].time && keys[k].tcb.continuity == 0.0;
}

std::vector<const tg::AffDocument*> allScenes() {
  return {&scene(kKitchen), &scene(kRobots), &scene(kMuseum)};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Scene facts

BOOST_AUTO_TEST_SUITE(bart_scenes, *utf::precondition(BartAvailable()))

BOOST_AUTO_TEST_CASE(triangle_totals_at_frame_zero) {
  const tg::AffTriangleCounts kitchen = scene(kKitchen).countTriangles();
  BOOST_TEST(kitchen.total() == 110561u);
  BOOST_TEST(kitchen.meshes == 110561u);
  BOOST_TEST(kitchen.meshCount == 393u);
  BOOST_TEST(kitchen.animated == 0u);

  const tg::AffTriangleCounts robots = scene(kRobots).countTriangles();
  BOOST_TEST(robots.total() == 71708u);
  BOOST_TEST(robots.meshCount == 1849u);

  const tg::AffTriangleCounts museum = scene(kMuseum).countTriangles();
  BOOST_TEST(museum.total() == 11564u);
  BOOST_TEST(museum.meshes == 10000u);
  BOOST_TEST(museum.polygons == 274u);
  BOOST_TEST(museum.texturedTriangles == 10u);
  BOOST_TEST(museum.coneCount == 8u);
  BOOST_TEST(museum.cones == 8u * 32u);
  BOOST_TEST(museum.animated == 1024u);
  BOOST_TEST(museum.staticTotal() - museum.cones == 10284u);
}

BOOST_AUTO_TEST_CASE(include_counts_and_blocks) {
  BOOST_TEST(scene(kKitchen).includeCount == 186u);
  BOOST_TEST(scene(kRobots).includeCount == 835u);
  BOOST_TEST(scene(kMuseum).includeCount == 6u);
  // Count xs / x blocks over the expanded tree.
  const auto countBlocks = [](const tg::AffDocument& d) {
    std::size_t xs = 0, x = 0;
    std::vector<const tg::AffBlock*> todo{&d.root};
    while (!todo.empty()) {
      const tg::AffBlock* b = todo.back();
      todo.pop_back();
      xs += b->kind == tg::AffBlock::Kind::Static;
      x += b->kind == tg::AffBlock::Kind::Animated;
      for (const tg::AffBlock& c : b->children) todo.push_back(&c);
    }
    return std::pair{xs, x};
  };
  BOOST_TEST(countBlocks(scene(kKitchen)).first == 416u);
  BOOST_TEST(countBlocks(scene(kKitchen)).second == 7u);
  BOOST_TEST(countBlocks(scene(kRobots)).first == 521u);
  BOOST_TEST(countBlocks(scene(kRobots)).second == 190u);
  BOOST_TEST(scene(kKitchen).tracks.size() == 6u);
  BOOST_TEST(scene(kKitchen).warnings.empty());  // re-included identical tracks: no warning
  BOOST_TEST(scene(kRobots).warnings.empty());
  BOOST_TEST(scene(kRobots).tracks.size() == 187u);
  BOOST_TEST(scene(kMuseum).tracks.size() == 1u);
}

BOOST_AUTO_TEST_CASE(kitchen_lights_view_animation) {
  const tg::AffDocument& d = scene(kKitchen);
  BOOST_TEST_REQUIRE(d.lights.size() == 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    const float grey = i < 4 ? 0.3f : 0.4f;
    BOOST_TEST(d.lights[i].hasColour);
    BOOST_TEST(d.lights[i].colour == (tg::Vec3f{grey, grey, grey}));
  }
  BOOST_TEST(maxDiff(d.lights[0].position, {2.15, 2.0, 0.9}) < 1e-12);
  BOOST_TEST(d.ambient == (tg::Vec3f{2.5f, 2.5f, 2.5f}));
  BOOST_TEST(d.background == (tg::Vec3f{0.5f, 0.5f, 1.0f}));
  BOOST_TEST(d.view.present);
  BOOST_TEST(d.view.angle == 40.0);
  BOOST_TEST(d.view.hither == 0.01);
  BOOST_TEST(d.view.width == 800);
  BOOST_TEST(d.view.height == 600);
  BOOST_TEST(d.animation.start == 0.0);
  BOOST_TEST(d.animation.end == 20.0);
  BOOST_TEST(d.animation.frames == 800);
  BOOST_TEST(d.animation.frameTime(1) == 20.0 / 799.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(d.animation.frameTime(799) == 20.0);
  // Textures resolve to ../TextureFiles and exist.
  std::size_t textured = 0;
  for (const tg::AffMaterial& m : d.materials) {
    if (m.textureName.empty()) continue;
    ++textured;
    BOOST_TEST(fs::is_regular_file(m.texturePath));
    BOOST_TEST(m.texturePath.parent_path().filename() == "TextureFiles");
  }
  BOOST_TEST(textured > 0u);
  // The glass: T 0.85, ior 1.55.
  BOOST_TEST(std::any_of(d.materials.begin(), d.materials.end(), [](const tg::AffMaterial& m) {
    return m.transmittance == 0.85f && m.ior == 1.55f;
  }));
}

BOOST_AUTO_TEST_CASE(robots_lights_view_animation) {
  const tg::AffDocument& d = scene(kRobots);
  BOOST_TEST_REQUIRE(d.lights.size() == 1u);
  BOOST_TEST(maxDiff(d.lights[0].position, {1, 500, 1}) == 0.0);
  BOOST_TEST(d.lights[0].colour == (tg::Vec3f{1, 1, 1}));
  BOOST_TEST(d.ambient == (tg::Vec3f{1, 1, 1}));
  BOOST_TEST(d.background == (tg::Vec3f{0, 0, 0}));  // no `b`: black
  BOOST_TEST(d.view.angle == 36.869890479389504);
  BOOST_TEST(d.view.hither == 1.0);
  BOOST_TEST(d.view.width == 800);
  BOOST_TEST(d.view.height == 600);
  BOOST_TEST(d.animation.start == 0.0);
  BOOST_TEST(d.animation.end == 50.0);
  BOOST_TEST(d.animation.frames == 800);
  BOOST_TEST(d.animation.frameTime(1) == 0.0625782227784731, boost::test_tools::tolerance(1e-12));
  // Transmissive materials with ior 0 render with ior 1.
  bool sawIorZero = false;
  for (const tg::AffMaterial& m : d.materials) {
    if (m.transmittance > 0.0f && m.ior == 0.0f) {
      sawIorZero = true;
      BOOST_TEST(m.refractiveIndex() == 1.0f);
    }
  }
  BOOST_TEST(sawIorZero);
}

BOOST_AUTO_TEST_CASE(museum_lights_view_animation) {
  const tg::AffDocument& d = scene(kMuseum);
  BOOST_TEST_REQUIRE(d.lights.size() == 2u);
  for (const tg::AffLight& l : d.lights) BOOST_TEST(l.colour == (tg::Vec3f{0.5f, 0.5f, 0.5f}));
  BOOST_TEST(maxDiff(d.lights[0].position, {-4, 4.5, 0}) == 0.0);
  BOOST_TEST(maxDiff(d.lights[1].position, {4, 4.5, 0}) == 0.0);
  BOOST_TEST(d.ambient == (tg::Vec3f{1, 1, 1}));  // default
  BOOST_TEST(d.background == (tg::Vec3f{0.5f, 0.5f, 1.0f}));
  BOOST_TEST(d.view.angle == 45.0);
  BOOST_TEST(d.view.hither == 0.1);
  BOOST_TEST(d.view.width == 800);
  BOOST_TEST(d.view.height == 600);
  BOOST_TEST(d.animation.start == -1.0);
  BOOST_TEST(d.animation.end == 5.0);
  BOOST_TEST(d.animation.frames == 300);
  BOOST_TEST(d.animation.frameTime(0) == -1.0);
  BOOST_TEST(d.animation.frameTime(1) == -1.0 + 6.0 / 299.0, boost::test_tools::tolerance(1e-14));
  BOOST_TEST(d.animation.frameTime(299) == 5.0);
  // tt textures are found in ../TextureFiles.
  for (const tg::AffMaterial& m : d.materials)
    if (!m.textureName.empty()) BOOST_TEST(fs::is_regular_file(m.texturePath));
  BOOST_TEST(d.warnings.empty());
}

BOOST_AUTO_TEST_CASE(cameras_at_frame_zero) {
  // Kitchen: keys at -1 and 0 are equal; t = 0 ≤ t1 holds key 1.
  {
    const tg::AffDocument& d = scene(kKitchen);
    const tg::AffCamera c = d.camera(d.animation.frameTime(0));
    BOOST_TEST(maxDiff(c.eye, {3.75, 2.3, 3.6}) < 1e-12);
    const tg::Affine3d r = tg::rotationMatrix({0.77895, -0.61838, -0.10410}, -31.77348 * kDeg);
    BOOST_TEST(maxDiff(c.direction, r.transformVector({0, 0, -1})) < 1e-9);
    BOOST_TEST(maxDiff(c.up, r.transformVector({0, 1, 0})) < 1e-9);
    BOOST_TEST(c.angle == 40.0);
    BOOST_TEST(c.hither == 0.01);
    // Held after 19.7 s.
    BOOST_TEST(maxDiff(d.camera(19.9).eye, {3.27488, 0.334545, 2.98028}) < 1e-12);
  }
  // Robots: the track named exactly `camera`, not `old_camera`.
  {
    const tg::AffDocument& d = scene(kRobots);
    BOOST_TEST_REQUIRE(d.cameraTrack() != nullptr);
    BOOST_TEST(d.cameraTrack()->name == "camera");
    BOOST_TEST_REQUIRE(d.findTrack("old_camera") != nullptr);
    const tg::AffCamera c = d.camera(0.0);
    BOOST_TEST(maxDiff(c.eye, {-3.5, 2, -203}) < 1e-12);
    const tg::Affine3d r = tg::rotationMatrix({-0.85813, 0.513, -0.02546}, -6.6 * kDeg);
    BOOST_TEST(maxDiff(c.direction, r.transformVector({0, 0, -1})) < 1e-9);
    BOOST_TEST(maxDiff(c.up, r.transformVector({0, 1, 0})) < 1e-9);
    // The two tracks start alike but part at 9.5 s (old_camera has a key at (1.8, 20, -151)).
    const tg::Vec3d oldEye = d.findTrack("old_camera")->evaluate(9.5).transformPoint({0, 0, 0});
    BOOST_TEST(maxDiff(oldEye, {1.8, 20, -151}) < 1e-12);
    BOOST_TEST(maxDiff(oldEye, d.camera(9.5).eye) > 1.0);
    // Held after 45 s.
    BOOST_TEST(maxDiff(d.camera(49.0).eye, {0, 80, 0}) < 1e-12);
  }
  // Museum: frame 0 is t = -1 = t1; rotation 180° about y looks along +z.
  {
    const tg::AffDocument& d = scene(kMuseum);
    const tg::AffCamera c = d.camera(d.animation.frameTime(0));
    BOOST_TEST(maxDiff(c.eye, {0, 1.8, -9}) < 1e-12);
    BOOST_TEST(maxDiff(c.direction, {0, 0, 1}) < 1e-12);
    BOOST_TEST(maxDiff(c.up, {0, 1, 0}) < 1e-12);
    BOOST_TEST(c.hither == 0.1);
  }
}

BOOST_AUTO_TEST_CASE(splines_hit_every_key) {
  std::size_t checked = 0, total = 0;
  for (const tg::AffDocument* d : allScenes()) {
    for (const auto& [name, track] : d->tracks) {
      BOOST_TEST_CONTEXT("track " << name) {
        for (const auto* channel : {&track.translation, &track.scale}) {
          if (!*channel) continue;
          const auto& keys = (*channel)->keys();
          total += keys.size() - 2;
          for (std::size_t k = 1; k + 1 < keys.size(); ++k) {
            if (!keyIsReached(keys, k)) continue;
            ++checked;
            BOOST_TEST(maxDiff((*channel)->evaluate(keys[k].time), keys[k].value) < 1e-9);
          }
        }
        if (track.rotation) {
          const auto& keys = track.rotation->keys();
          total += keys.size() - 2;
          for (std::size_t k = 1; k + 1 < keys.size(); ++k) {
            if (!keyIsReached(keys, k)) continue;
            ++checked;
            const tg::Affine3d expected = tg::rotationMatrix(keys[k].axis, keys[k].degrees * kDeg);
            BOOST_TEST(maxDiff(track.rotation->matrix(keys[k].time), expected) < 1e-9,
                       "key " << k << " at t = " << keys[k].time);
          }
        }
      }
    }
  }
  BOOST_TEST_MESSAGE("keys met exactly: " << checked << " of " << total);
  // Only repeated times and the second list of gun_rot1 are not reached by the search.
  BOOST_TEST(checked > total * 9 / 10);
}

BOOST_AUTO_TEST_CASE(splines_are_c1_at_interior_keys) {
  std::size_t positions = 0, rotations = 0, smoothRotations = 0;
  const double eps = 1e-5;
  for (const tg::AffDocument* d : allScenes()) {
    for (const auto& [name, track] : d->tracks) {
      BOOST_TEST_CONTEXT("track " << name) {
        if (track.translation) {
          const auto& spline = *track.translation;
          const auto& keys = spline.keys();
          for (std::size_t k = 2; k + 2 < keys.size(); ++k) {
            if (!keyIsInterior(keys, k)) continue;
            const double span =
                std::min(keys[k].time - keys[k - 1].time, keys[k + 1].time - keys[k].time);
            if (span < 8 * eps) continue;
            ++positions;
            const auto [l, r] =
                sideDerivatives([&](double t) { return spline.evaluate(t); }, keys[k].time, eps);
            BOOST_TEST(maxDiff(l, r) < 1e-5 * (1.0 + tg::length(l)), "key " << k);
          }
        }
        if (track.rotation) {
          const auto& spline = *track.rotation;
          const auto& keys = spline.keys();
          const auto& q = spline.quaternions();
          for (std::size_t k = 2; k + 2 < keys.size(); ++k) {
            if (!keyIsInterior(keys, k)) continue;
            const double span =
                std::min(keys[k].time - keys[k - 1].time, keys[k + 1].time - keys[k].time);
            if (span < 8 * eps) continue;
            // The reference builds the incoming tangent from the next key before its sign
            // fix; where that key gets flipped, the spline has a kink by design.
            const tg::Quatd next =
                tg::Quatd::fromAxisAngle(keys[k + 1].axis, keys[k + 1].degrees * kDeg);
            if (q[k].dot(next) < 0.0) continue;
            // Below the slerp cut-off (keys < 0.12° apart but not equal) squad degenerates.
            const auto sinHalf = [&](std::size_t a, std::size_t b) {
              const double c = std::clamp(std::abs(q[a].dot(q[b])), 0.0, 1.0);
              return std::sqrt(1.0 - c * c);
            };
            const double s0 = sinHalf(k - 1, k), s1 = sinHalf(k, k + 1);
            if ((s0 > 0 && s0 < 2e-3) || (s1 > 0 && s1 < 2e-3)) continue;
            ++rotations;
            const double hl = keys[k].time - keys[k - 1].time, hr = keys[k + 1].time - keys[k].time;
            const auto [kink, relative] =
                quaternionKink(spline, keys[k].time, std::min(eps, 1e-4 * span));
            // The reference's outer slerp returns its first input when the squad correction is
            // below its 1e-3 cut-off, dropping a tangent term of at most 2e-3 per unit of the
            // segment parameter on either side. Everything else must be C¹.
            if (relative < 1e-6) {
              ++smoothRotations;
            } else {
              BOOST_TEST(kink < 2.05e-3 * (1.0 / hl + 1.0 / hr), "key " << k << " kink " << kink);
            }
          }
        }
      }
    }
  }
  BOOST_TEST_MESSAGE("C1 checked at " << positions << " position keys and " << rotations
                                      << " rotation keys (" << rotations - smoothRotations
                                      << " with a kink from the slerp cut-off)");
  BOOST_TEST(positions > 100u);
  BOOST_TEST(rotations > 100u);
  BOOST_TEST(smoothRotations > rotations * 99 / 100);
}

BOOST_AUTO_TEST_CASE(robots_gun_rot1_two_lists) {
  const tg::AffTrack* track = scene(kRobots).findTrack("gun_rot1");
  BOOST_TEST_REQUIRE(track != nullptr);
  BOOST_TEST_REQUIRE(track->rotation.has_value());
  const auto& keys = track->rotation->keys();
  BOOST_TEST(keys.size() == 116u);
  // Kept in file order, not sorted: the second list restarts at 42.
  BOOST_TEST(!std::is_sorted(keys.begin(), keys.end(),
                             [](const auto& a, const auto& b) { return a.time < b.time; }));
  const auto rz = [](double deg) { return tg::rotationMatrix({0, 0, 1}, deg * kDeg); };
  // First list governs up to 48 s (45 s: 8100° ≡ 180°, 45.5 s: 8190° ≡ 270°, uniform steps:
  // squad with equal spacing and steps is linear in angle).
  BOOST_TEST(maxDiff(track->rotation->matrix(45.0), rz(180)) < 1e-9);
  BOOST_TEST(maxDiff(track->rotation->matrix(45.25), rz(225)) < 1e-9);
  // The second list governs [48, 50]: 48 s = 1080° ≡ 0°, 49 s = 1260° ≡ 180°.
  BOOST_TEST(maxDiff(track->rotation->matrix(48.0), rz(0)) < 1e-9);
  BOOST_TEST(maxDiff(track->rotation->matrix(48.25), rz(45)) < 1e-9);
  BOOST_TEST(maxDiff(track->rotation->matrix(49.0), rz(180)) < 1e-9);
  // Held at and after t(n-2) = 50 (1440° with a stray, non-unit axis: a whole turn).
  BOOST_TEST(maxDiff(track->rotation->matrix(50.0), rz(0)) < 1e-9);
  BOOST_TEST(maxDiff(track->rotation->matrix(60.0), rz(0)) < 1e-9);
}

BOOST_AUTO_TEST_CASE(non_unit_axes_are_normalised) {
  std::size_t nonUnit = 0;
  for (const auto& [name, track] : scene(kRobots).tracks) {
    if (!track.rotation) continue;
    const auto& keys = track.rotation->keys();
    bool hasNonUnit = false;
    for (const auto& k : keys) hasNonUnit |= std::abs(tg::length(k.axis) - 1.0) > 0.02;
    if (!hasNonUnit) continue;
    ++nonUnit;
    BOOST_TEST_CONTEXT("track " << name) {
      for (double t = keys.front().time - 1; t <= keys.back().time + 1; t += 0.173) {
        const tg::Affine3d r = track.rotation->matrix(t);
        // R·Rᵀ = I and det = +1: a pure rotation whatever the axis length.
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) {
            const double dot =
                r.m[i][0] * r.m[j][0] + r.m[i][1] * r.m[j][1] + r.m[i][2] * r.m[j][2];
            BOOST_TEST(std::abs(dot - (i == j ? 1.0 : 0.0)) < 1e-12);
          }
        }
        BOOST_TEST(std::abs(r.determinant() - 1.0) < 1e-12);
      }
    }
  }
  // 28 tracks plus the camera key of 0.974.
  BOOST_TEST(nonUnit >= 28u);
}

BOOST_AUTO_TEST_CASE(museum_animated_triangles) {
  const tg::AffDocument& d = scene(kMuseum);
  std::vector<const tg::AffAnimatedTriangle*> tris;
  std::vector<const tg::AffBlock*> todo{&d.root};
  while (!todo.empty()) {
    const tg::AffBlock* b = todo.back();
    todo.pop_back();
    for (const auto& t : b->animatedTriangles) tris.push_back(&t);
    for (const auto& c : b->children) todo.push_back(&c);
  }
  BOOST_TEST_REQUIRE(tris.size() == 1024u);
  std::array<tg::Vec3f, 3> p, n;
  for (const tg::AffAnimatedTriangle* tri : tris) {
    BOOST_TEST_REQUIRE(tri->keys.size() == 5u);
    // Never textured.
    BOOST_TEST(d.materials[tri->material].textureName.empty());
    for (std::size_t k = 0; k < 5; ++k) {
      tri->evaluate(tri->keys[k].time, p, n);
      BOOST_TEST(p == tri->keys[k].positions);
      for (const tg::Vec3f& v : n) BOOST_TEST(std::abs(tg::length(v) - 1.0f) < 1e-5f);
    }
    // Halfway between keys 1 and 2: the average of the positions.
    tri->evaluate(1.5, p, n);
    for (std::size_t c = 0; c < 3; ++c) {
      const tg::Vec3f mid = (tri->keys[1].positions[c] + tri->keys[2].positions[c]) * 0.5f;
      BOOST_TEST(tg::length(p[c] - mid) < 1e-5f);
    }
    // Clamped outside [0, 4].
    tri->evaluate(-1.0, p, n);
    BOOST_TEST(p == tri->keys[0].positions);
    tri->evaluate(5.0, p, n);
    BOOST_TEST(p == tri->keys[4].positions);
  }
}

BOOST_AUTO_TEST_CASE(block_transforms_compose) {
  const tg::AffDocument& d = scene(kKitchen);
  // The dragon: xs 0.1 0.1 0.1  0 1 0 90  1.16 0.1 1.16 in kitchen.aff.
  const tg::AffBlock* dragon = nullptr;
  for (const tg::AffBlock& b : d.root.children)
    if (b.kind == tg::AffBlock::Kind::Static && b.translation == tg::Vec3d{1.16, 0.1, 1.16})
      dragon = &b;
  BOOST_TEST_REQUIRE(dragon != nullptr);
  const tg::Vec3d p = d.blockMatrix(*dragon, 0).transformPoint({1, 0, 0});
  BOOST_TEST(maxDiff(p, {1.16, 0.1, 1.16 - 0.1}) < 1e-12);  // x → -z after 90° about y
  // The toy car is animated by `toycar`.
  const tg::AffBlock* car = nullptr;
  for (const tg::AffBlock& b : d.root.children)
    if (b.kind == tg::AffBlock::Kind::Animated && b.name == "toycar") car = &b;
  BOOST_TEST_REQUIRE(car != nullptr);
  BOOST_TEST(maxDiff(d.blockMatrix(*car, 0).transformPoint({0, 0, 0}), {4.45, 0, 2.75}) < 1e-12);
  BOOST_TEST(d.blockVisible(*car, 0));
}

BOOST_AUTO_TEST_CASE(kitchen_parse_time) {
  double best = 1e9;
  for (int i = 0; i < 5; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const tg::AffDocument d = tg::parseAffFile(kKitchen);
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::milli>(t1 - t0).count());
    BOOST_TEST(d.countTriangles().total() == 110561u);
  }
  BOOST_TEST_MESSAGE("kitchen.aff parse time (best of 5): " << best << " ms");
  BOOST_WARN(best < 100.0);
}

BOOST_AUTO_TEST_SUITE_END()

// ---------------------------------------------------------------------------------------------
// NFF samples

BOOST_AUTO_TEST_CASE(nff_samples, *utf::precondition([](utf::test_unit_id) {
                       boost::test_tools::assertion_result r(
                           fs::exists(kData / "nff/WithCamera.nff"));
                       r.message() << "NFF samples not found under " << kData.string();
                       return r;
                     })) {
  const tg::AffDocument camera = tg::parseAffFile(kData / "nff/WithCamera.nff");
  BOOST_TEST(camera.view.angle == 60.0);
  BOOST_TEST(camera.view.width == 640);
  BOOST_TEST(camera.view.hither == 0.0);
  BOOST_TEST(camera.view.effectiveHither() == 1.0);
  BOOST_TEST(camera.countTriangles().sphereCount == 3u);
  BOOST_TEST(camera.countTriangles().polygons == 2u);
  BOOST_TEST(camera.materials.size() == 4u);
  BOOST_TEST(camera.materials[0].diffuse == (tg::Vec3f{0.8f, 0, 0}));
  BOOST_TEST(camera.materials[0].specular == (tg::Vec3f{0.8f, 0.8f, 0.8f}));

  const tg::AffDocument earths = tg::parseAffFile(kData / "nff/ManyEarthsNotJustOne.nff");
  BOOST_TEST(earths.lights.size() == 3u);
  BOOST_TEST(earths.countTriangles().sphereCount == 10u);
  BOOST_TEST_REQUIRE(!earths.materials.empty());
  BOOST_TEST(earths.materials[0].textureName == "earthSpherical.jpg");
  BOOST_TEST(fs::is_regular_file(earths.materials[0].texturePath));

  // Assimp's extensions are refused with a message that says so.
  for (const char* name : {"cone.nff", "cylinder.nff", "positionTest.nff", "dodecahedron.nff",
                           "octahedron.nff", "tetrahedron.nff"}) {
    const std::string msg = errorOf(kData / "nff" / name);
    BOOST_TEST_INFO(name << ": " << msg);
    BOOST_TEST(msg.find("Assimp extension") != std::string::npos);
  }
  for (const char* name : {"hexahedron.nff", "spheres.nff"}) {
    const std::string msg = errorOf(kData / "nff" / name);
    BOOST_TEST_INFO(name << ": " << msg);
    BOOST_TEST(msg.find("bad number") != std::string::npos);
  }
}

// ---------------------------------------------------------------------------------------------
// Lexing and semantics on small inputs

BOOST_AUTO_TEST_CASE(lexing_rules) {
  // CR, CRLF, tabs, comments (also trailing and glued), Latin-1 bytes, strtod number forms.
  const std::string text =
      "# comment with \xF6 Latin-1\r\n"
      "fm 1 1 1\t1 1 1 0 0 0 10 0 1 % trailing comment\r"
      "\nm vertices 3\r\n-.279 3. 2.6E-4\n+1 0 0\n0 1e0 -0\n"
      "triangles 1 0 1 2#glued comment\n"
      "xs 1 1 1 0 1 0 0 0 0 0{ }\n";
  const tg::AffDocument d = parseText(text);
  BOOST_TEST_REQUIRE(d.root.meshes.size() == 1u);
  const tg::AffMesh& m = d.root.meshes[0];
  BOOST_TEST(m.positions[0] == (tg::Vec3f{-0.279f, 3.0f, 2.6e-4f}));
  BOOST_TEST(m.positions[1] == (tg::Vec3f{1, 0, 0}));
  BOOST_TEST(m.where.line == 3u);
  BOOST_TEST(d.root.children.size() == 1u);
  BOOST_TEST(d.root.children[0].where.line == 8u);
  // Keywords are case-sensitive.
  BOOST_CHECK_THROW(parseText("M vertices 0 triangles 0\n"), tg::Error);
}

BOOST_AUTO_TEST_CASE(numbers_parse_like_strtod) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(-1000.0, 1000.0);
  std::uniform_int_distribution<int> exp10(-30, 30), prec(1, 17);
  for (int i = 0; i < 20000; ++i) {
    char buf[64];
    const int n =
        std::snprintf(buf, sizeof buf, "%.*e", prec(rng), mant(rng) * std::pow(10.0, exp10(rng)));
    std::string s(buf, static_cast<std::size_t>(n));
    if (i % 3 == 1) {
      std::snprintf(buf, sizeof buf, "%.*f", prec(rng) % 9, mant(rng));
      s = buf;
    }
    const tg::AffDocument d = parseText("l " + s + " 0 0\n");
    BOOST_TEST(d.lights[0].position.x == std::strtod(s.c_str(), nullptr), s);
  }
}

BOOST_AUTO_TEST_CASE(material_is_global_state) {
  TempDir tmp;
  tmp.write("leaf.aff",
            "p 3 0 0 0 1 0 0 0 1 0\n"
            "fm 0 0 0  0 1 0  0 0 0  1 0 1\n");  // leaks green to the includer
  const fs::path main = tmp.write("main.aff",
                                  "fm 0 0 0  1 0 0  0 0 0  1 0 1\n"  // red
                                  "xs 1 1 1 0 1 0 0 0 0 0 {\n"
                                  "  i 0 leaf.aff\n"
                                  "  i 0 leaf.aff\n"
                                  "}\n"
                                  "p 3 0 0 0 1 0 0 0 1 0\n");
  const tg::AffDocument d = tg::parseAffFile(main);
  BOOST_TEST_REQUIRE(d.root.children.size() == 1u);
  const tg::AffBlock& b = d.root.children[0];
  BOOST_TEST_REQUIRE(b.meshes.size() == 2u);  // two instances of the include
  BOOST_TEST(d.materials[b.meshes[0].material].diffuse == (tg::Vec3f{1, 0, 0}));
  BOOST_TEST(d.materials[b.meshes[1].material].diffuse == (tg::Vec3f{0, 1, 0}));
  BOOST_TEST_REQUIRE(d.root.meshes.size() == 1u);
  BOOST_TEST(d.materials[d.root.meshes[0].material].diffuse == (tg::Vec3f{0, 1, 0}));
  BOOST_TEST(d.materials.size() == 2u);  // shared entries
  BOOST_TEST(d.files.size() == 2u);
  BOOST_TEST(d.includeCount == 2u);
  BOOST_TEST(d.describe(b.meshes[0].where) == (tmp.dir / "leaf.aff").string() + ":1");
}

BOOST_AUTO_TEST_CASE(texture_lookup_order) {
  TempDir tmp;
  fs::create_directories(tmp.dir / "aff");
  fs::create_directories(tmp.dir / "TextureFiles");
  tmp.write("TextureFiles/a.ppm", "P6 1 1 255\n...");
  tmp.write("TextureFiles/b.ppm", "P6 1 1 255\n...");
  tmp.write("aff/b.ppm", "P6 1 1 255\n...");
  const fs::path main = tmp.write("aff/main.aff",
                                  "tt a.ppm 0 0 0 0 0  1 0 0 1 0  0 1 0 0 1\n"
                                  "tt b.ppm 0 0 0 0 0  1 0 0 1 0  0 1 0 0 1\n"
                                  "tt c.ppm 0 0 0 0 0  1 0 0 1 0  0 1 0 0 1\n");
  const tg::AffDocument d = tg::parseAffFile(main);
  BOOST_TEST_REQUIRE(d.materials.size() == 3u);
  BOOST_TEST(d.materials[0].texturePath == tmp.dir / "TextureFiles/a.ppm");
  BOOST_TEST(d.materials[1].texturePath == tmp.dir / "aff/b.ppm");
  BOOST_TEST(d.materials[2].texturePath.empty());
  BOOST_TEST_REQUIRE(d.warnings.size() == 1u);
  BOOST_TEST(d.warnings[0].find("main.aff:3: texture 'c.ppm' not found") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(separate_indices_expand_per_corner) {
  const tg::AffDocument d = parseText(
      "m vertices 4  0 0 0  1 0 0  1 1 0  0 1 0\n"
      "normals 2  0 0 1  0 0 -1\n"
      "texturecoords 3 t.ppm  0 0  1 0  1 1\n"
      "triangles 2\n"
      "0 1 2  0 0 0  0 1 2\n"
      "0 2 3  0 1 1  0 2 2\n");
  BOOST_TEST_REQUIRE(d.root.meshes.size() == 1u);
  const tg::TriangleMesh tm = tg::toTriangleMesh(d.root.meshes[0]);
  BOOST_TEST(tm.validate() == "");
  BOOST_TEST(tm.triangleCount() == 2u);
  // Distinct (p, n, t) triples: (0,0,0) (1,0,1) (2,0,2) (2,1,2) (3,1,2) → 5 vertices.
  BOOST_TEST(tm.positions.size() == 5u);
  for (std::size_t c = 0; c < 6; ++c) {
    const tg::AffMesh& m = d.root.meshes[0];
    BOOST_TEST(tm.positions[tm.indices[c]] == m.positions[m.positionIndices[c]]);
    BOOST_TEST(tm.normals[tm.indices[c]] == m.normals[m.normalIndices[c]]);
    BOOST_TEST(tm.uvs[tm.indices[c]] == m.uvs[m.uvIndices[c]]);
  }
}

BOOST_AUTO_TEST_CASE(cones_and_spheres_tessellate_outwards) {
  tg::AffParseOptions options;
  const tg::AffDocument d = parseText("c 0 0 0 1  0 2 0 0.5\nc 1 1 1 0  3 1 1 1\ns 1 2 3 2\n");
  BOOST_TEST_REQUIRE(d.root.meshes.size() == 3u);
  BOOST_TEST(d.root.meshes[0].triangleCount() == 32u);
  BOOST_TEST(d.root.meshes[1].triangleCount() == 16u);  // pointed base: one triangle a segment
  BOOST_TEST(d.root.meshes[2].triangleCount() == 224u);
  for (const tg::AffMesh& m : d.root.meshes) {
    const tg::TriangleMesh tm = tg::toTriangleMesh(m);
    BOOST_TEST(tm.validate() == "");
    const tg::AffShape& s = *m.shape;
    const tg::Vec3d axis =
        m.primitive == tg::AffPrimitive::Cone ? tg::normalize(s.apex - s.base) : tg::Vec3d{};
    for (std::size_t t = 0; t < tm.triangleCount(); ++t) {
      const tg::Vec3d a(tm.positions[tm.indices[3 * t]]), b(tm.positions[tm.indices[3 * t + 1]]),
          c(tm.positions[tm.indices[3 * t + 2]]);
      const tg::Vec3d n = tg::cross(b - a, c - a);
      tg::Vec3d out = (a + b + c) / 3.0 - s.base;
      if (m.primitive == tg::AffPrimitive::Cone) out -= axis * tg::dot(out, axis);
      BOOST_TEST(tg::dot(n, out) > 0.0);
      for (std::size_t k = 0; k < 3; ++k) {
        const tg::Vec3d sn(tm.normals[tm.indices[3 * t + k]]);
        BOOST_TEST(std::abs(tg::length(sn) - 1.0) < 1e-6);
        BOOST_TEST(tg::dot(sn, out) > 0.0);
      }
    }
  }
  options.coneSegments = 8;
  BOOST_TEST(parseText("c 0 0 0 1  0 2 0 0.5\n", options).root.meshes[0].triangleCount() == 16u);
}

// ---------------------------------------------------------------------------------------------
// Keyframe mathematics on synthetic tracks

BOOST_AUTO_TEST_CASE(synthetic_splines_hit_keys_and_are_c1) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), gap(0.5, 2.0);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<tg::KbVectorSpline::Key> pk(9);
    std::vector<tg::KbRotationSpline::Key> rk(9);
    double t = unit(rng);
    for (std::size_t k = 0; k < pk.size(); ++k) {
      pk[k] = {t,
               {unit(rng) * 10, unit(rng) * 10, unit(rng) * 10},
               {0.4 * unit(rng), 0.0, 0.6 * unit(rng)}};
      // Rotations about random axes with moderate steps: no sign flips, no cut-offs.
      rk[k] = {t,
               {unit(rng), unit(rng), unit(rng) + 2.0},
               40.0 * unit(rng),
               {0.4 * unit(rng), 0.0, 0.6 * unit(rng)}};
      t += gap(rng);
    }
    const tg::KbVectorSpline ps(pk);
    const tg::KbRotationSpline rs(rk);
    for (std::size_t k = 1; k + 1 < pk.size(); ++k) {
      BOOST_TEST(maxDiff(ps.evaluate(pk[k].time), pk[k].value) < 1e-9);
      BOOST_TEST(maxDiff(rs.matrix(rk[k].time),
                         tg::rotationMatrix(rk[k].axis, rk[k].degrees * kDeg)) < 1e-9);
    }
    for (std::size_t k = 2; k + 2 < pk.size(); ++k) {
      const auto [l, r] =
          sideDerivatives([&](double x) { return ps.evaluate(x); }, pk[k].time, 1e-5);
      BOOST_TEST(maxDiff(l, r) < 1e-5 * (1.0 + tg::length(l)));
      BOOST_TEST(quaternionKink(rs, rk[k].time, 1e-5).second < 1e-6);
    }
    // Held outside [t1, t(n-2)].
    BOOST_TEST(maxDiff(ps.evaluate(pk[0].time - 5), pk[1].value) == 0.0);
    BOOST_TEST(maxDiff(ps.evaluate(pk[8].time + 5), pk[7].value) == 0.0);
  }
  // Non-zero continuity makes a kink (sanity check of the finite differences).
  std::vector<tg::KbVectorSpline::Key> kink = {{0, {0, 0, 0}, {}},
                                               {1, {1, 0, 0}, {}},
                                               {2, {1, 1, 0}, {0, 0.8, 0}},
                                               {3, {0, 1, 0}, {}},
                                               {4, {0, 0, 0}, {}}};
  const tg::KbVectorSpline ks(kink);
  const auto [l, r] = sideDerivatives([&](double x) { return ks.evaluate(x); }, 2.0, 1e-5);
  BOOST_TEST(maxDiff(l, r) > 0.1);
}

BOOST_AUTO_TEST_CASE(spline_segment_rules) {
  // Catmull-Rom-like values: with uniform spacing and zero TCB the midpoint of segment 1 of
  // 0, 1, 2, 3 (linear data) is 1.5, and the track holds P1 / P(n-2) outside.
  const tg::KbVectorSpline s(
      {{0, {0, 0, 0}, {}}, {1, {1, 0, 0}, {}}, {2, {2, 0, 0}, {}}, {3, {3, 0, 0}, {}}});
  BOOST_TEST(s.evaluate(1.5).x == 1.5, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(s.evaluate(0.5).x == 1.0);
  BOOST_TEST(s.evaluate(2.5).x == 2.0);
  BOOST_TEST(s.evaluate(std::nan("")).x == 1.0);
  BOOST_CHECK_THROW((tg::KbVectorSpline({{0, {}, {}}, {1, {}, {}}, {2, {}, {}}})), tg::Error);
  // Opposite quaternions: the end key is flipped so the short way is taken (358° ≡ -2°).
  const tg::KbRotationSpline r({{0, {0, 1, 0}, 0, {}},
                                {1, {0, 1, 0}, 0, {}},
                                {2, {0, 1, 0}, 358, {}},
                                {3, {0, 1, 0}, 358, {}}});
  BOOST_TEST(r.quaternions()[2].w > 0.0);  // cos(179°) < 0 before the flip
  const tg::Affine3d mid = r.matrix(1.5);
  BOOST_TEST(std::abs(std::atan2(mid.m[0][2], mid.m[0][0]) / kDeg + 1.0) < 0.5);
  // Visibility: visible before the first key, then the latest flag.
  const std::vector<tg::VisibilityKey> vis = {{1.0, false}, {2.0, true}};
  BOOST_TEST(tg::evaluateVisibility(vis, 0.5));
  BOOST_TEST(!tg::evaluateVisibility(vis, 1.0));
  BOOST_TEST(tg::evaluateVisibility(vis, 2.5));
}

BOOST_AUTO_TEST_CASE(track_composition_and_visibility) {
  const tg::AffDocument d = parseText(
      "x spin { p 3 0 0 0 1 0 0 0 1 0 }\n"
      "la spin 9 9 9\n"
      "k spin {\n"
      " transl 4  0 1 2 3 0 0 0  1 1 2 3 0 0 0  2 1 2 3 0 0 0  3 1 2 3 0 0 0\n"
      " scale 4   0 2 2 2 0 0 0  1 2 2 2 0 0 0  2 2 2 2 0 0 0  3 2 2 2 0 0 0\n"
      " rot 4     0 0 0 1 90 0 0 0  1 0 0 1 90 0 0 0  2 0 0 1 90 0 0 0  3 0 0 1 90 0 0 0\n"
      " visibility 2  0.5 0  1.5 1\n"
      "}\n");
  const tg::AffBlock& b = d.root.children.at(0);
  BOOST_TEST(b.kind == tg::AffBlock::Kind::Animated);
  // T·R·S: (1,0,0) → scale 2 → rotate 90° about z → (0,2,0) → translate.
  BOOST_TEST(maxDiff(d.blockMatrix(b, 1.0).transformPoint({1, 0, 0}), {1, 4, 3}) < 1e-12);
  BOOST_TEST(d.blockVisible(b, 0.0));
  BOOST_TEST(!d.blockVisible(b, 1.0));
  BOOST_TEST(d.blockVisible(b, 2.0));
  BOOST_TEST(maxDiff(d.lightPosition(d.lights.at(0), 1.0), {1, 2, 3}) == 0.0);
  BOOST_TEST(d.lights[0].track == "spin");
  // No camera track: fall back to v.
  BOOST_TEST(maxDiff(d.camera(0).direction, {0, 0, -1}) == 0.0);
}

// ---------------------------------------------------------------------------------------------
// Errors: always tg::Error with "FILE:LINE: what"

BOOST_AUTO_TEST_CASE(error_unknown_command) {
  expectError("fm 1 1 1 1 1 1 1 1 1 1 0 1\n\nfoo 1 2\n", 3, "unknown command 'foo'");
}

BOOST_AUTO_TEST_CASE(error_missing_include) {
  expectError("\ni 0 nothere.aff\n", 2, "missing include 'nothere.aff'");
}

BOOST_AUTO_TEST_CASE(error_include_cycle) {
  TempDir tmp;
  const fs::path a = tmp.write("a.aff", "i 0 b.aff\n");
  tmp.write("b.aff", "\n\ni 0 a.aff\n");
  const std::string msg = errorOf(a);
  BOOST_TEST_INFO(msg);
  BOOST_TEST(
      msg.find((tmp.dir / "b.aff").string() + ":3: include cycle: a.aff -> b.aff -> a.aff") == 0u);
  // Self-inclusion too.
  const fs::path self = tmp.write("self.aff", "i 0 self.aff\n");
  BOOST_TEST(errorOf(self).find("self.aff:1: include cycle") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(error_truncated) {
  expectError("m vertices 2\n0.0000000000 0.0000000000 0.0000000000\n1.000000000000 0.00000", 3,
              "unexpected end of file");
  expectError("m vertices 3 0 0 0 1 0 0 0 1 0 triangles 1\n0 1      ", 2, "unexpected end of file");
  expectError("m vertices 3\n0 0 0\n1 0 0\n", 1, "more than the remaining");
  expectError(
      "k cam {\n transl 4\n 0 0 0 0 0 0 0\n 1 0 0 0 0 0 0\n 2 0 0 0 0 0 0\n 3 0 0 0 0 0 0\n", 6,
      "unexpected end of file in keyframe block 'cam'");
  expectError("v from 0 0 0 at 0 0 -1 up 0 1 0 angle 45\n", 1, "expected 'hither'");
}

BOOST_AUTO_TEST_CASE(error_bad_numbers) {
  expectError("l 1 2 3\nl 1.2.3 0 0\n", 2, "bad number '1.2.3'");
  expectError("b 0 nan 0\n", 1, "NaN or infinite number 'nan'");
  expectError("b 0 0 -inf\n", 1, "NaN or infinite number '-inf'");
  expectError("l 1e999 0 0\n", 1, "NaN or infinite number '1e999'");
  expectError("m vertices 1 1e39 0 0 triangles 0\n", 1, "single-precision range");
  expectError("m vertices 3.0 0 0 0 1 0 0 0 1 0 triangles 0\n", 1, "bad count '3.0'");
  expectError("a 0 1 x\n", 1, "bad integer 'x'");
  expectError("l \xFF\x01 0 0\n", 1, "bad number '\\xFF\\x01'");
}

BOOST_AUTO_TEST_CASE(error_index_out_of_range) {
  expectError("m vertices 3 0 0 0 1 0 0 0 1 0\ntriangles 1\n0 1 3\n", 3,
              "mesh vertex index 3 out of range (3 entries)");
  expectError("m vertices 3 0 0 0 1 0 0 0 1 0 normals 1 0 0 1\ntriangles 1\n0 1 2 0 0 1\n", 3,
              "mesh normal index 1 out of range (1 entries)");
}

BOOST_AUTO_TEST_CASE(error_absurd_counts) {
  // A 100-byte file announcing 2e9 vertices must be rejected before any allocation.
  std::string text = "m vertices 2000000000\n";
  while (text.size() < 100) text += "0 0 0\n";
  expectError(text, 1, "mesh vertex count 2000000000 is more than the remaining");
  expectError("tpa 99999999 0\n", 1, "'tpa' key count 99999999 is more than the remaining");
  expectError("k a { rot 4000000000 }\n", 1, "key count 4000000000 is more than the remaining");
  expectError("p 99999999999999999999\n", 1, "bad count");
  expectError("p 2 0 0 0 1 1 1\n", 1, "at least 3 vertices");
}

BOOST_AUTO_TEST_CASE(error_unbalanced_braces) {
  expectError("xs 1 1 1 0 1 0 0 0 0 0 {\n}\n}\n", 3, "'}' without a matching block");
  expectError("\nx name {\n p 3 0 0 0 1 0 0 0 1 0\n", 3,
              "end of file inside the block opened at line 2");
  expectError("{\n", 1, "'{' without a block command");
  // An included file may not close the includer's block.
  TempDir tmp;
  tmp.write("closer.aff", "}\n");
  const fs::path main = tmp.write("main.aff", "xs 1 1 1 0 1 0 0 0 0 0 {\ni 0 closer.aff\n}\n");
  BOOST_TEST(errorOf(main).find("closer.aff:1: '}' without a matching block") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(error_keyframes_and_limits) {
  expectError("k t { transl 3 0 0 0 0 0 0 0 1 0 0 0 0 0 0 2 0 0 0 0 0 0 }\n", 1, "at least 4 keys");
  expectError("k t { wobble 1 }\n", 1, "unknown keyframe channel 'wobble'");
  expectError("k t { visibility 1 0 2 }\n", 1, "visibility flag must be 0 or 1");
  expectError("k t { visibility 1 0 1 visibility 1 0 1 }\n", 1, "'visibility' given twice");
  // A track defined twice in different places: the last wins, with a warning.
  const tg::AffDocument twice = parseText("k t { visibility 1 0 0 }\nk t { visibility 1 0 1 }\n");
  BOOST_TEST(twice.tracks.at("t").visibility.at(0).visible);
  BOOST_TEST_REQUIRE(twice.warnings.size() == 1u);
  BOOST_TEST(twice.warnings[0].find(
                 "inline.aff:2: track 't' defined again (first at inline.aff:1)") == 0u);
  expectError("tess 4\n", 1, "Assimp extension");
  expectError("nff\nversion 2.0\n", 1, "Sense8");
  // Nesting and expansion limits.
  std::string deep;
  for (int i = 0; i < 300; ++i) deep += "x a {\n";
  expectError(deep, 257, "nested deeper than 256");
  TempDir tmp;
  std::string bomb = "p 3 0 0 0 1 0 0 0 1 0\n";
  for (int level = 0; level < 40; ++level) {
    // (Built by appending: GCC 12 gives a false -Wrestrict for "literal" + std::string&&.)
    std::string name = "l";
    name += std::to_string(level);
    name += ".aff";
    tmp.write(name, bomb);
    const std::string line = "i 0 " + name + "\n";
    bomb = line;
    bomb += line;
  }
  const fs::path top = tmp.write("top.aff", bomb);
  tg::AffParseOptions small;
  small.maxTotalBytes = 1 << 20;
  BOOST_TEST(errorOf(top, small).find("bytes in total") != std::string::npos);
  small = {};
  small.maxTriangles = 1000;
  BOOST_TEST(errorOf(top, small).find("more than 1000 triangles") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(mutated_input_never_crashes, *utf::precondition(BartAvailable())) {
  // A light-weight in-test fuzz: byte mutations of a real file must parse or throw tg::Error.
  const fs::path source = kData / "bart/kitchen/aff/car_body.aff";
  std::string original(fs::file_size(source), '\0');
  std::ifstream(source, std::ios::binary)
      .read(original.data(), static_cast<std::streamsize>(original.size()));
  BOOST_TEST_REQUIRE(original.size() > 1000u);
  std::mt19937_64 rng(1);
  const std::string alphabet = "0123456789.-+eE \n{}#%xmkpi";
  std::size_t parsed = 0, rejected = 0;
  for (int i = 0; i < 300; ++i) {
    std::string text = original.substr(0, 4000 + rng() % 4000);
    for (int m = 0; m < 1 + static_cast<int>(rng() % 4); ++m)
      text[rng() % text.size()] = alphabet[rng() % alphabet.size()];
    try {
      parseText(text);
      ++parsed;
    } catch (const tg::Error&) {
      ++rejected;
    }
  }
  BOOST_TEST(parsed + rejected == 300u);
}
