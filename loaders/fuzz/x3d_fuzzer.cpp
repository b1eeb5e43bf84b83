// libFuzzer harness for the X3D loader: any input must either load into a graph that syncs
// and animates, or raise tg::Error; crashes, sanitizer reports, hangs and other exceptions
// are bugs. Build with -DTG_BUILD_FUZZERS=ON and clang; run e.g.
//   tg_x3d_fuzzer corpus/ shared/data/x3d -max_len=65536 -max_total_time=600
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/X3dLoader.h"
#include "tracegraph/scenegraph/SceneGraph.h"

namespace {

/// A folder of small files the fuzzed text can inline, so that Inline resolution, sharing and
/// cycle detection are exercised as well.
const std::filesystem::path& fixtureDir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("tg_x3d_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    const auto write = [&](const char* name, const char* text) {
      std::ofstream(d / name, std::ios::binary) << text;
    };
    write("box.x3d", "<X3D><Scene><Shape><Box/></Shape></Scene></X3D>");
    write("self.x3d", "<X3D><Scene><Inline url='\"self.x3d\"'/></Scene></X3D>");
    write("a.x3d", "<X3D><Scene><Inline url='\"b.x3d\"'/></Scene></X3D>");
    write("b.x3d", "<X3D><Scene><Group><Inline url='\"a.x3d\"'/></Group></Scene></X3D>");
    write("bad.x3d", "<X3D><Scene><Transform translation='1 2'/></Scene></X3D>");
    write("t.png", "not really a png");
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tg::X3dOptions options;
  // Small limits keep single inputs fast; the loader's own checks are what is under test.
  options.maxTriangles = 200'000;
  options.sphereSlices = 8;
  options.sphereStacks = 4;
  options.cylinderSlices = 8;
  options.maxEarClipCorners = 256;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  tg::LoadedScene scene;
  try {
    scene = tg::loadX3dString(text, fixtureDir(), "fuzz.x3d", options);
  } catch (const tg::Error&) {
    return 0;  // rejected input: the expected outcome for most mutations
  }
  // An accepted scene must sync and animate without errors: the loader promises valid
  // nodes, so an exception here is a bug and must surface.
  if (!scene.root) std::abort();
  tg::SceneGraph graph;
  graph.setRoot(scene.root);
  for (const double t : {0.0, 0.37, 1e9}) {
    graph.advanceTo(t);
    graph.sync();
  }
  return 0;
}
