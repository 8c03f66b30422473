// PatientSimulator through the components on the lockstep clock: a needle driven by the
// simulated I-SUR into the phantom, the wrench fed back to the robot's sensor, the monitor's events;
// the ultrasound image port: the tumour where the probe sees it, the image's rate and bands, no
// allocation.
#include "cobra/components/sim/patient_simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <memory>

#include "cobra/kinematics/frame_product.hpp"
#include "cobra/sim/ultrasound_image.hpp"
#include "cobra/test_support/counting_new.hpp"
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

// The image's set-up, as sim/test/ultrasound_image_test.cpp has it: the two_needles phantom (tumour
// of 12 mm at (0, 0, -0.06) in P), the probe on the skin 35 mm aside looking at the tumour's
// centre with its array along -x, the scenario's first needle (entry to target, crossing the
// plane). The phantom is placed off the world's axes, so that the image's pose is mapped.
struct ImagingPatient {
  const std::string scenario = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/scenarios/two_needles/phantom.txt";
  const KDL::Frame phantom{KDL::Rotation::RPY(0.1, -0.2, 0.3), KDL::Vector(0.3, -0.1, 0.1)};  // W_T_P
  core::LockstepClock clock;
  PatientSimulator patient{"patient"};
  core::OutputPort<KDL::Frame> probe_pose{"probePose", "", "m"};
  core::OutputPort<KDL::Frame> tip_pose{"tipPose", "", "m"};
  core::InputPort<types::GrayImage> image{"image", "", "m"};
  std::unique_ptr<types::GrayImage> got = std::make_unique<types::GrayImage>();

  ImagingPatient() {
    patient.setProperty("scenario_file", scenario);
    patient.setProperty("phantom_pose", phantom);
    patient.setProperty("tip_to_needle", KDL::Frame::Identity());
    clock.add(patient, 1ms);
    core::connectPorts(probe_pose, patient.port("probePose"));
    core::connectPorts(tip_pose, patient.port("needleTipPose"));
    core::connectPorts(patient.port("usImage"), image);
  }

  /// The probe looking from the skin at `target` (P), its array along `array` (made orthogonal).
  static KDL::Frame probeLookingAt(const KDL::Vector& face, const KDL::Vector& target, const KDL::Vector& array) {
    KDL::Vector z = target - face;
    z.Normalize();
    KDL::Vector x = array - z * KDL::dot(array, z);
    x.Normalize();
    return {KDL::Rotation(x, z * x, z), face};
  }
  KDL::Frame probeInP(double shift = 0.0) const {
    return probeLookingAt({0.035 + shift, 0.0, -0.001}, {shift, 0.0, -0.06}, {-1, 0, 0});
  }
  KDL::Frame tipInP() const { return probeLookingAt({-0.02, -0.006, 0.0}, {-0.005, 0.0, -0.058}, {1, 0, 0}); }

  /// One 1 ms step with the probe and the needle tip at these poses (P, sent in W); true when an
  /// image arrived (then in *got).
  bool step(const KDL::Frame& probe, const KDL::Frame& tip) {
    probe_pose.write(phantom * probe);
    tip_pose.write(phantom * tip);
    clock.advance(1ms);
    return image.readNew(*got) == core::FlowStatus::NewData;
  }

  /// A pose the patient received in W, back in P exactly as the patient maps it.
  KDL::Frame asThePatientSeesIt(const KDL::Frame& in_p) const {
    return kinematics::frameProduct(phantom.Inverse(), phantom * in_p);
  }
};

TEST(PatientSimulator, TheUltrasoundImageShowsTheTumourWhereTheProbeSeesIt) {
  ImagingPatient world;
  ASSERT_TRUE(world.patient.configure());
  ASSERT_TRUE(world.patient.start());
  int steps = 0;
  while (!world.step(world.probeInP(), world.tipInP()) && ++steps < 50) {
  }
  ASSERT_LT(steps, 50) << "no image";
  const types::GrayImage& image = *world.got;
  EXPECT_EQ(image.width, 128u);
  EXPECT_EQ(image.height, 128u);
  EXPECT_EQ(image.spacing_x, 0.0008);
  EXPECT_EQ(image.spacing_y, 0.0008);

  // The imager's own image of these poses, bit for bit; its frame I (pixel (0, 0)'s outer corner)
  // carried from P into W and half a pixel on, to pixel (0, 0)'s centre, as GrayImage places pixels.
  sim::UltrasoundImageModel model;
  const sim::UltrasoundImager imager(model, sim::loadScenario(world.scenario), 1);
  auto expected = std::make_unique<sim::UltrasoundImage>();
  const KDL::Frame probe = world.asThePatientSeesIt(world.probeInP()), tip = world.asThePatientSeesIt(world.tipInP());
  imager.render(probe, &tip, *expected);
  EXPECT_TRUE(std::equal(expected->pixels.begin(), expected->pixels.begin() + 128 * 128, image.pixels.begin()));
  EXPECT_LT((image.pose.p - world.phantom * (expected->pose * KDL::Vector(0.0004, 0.0004, 0.0))).Norm(), 1e-12);
  EXPECT_LT((image.pose.M.UnitX() - world.phantom.M * expected->pose.M.UnitX()).Norm(), 1e-12);
  EXPECT_LT((image.pose.M.UnitY() - world.phantom.M * expected->pose.M.UnitY()).Norm(), 1e-12);

  // The tumour (the patient's `tumour`: centre in W, radius) lies in the image's plane, and the
  // image is dark there: its hypoechoic disc against the tissue round it.
  const std::vector<double> tumour = world.patient.getProperty<std::vector<double>>("tumour");
  const KDL::Vector centre = image.pose.Inverse(KDL::Vector(tumour[0], tumour[1], tumour[2]));  // frame I, m
  EXPECT_NEAR(centre.z(), 0.0, 1e-9);
  const double radius = tumour[3];
  double inside = 0.0, around = 0.0;
  int inside_count = 0, around_count = 0;
  for (std::size_t r = 0; r < image.height; ++r) {
    for (std::size_t c = 0; c < image.width; ++c) {
      const double distance = std::hypot(static_cast<double>(c) * image.spacing_x - centre.x(),
                                          static_cast<double>(r) * image.spacing_y - centre.y());
      if (distance < 0.7 * radius) {
        inside += image.at(c, r);
        ++inside_count;
      } else if (distance > radius + 0.002 && distance < radius + 0.008 && image.at(c, r) > 0) {
        around += image.at(c, r);  // the tissue round the tumour within the field of view
        ++around_count;
      }
    }
  }
  ASSERT_GT(inside_count, 100);
  ASSERT_GT(around_count, 100);
  EXPECT_LT(inside / inside_count, 0.5 * around / around_count);
}

TEST(PatientSimulator, TheUltrasoundImageComesAtItsRateOfThePosesItsBandsStartedAt) {
  ImagingPatient world;
  world.patient.setProperty("image_rate", 10.0);  // Hz: every 100 updates at 1 kHz
  ASSERT_TRUE(world.patient.configure());
  ASSERT_TRUE(world.patient.start());
  std::vector<int> published;
  std::vector<KDL::Frame> sent;  // the probe of each step (P)
  for (int ms = 0; ms < 1000; ++ms) {
    sent.push_back(world.probeInP(1e-5 * ms));  // sliding 10 mm/s along x
    if (!world.step(sent.back(), world.tipInP())) continue;
    published.push_back(ms);
    // 1024 px per update of a 128-row image: 8 columns, 16 updates; the image is of the probe at
    // the first of them, carried into W: pixel (0, 0)'s centre 63.5 px to the array's -x side of
    // the probe's face and half a pixel deep.
    const KDL::Frame first = world.asThePatientSeesIt(sent[static_cast<std::size_t>(ms - 15)]);
    const KDL::Vector corner_centre = first.p - first.M.UnitX() * (63.5 * 0.0008) + first.M.UnitZ() * 0.0004;
    EXPECT_LT((world.got->pose.p - world.phantom * corner_centre).Norm(), 1e-12) << "image at step " << ms;
  }
  EXPECT_EQ(published, (std::vector<int>{15, 115, 215, 315, 415, 515, 615, 715, 815, 915}));

  // Turned off and on again while running (a configuration's property values), at another rate.
  world.patient.setProperty("image_rate", 0.0);
  published.clear();
  for (int ms = 1000; ms < 1300; ++ms)
    if (world.step(world.probeInP(), world.tipInP())) published.push_back(ms);
  EXPECT_EQ(published, std::vector<int>{});
  world.patient.setProperty("image_rate", 20.0);
  for (int ms = 1300; ms < 1500; ++ms)
    if (world.step(world.probeInP(), world.tipInP())) published.push_back(ms);
  EXPECT_EQ(published, (std::vector<int>{1315, 1365, 1415, 1465}));

  // The whole image in one update (0), another rate, none at 0 Hz.
  for (const auto& [rate, pixels, expected] :
       std::vector<std::tuple<double, int, std::vector<int>>>{{25.0, 0, {0, 40, 80, 120, 160}},
                                                              {25.0, 8192, {1, 41, 81, 121, 161}},
                                                              {0.0, 1024, {}}}) {
    ImagingPatient other;
    other.patient.setProperty("image_rate", rate);
    other.patient.setProperty("image_pixels_per_step", pixels);
    ASSERT_TRUE(other.patient.configure());
    ASSERT_TRUE(other.patient.start());
    std::vector<int> at;
    for (int ms = 0; ms < 200; ++ms)
      if (other.step(other.probeInP(), other.tipInP())) at.push_back(ms);
    EXPECT_EQ(at, expected) << rate << " Hz, " << pixels << " px per update";
  }
}

TEST(PatientSimulator, NoUltrasoundImageIsRenderedWhileNobodyReadsIt) {
  ImagingPatient world;
  world.image.disconnect();
  ASSERT_TRUE(world.patient.configure());
  ASSERT_TRUE(world.patient.start());
  for (int ms = 0; ms < 1030; ++ms) world.step(world.probeInP(), world.tipInP());
  // Connected at 1030 ms: had the images gone on unread every 100 ms since the first probe pose
  // (0 ms), the next would start at 1100 ms; none was being rendered, so the first starts now.
  core::connectPorts(world.patient.port("usImage"), world.image);
  std::vector<int> at;
  for (int ms = 1030; ms < 1200; ++ms)
    if (world.step(world.probeInP(), world.tipInP())) at.push_back(ms);
  EXPECT_EQ(at, (std::vector<int>{1045, 1145}));
}

TEST(PatientSimulator, TheUltrasoundImagesSizeIsItsPropertiesAndARateItsBandsCannotKeepIsRefused) {
  ImagingPatient world;
  world.patient.setProperty("image_width", 64);
  world.patient.setProperty("image_height", 200);
  world.patient.setProperty("image_spacing", 0.0005);
  ASSERT_TRUE(world.patient.configure());
  ASSERT_TRUE(world.patient.start());
  std::vector<int> at;
  for (int ms = 0; ms < 120; ++ms)
    if (world.step(world.probeInP(), world.tipInP())) at.push_back(ms);
  EXPECT_EQ(at, (std::vector<int>{12, 112}));  // 1024 / 200 = 5 columns per update: 13 updates
  EXPECT_EQ(world.got->width, 64u);
  EXPECT_EQ(world.got->height, 200u);
  EXPECT_EQ(world.got->spacing_x, 0.0005);

  EXPECT_EQ(test_support::messageOf([&] { world.patient.setProperty("image_width", 300); }),
            "component 'patient': property 'image_width' = 300 is out of range [1, 256] (px)");
  EXPECT_EQ(test_support::messageOf([&] { world.patient.setProperty("image_rate", -1.0); }),
            "component 'patient': property 'image_rate' = -1 is out of range [0, 1000] (Hz)");
  ImagingPatient fast;
  fast.patient.setProperty("image_rate", 100.0);  // 10 ms apart; 128 x 128 in bands of 1024 px takes 16 ms
  core::Result r = fast.patient.configure();
  EXPECT_FALSE(r);
  EXPECT_EQ(r.message,
            "component 'patient': property image_rate is 100 Hz, but an image of 128 x 128 px takes 16 updates of 0.001 "
            "s (image_pixels_per_step = 1024 px); expected image_rate <= 62.5 Hz, or more image_pixels_per_step");
  fast.patient.setProperty("image_pixels_per_step", 2048);
  EXPECT_TRUE(fast.patient.configure());
}

TEST(PatientSimulator, TheUltrasoundImagesUpdatesAllocateNothing) {
  ImagingPatient world;
  world.patient.setProperty("image_rate", 50.0);
  ASSERT_TRUE(world.patient.configure());
  ASSERT_TRUE(world.patient.start());
  for (int ms = 0; ms < 100; ++ms) world.step(world.probeInP(), world.tipInP());  // every port has carried data
  int images = 0;
  EXPECT_EQ(test_support::allocationsDuring([&] {
              for (int ms = 0; ms < 200; ++ms) images += world.step(world.probeInP(1e-5 * ms), world.tipInP()) ? 1 : 0;
            }),
            0);
  EXPECT_EQ(images, 10);
}

}  // namespace
}  // namespace cobra::components::test
