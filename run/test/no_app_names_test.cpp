// The runner knows no application (ARCHITECTURE §3): no component name that an application
// under apps/ gives (`peer_name = "X"` in its Lua files) appears quoted in the C++ of run/ or
// tools/cobra.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <string>

namespace {

const std::filesystem::path kSource(COBRA_SOURCE_DIR);

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Every peer_name of the applications' Lua files (names built with a prefix, e.g. n("Planner")
/// in apps/puncturing/deployment/controller.lua, are taken with both robots' prefixes).
std::set<std::string> appComponentNames() {
  std::set<std::string> names;
  const std::regex peer(R"re(peer_name\s*=\s*"([A-Za-z0-9_]+)")re"),
      prefixed(R"re(peer_name\s*=\s*n\("([A-Za-z0-9_]+)"\))re");
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kSource / "apps")) {
    if (entry.path().extension() != ".lua") continue;
    const std::string text = readFile(entry.path());
    for (std::sregex_iterator it(text.begin(), text.end(), peer), end; it != end; ++it) names.insert((*it)[1]);
    for (std::sregex_iterator it(text.begin(), text.end(), prefixed), end; it != end; ++it)
      for (const char* prefix : {"Needle", "Probe"}) names.insert(prefix + (*it)[1].str());
  }
  return names;
}

TEST(NoAppNames, TheRunnerAndTheToolNameNoComponentOfAnyApplication) {
  const std::set<std::string> names = appComponentNames();
  ASSERT_TRUE(names.count("NeedleTaskSup")) << "the scan of apps/ found no puncturing component names";
  ASSERT_TRUE(names.count("Patient"));
  std::size_t files = 0;
  for (const std::filesystem::path& folder : {kSource / "run" / "src", kSource / "run" / "include", kSource / "tools" / "cobra"}) {
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
      const auto extension = entry.path().extension();
      if (extension != ".cpp" && extension != ".hpp") continue;
      if (entry.path().string().find("/test/") != std::string::npos) continue;
      ++files;
      const std::string text = readFile(entry.path());
      for (const std::string& name : names)
        EXPECT_EQ(text.find('"' + name + '"'), std::string::npos) << entry.path() << " names component \"" << name << "\"";
    }
  }
  EXPECT_GT(files, 10u);
}

}  // namespace
