// Nothing below apps/, tools/ and studio/ depends on them (ARCHITECTURE §3): no library of the
// runtime, the libraries, run/ or components/ links a target of theirs (dependency_targets.txt,
// written when CMake configures) or includes one of their headers. The checker is shown to fail
// on a synthetic violation of each kind first.

#include "dependency_check.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace cobra::architecture {
namespace {

namespace fs = std::filesystem;

const Rule kRule{{"core", "statechart", "trajectory", "kinematics", "control", "planning", "sim", "fieldbus", "script",
                  "deploy", "run", "components", "task", "bridges", "dds", "text", "types"},
                 {"apps", "tools", "studio"},
                 {"test", "tests"}};

// Dependencies tolerated for now: none (run/ sits below tools/: it writes its data, and
// tools/report renders the report). A violation that is not on this list fails the test, and an
// entry no violation needs is printed (remove it). (The test libraries_know_no_app,
// cmake/CobraApps.cmake, checks the apps/ part for the tools and the tests too.)
const std::vector<std::string> kAllowed = {};

std::string listed(const std::vector<Violation>& violations) {
  std::string out;
  for (const Violation& v : violations) out += "  " + v.message + "\n    (allow-list key: \"" + v.key + "\")\n";
  return out;
}

TEST(DependencyDirection, ALibraryLinkingAnAppDirectlyOrThroughAnotherTargetIsReportedWithItsChain) {
  const std::vector<Target> targets = {
      {"cobra_core", "STATIC_LIBRARY", "core", {"cobra_text"}},
      {"cobra_text", "STATIC_LIBRARY", "text", {}},
      {"cobra_helper", "STATIC_LIBRARY", "third_party/helper", {"cobra_plot"}},
      {"cobra_run", "STATIC_LIBRARY", "run", {"cobra_core", "cobra_helper"}},
      {"cobra_plot", "STATIC_LIBRARY", "tools/plot", {"cobra_core"}},
      {"cobra_builtin", "STATIC_LIBRARY", "components/builtin", {"cobra_door"}},
      {"cobra_door", "STATIC_LIBRARY", "apps/door", {"cobra_core"}},
      {"run_test", "EXECUTABLE", "run/test", {"cobra_door"}},  // a test, no library: not checked
  };
  const std::vector<Violation> found = linkViolations(targets, kRule);
  ASSERT_EQ(found.size(), 2U) << listed(found);
  EXPECT_EQ(found[0].message,
            "target cobra_run (run/) links cobra_plot (tools/plot/): cobra_run -> cobra_helper -> cobra_plot; run must not "
            "depend on tools/");
  EXPECT_EQ(found[0].key, "cobra_run -> cobra_plot");
  EXPECT_EQ(found[1].message,
            "target cobra_builtin (components/builtin/) links cobra_door (apps/door/): cobra_builtin -> cobra_door; components "
            "must not depend on apps/");
  std::vector<std::string> unused;
  EXPECT_EQ(notAllowed(found, {"cobra_run -> cobra_plot", "cobra_core -> cobra_door"}, unused).size(), 1U);
  EXPECT_EQ(unused, std::vector<std::string>{"cobra_core -> cobra_door"});
}

TEST(DependencyDirection, AnIncludeOfAnAppsOrToolsHeaderIsReportedWithItsFileAndLine) {
  const fs::path root = fs::path(::testing::TempDir()) / "cobra_dependency_direction_tree";
  fs::remove_all(root);
  const auto write = [&](const std::string& file, const std::string& text) {
    fs::create_directories((root / file).parent_path());
    std::ofstream(root / file) << text;
  };
  write("tools/report/include/cobra/report/report.hpp", "#pragma once\n");
  write("studio/src/extras.hpp", "#pragma once\n");
  write("core/include/cobra/core/port.hpp", "#pragma once\n");
  write("run/include/cobra/run/extras.hpp", "#pragma once\n");  // the same name in an allowed folder
  write("run/src/runner.cpp",
        "#include \"cobra/core/port.hpp\"\n#include <vector>\n  #  include \"cobra/report/report.hpp\"\n#include \"extras.hpp\"\n");
  write("run/src/local.cpp", "#include \"../../studio/src/extras.hpp\"\n");
  write("run/test/runner_test.cpp", "#include \"cobra/report/report.hpp\"\n");  // tests are not scanned
  const std::vector<Violation> found = includeViolations(root, kRule);
  ASSERT_EQ(found.size(), 2U) << listed(found);
  EXPECT_EQ(found[0].message, "run/src/local.cpp:1: #include \"../../studio/src/extras.hpp\" is studio/src/extras.hpp; run must "
                              "not depend on studio/");
  EXPECT_EQ(found[1].message, "run/src/runner.cpp:3: #include \"cobra/report/report.hpp\" is "
                              "tools/report/include/cobra/report/report.hpp; run must not depend on tools/");
  EXPECT_EQ(found[1].key, "run/src/runner.cpp -> tools/report/include/cobra/report/report.hpp");
}

TEST(DependencyDirection, NoLibraryBelowAppsToolsAndStudioDependsOnThem) {
  std::vector<Violation> all = linkViolations(readTargets(COBRA_DEPENDENCY_TARGETS), kRule);
  const std::vector<Violation> includes = includeViolations(COBRA_SOURCE_DIR, kRule);
  all.insert(all.end(), includes.begin(), includes.end());
  std::vector<std::string> unused;
  const std::vector<Violation> bad = notAllowed(all, kAllowed, unused);
  EXPECT_TRUE(bad.empty()) << "dependencies against ARCHITECTURE §3 (apps/, tools/ and studio/ sit on top):\n" << listed(bad);
  for (const std::string& entry : unused)
    std::cout << "architecture/test/dependency_direction_test.cpp: the allow-list entry \"" << entry
              << "\" is no longer needed: remove it\n";
}

}  // namespace
}  // namespace cobra::architecture
