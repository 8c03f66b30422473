// PatientSimulator through the components on the lockstep clock: a needle driven by the
// simulated I-SUR into the phantom, the wrench fed back to the robot's sensor, the monitor's events.
#include "cobra/components/sim/patient_simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "cobra/test_support/test_support.hpp"
#include "puncturing_world.hpp"

namespace cobra::components::test {
namespace {

constexpr double kSpeed = 0.005;  // m/s, insertion speed

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = ::cobra::test_support::scratchPath(name).string();
  std::ofstream(path) << text;
  return path;
}

// Skin over one thick fat layer with a friction large enough to read; tumour and regions far away.
std::string thickFatScenario() {
  return writeFile("cobra_sim_thick_fat.txt",
                   "layer skin thickness=0.002 puncture_force=1.5 k1=500 k2=3e5 cutting_force=0.4\n"
                   "layer fat thickness=0.1 puncture_force=0.4 cutting_force=0.1 coulomb_friction=20 "
                   "viscous_friction=0\n"
                   "tumour center=0,0,-0.5 radius=0.01\n");
}

std::vector<std::string> only(const std::vector<std::string>& events, std::initializer_list<const char*> names) {
  std::vector<std::string> out;
  for (const std::string& e : events)
    if (std::find(names.begin(), names.end(), e) != names.end()) out.push_back(e);
  return out;
}

TEST(PatientSimulator, InsertionShowsThePuncturePeakThenFrictionGrowingWithDepth) {
  PuncturingWorld world(1, thickFatScenario());
  ASSERT_EQ(world.start(), "");
  std::vector<double> depth_at, axial_at;
  std::vector<std::string> events;
  double depth_at_penetrated = NAN, depth_at_touched = NAN;
  for (int ms = 0; ms <= 8000; ++ms) {
    world.step(kSpeed * ms * 1e-3);
    depth_at.push_back(world.read(world.depth));
    axial_at.push_back(world.read(world.axial));
    for (const std::string& e : world.takeEvents()) {
      if (e == "e_skin_touched") depth_at_touched = depth_at.back();
      if (e == "e_skin_penetrated") depth_at_penetrated = depth_at.back();
      events.push_back(e);
    }
  }
  // The skin: a peak at its puncture force, then a drop when it ruptures (1.55 mm deep).
  std::size_t peak = 0;
  for (std::size_t i = 0; i < depth_at.size() && depth_at[i] < 0.002; ++i)
    if (axial_at[i] > axial_at[peak]) peak = i;
  EXPECT_GT(axial_at[peak], 1.3);
  EXPECT_LE(axial_at[peak], 1.5);
  EXPECT_NEAR(depth_at[peak], 0.00155, 0.0002);
  EXPECT_LT(axial_at[peak + 1], 0.7 * axial_at[peak]);
  // In the fat: cutting plus a friction of 20 N/m times the inserted length, growing with depth.
  auto axialAtDepth = [&](double d) -> double {
    for (std::size_t i = 0; i < depth_at.size(); ++i)
      if (depth_at[i] >= d) return axial_at[i];
    return NAN;
  };
  double previous = axialAtDepth(0.006);
  for (double d = 0.008; d <= 0.030; d += 0.002) {
    EXPECT_GT(axialAtDepth(d), previous) << "depth " << d;
    previous = axialAtDepth(d);
  }
  EXPECT_NEAR(axialAtDepth(0.030) - axialAtDepth(0.010), 20.0 * 0.020, 0.05);
  // The monitor saw the same thing through the robot's force sensor, in this order.
  EXPECT_EQ(only(events, {"e_skin_touched", "e_skin_penetrated"}),
            (std::vector<std::string>{"e_skin_touched", "e_skin_penetrated"}));
  EXPECT_GT(depth_at_touched, 0.0);
  EXPECT_LT(depth_at_touched, 0.0005);
  EXPECT_NEAR(depth_at_penetrated, 0.00155, 0.0003);
}

TEST(PatientSimulator, ATrappedNeedleResistsExtractionUntilThawed) {
  PuncturingWorld world(1, thickFatScenario());
  world.patient.setProperty("freeze_time_constant", 0.5);
  world.patient.setProperty("thaw_time_constant", 0.3);
  ASSERT_EQ(world.start(), "");
  double advance = 0.0;
  for (int ms = 0; ms < 4000; ++ms) world.step(advance = kSpeed * ms * 1e-3);  // 20 mm, then hold
  for (int ms = 0; ms < 200; ++ms) world.step(advance);
  world.patient.call<void>("startFreeze");
  for (int ms = 0; ms < 1000; ++ms) world.step(advance);
  (void)world.takeEvents();
  for (int ms = 0; ms < 300; ++ms) world.step(advance -= 0.00001);  // pull back 3 mm at 10 mm/s
  double weakest_hold = INFINITY;
  for (int ms = 0; ms < 1000; ++ms) {
    world.step(advance);
    weakest_hold = std::min(weakest_hold, -world.read(world.axial));
  }
  EXPECT_GT(weakest_hold, 10.0);  // the iceball pulls back with more than the monitor's threshold
  std::vector<std::string> events = world.takeEvents();
  EXPECT_EQ(only(events, {"e_needle_trapped", "e_needle_free"}), (std::vector<std::string>{"e_needle_trapped"}));

  world.patient.call<void>("startThaw");
  for (int ms = 0; ms < 1500; ++ms) world.step(advance);
  events = world.takeEvents();
  EXPECT_EQ(only(events, {"e_needle_trapped", "e_needle_free"}), (std::vector<std::string>{"e_needle_free"}));
  EXPECT_GT(world.read(world.axial), -1.0);  // thawed: held still, no friction left
}

TEST(PatientSimulator, AFreezeDurationThawsByItself) {
  PuncturingWorld world(1, thickFatScenario());
  world.patient.setProperty("freeze_time_constant", 0.5);
  world.patient.setProperty("thaw_time_constant", 0.3);
  world.patient.setProperty("freeze_duration", 1.0);
  core::InputPort<double> radius{"radius", "", "m"};
  core::connectPorts(world.patient.port("iceballRadius"), radius);
  ASSERT_EQ(world.start(), "");
  for (int ms = 0; ms < 2000; ++ms) world.step(kSpeed * ms * 1e-3);
  world.patient.call<void>("startFreeze");
  for (int ms = 0; ms < 1000; ++ms) world.step(0.01);
  const double frozen = world.read(radius);
  EXPECT_GT(frozen, 0.012);
  for (int ms = 0; ms < 2000; ++ms) world.step(0.01);
  EXPECT_LT(world.read(radius), 0.002);
}

TEST(PatientSimulator, TheTumourAndTheLayerDepthsAreReadOnlyPropertiesSetAtConfigure) {
  PatientSimulator patient("patient");
  // A file of its own: tests run in parallel processes, and thickFatScenario() rewrites its file.
  patient.setProperty("scenario_file", writeFile("cobra_sim_layer_depths.txt",
                                                 "layer skin thickness=0.002\nlayer fat thickness=0.1\n"
                                                 "tumour center=0,0,-0.5 radius=0.01\n"));
  const KDL::Frame pose(KDL::Rotation::RotX(0.2), KDL::Vector(0.1, -0.2, 0.3));
  patient.setProperty("phantom_pose", pose);
  ASSERT_TRUE(patient.configure());
  const std::vector<double> tumour = patient.getProperty<std::vector<double>>("tumour");
  ASSERT_EQ(tumour.size(), 4u);
  const KDL::Vector centre = pose * KDL::Vector(0, 0, -0.5);  // the file's centre, frame P
  EXPECT_NEAR((KDL::Vector(tumour[0], tumour[1], tumour[2]) - centre).Norm(), 0.0, 1e-12);
  EXPECT_EQ(tumour[3], 0.01);
  EXPECT_EQ(patient.getProperty<std::vector<double>>("layer_depths"), (std::vector<double>{0.0, 0.002, 0.002, 0.002 + 0.1}));
  EXPECT_CONTAINS(test_support::messageOf([&] { patient.setProperty("tumour", std::vector<double>{0, 0, 0, 1}); }),
                  "read-only");
}

TEST(PatientSimulator, BadScenarioFilesAreRefusedNamingTheFileAndLine) {
  PatientSimulator missing("patient");
  missing.setProperty("scenario_file", std::string("/nonexistent/abdomen.txt"));
  core::Result r = missing.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "component 'patient'");
  EXPECT_CONTAINS(r.message, "scenario_file");
  EXPECT_CONTAINS(r.message, "/nonexistent/abdomen.txt");

  const std::string path = writeFile("cobra_sim_bad.txt", "layer skin thickness=0.002\nlayer fat thickness=-1\n");
  PatientSimulator bad("patient");
  bad.setProperty("scenario_file", path);
  r = bad.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, path + ":2:");
  EXPECT_CONTAINS(r.message, "thickness");

  PatientSimulator negative("patient");
  negative.setProperty("freeze_duration", -1.0);
  r = negative.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "freeze_duration");
}

}  // namespace
}  // namespace cobra::components::test
