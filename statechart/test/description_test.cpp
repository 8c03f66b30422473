// The read-only description of a chart (description.hpp): its nodes and transitions as written
// (the thesis' Fig. 3.2), time and completion events by the names the machine matches, and a
// cross-check against the machine itself: along a seeded random walk of 300 events, an event is
// offered by the description (a transition leaving the active leaf or one of its ancestors names
// it) exactly when raising it makes the machine take a transition.
#include "cobra/statechart/description.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "cobra/statechart/machine.hpp"
#include "figure32.hpp"

namespace cobra::statechart {
namespace {

using test::figure32;
using test::trans;

const ChartDescription::Node* node(const ChartDescription& d, const std::string& path) {
  const auto found = std::find_if(d.nodes.begin(), d.nodes.end(), [&](const auto& n) { return n.path == path; });
  return found == d.nodes.end() ? nullptr : &*found;
}

TEST(ChartDescription, ListsEveryNodeWithItsParentAndEveryTransitionWithItsEventNames) {
  const ChartDescription d = describe(figure32());
  std::vector<std::string> paths;
  for (const auto& n : d.nodes) paths.push_back(n.path);
  EXPECT_EQ(paths.front(), "root");
  for (const char* p : {"root.on", "root.on.moving", "root.on.waiting", "root.on.initial", "root.error",
                        "root.fatal_error", "root.initial"})
    EXPECT_NE(node(d, p), nullptr) << p;
  EXPECT_EQ(d.nodes.size(), 8u);
  EXPECT_EQ(node(d, "root")->parent, "");
  EXPECT_EQ(node(d, "root.on.moving")->parent, "root.on");
  EXPECT_TRUE(node(d, "root.on")->composite);
  EXPECT_FALSE(node(d, "root.error")->composite);
  EXPECT_TRUE(node(d, "root.on.initial")->connector);
  EXPECT_FALSE(node(d, "root.on.waiting")->connector);

  ASSERT_EQ(d.transitions.size(), 8u);
  const auto from = [&](const std::string& src, const std::string& event) {
    return std::find_if(d.transitions.begin(), d.transitions.end(), [&](const auto& t) {
      return t.src == src && std::find(t.events.begin(), t.events.end(), event) != t.events.end();
    });
  };
  const auto error = from("root.on", "e_error");
  ASSERT_NE(error, d.transitions.end());
  EXPECT_EQ(error->tgt, "root.error");
  // A composite target is its initial connector; a transition from `initial` waits for any event.
  EXPECT_EQ(from("root.error", "e_error_fixed")->tgt, "root.on.initial");
  const auto initial = std::find_if(d.transitions.begin(), d.transitions.end(), [](const auto& t) { return t.src == "root.initial"; });
  ASSERT_NE(initial, d.transitions.end());
  EXPECT_TRUE(initial->events.empty());
}

TEST(ChartDescription, NamesTimeAndCompletionEventsAsTheMachineMatchesThemAndMarksGuardsAndPriorities) {
  ChartBuilder b;
  b.addState("root", "a");
  b.addState("root", "b");
  b.addState("root", "c");
  b.addTransition("root", trans("initial", "a"));
  b.addTransition("root", trans("a", "b", {"e_after(1.50)"}));
  b.addTransition("root", trans("b", "c", {"e_done"}));
  TransitionSpec guarded = trans("a", "c", {"e_go"});
  guarded.guard = [](const StepEvents&) { return true; };
  guarded.pn = 5;
  b.addTransition("root", std::move(guarded));
  const ChartDescription d = describe(b.build());
  std::vector<std::string> a_events;
  for (const auto& t : d.transitions)
    if (t.src == "root.a") a_events.push_back(t.events.at(0));
  // Tried in the machine's order: the higher pn first.
  EXPECT_EQ(a_events, (std::vector<std::string>{"e_go", "e_after(1.5)@root.a"}));
  for (const auto& t : d.transitions) {
    if (t.src == "root.a" && t.events[0] == "e_go") {
      EXPECT_TRUE(t.guarded);
      EXPECT_EQ(t.pn, 5);
    }
    if (t.src == "root.b") {
      EXPECT_EQ(t.events, std::vector<std::string>{"e_done@root.b"});
    }
  }
}

// The events the description says the active configuration waits for (unguarded transitions
// leaving the active leaf or an ancestor).
std::vector<std::string> offered(const ChartDescription& d, const std::string& leaf) {
  std::vector<std::string> out;
  for (const auto& t : d.transitions) {
    const bool active = leaf == t.src || leaf.rfind(t.src + ".", 0) == 0;
    if (active) out.insert(out.end(), t.events.begin(), t.events.end());
  }
  return out;
}

TEST(ChartDescription, OffersAnEventExactlyWhenTheMachineTakesATransitionOnItOnASeededRandomWalk) {
  const Chart chart = figure32();
  const ChartDescription d = describe(chart);
  const std::vector<std::string> events = {"e_start", "e_stop", "e_error", "e_error_fixed", "e_fatal_error", "e_reset", "e_other"};
  Machine m(chart, {});
  ASSERT_TRUE(m.run());
  std::mt19937 random(20261125);  // seeded: the same 300 events every run
  int moved = 0;
  for (int i = 0; i < 300; ++i) {
    const std::string& event = events[random() % events.size()];
    const std::string leaf(m.activeLeaf());
    const std::vector<std::string> offer = offered(d, leaf);
    const bool expected = std::find(offer.begin(), offer.end(), event) != offer.end();
    ASSERT_EQ(m.raise(event), RaiseStatus::Queued);
    ASSERT_EQ(m.step() == StepResult::Transitioned, expected) << event << " in " << leaf;
    m.run();
    moved += expected ? 1 : 0;
  }
  EXPECT_GT(moved, 50);  // the walk visits the transitions, not only ignored events
}

}  // namespace
}  // namespace cobra::statechart
