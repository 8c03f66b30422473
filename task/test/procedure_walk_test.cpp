// The procedure walker (cobra/task/procedure_walk.hpp) against a fake task and a fake verifier:
// each step's goal from its row for its item, `hold` where the walk left the arm, the candidates
// with their checks, and the refusal of the first step that cannot be made.
#include "cobra/task/procedure_walk.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace cobra::task {
namespace {

const TableVocabulary kWords{{"left", "right"}, {"cup", "next_cup"}};

/// Cup i stands at x = i + 1 (m); there is no cup after the last.
struct Cups final : ItemDatumSource {
  std::size_t count = 2, current = 0;
  void select(std::size_t item) override { current = item; }
  std::string itemName(std::size_t item) const override { return "cup " + std::to_string(item + 1); }
  Outcome resolve(const Datum& datum, std::size_t, KDL::Frame& pose, const char*& why) override {
    const std::size_t i = current + (datum.name == "next_cup" ? 1 : 0);
    if (i >= count) {
      why = "no cup after this one";
      return datum.name == "next_cup" ? Outcome::NotComing : Outcome::Missing;
    }
    pose = KDL::Frame(KDL::Vector(static_cast<double>(i + 1), 0, 0));
    return Outcome::Resolved;
  }
};

/// Records what it is asked; refuses the steps whose state is `refuse`, and in planned steps
/// every candidate whose goal x of the moving arm is in `blocked`.
struct Recorder final : StepVerifier {
  std::string refuse;
  std::vector<double> blocked;  // in root.Park
  std::vector<std::string> asked;
  std::vector<std::vector<GoalCandidate>> candidates;
  std::vector<PosePair> froms;
  StepOutcome planned(const ProcedureStep& step, std::span<const GoalCandidate> c) override {
    asked.push_back(step.state);
    candidates.emplace_back(c.begin(), c.end());
    StepOutcome out;
    if (step.state == refuse) {
      out.why = "no path found";
      return out;
    }
    for (std::size_t k = 0; k < c.size(); ++k) {
      const bool park = step.state == "root.Park";
      if (park && std::find(blocked.begin(), blocked.end(), c[k].goal[step.arm].p.x()) != blocked.end()) continue;
      out.ok = true;
      out.chosen = k;
      out.reached = c[k].goal;
      return out;
    }
    out.why = "every alternative blocked";
    return out;
  }
  StepOutcome straight(const ProcedureStep& step, const PosePair& from, const PosePair& to) override {
    asked.push_back(step.state);
    froms.push_back(from);
    StepOutcome out;
    out.ok = step.state != refuse;
    out.why = out.ok ? "" : "collision between 'arm' and 'table'";
    out.reached = to;
    return out;
  }
};

constexpr const char* kTable =
    "pose park xyz=0,5,0\n"
    "pose aside xyz=0,6,0\n"
    "state Reach left=cup-0.1 right=hold then_left=cup\n"       // line 3
    "state Touch left=cup right=hold\n"                          // line 4
    "state Park left=park|hold|aside right=hold room_for_right=next_cup..next_cup+0.2\n"  // line 5
    "state Look left=hold right=cup\n";                          // line 6

std::vector<ProcedureStep> twoCups() {
  std::vector<ProcedureStep> steps;
  for (std::size_t i = 0; i < 2; ++i) {
    steps.push_back({"root.Look", 1, true, i});
    steps.push_back({"root.Reach", 0, true, i});
    steps.push_back({"root.Touch", 0, false, i});
    steps.push_back({"root.Park", 0, true, i});
  }
  return steps;
}

const PosePair kStart{KDL::Frame(KDL::Vector(0, 5, 0)), KDL::Frame(KDL::Vector(0, -5, 0))};

TEST(ProcedureWalk, EachStepStartsWhereThePreviousLeftTheArms) {
  const StateTable table = parseStateTable(kTable, "t.txt", kWords);
  Cups cups;
  Recorder verifier;
  const std::vector<ProcedureStep> steps = twoCups();
  const ProcedureVerdict verdict = walkProcedure(table, "t.txt", kWords.arms, steps, kStart, cups, verifier);
  ASSERT_TRUE(verdict.ok) << verdict.refusal.text("t.txt");
  EXPECT_EQ(verdict.chosen, std::vector<std::size_t>(8, 0));
  ASSERT_EQ(verifier.asked.size(), 8u);
  // Look: the left arm holds where it started, the right goes to the cup.
  EXPECT_DOUBLE_EQ(verifier.candidates[0][0].goal[0].p.y(), 5.0);
  EXPECT_DOUBLE_EQ(verifier.candidates[0][0].goal[1].p.x(), 1.0);
  // Reach: the approach with its follow-on to the cup; the right arm holds at cup 1.
  const GoalCandidate& reach = verifier.candidates[1][0];
  EXPECT_NEAR(reach.goal[0].p.z(), -0.1, 1e-12);
  EXPECT_TRUE(reach.has_then);
  EXPECT_DOUBLE_EQ(reach.then[0].p.x(), 1.0);
  EXPECT_DOUBLE_EQ(reach.goal[1].p.x(), 1.0);
  // Touch: a straight motion from where Reach left the left arm.
  EXPECT_NEAR(verifier.froms[0][0].p.z(), -0.1, 1e-12);
  // Park for cup 1: three alternatives, each with room for the right arm's motion at cup 2.
  const std::vector<GoalCandidate>& park = verifier.candidates[2];
  ASSERT_EQ(park.size(), 3u);
  EXPECT_EQ(park[1].datum, "hold");
  EXPECT_DOUBLE_EQ(park[1].goal[0].p.x(), 1.0);  // hold: where Touch left it
  ASSERT_EQ(park[0].rooms.size(), 1u);
  EXPECT_DOUBLE_EQ(park[0].rooms[0].first[1].p.x(), 2.0);
  EXPECT_NEAR(park[0].rooms[0].second[1].p.z(), 0.2, 1e-12);
  // Park after the last cup: no room to leave (the motion will not come).
  EXPECT_TRUE(verifier.candidates[5][0].rooms.empty());
}

TEST(ProcedureWalk, TheFirstRefusedStepNamesItsItemStateDatumAndWhy) {
  const StateTable table = parseStateTable(kTable, "t.txt", kWords);
  Cups cups;
  Recorder verifier;
  verifier.refuse = "root.Touch";
  const std::vector<ProcedureStep> steps = twoCups();
  const ProcedureVerdict verdict = walkProcedure(table, "t.txt", kWords.arms, steps, kStart, cups, verifier);
  ASSERT_FALSE(verdict.ok);
  EXPECT_EQ(verdict.refusal.step, 2u);
  EXPECT_EQ(verdict.refusal.text("t.txt"),
            "cup 1, task state 'root.Touch' (t.txt:4), left=cup: collision between 'arm' and 'table'");
  EXPECT_EQ(verifier.asked.size(), 3u);  // nothing after the refused step is asked
}

TEST(ProcedureWalk, APlannedStepNamesEveryAlternativeAndTheOneTaken) {
  const StateTable table = parseStateTable(kTable, "t.txt", kWords);
  Cups cups;
  Recorder verifier;
  verifier.blocked = {0.0};  // park and aside (x = 0) are blocked: hold (x = 1, 2) is taken
  const std::vector<ProcedureStep> steps = twoCups();
  const ProcedureVerdict verdict = walkProcedure(table, "t.txt", kWords.arms, steps, kStart, cups, verifier);
  ASSERT_TRUE(verdict.ok) << verdict.refusal.text("t.txt");
  EXPECT_EQ(verdict.chosen[3], 1u);
  verifier = Recorder{};
  verifier.blocked = {0.0, 1.0};
  const ProcedureVerdict refused = walkProcedure(table, "t.txt", kWords.arms, steps, kStart, cups, verifier);
  ASSERT_FALSE(refused.ok);
  EXPECT_EQ(refused.refusal.text("t.txt"),
            "cup 1, task state 'root.Park' (t.txt:5), left=park|hold|aside: every alternative blocked");
}

TEST(ProcedureWalk, AMissingDatumOrRowIsARefusal) {
  const StateTable table = parseStateTable(kTable, "t.txt", kWords);
  Cups cups;
  cups.count = 1;  // the walk asks for cup 2
  Recorder verifier;
  const std::vector<ProcedureStep> steps = twoCups();
  const ProcedureVerdict verdict = walkProcedure(table, "t.txt", kWords.arms, steps, kStart, cups, verifier);
  ASSERT_FALSE(verdict.ok);
  EXPECT_EQ(verdict.refusal.text("t.txt"),
            "cup 2, task state 'root.Look' (t.txt:6), right=cup: no cup after this one");
  const std::vector<ProcedureStep> unknown{{"root.Dance", 0, false, 0}};
  const ProcedureVerdict none = walkProcedure(table, "t.txt", kWords.arms, unknown, kStart, cups, verifier);
  ASSERT_FALSE(none.ok);
  EXPECT_EQ(none.refusal.text("t.txt"), "cup 1, task state 'root.Dance': the task state matches no row of t.txt");
}

}  // namespace
}  // namespace cobra::task
