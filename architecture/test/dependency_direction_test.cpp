// Nothing below apps/, tools/ and studio/ depends on them (ARCHITECTURE §3): no library of the
// runtime, the libraries, run/ or components/ links a target of theirs (dependency_targets.txt,
// written when CMake configures) or includes one of their headers. And libraries know no app:
// no target at all outside apps/ (tools, the studio and every module's tests included) links an
// application's target or includes an application's header. The checker is shown to fail on a
// synthetic violation of each kind first.

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

// Libraries know no app: an application is a loadable package found by name (cmake/CobraApps.cmake).
// Every folder but apps/ itself, bench/ (it measures the applications' procedures too) and fuzz/
// (it fuzzes the applications' parsers), with its executables and tests.
const Rule kAppRule{{"core", "statechart", "trajectory", "kinematics", "control", "planning", "sim", "fieldbus", "script",
                     "deploy", "run", "components", "task", "bridges", "dds", "text", "types", "plot", "studio", "tools",
                     "test_support", "examples", "architecture"},
                    {"apps"},
                    {},
                    true};

// Dependencies tolerated for now: none (run/ sits below tools/: it writes its data, and
// tools/report renders the report). A violation that is not on this list fails the test, and an
// entry no violation needs is printed (remove it). It serves both rules.
const std::vector<std::string> kAllowed = {};

// A file of a synthetic source tree, its folders created.
void writeFile(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

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
  const auto write = [&](const std::string& file, const std::string& text) { writeFile(root / file, text); };
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

TEST(DependencyDirection, WithExecutablesATestOrToolLinkingOrIncludingAnAppIsReportedToo) {
  const std::vector<Target> targets = {
      {"cobra_door", "STATIC_LIBRARY", "apps/door", {}},
      {"door_test", "EXECUTABLE", "apps/door/test", {"cobra_door"}},  // the app's own test: not checked
      {"run_test", "EXECUTABLE", "run/test", {"cobra_door"}},
      {"cobra_bench", "EXECUTABLE", "bench", {"cobra_door"}},  // not a checked folder
  };
  EXPECT_TRUE(linkViolations(targets, kRule).empty()) << "kRule checks libraries only";
  const std::vector<Violation> links = linkViolations(targets, kAppRule);
  ASSERT_EQ(links.size(), 1U) << listed(links);
  EXPECT_EQ(links[0].message,
            "target run_test (run/test/) links cobra_door (apps/door/): run_test -> cobra_door; run must not depend on apps/");

  const fs::path root = fs::path(::testing::TempDir()) / "cobra_dependency_app_tree";
  fs::remove_all(root);
  const auto write = [&](const std::string& file, const std::string& text) { writeFile(root / file, text); };
  write("apps/door/include/cobra/door/door.hpp", "#pragma once\n");
  write("apps/door/test/door_test.cpp", "#include \"cobra/door/door.hpp\"\n");  // the app's own test
  write("tools/cobra/test/run_test.cpp", "#include <vector>\n#include \"cobra/door/door.hpp\"\n");
  const std::vector<Violation> includes = includeViolations(root, kAppRule);
  ASSERT_EQ(includes.size(), 1U) << listed(includes);
  EXPECT_EQ(includes[0].message, "tools/cobra/test/run_test.cpp:2: #include \"cobra/door/door.hpp\" is "
                                 "apps/door/include/cobra/door/door.hpp; tools must not depend on apps/");
}

TEST(DependencyDirection, NoLibraryBelowAppsToolsAndStudioDependsOnThemAndNothingOutsideAppsKnowsAnApp) {
  const std::vector<Target> targets = readTargets(COBRA_DEPENDENCY_TARGETS);
  std::vector<Violation> all;
  for (const Rule* rule : {&kRule, &kAppRule}) {
    const std::vector<Violation> links = linkViolations(targets, *rule);
    const std::vector<Violation> includes = includeViolations(COBRA_SOURCE_DIR, *rule);
    all.insert(all.end(), links.begin(), links.end());
    all.insert(all.end(), includes.begin(), includes.end());
  }
  std::vector<std::string> unused;
  const std::vector<Violation> bad = notAllowed(all, kAllowed, unused);
  EXPECT_TRUE(bad.empty()) << "dependencies against ARCHITECTURE §3 (apps/, tools/ and studio/ sit on top; nothing "
                               "outside apps/ knows an application):\n"
                            << listed(bad);
  for (const std::string& entry : unused)
    std::cout << "architecture/test/dependency_direction_test.cpp: the allow-list entry \"" << entry
              << "\" is no longer needed: remove it\n";
}

}  // namespace
}  // namespace cobra::architecture
