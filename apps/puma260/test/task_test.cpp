// The Puma 260 task (thesis §6.3-6.4) end to end through the runner's API, as `cobra run
// apps/puma260` runs it: the MuJoCo world (world/puma260.xml) with the surface across the nominal
// path, the controller of Fig. 6.5 with its one configuration, the chart A-H. Both kinematics
// solvers (scenarios/closed_form, scenarios/kdl: one line apart). What the run's own data must show:
//  - phases A-H in order, E-G from the contact monitor's events (force and distance, not time);
//  - while in contact the tool stays on the surface: penetration below kMaxPenetration (the
//    surface's stiffness against the largest force), contact force at most the configured limit;
//  - the compliance the admittance predicts: with stiffness K along z and a surface much stiffer
//    than K, the tool rides on the surface, so its deviation from the nominal path is the surface's
//    height h(y) above the path, and the force is K·h(y) up to the damping's share D·ḣ (the
//    surface rises under the moving tool at v·|dh/dy|) and the sensor's noise;
//  - after the surface, the tool back on the nominal path within 1 mm; the tank above its minimum.

#include <gtest/gtest.h>

#include "puma260_task_expectations.hpp"

namespace cobra::run::puma260 {
namespace {

TEST(Puma260Task, TheClosedFormVariantPassesAToHRidingOnTheSurfaceAsTheAdmittancePredicts) {
  const RunOptions o = options("closed_form", "closed_form");
  const RunResult r = runApp(o);
  expectTheTask(r, o);
  // Fig. 6.7 in the report: the two paths and the letters of the phases.
  std::ifstream html(r.report);
  const std::string page((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  EXPECT_NE(page.find("Fig. 6.7: nominal and actual tool path in the y-z plane"), std::string::npos);
  for (const char* letter : {"A", "B", "C", "D", "E", "F", "G", "H"})
    EXPECT_NE(page.find(std::string("font-weight='bold' fill='#D55E00'>") + letter + "</text>"), std::string::npos)
        << letter;
}

// The same task with KDL's solver: scenarios/kdl/scenario.lua differs from closed_form's in its one
// line `kinematics_solver = ...` (thesis §6.2.4: the two solvers are interchangeable).
TEST(Puma260Task, TheKdlVariantPassesTheSameChecks) {
  const auto code = [](const char* scenario) {
    std::ifstream in(kApp / "scenarios" / scenario / "scenario.lua");
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);)
      if (line.rfind("--", 0) != 0 && !line.empty()) lines.push_back(line);
    return lines;
  };
  ASSERT_EQ(code("closed_form"), std::vector<std::string>{"kinematics_solver = \"closed_form\""});
  ASSERT_EQ(code("kdl"), std::vector<std::string>{"kinematics_solver = \"kdl_nr\""});
  const RunOptions o = options("kdl", "kdl");
  expectTheTask(runApp(o), o);
}

}  // namespace
}  // namespace cobra::run::puma260
