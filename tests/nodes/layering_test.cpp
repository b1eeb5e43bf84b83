// Dependencies point downwards: nodes/ knows nothing about accelerators or the sync, and
// scenegraph/'s public headers name no loader or sample.
#define BOOST_TEST_MODULE layering
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

/// The repository root, found from this file's own path (tests/nodes/layering_test.cpp).
fs::path repoRoot() {
  return fs::path(__FILE__).parent_path().parent_path().parent_path();
}

/// Files under `dir` whose text contains any of `needles`, with the needle found.
std::vector<std::string> offenders(const fs::path& dir, const std::vector<std::string>& needles) {
  std::vector<std::string> out;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    for (const std::string& n : needles)
      if (text.str().find(n) != std::string::npos)
        out.push_back(entry.path().string() + " includes " + n);
  }
  return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(nodes_know_no_accelerator_and_no_sync) {
  const fs::path nodes = repoRoot() / "nodes";
  if (!fs::exists(nodes)) return;  // installed tests without sources
  const std::vector<std::string> found =
      offenders(nodes, {"backend/KdTree", "backend/ObjectAccel", "backend/TopLevel",
                        "backend/Scene.h", "scenegraph/SceneGraph.h", "tracegraph/loaders/"});
  for (const std::string& f : found) BOOST_ERROR(f);
}

BOOST_AUTO_TEST_CASE(scenegraph_knows_no_loader_and_no_sample) {
  const fs::path sg = repoRoot() / "scenegraph";
  if (!fs::exists(sg)) return;
  for (const std::string& f : offenders(sg, {"tracegraph/loaders/", "tracegraph/nodes/"}))
    BOOST_ERROR(f);
}
