// The state table (cobra/task/state_table.hpp) with a vocabulary of its own, and its evaluator
// (cobra/task/goals.hpp) against a fake task's datums.
#include "cobra/task/state_table.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cobra/task/goals.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::task {
namespace {

using test_support::messageOf;

const TableVocabulary kWords{{"left", "right"}, {"cup", "next_cup"}};

StateTable table(const std::string& text) { return parseStateTable(text, "t.txt", kWords); }

/// A task whose datum `cup` is at x = 1 and `next_cup` at x = 2, unless there is no next cup.
struct Cups final : DatumSource {
  bool next_coming = true;
  Outcome resolve(const Datum& datum, std::size_t arm, KDL::Frame& pose, const char*& why) override {
    if (datum.name == "hold") {
      pose = KDL::Frame(KDL::Vector(0, arm == 0 ? -1.0 : 1.0, 0));
      return Outcome::Resolved;
    }
    if (datum.name == "next_cup" && !next_coming) {
      why = "no cup after this one";
      return Outcome::NotComing;
    }
    if (datum.name == "cup" || datum.name == "next_cup") {
      pose = KDL::Frame(KDL::Vector(datum.name == "cup" ? 1.0 : 2.0, 0, 0));
      return Outcome::Resolved;
    }
    why = "unknown";
    return Outcome::Missing;
  }
};

TEST(StateTable, ARowTakesItsKeysFromTheVocabularysArms) {
  const StateTable t = table("pose home xyz=0,0,0.5\nstate Reach left=cup-0.01 right=home then_left=cup\n");
  const StateRow* row = t.find("root.Task.Reach.Moving");
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(row->goal(0).at(0).name, "cup");
  EXPECT_DOUBLE_EQ(row->goal(0).at(0).offset, -0.01);
  EXPECT_EQ(row->goal(1).at(0).name, "home");
  EXPECT_EQ(row->then(0).name, "cup");
  EXPECT_TRUE(row->then(1).name.empty());
  ASSERT_NE(t.pose("home"), nullptr);
  EXPECT_DOUBLE_EQ(t.pose("home")->p.z(), 0.5);
}

TEST(StateTable, ErrorsNameTheFileTheLineAndTheVocabulary) {
  EXPECT_EQ(messageOf([] { table("state Reach needle=cup right=hold\n"); }),
            "t.txt:1: 'state' needs left=");
  EXPECT_EQ(messageOf([] { table("\nstate Reach left=mug right=hold\n"); }),
            "t.txt:2: unknown datum 'mug' (expected cup, next_cup, hold or a pose defined above)");
  EXPECT_EQ(messageOf([] { table("pose cup xyz=0,0,0\n"); }), "t.txt:1: pose name 'cup' is reserved (cup, next_cup, hold)");
  EXPECT_EQ(messageOf([] { table("state A left=cup right=hold\nstate A left=hold right=hold\n"); }),
            "t.txt:2: state 'A' is already at line 1");
}

TEST(StateTable, TheDeepestMatchingRowWinsAndPathsMatchWholeComponents) {
  const StateTable t = table("state Reach left=cup right=hold\nstate Reach.Back left=hold right=hold\n");
  EXPECT_EQ(t.find("root.Reach.Back.Moving")->state, "Reach.Back");
  EXPECT_EQ(t.find("root.Reach.Moving")->state, "Reach");
  EXPECT_EQ(t.find("root.Reaching"), nullptr);
  EXPECT_TRUE(pathContains("root.Reach.Back.Moving", "Reach.Back"));
  EXPECT_FALSE(pathContains("root.Reach.Backward", "Reach.Back"));
}

TEST(StateTableGoals, TheFirstGoalAndTheChecksComeFromTheTasksDatums) {
  const StateTable t = table("state Reach left=cup-0.1|hold right=hold then_left=cup room_for_right=next_cup..next_cup+0.1\n");
  const StateRow& row = t.rows.at(0);
  Cups cups;
  std::array<KDL::Frame, 2> first;
  GoalFailure failure;
  ASSERT_TRUE(firstGoal(row, kWords.arms, cups, first, failure)) << failure.message();
  EXPECT_DOUBLE_EQ(first[0].p.x(), 1.0);
  EXPECT_DOUBLE_EQ(first[0].p.z(), -0.1);  // moved along the datum's own z
  EXPECT_DOUBLE_EQ(first[1].p.y(), 1.0);
  EXPECT_TRUE(hasChecks(row));
  std::vector<std::vector<double>> waypoints(goalAlternatives(row));
  ASSERT_TRUE(checkedGoals(row, kWords.arms, cups, waypoints, failure)) << failure.message();
  ASSERT_EQ(waypoints.size(), 2u);  // one per alternative
  EXPECT_EQ(waypoints[0].size(), 4 * 2 * kPoseValues);  // goal pair, then pair, room's start and end pairs
  cups.next_coming = false;  // the room for a motion that will not come is left out
  ASSERT_TRUE(checkedGoals(row, kWords.arms, cups, waypoints, failure));
  EXPECT_EQ(waypoints[0].size(), 2 * 2 * kPoseValues);
}

TEST(StateTableGoals, AMissingDatumNamesItsKeyAndWhy) {
  const StateTable t = table("pose home xyz=0,0,0\nstate Reach left=next_cup right=home\n");
  Cups cups;
  cups.next_coming = false;
  std::array<KDL::Frame, 2> first;
  GoalFailure failure;
  EXPECT_FALSE(firstGoal(t.rows.at(0), kWords.arms, cups, first, failure));
  EXPECT_EQ(failure.message(), "left=next_cup: no cup after this one");
  FailureText no_row;
  EXPECT_EQ(rowFor(t, "root.Wait", "t.txt", no_row), nullptr);
  EXPECT_EQ(no_row.view(), "task state 'root.Wait' matches no row of t.txt");
}

}  // namespace
}  // namespace cobra::task
