// The `cobra` tool links neither cobra::dds nor Fast DDS: its dds transport is the package
// cobra_dds (libcobra_dds.so, loaded RTLD_LOCAL), and a package's DDS type reaches it through
// core::TypeFacets. Were the tool to link the dds objects too, a package's calls would bind to the
// tool's copies and every install of the tool would need the Fast DDS runtime. Checked twice: in
// the CMake link graph (dependency_targets.txt, written when CMake configures: a target reaching a
// dds target, however indirectly) and in the built tool (its dynamic section and its exported
// symbols).

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

// target -> its direct links, from lines "name\ttype\tfolder\tlink link ...".
std::map<std::string, std::vector<std::string>> readLinkGraph(const std::string& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in) << "cannot read " << file;
  std::map<std::string, std::vector<std::string>> graph;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> columns;
    std::stringstream row(line);
    for (std::string column; std::getline(row, column, '\t');) columns.push_back(column);
    if (columns.empty()) continue;
    std::vector<std::string>& links = graph[columns[0]];
    if (columns.size() < 4) continue;
    std::stringstream words(columns[3]);
    for (std::string link; words >> link;) links.push_back(link);
  }
  return graph;
}

// The chain from `from` to the first target of `forbidden` it reaches, "" when none.
std::string chainTo(const std::map<std::string, std::vector<std::string>>& graph, const std::string& from,
                    const std::set<std::string>& forbidden) {
  std::map<std::string, std::string> parent{{from, ""}};
  std::vector<std::string> queue{from};
  for (std::size_t i = 0; i < queue.size(); ++i) {
    const std::string target = queue[i];
    if (forbidden.count(target) != 0) {
      std::string chain = target;
      for (std::string at = parent[target]; !at.empty(); at = parent[at]) chain = at + " -> " + chain;
      return chain;
    }
    const auto it = graph.find(target);
    if (it == graph.end()) continue;
    for (const std::string& link : it->second)
      if (parent.emplace(link, target).second) queue.push_back(link);
  }
  return "";
}

// The DDS side: the dds objects and archive, the generated type support (which links Fast DDS).
const std::set<std::string> kDdsTargets = {"cobra_dds", "dds_objects", "dds_generated_types", "cobra_dds_package"};

TEST(ToolLinksNoDds, TheToolReachesNoDdsTargetInTheLinkGraph) {
  const auto graph = readLinkGraph(COBRA_DEPENDENCY_TARGETS);
  ASSERT_EQ(graph.count("cobra"), 1U) << "no target cobra in " << COBRA_DEPENDENCY_TARGETS;
  // The graph does record the links that bring DDS: the package reaches the type support, and the
  // tool reaches core.
  EXPECT_EQ(chainTo(graph, "cobra_dds_package", {"dds_generated_types"}), "cobra_dds_package -> dds_generated_types");
  EXPECT_NE(chainTo(graph, "cobra", {"cobra_core"}), "");
  EXPECT_EQ(chainTo(graph, "cobra", kDdsTargets), "")
      << "the cobra tool links the DDS side; it must load it as the package cobra_dds (types/README.md)";
}

// The lines `command` prints, or a failure.
std::vector<std::string> linesOf(const std::string& command) {
  std::vector<std::string> lines;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  EXPECT_NE(pipe, nullptr) << command;
  if (pipe == nullptr) return lines;
  std::string line;
  for (int c = std::fgetc(pipe.get()); c != EOF; c = std::fgetc(pipe.get())) {
    if (c != '\n') {
      line += static_cast<char>(c);
      continue;
    }
    lines.push_back(line);
    line.clear();
  }
  EXPECT_EQ(pclose(pipe.release()), 0) << command;
  return lines;
}

TEST(ToolLinksNoDds, TheBuiltToolNeedsNoFastDdsAndExportsNoDdsSymbol) {
  const std::string tool = COBRA_TOOL;
  std::vector<std::string> needed;
  for (const std::string& line : linesOf("readelf -d --wide '" + tool + "'"))
    if (line.find("(NEEDED)") != std::string::npos) needed.push_back(line);
  ASSERT_FALSE(needed.empty()) << "readelf -d listed no needed library of " << tool;
  for (const std::string& line : needed)
    for (const char* library : {"libfastrtps", "libfastcdr", "libcobra_dds"})
      EXPECT_EQ(line.find(library), std::string::npos) << tool << " needs " << library << ": " << line;

  std::size_t core_symbols = 0;
  std::vector<std::string> dds_symbols;
  for (const std::string& line : linesOf("nm -DC --defined-only '" + tool + "'")) {
    if (line.find("cobra::core::") != std::string::npos) ++core_symbols;
    if (line.find("cobra::dds::") != std::string::npos || line.find("eprosima::") != std::string::npos)
      dds_symbols.push_back(line);
  }
  EXPECT_GT(core_symbols, 0U) << "the tool exports core to its packages; nm found none";
  EXPECT_TRUE(dds_symbols.empty()) << tool << " defines " << dds_symbols.size() << " DDS symbol(s), e.g. "
                                   << dds_symbols.front();
}

}  // namespace
