// The puncturing data: the scenarios parse, are feasible and match their simulated phantoms;
// text round trips; errors name file:line; mutated files never crash the parsers.
#include "cobra/puncturing/plan.hpp"

#include <gtest/gtest.h>

#include <random>

#include "cobra/sim/phantom.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::puncturing {
namespace {

using cobra::test_support::messageOf;

const std::string kApp = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/";
const std::vector<std::string> kScenarios = {"two_needles", "three_needles"};

std::string file(const std::string& scenario, const std::string& name) { return kApp + "scenarios/" + scenario + "/" + name; }

PuncturingPlan load(const std::string& scenario) {
  return loadPlan(file(scenario, "preoperative.txt"), file(scenario, "cryo_plan.txt"), file(scenario, "us_plan.txt"));
}

TEST(PuncturingPlan, BothScenariosLoadWithTheirNeedlesAndOneProbePoseEach) {
  EXPECT_EQ(load("two_needles").needles.size(), 2u);
  const PuncturingPlan three = load("three_needles");
  ASSERT_EQ(three.needles.size(), 3u);
  EXPECT_EQ(three.probes.size(), 3u);
  EXPECT_EQ(three.needles[2].name, "n3");
  EXPECT_DOUBLE_EQ(three.needles[2].roll, 0.0);  // no needle rolled to dodge the wrist's gimbal lock
  EXPECT_NE(load("two_needles").preoperative.tumour_center, three.preoperative.tumour_center);
}

TEST(PuncturingPlan, NeedlePosesPointIntoTheBodyFromAboveAndFitA15CmNeedle) {
  for (const std::string& scenario : kScenarios) {
    const PuncturingPlan plan = load(scenario);
    for (const PlannedNeedle& n : plan.needles) {
      const KDL::Frame tip = needleTargetPose(n), entry = needleEntryPose(n);
      EXPECT_LT(tip.M.UnitZ().z(), -0.5) << scenario << " " << n.name;  // z along the needle, down
      EXPECT_LT((tip.p - n.target).Norm(), 1e-12);
      // The target is reached by advancing the entry pose along its own z by the inserted length.
      EXPECT_LT((alongZ(entry, (n.target - n.entry).Norm()).p - n.target).Norm(), 1e-12);
      EXPECT_LT((n.target - n.entry).Norm(), 0.15 - 0.05) << "leaves at least 5 cm of needle outside the skin";
      // The probe's imaging plane (its x-z plane) contains the needle.
    }
    for (std::size_t i = 0; i < plan.probes.size(); ++i) {
      const KDL::Vector normal = plan.probes[i].pose.M.UnitY();
      EXPECT_NEAR(KDL::dot(normal, plan.needles[i].entry - plan.probes[i].pose.p), 0.0, 1e-6);
      EXPECT_NEAR(KDL::dot(normal, plan.needles[i].target - plan.probes[i].pose.p), 0.0, 1e-6);
    }
  }
}

TEST(PuncturingPlan, RollTurnsTheTipFrameAboutTheNeedleOnly) {
  PlannedNeedle n{"n", KDL::Vector(0.01, 0, 0), KDL::Vector(0, 0, -0.05), 0.0, 1};
  const KDL::Frame a = needleTargetPose(n);
  n.roll = 0.7;
  const KDL::Frame b = needleTargetPose(n);
  EXPECT_TRUE(KDL::Equal(a.M.UnitZ(), b.M.UnitZ(), 1e-12));
  EXPECT_NEAR(std::acos(KDL::dot(a.M.UnitX(), b.M.UnitX())), 0.7, 1e-9);
}

TEST(PuncturingPlan, EachScenarioPhantomHasTheSameTumourAndForbiddenRegionsAsItsPreoperativeInformation) {
  for (const std::string& scenario : kScenarios) {
    const PreoperativeInfo info = load(scenario).preoperative;
    const sim::PhantomScenario phantom = sim::loadScenario(file(scenario, "phantom.txt"));
    EXPECT_TRUE(KDL::Equal(phantom.tumour_center, info.tumour_center, 1e-12)) << scenario;
    EXPECT_DOUBLE_EQ(phantom.tumour_radius, info.tumour_radius) << scenario;
    ASSERT_EQ(phantom.forbidden.size(), info.forbidden.size()) << scenario;
    for (std::size_t i = 0; i < info.forbidden.size(); ++i) {
      EXPECT_EQ(phantom.forbidden[i].name, info.forbidden[i].name);
      EXPECT_TRUE(KDL::Equal(phantom.forbidden[i].a, info.forbidden[i].a, 1e-12));
      EXPECT_TRUE(KDL::Equal(phantom.forbidden[i].b, info.forbidden[i].b, 1e-12));
      EXPECT_DOUBLE_EQ(phantom.forbidden[i].radius, info.forbidden[i].radius);
    }
    // The tumour lies within the phantom's layers.
    double depth = 0.0;
    for (const auto& layer : phantom.layers) depth += layer.thickness;
    EXPECT_LT(-(info.tumour_center.z() - info.tumour_radius), depth) << scenario;
  }
}

TEST(PuncturingPlan, TextFormsRoundTrip) {
  for (const std::string& scenario : kScenarios) {
    const PuncturingPlan plan = load(scenario);
    const PreoperativeInfo info = parsePreoperative(print(plan.preoperative), "printed");
    EXPECT_TRUE(KDL::Equal(info.abdomen_in_task, plan.preoperative.abdomen_in_task, 1e-9));
    EXPECT_EQ(print(info), print(plan.preoperative));
    const auto needles = parseCryoPlan(printCryoPlan(plan.needles), "printed");
    ASSERT_EQ(needles.size(), plan.needles.size());
    for (std::size_t i = 0; i < needles.size(); ++i) {
      EXPECT_TRUE(KDL::Equal(needleTargetPose(needles[i]), needleTargetPose(plan.needles[i]), 1e-9));
    }
    const auto probes = parseProbePlan(printProbePlan(plan.probes), "printed");
    for (std::size_t i = 0; i < probes.size(); ++i) EXPECT_TRUE(KDL::Equal(probes[i].pose, plan.probes[i].pose, 1e-9));
  }
}

// Numbers print as their shortest exact decimal: a value next to a parser's limit (a tumour whose
// top is 1e-13 m below the skin) is not rounded onto it, so the printed text is accepted again.
TEST(PuncturingPlan, PrintedNumbersParseBackExactly) {
  const std::string text =
      "abdomen xyz=0.1,0,0.3 rpy=0,0,0\ntumour center=0,0,-0.0100000000001 radius=0.01\n"
      "entry_region center=0,0,0 radius=0.05\n";
  const PreoperativeInfo info = parsePreoperative(text, "near_limit.txt");
  const PreoperativeInfo again = parsePreoperative(print(info), "printed");
  EXPECT_EQ(again.tumour_center.z(), info.tumour_center.z());  // exactly (KDL's == on vectors allows 1e-6)
  EXPECT_EQ(again.abdomen_in_task.p.x(), info.abdomen_in_task.p.x());
  const std::vector<PlannedNeedle> needles = {{"n1", KDL::Vector(0.1, 1.0 / 3.0, 0), KDL::Vector(0, 0, -0.06), 0.7, 1}};
  const std::vector<PlannedNeedle> needles_again = parseCryoPlan(printCryoPlan(needles), "printed");
  EXPECT_EQ(needles_again[0].entry.y(), needles[0].entry.y());
  EXPECT_EQ(needles_again[0].roll, 0.7);
}

TEST(PuncturingPlan, ParseErrorsNameTheFileAndLine) {
  const std::string tumour = "abdomen xyz=0,0,0\ntumour center=0,0,-0.05 radius=0.01\nentry_region center=0,0,0 radius=0.05\n";
  EXPECT_EQ(messageOf([&] { parsePreoperative(tumour + "spere vessel center=0,0,-0.02 radius=0.01\n", "pre.txt"); }),
            "pre.txt:4: unknown statement 'spere' (expected abdomen, tumour, sphere, capsule or entry_region)");
  EXPECT_EQ(messageOf([&] { parsePreoperative(tumour + "sphere v center=0,0 radius=0.01\n", "pre.txt"); }),
            "pre.txt:4: value of 'center' must be X,Y,Z (m)");
  EXPECT_EQ(messageOf([&] { parsePreoperative(tumour + "capsule rib a=0,0,-0.02 b=1,0,-0.02 radius=-1\n", "p"); }),
            "p:4: radius = -1, expected > 0 m");
  EXPECT_EQ(messageOf([&] { parsePreoperative("tumour center=0,0,-0.05 radius=0.01 colour=red\n", "p"); }),
            "p:1: unknown key 'colour' in 'tumour' (expected 'tumour center=X,Y,Z radius=M')");
  EXPECT_EQ(messageOf([&] { parsePreoperative("tumour center=0,0,-0.005 radius=0.01\n", "p"); }),
            "p:1: the tumour reaches the skin (z = 0) or above it");
  EXPECT_EQ(messageOf([&] { parsePreoperative("abdomen xyz=0,0,0\n", "p"); }), "p: no 'tumour center=X,Y,Z radius=M'");
  EXPECT_EQ(messageOf([&] { parseCryoPlan("# plan\nneedle a entry=0,0,0 target=0,0,-0.05\nneedle a entry=0,0,0 "
                                          "target=0,0,-0.04\n", "cryo.txt"); }),
            "cryo.txt:3: needle 'a' is already planned at line 2");
  EXPECT_EQ(messageOf([&] { parseCryoPlan("needle a entry=0,0,0 target=0,0,x\n", "cryo.txt"); }),
            "cryo.txt:1: value of 'target' is 'x', expected a number (m)");
  EXPECT_EQ(messageOf([&] { parseProbePlan("probe n1 xyz=0,0,0 rpy=0,0\n", "us.txt"); }),
            "us.txt:1: value of 'rpy' must be X,Y,Z (rad)");
  EXPECT_EQ(messageOf([&] { parseSurgeonScript("on needle.WaitCryoCycle e_cryo_finished after=2\n", "s.txt"); }),
            "s.txt:1: 'e_cryo_finished' is not a surgeon event (expected one of e_iceball_configured, "
            "e_needle_mounted, e_needle_removed, e_cryo_done, e_recover, e_take_over, e_teleop_done)");
  EXPECT_EQ(messageOf([&] { parseSurgeonScript("\non robot.WaitCryoCycle e_cryo_done\n", "s.txt"); }),
            "s.txt:2: chart 'robot' is neither needle nor us");
  EXPECT_EQ(messageOf([&] { parseStateTable("state MoveToSkin needle=entri probe=hold\n", "t.txt"); }),
            "t.txt:1: unknown datum 'entri' (expected entry, target, probe, next_entry, next_target, next_probe, hold "
            "or a pose defined above)");
  EXPECT_EQ(messageOf([&] { parseStateTable("state MoveToSkin needle=hold probe=probe then_probe=prob+0.004\n", "t.txt"); }),
            "t.txt:1: unknown datum 'prob' (expected entry, target, probe, next_entry, next_target, next_probe, hold "
            "or a pose defined above)");
  EXPECT_EQ(messageOf([&] { parseStateTable("state MoveToSkin needle=hold probe=probe then_prob=probe\n", "t.txt"); }),
            "t.txt:1: unknown key 'then_prob' in 'state' (expected 'state PATH needle=DATUM[|DATUM...] "
            "probe=DATUM[|DATUM...] [then_needle=DATUM] [then_probe=DATUM] [room_for_needle=DATUM..DATUM] "
            "[room_for_probe=DATUM..DATUM]')");
  EXPECT_EQ(messageOf([&] { parseStateTable("pose a xyz=0,0,0\npose b xyz=0,0,0\nstate S needle=a|b probe=hold|a\n",
                                            "t.txt"); }),
            "t.txt:3: both arms list alternatives (A|B); list them for one arm, the other's goal is the same for each");
  EXPECT_EQ(messageOf([&] { parseStateTable("state S needle=hold probe=hold room_for_probe=next_probe\n", "t.txt"); }),
            "t.txt:1: value of 'room_for_probe' is 'next_probe', expected FROM..TO (two datums: where the motion "
            "starts and ends)");
  EXPECT_EQ(messageOf([&] { parseStateTable("state S needle=hold|entri probe=hold\n", "t.txt"); }),
            "t.txt:1: unknown datum 'entri' (expected entry, target, probe, next_entry, next_target, next_probe, hold "
            "or a pose defined above)");
  EXPECT_EQ(messageOf([&] { parseStateTable("pose change-2 xyz=0,0,0\n", "t.txt"); }),
            "t.txt:1: pose name 'change-2' holds + - or |, which a datum reads as an offset or an alternative");
  EXPECT_EQ(messageOf([&] { parseStateTable("pose next_probe xyz=0,0,0\n", "t.txt"); }),
            "t.txt:1: pose name 'next_probe' is reserved (entry, target, probe, next_entry, next_target, next_probe, "
            "hold)");
  EXPECT_EQ(messageOf([&] { loadPlan(kApp + "nowhere.txt", "", ""); }), kApp + "nowhere.txt: cannot be read");
}

TEST(PuncturingPlan, AStateRowMayNameTheMotionAfterItsGoal) {
  const StateTable table =
      parseStateTable("state Approach needle=hold probe=probe-0.03 then_probe=probe+0.004\n"
                      "state Descend needle=entry+0.004 probe=hold\n", "t.txt");
  const StateRow* approach = table.find("root.Approach.AskingGoal");
  ASSERT_NE(approach, nullptr);
  EXPECT_EQ(approach->then(1).name, "probe");
  EXPECT_DOUBLE_EQ(approach->then(1).offset, 0.004);
  EXPECT_TRUE(approach->then(0).name.empty());  // the needle stays at its goal
  EXPECT_TRUE(table.find("root.Descend")->then(1).name.empty());
}

TEST(PuncturingPlan, AStateRowMayListGoalAlternativesAndTheRoomTheyMustLeave) {
  const StateTable table = parseStateTable(
      "pose change xyz=0,0,0.3\npose change_left xyz=-0.1,0,0.3\n"
      "state MoveToNeedleChange needle=change|change_left|hold probe=hold "
      "room_for_probe=next_probe-0.03..next_probe+0.004\n",
      "t.txt");
  const StateRow* row = table.find("root.InsertingNeedles.MoveToNeedleChange.Planning");
  ASSERT_NE(row, nullptr);
  ASSERT_EQ(row->goal(0).size(), 3u);  // in the table's order: the preferred first
  EXPECT_EQ(row->goal(0)[0].name, "change");
  EXPECT_EQ(row->goal(0)[1].name, "change_left");
  EXPECT_EQ(row->goal(0)[2].name, "hold");
  ASSERT_EQ(row->goal(1).size(), 1u);
  EXPECT_EQ(row->roomFor(1).from.name, "next_probe");
  EXPECT_DOUBLE_EQ(row->roomFor(1).from.offset, -0.03);
  EXPECT_EQ(row->roomFor(1).to.name, "next_probe");
  EXPECT_DOUBLE_EQ(row->roomFor(1).to.offset, 0.004);
  EXPECT_TRUE(row->roomFor(0).from.name.empty());
  bool next = false;
  EXPECT_TRUE(planDatum("next_target", next));
  EXPECT_TRUE(next);
  EXPECT_TRUE(planDatum("entry", next));
  EXPECT_FALSE(next);
  EXPECT_FALSE(planDatum("next_hold", next));
}

TEST(PuncturingPlan, InfeasiblePlansAreRefusedNamingTheNeedleAndWhy) {
  PuncturingPlan plan = load("two_needles");
  auto message = [&](PuncturingPlan p) { return messageOf([&] { validate(p, "cryo.txt", "us.txt"); }); };
  PuncturingPlan p = plan;
  p.needles[1].target = KDL::Vector(0.02, -0.02, -0.066);  // into the vessel's side
  EXPECT_CONTAINS(message(p), "cryo.txt:4: needle 'n2': target is 28.9 mm from the tumour centre");
  p = plan;
  p.needles[0].entry = KDL::Vector(-0.1, 0.0, 0.0);
  EXPECT_EQ(message(p), "cryo.txt:3: needle 'n1': entry is 100.0 mm from the entry region's centre, outside its radius "
                        "50.0 mm");
  p = plan;
  p.preoperative.forbidden.push_back({"nerve", KDL::Vector(-0.01, -0.003, -0.03), KDL::Vector(-0.01, -0.003, -0.03), 0.002});
  EXPECT_EQ(message(p), "cryo.txt:3: needle 'n1': passes 0.2 mm from forbidden region 'nerve' (at least 2.0 mm)");
  p = plan;
  p.needles[0].entry = KDL::Vector(0.09, 0.0, 0.0);
  p.needles[0].target = KDL::Vector(-0.01, 0.0, -0.055);
  p.preoperative.entry_radius = 0.1;
  EXPECT_EQ(message(p), "cryo.txt:3: needle 'n1': tilted 61.2 deg from the vertical, expected a needle from above "
                        "within 60 deg");
  p = plan;
  p.probes[0].pose.p.z(0.01);
  EXPECT_EQ(message(p), "us.txt:3: probe for 'n1': z = 10.0 mm, expected the probe face on the skin (z = 0)");
  p = plan;
  p.probes[1].pose = p.probes[1].pose * KDL::Frame(KDL::Rotation::RotZ(0.2));
  EXPECT_CONTAINS(message(p), "us.txt:4: probe for 'n2': the needle's entry is");
  p = plan;
  p.probes.pop_back();
  EXPECT_EQ(message(p), "us.txt: 1 probe pose(s) for 2 needle(s), expected one each");
}

TEST(PuncturingPlan, StateTableFindsTheDeepestMatchingRow) {
  const StateTable table = parseStateTable(
      "pose change xyz=0.3,0.2,0.4 rpy=3.14159,0,0\n"
      "state MoveToSkin needle=entry-0.02 probe=hold\n"
      "state MoveToSkin.Descend needle=entry+0.005 probe=hold\n"
      "state InsertingNeedles needle=change probe=probe-0.03\n",
      "t.txt");
  ASSERT_EQ(table.rows.size(), 3u);
  EXPECT_EQ(table.find("root.InsertingNeedles.MoveToSkin.Approach.AskingGoal")->line, 2);
  EXPECT_EQ(table.find("root.InsertingNeedles.MoveToSkin.Descend.AskingGoal")->line, 3);
  EXPECT_EQ(table.find("root.InsertingNeedles.WaitNeedleMounted")->line, 4);
  EXPECT_EQ(table.find("root.WaitCryoCycle"), nullptr);
  EXPECT_EQ(table.find("root.InsertingNeedles.MoveToSkinny"), table.find("root.InsertingNeedles"));
  EXPECT_DOUBLE_EQ(table.rows[1].goal(0).at(0).offset, 0.005);
  EXPECT_DOUBLE_EQ(table.rows[0].goal(0).at(0).offset, -0.02);
  EXPECT_EQ(table.rows[2].goal(0).at(0).name, "change");
  ASSERT_NE(table.pose("change"), nullptr);
  EXPECT_DOUBLE_EQ(table.pose("change")->p.z(), 0.4);
}

TEST(PuncturingPlan, TheAppsStateTableAndSurgeonScriptsParse) {
  const StateTable table = parseStateTable(readText(kApp + "state_table.txt"), "state_table.txt");
  EXPECT_NE(table.find("root.InsertingNeedles.MoveToTumor.Moving"), nullptr);
  for (const std::string& scenario : kScenarios) {
    const SurgeonScript script = parseSurgeonScript(readText(file(scenario, "surgeon.txt")), scenario);
    EXPECT_EQ(script.actions.front().trigger, SurgeonAction::Trigger::At);
    EXPECT_EQ(script.actions.front().event, "e_iceball_configured");
  }
}

TEST(PuncturingPlan, TwoThousandSeededMutationsParseOrFailNamingTheSource) {
  std::mt19937_64 rng(20240917);
  const std::vector<std::pair<std::string, int>> files = {
      {readText(file("three_needles", "preoperative.txt")), 0}, {readText(file("three_needles", "cryo_plan.txt")), 1},
      {readText(file("three_needles", "us_plan.txt")), 2},        {readText(file("three_needles", "surgeon.txt")), 3},
      {readText(kApp + "state_table.txt"), 4}};
  const std::string alphabet = "0123456789.,=-+e# \nabcxyz_";
  int failed = 0;
  for (int i = 0; i < 2000; ++i) {
    auto [text, kind] = files[static_cast<std::size_t>(i) % files.size()];
    for (int edits = 1 + static_cast<int>(rng() % 4); edits > 0 && !text.empty(); --edits) {
      const std::size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0: text[at] = alphabet[rng() % alphabet.size()]; break;
        case 1: text.erase(at, 1 + rng() % 3); break;
        default: text.insert(at, text.substr(at, 1 + rng() % 8)); break;
      }
    }
    try {
      switch (kind) {
        case 0: parsePreoperative(text, "mutant"); break;
        case 1: parseCryoPlan(text, "mutant"); break;
        case 2: parseProbePlan(text, "mutant"); break;
        case 3: parseSurgeonScript(text, "mutant"); break;
        default: parseStateTable(text, "mutant"); break;
      }
    } catch (const std::invalid_argument& e) {
      ++failed;
      ASSERT_EQ(std::string(e.what()).rfind("mutant", 0), 0u) << e.what();
    }
  }
  EXPECT_GT(failed, 200);  // the mutations do reach the error paths
}

}  // namespace
}  // namespace cobra::puncturing
