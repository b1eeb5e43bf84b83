// libFuzzer harness for the AFF/NFF parser: any input must either parse into a consistent
// document or raise tg::Error; crashes, sanitizer reports, hangs and other exceptions are bugs.
// Build with -DTG_BUILD_FUZZERS=ON and clang; run e.g.
//   tg_aff_fuzzer corpus/ -max_len=65536 -max_total_time=600
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AffParser.h"

namespace {

/// A folder of small files the fuzzed text can include, so that include resolution, caching,
/// cycle detection and per-file brace balance are exercised as well.
const std::filesystem::path& fixtureDir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("tg_aff_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d / "aff");
    std::filesystem::create_directories(d / "TextureFiles");
    const auto write = [&](const char* name, const char* text) {
      std::ofstream(d / name, std::ios::binary) << text;
    };
    write("aff/inc.aff",
          "fm .1 .1 .1 .5 .5 .5 .2 .2 .2 10 0 1\n"
          "m vertices 3 0 0 0 1 0 0 0 1 0 normals 1 0 0 1\n"
          "texturecoords 3 t.ppm 0 0 1 0 0 1 triangles 1 0 1 2 0 0 0 0 1 2\n");
    write("aff/self.aff", "i 0 self.aff\n");
    write("aff/loop.aff", "i 0 inc.aff\ni 0 loop.aff\n");
    write("aff/open.aff", "xs 1 1 1 0 1 0 0 0 0 0 {\n");
    write("aff/close.aff", "}\n");
    write("aff/keys.aff",
          "k spin { rot 4 0 0 1 0 0 0 0 0 1 0 1 0 90 0 0 0 2 0 1 0 180 0 0 0 "
          "3 0 1 0 270 0 0 0 }\n");
    write("TextureFiles/t.ppm", "P6 1 1 255\nabc");
    return d / "aff";
  }();
  return dir;
}

/// Evaluates everything that depends on parsed numbers, to let the sanitizers see the
/// animation code run on hostile keys, and checks invariants the parser promises.
void exercise(const tg::AffDocument& doc) {
  constexpr std::array<double, 6> kTimes = {-1e9, -1.0, 0.0, 0.37, 2.5, 1e9};
  for (const double t : kTimes) {
    (void)doc.camera(t);
    for (const auto& [name, track] : doc.tracks) {
      (void)track.evaluate(t);
      (void)track.visibleAt(t);
    }
    for (const tg::AffLight& l : doc.lights) (void)doc.lightPosition(l, t);
  }
  (void)doc.camera(std::nan(""));
  (void)doc.animation.frameTime(doc.animation.frames - 1);
  std::vector<const tg::AffBlock*> todo{&doc.root};
  while (!todo.empty()) {
    const tg::AffBlock* b = todo.back();
    todo.pop_back();
    for (const tg::AffBlock& c : b->children) todo.push_back(&c);
    for (const double t : kTimes) (void)doc.blockMatrix(*b, t);
    for (const tg::AffMesh& m : b->meshes) {
      if (m.material >= doc.materials.size()) std::abort();
      // Parser-made meshes are always convertible and valid (finite, in-range indices).
      if (!tg::toTriangleMesh(m).validate().empty()) std::abort();
    }
    for (const tg::AffAnimatedTriangle& tri : b->animatedTriangles) {
      if (tri.keys.empty() || tri.material >= doc.materials.size()) std::abort();
      std::array<tg::Vec3f, 3> p, n;
      for (const double t : kTimes) tri.evaluate(t, p, n);
    }
  }
  (void)doc.countTriangles();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tg::AffParseOptions options;
  // Small limits keep single inputs fast; the parser's own checks are what is under test.
  options.maxTriangles = 200'000;
  options.maxTotalBytes = 4u << 20;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  tg::AffDocument doc;
  try {
    doc = tg::parseAffText(text, fixtureDir(), options, "fuzz.aff");
  } catch (const tg::Error&) {
    return 0;  // rejected input: the expected outcome for most mutations
  }
  // Outside the try: an exception from an accepted document is a bug and must surface.
  exercise(doc);
  return 0;
}
