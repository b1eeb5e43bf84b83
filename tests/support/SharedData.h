// Test preconditions on the shared data folder (TG_DATA_DIR), for suites that read its scenes.
#pragma once

#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace tg::test {

/// A Boost.Test precondition that skips a test, with the reason, when any of `files` is
/// missing: the shared scenes are optional for a build, not for a test run that has them.
struct FilesAvailable {
  /// What the files are, for the message ("BART scenes").
  std::string what;
  /// The folder they were looked for under.
  std::filesystem::path folder;
  /// Every file the tests read.
  std::vector<std::filesystem::path> files;

  boost::test_tools::assertion_result operator()(boost::unit_test::test_unit_id) const {
    bool all = true;
    for (const std::filesystem::path& f : files) all = all && std::filesystem::exists(f);
    boost::test_tools::assertion_result r(all);
    r.message() << what << " not found under " << folder.string() << " (TG_DATA_DIR); skipped";
    return r;
  }
};

}  // namespace tg::test
