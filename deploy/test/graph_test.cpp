#include "cobra/deploy/graph.hpp"

#include <gtest/gtest.h>

#include "cobra/test_support/test_support.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "cobra/components/signal/gain.hpp"
#include "cobra/components/signal/sine_generator.hpp"
#include "cobra/components/signal/threshold_detector.hpp"
#include "cobra/core/core.hpp"

namespace cobra::deploy {
namespace {

struct Pipeline {
  core::ComponentRegistry registry;
  core::InputPort<core::Event> outside{"monitor", "outside the registry", ""};
  Pipeline() {
    auto& sine = registry.make<components::SineGenerator>("Sine");
    auto& gain = registry.make<components::Gain>("Gain");
    auto& detector = registry.make<components::ThresholdDetector>("Detector");
    core::connectPorts(sine.port("out"), gain.port("in"));
    core::connectPorts(gain.port("out"), detector.port("in"), core::ConnPolicy::buffer(8));
    core::connectPorts(detector.port("events"), outside, core::ConnPolicy::circular(4));
  }
};

TEST(Graph, DrawsComponentsColouredByRoleWithPortsAndPolicies) {
  Pipeline p;
  const std::string dot = graphvizDot(p.registry, "demo");
  EXPECT_EQ(dot.rfind("digraph \"demo\" {", 0), 0U);
  EXPECT_CONTAINS(dot, "\"Sine\" [fillcolor=\"" + roleColour(core::Role::Calculation) + "\"");
  EXPECT_CONTAINS(dot, "\"Detector\" [fillcolor=\"" + roleColour(core::Role::Decision) + "\"");
  EXPECT_CONTAINS(dot, "<p_out> out : double");
  EXPECT_CONTAINS(dot, "\"Sine\":p_out:e -> \"Gain\":p_in:w [label=\"data\"];");
  EXPECT_CONTAINS(dot, "\"Gain\":p_out:e -> \"Detector\":p_in:w [label=\"buffer(8)\"];");
  // Logic data is dashed; a reader outside the registry gets a plain node.
  EXPECT_CONTAINS(dot, "\"Detector\":p_events:e -> \"monitor\" [label=\"circular(4)\", style=dashed];");
  EXPECT_CONTAINS(dot, "\"monitor\" [shape=plaintext");
  EXPECT_EQ(dot.back(), '\n');
}

TEST(Graph, RolesHaveDistinctColours) {
  std::set<std::string> colours;
  for (auto role : {core::Role::Calculation, core::Role::Supervision, core::Role::Decision, core::Role::Bridge})
    colours.insert(roleColour(role));
  EXPECT_EQ(colours.size(), 4U);
}

TEST(Graph, GraphvizAcceptsTheOutput) {
  if (std::system("command -v dot > /dev/null 2>&1") != 0) GTEST_SKIP() << "Graphviz (dot) is not installed";
  Pipeline p;
  const std::string dot_path = ::cobra::test_support::scratchPath("cobra_graph_test.dot").string();
  const std::string svg_path = ::cobra::test_support::scratchPath("cobra_graph_test.svg").string();
  std::ofstream(dot_path) << graphvizDot(p.registry);
  ASSERT_EQ(std::system(("dot -Tsvg " + dot_path + " -o " + svg_path).c_str()), 0);
  std::stringstream svg;
  svg << std::ifstream(svg_path).rdbuf();
  EXPECT_CONTAINS(svg.str(), "<svg");
  EXPECT_CONTAINS(svg.str(), "Detector");
}

}  // namespace
}  // namespace cobra::deploy
