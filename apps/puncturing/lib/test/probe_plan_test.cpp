// The probe plan in C++: the same poses as the us_plan.txt files shipped with the scenarios (written
// by tools/probe_plan.py; the vertical needles' by hand, as its header says) and as the script
// itself on seeded random cryo plans; refusals name the cryo plan's file and line.
#include "cobra/puncturing/probe_plan.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "cobra/test_support/test_support.hpp"

namespace cobra::puncturing {
namespace {

using cobra::test_support::messageOf;

const std::string kApp = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/";

/// Expects the same probe poses: names, lines, positions within 1e-6 m, orientations within 1e-6 rad.
void expectSamePlan(const std::vector<PlannedProbe>& computed, const std::vector<PlannedProbe>& expected,
                    const std::string& what) {
  ASSERT_EQ(computed.size(), expected.size()) << what;
  for (std::size_t i = 0; i < computed.size(); ++i) {
    EXPECT_EQ(computed[i].needle, expected[i].needle) << what;
    EXPECT_LT((computed[i].pose.p - expected[i].pose.p).Norm(), 1e-6) << what << " probe " << expected[i].needle;
    // The angle of the rotation between the two orientations.
    EXPECT_LT(KDL::diff(computed[i].pose.M, expected[i].pose.M).Norm(), 1e-6) << what << " probe " << expected[i].needle;
  }
}

TEST(ProbePlan, EqualsTheShippedProbePlansOfTheThreeScenarios) {
  for (const std::string scenario : {"two_needles", "three_needles", "vertical_needle"}) {
    const std::string dir = kApp + "scenarios/" + scenario + "/";
    const PreoperativeInfo info = parsePreoperative(readText(dir + "preoperative.txt"), dir + "preoperative.txt");
    const std::vector<PlannedNeedle> needles = parseCryoPlan(readText(dir + "cryo_plan.txt"), dir + "cryo_plan.txt");
    const std::vector<PlannedProbe> shipped = parseProbePlan(readText(dir + "us_plan.txt"), dir + "us_plan.txt");
    const std::vector<PlannedProbe> computed = probePlan(needles, info, dir + "cryo_plan.txt");
    expectSamePlan(computed, shipped, scenario);
    for (std::size_t i = 0; i < computed.size(); ++i) EXPECT_EQ(computed[i].line, needles[i].line) << scenario;
  }
}

TEST(ProbePlan, TheImagingPlaneContainsTheNeedleAndTheBeamHitsItsTarget) {
  const PlannedNeedle needle{"n", KDL::Vector(0.01, -0.02, 0.0), KDL::Vector(-0.004, 0.003, -0.055), 0.4, 7};
  const KDL::Frame probe = probePose(needle);
  EXPECT_NEAR(probe.p.z(), 0.0, 1e-15) << "the face on the skin";
  for (const KDL::Vector& point : {needle.entry, needle.target}) {
    EXPECT_NEAR(KDL::dot(probe.M.UnitY(), point - probe.p), 0.0, 1e-12);
  }
  const KDL::Vector to_target = probe.M.Inverse(needle.target - probe.p);
  EXPECT_NEAR(to_target.x(), 0.0, 1e-12);
  EXPECT_GT(to_target.z(), 0.0) << "the beam points at the target";
  // Seen from above, the face lies 45 mm beyond the tip, on the needle's line.
  const KDL::Vector lean(needle.target.x() - needle.entry.x(), needle.target.y() - needle.entry.y(), 0.0);
  const KDL::Vector beyond(probe.p.x() - needle.target.x(), probe.p.y() - needle.target.y(), 0.0);
  EXPECT_NEAR(beyond.Norm(), kProbeBeyondTip, 1e-12);
  EXPECT_NEAR((lean * beyond).Norm(), 0.0, 1e-15);
  EXPECT_GT(KDL::dot(lean, beyond), 0.0);
  // The array points away from the needle: the needle's entry is at negative x in the image.
  EXPECT_LT(probe.M.Inverse(needle.entry - probe.p).x(), 0.0);
}

TEST(ProbePlan, RefusesWithTheCryoPlansFileAndLine) {
  PreoperativeInfo info;
  // A shallow tumour: the probe 45 mm aside looks at it 66 deg from the vertical.
  info.tumour_center = KDL::Vector(0.0, 0.0, -0.02);
  info.tumour_radius = 0.005;
  info.entry_radius = 0.05;
  const std::vector<PlannedNeedle> shallow{{"n1", KDL::Vector(-0.01, 0.0, 0.0), KDL::Vector(0.0, 0.0, -0.02), 0.0, 4}};
  EXPECT_EQ(messageOf([&] { probePlan(shallow, info, "cryo_plan.txt"); }),
            "cryo_plan.txt:4: probe for 'n1': beam tilted 66.0 deg from the vertical, expected into the body within 60 deg");
  const std::vector<PlannedNeedle> missing{{"n2", KDL::Vector(-0.01, 0.0, 0.0), KDL::Vector(0.0, 0.0, -0.03), 0.0, 9}};
  EXPECT_EQ(messageOf([&] { probePlan(missing, info, "cryo_plan.txt"); }),
            "cryo_plan.txt:9: needle 'n2': target is 10.0 mm from the tumour centre, outside its radius 5.0 mm");
}

/// Needles with seeded random entries in the entry disc and targets in the tumour of the
/// two_needles scenario, each kept when probePlan accepts it (a valid cryo plan whose probe sees it).
std::vector<PlannedNeedle> randomNeedles(const PreoperativeInfo& info, std::uint64_t seed, std::size_t count) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<PlannedNeedle> needles;
  for (int attempt = 0; needles.size() < count && attempt < 10000; ++attempt) {
    PlannedNeedle n;
    n.name = "r" + std::to_string(needles.size() + 1);
    n.line = static_cast<int>(needles.size()) + 1;
    n.entry = info.entry_center + KDL::Vector(unit(random), unit(random), 0.0) * info.entry_radius;
    n.target = info.tumour_center + KDL::Vector(unit(random), unit(random), unit(random)) * (0.55 * info.tumour_radius);
    n.roll = unit(random);
    if (messageOf([&] { probePlan({n}, info); }) == "(no error)") needles.push_back(n);
  }
  return needles;
}

// Three seeds, six needles each (18 needles): the cryo plan printed, the script run on it, its
// us_plan.txt parsed and compared with probePlan on the same printed plan.
TEST(ProbePlan, EqualsTheScriptOnSeededRandomCryoPlans) {
  if (std::system("command -v python3 > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3 is not installed: the cross-check against tools/probe_plan.py is skipped";
  }
  const std::string dir = kApp + "scenarios/two_needles/";
  const PreoperativeInfo info = parsePreoperative(readText(dir + "preoperative.txt"), dir + "preoperative.txt");
  const std::filesystem::path work = std::filesystem::temp_directory_path() / ("cobra_probe_plan_" + std::to_string(::getpid()));
  std::filesystem::create_directories(work);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const std::vector<PlannedNeedle> needles = randomNeedles(info, seed, 6);
    ASSERT_EQ(needles.size(), 6u) << "seed " << seed;
    const std::filesystem::path cryo = work / "cryo_plan.txt", us = work / "us_plan.txt";
    std::ofstream(cryo) << printCryoPlan(needles);
    const std::string command = "python3 " + kApp + "tools/probe_plan.py " + cryo.string() + " > " + us.string();
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const std::vector<PlannedNeedle> parsed = parseCryoPlan(readText(cryo.string()), cryo.string());
    expectSamePlan(probePlan(parsed, info, cryo.string()), parseProbePlan(readText(us.string()), us.string()),
                   "seed " + std::to_string(seed));
  }
  std::filesystem::remove_all(work);
}

}  // namespace
}  // namespace cobra::puncturing
