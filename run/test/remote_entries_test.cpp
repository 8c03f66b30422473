// A run split over hosts (src/remote_entries.hpp): each host's run drops the run table's entries
// that name another host's components, and those that depend on a chart or tracking dropped so.

#include "../src/remote_entries.hpp"

#include <gtest/gtest.h>

namespace cobra::run {
namespace {

using Names = std::vector<std::string>;

/// Components whose names start with "B" live on host "b"; everything else is local.
std::string hostB(const std::string& component) { return component.rfind('B', 0) == 0 ? "b" : ""; }

/// A run table observing a local robot A and a remote robot B, their charts and both.
RunSpec twoRobots() {
  RunSpec spec;
  spec.charts = {{"a", "ASup", "root.Done", "root.SafeStop", "a", {}, {}},
                 {"b", "BSup", "root.Done", "root.SafeStop", "b", {}, {}}};
  TrackingSpec a_track;
  a_track.name = "A tool";
  a_track.commanded = "AAdm.pose";
  a_track.measured = "ARobot.pose";
  TrackingSpec b_track = a_track;
  b_track.name = "B tool";
  b_track.commanded = "BAdm.pose";
  b_track.measured = "BRobot.pose";
  TrackingSpec b_chart_track = a_track;  // local ports, but kept with the remote chart's states
  b_chart_track.name = "A for b";
  b_chart_track.chart = "b";
  spec.tracking = {a_track, b_track, b_chart_track};
  spec.record.ports = {{"ARobot.pose", {}}, {"BRobot.pose", {}}};
  PlotSpec a_plot, b_plot, derived;
  a_plot.title = "A";
  a_plot.series = {"ARobot.pose.z"};
  b_plot.title = "both";
  b_plot.series = {"ARobot.pose.z", "BRobot.pose.z"};
  derived.title = "B tracking";
  derived.series = {"tracking.B tool.mm"};
  spec.plots = {a_plot, b_plot, derived};
  SummarySpec distance;
  distance.name = "placement";
  distance.kind = SummarySpec::Kind::Distance;
  distance.ports = {"ARobot.pose", "AFrames.target"};
  distance.chart = "a";
  distance.of = "BFrames.count";
  SummarySpec count;
  count.name = "faults";
  count.events = {"e_fault"};
  SummarySpec on_b = distance;
  on_b.name = "when b";
  on_b.chart = "b";
  on_b.of.clear();
  spec.summary = {distance, count, on_b};
  spec.clearance.declared = true;
  spec.clearance.port = "APlanner.minDistance";
  spec.clearance.contacts = {{"probe", "BPlanner.contact"}, {"tissue", "APlanner.contact"}};
  spec.studio.scene = "BPlanner";
  // "a" has its joints here but its model from the scene, another host's: it goes with it.
  spec.studio.robots = {{"a", "ARobot.joints", 0, {}, {}}, {"b", "BRobot.joints", 0, {}, {}}, {"a6", "ARobot.joints", 6, {}, {}}};
  spec.studio.signals = {{"ARobot.force", {}}, {"BRobot.force", {}}};
  ActionSpec call_b;
  call_b.kind = ActionSpec::Kind::Call;
  call_b.component = "BRobot";
  call_b.text = "call BRobot.halt";
  ActionSpec on_b_state;
  on_b_state.kind = ActionSpec::Kind::Call;
  on_b_state.component = "ARobot";
  on_b_state.text = "call ARobot.halt";
  on_b_state.on.kind = Trigger::Kind::State;
  on_b_state.on.chart = "b";
  ActionSpec local = on_b_state;
  local.on.chart = "a";
  local.text = "call ARobot.halt (a)";
  spec.actions = {call_b, on_b_state, local};
  return spec;
}

TEST(RemoteEntries, EntriesOfOtherHostsAreDroppedAndListed) {
  RunSpec spec = twoRobots();
  const RemoteEntries dropped = dropRemoteEntries(spec, hostB);
  ASSERT_EQ(spec.charts.size(), 1u);
  EXPECT_EQ(spec.charts[0].name, "a");
  ASSERT_EQ(spec.tracking.size(), 1u);
  EXPECT_EQ(spec.tracking[0].name, "A tool");
  ASSERT_EQ(spec.record.ports.size(), 1u);
  EXPECT_EQ(spec.record.ports[0].first, "ARobot.pose");
  ASSERT_EQ(spec.plots.size(), 2u);
  EXPECT_EQ(spec.plots[0].title, "A");
  EXPECT_EQ(spec.plots[1].title, "both");
  EXPECT_EQ(spec.plots[1].series, Names{"ARobot.pose.z"}) << "a plot keeps this host's series";
  ASSERT_EQ(spec.summary.size(), 2u);
  EXPECT_EQ(spec.summary[0].name, "placement");
  EXPECT_EQ(spec.summary[0].of, "") << "the expected count is asked of a remote component: left out";
  EXPECT_EQ(spec.summary[1].name, "faults") << "counts of events stay: they count this host's events";
  EXPECT_TRUE(spec.clearance.declared);
  ASSERT_EQ(spec.clearance.contacts.size(), 1u);
  EXPECT_EQ(spec.clearance.contacts[0].first, "tissue");
  EXPECT_EQ(spec.studio.scene, "");
  ASSERT_EQ(spec.studio.robots.size(), 1u);
  EXPECT_EQ(spec.studio.robots[0].name, "a6") << "its joint count needs no scene";
  ASSERT_EQ(spec.studio.signals.size(), 1u);
  ASSERT_EQ(spec.actions.size(), 1u);
  EXPECT_EQ(spec.actions[0].text, "call ARobot.halt (a)");

  ASSERT_EQ(dropped.by_host.size(), 1u);
  EXPECT_EQ(dropped.by_host.at("b"),
            (Names{"run.charts 'b'", "run.tracking 'B tool'", "run.tracking 'A for b'", "run.summary 'when b'",
                          "run.record BRobot.pose", "run.plots 'both' series BRobot.pose.z", "run.plots 'B tracking'",
                          "run.clearance contact 'probe'", "run.studio.scene BPlanner",
                          "run.studio.robots 'a' (its model is the scene's)", "run.studio.robots 'b'",
                          "run.studio.signals BRobot.force", "run.actions call BRobot.halt (:0)",
                          "run.actions call ARobot.halt (:0)"}));
  EXPECT_EQ(dropped.charts.at("b"), "b");
}

TEST(RemoteEntries, ARemoteClearanceGoesWhole) {
  RunSpec spec = twoRobots();
  spec.clearance.port = "BPlanner.minDistance";
  const RemoteEntries dropped = dropRemoteEntries(spec, hostB);
  EXPECT_FALSE(spec.clearance.declared);
  EXPECT_TRUE(spec.clearance.contacts.empty());
  EXPECT_EQ(std::count(dropped.by_host.at("b").begin(), dropped.by_host.at("b").end(), "run.clearance"), 1);
}

TEST(RemoteEntries, FaultsOfOtherHostsAreTheirs) {
  RunSpec spec = twoRobots();
  const RemoteEntries dropped = dropRemoteEntries(spec, hostB);
  ActionSpec fault;
  fault.kind = ActionSpec::Kind::Set;
  fault.component = "BRobot";
  EXPECT_EQ(remoteHostOfAction(fault, dropped, hostB), "b");
  fault.component = "ARobot";
  EXPECT_EQ(remoteHostOfAction(fault, dropped, hostB), "");
  fault.on.kind = Trigger::Kind::State;
  fault.on.chart = "b";
  EXPECT_EQ(remoteHostOfAction(fault, dropped, hostB), "b") << "waits for a state of the other host's chart";
  fault.on.chart = "typo";
  EXPECT_EQ(remoteHostOfAction(fault, dropped, hostB), "") << "unknown charts are the run's error, not dropped";
}

TEST(RemoteEntries, NothingRemoteDropsNothing) {
  RunSpec spec = twoRobots();
  const RemoteEntries dropped = dropRemoteEntries(spec, [](const std::string&) { return std::string(); });
  EXPECT_TRUE(dropped.by_host.empty());
  EXPECT_EQ(spec.charts.size(), 2u);
  EXPECT_EQ(spec.tracking.size(), 3u);
  EXPECT_EQ(spec.plots.size(), 3u);
  EXPECT_EQ(spec.actions.size(), 3u);
}

}  // namespace
}  // namespace cobra::run
