// The puncturing task's take-over through the two-layer coupling (thesis §4.5.4 in the
// deployments of §4.6), end to end in simulation (the runner's API, lockstep clock): the needle
// near a forbidden region in the tissue, the surgeon takes it over with the Phantom Omni or the
// Leap Motion, without and with an impaired link (100 ms delay, 10 % loss), pushes it 2 mm
// deeper and turns it 10 degrees, and gives it back; the probe likewise on the skin. Asserted on
// the recorded signals: nothing jumps at the switches, the master feels the contact's force on
// the tool, the tool follows the master's motion and turn, the coupling's tanks stay above their
// minimum, the clearance and the autonomous tracking hold; and the procedure goes on to the end.
// Also the configuration errors of a master the coupling cannot use.

#include <gtest/gtest.h>

#include "procedure_expectations.hpp"

#include <kdl/frames.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace cobra::run::testing {
namespace {

/// A run folder's signals.csv: the column of each recorded name ("NeedleAdmittance.admPose.x"),
/// and the rows (NaN: no data yet).
struct Recording {
  std::map<std::string, std::size_t> columns;
  std::vector<std::vector<double>> rows;

  explicit Recording(const std::filesystem::path& folder) {
    std::ifstream in(folder / "signals.csv");
    std::string line, cell;
    std::getline(in, line);
    std::istringstream header(line);
    for (std::size_t i = 0; std::getline(header, cell, ','); ++i) {
      if (!cell.empty() && cell.front() == '"') cell = cell.substr(1);
      columns[cell.substr(0, cell.find(" ["))] = i;
    }
    while (std::getline(in, line)) {
      std::vector<double>& row = rows.emplace_back();
      std::istringstream values(line);
      while (std::getline(values, cell, ','))
        row.push_back(cell.empty() ? std::numeric_limits<double>::quiet_NaN() : std::stod(cell));
      row.resize(columns.size(), std::numeric_limits<double>::quiet_NaN());
    }
  }
  std::size_t column(const std::string& name) const {
    const auto it = columns.find(name);
    if (it == columns.end()) ADD_FAILURE() << "no recorded column " << name;
    return it == columns.end() ? 0 : it->second;
  }
  /// The row recorded at or just after `time` (s).
  const std::vector<double>& at(double time) const {
    for (const auto& row : rows)
      if (row[0] >= time - 1e-9) return row;
    return rows.back();
  }
  KDL::Vector position(const std::vector<double>& row, const std::string& frame) const {
    const std::size_t x = column(frame + ".x");
    return {row[x], row[x + 1], row[x + 2]};
  }
  KDL::Rotation orientation(const std::vector<double>& row, const std::string& frame) const {
    const std::size_t q = column(frame + ".qx");
    return KDL::Rotation::Quaternion(row[q], row[q + 1], row[q + 2], row[q + 3]);
  }
  KDL::Vector force(const std::vector<double>& row, const std::string& wrench) const {
    const std::size_t f = column(wrench + ".fx");
    return {row[f], row[f + 1], row[f + 2]};
  }
};

/// Time (s) of the first event `event` from `source`, NaN when there is none.
double timeOf(const RunResult& r, const std::string& source, const std::string& event) {
  for (const report::EventRecord& e : r.events)
    if (e.source == source && e.event.rfind(event, 0) == 0) return e.time;
  return std::nan("");
}

struct Figures {
  double force_along_contact = 0.0;  // N: the master's force along the contact's force on the tool, mean
  double contact_force = 0.0;        // N: the contact's force on the tool meanwhile, mean magnitude
  double follow_error = 0.0;         // m: the tool's motion minus the master's (mapped) motion
  double master_motion = 0.0;       // m
  double lowest_tank = 1e9;         // J: either coupling tank, over the teleoperation
  double switch_step = 0.0;         // m: the commanded pose's largest change across a switch
  double switch_turn = 0.0;         // rad
  double orientation_error = 0.0;   // rad: the tool's against the master's (mapped), turned and settled
  double master_turn = 0.0;         // rad: the master's turn since the engagement, then
};

/// The robot a take-over takes: its controller's prefix, its chart's log lines, its measured
/// pose and the contact wrench on its tool (world axes).
struct Robot {
  const char* prefix;        // "Needle", "Probe"
  const char* faults;        // test/faults/take_over_<faults>_<device>.lua
  const char* surgeon;       // test/faults/<surgeon>.txt
  const char* measured;      // the tool's measured pose port
  const char* contact;       // the contact's wrench on the tool
  std::size_t tracked;       // its index in run.tracking
  std::vector<std::string> log;  // the take-over's lines, in order
};

const Robot kNeedleRobot{
    "Needle", "needle", "take_over_surgeon", "ISUR.measCartPose", "Patient.needleWrench", kNeedle,
    {"needle > root.InsertingNeedles.MoveToTumor", "NeedleMonitor: e_forbidden_region", "needle > root.WaitReaction",
     "Surgeon: e_take_over", "needle > root.NeedleTeleoperation.InitHapticDevice",
     "needle deployment > needle_teleoperated", "needle > root.NeedleTeleoperation.TeleoperationActive",
     "Surgeon: e_teleop_done", "needle > root.InsertingNeedles.MoveToTumor", "NeedleMonitor: e_target_reached",
     "needle > root.WaitCryoCycle"}};
const Robot kProbeRobot{
    "Probe", "probe", "take_over_probe_surgeon", "UR5.measCartPose", "Patient.probeWrench", kProbe,
    {"us > root.USPositioned.NeedleTracked", "USMonitor: e_probe_contact_lost", "us > root.WaitReaction",
     "Surgeon: e_take_over", "us > root.USTeleoperation.InitHapticDevice", "probe deployment > probe_teleoperated",
     "us > root.USTeleoperation.TeleoperationActive", "Surgeon: e_teleop_done", "us > root.USPositioned.NeedleTracked"}};

/// The take-over of `robot` (take_over_<robot.faults>_<device>.lua), with `link` the Lua table of
/// the coupling's link impairment ("" = none).
Figures takeOver(const Robot& robot, const std::string& device, const std::string& link) {
  const std::string P = robot.prefix;
  RunOptions o = options("two_needles");
  o.faults_file = kFaults / ("take_over_" + std::string(robot.faults) + "_" + device + ".lua");
  o.before_lua = "surgeon_file = [[" + (kFaults / (std::string(robot.surgeon) + ".txt")).string() +
                 "]]\nteleop_device = '" + device + "'";
  if (!link.empty()) o.before_lua += "\nteleop_link = " + link;
  // Recorded beside the application's ports: the master's motion mapped onto the tool (the
  // clutch's output), the force the master feels (the Omni: what its side's Passivity layer
  // renders; the Leap renders none: the master's wrench as it arrives over the link, what a
  // haptic device would be given), the two sides' tanks, the contact's force on the tool, the
  // tool's pose. (Last: a port without data yet is one empty cell, whatever its width.)
  const std::string felt_port = device == "leap" ? P + "Link.linkedSlaveWrench" : P + "MasterPassivity.force";
  o.extra_lua = "for _, p in ipairs({ '" + std::string(robot.contact) + "', '" + P + "MasterPassivity.tankEnergy', '" +
                P + "SlavePassivity.tankEnergy', '" + felt_port + "', '" + P + "Clutch.desPose', '" + P +
                "Admittance.admPose', '" + robot.measured + "' }) do run.record.ports[#run.record.ports + 1] = p end";
  o.report_folder = std::filesystem::temp_directory_path() /
                    ("cobra_puncturing_take_over_" + std::string(robot.faults) + "_" + device +
                     (link.empty() ? "" : "_link") + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(o.report_folder);
  const RunResult r = runApp(o);
  Figures f;
  EXPECT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 2);
  if (::testing::Test::HasFailure()) return f;
  expectInOrder(r, robot.log);
  // The autonomous motions tracked, no IK discontinuity, the clearance above its threshold
  // outside the declared contacts, the whole run long; the robot's command never jumped.
  expectFaithful(r);
  EXPECT_LT(r.tracking[robot.tracked].max_command_step, 1e-3) << "at " << r.tracking[robot.tracked].max_command_step_at;

  const double active = timeOf(r, P + "TaskSup", "e_teleoperation_active");
  const double done = timeOf(r, "Surgeon", "e_teleop_done");
  const double moved = active + 1.0;  // the fault file moves the hand 1 s into the teleoperation
  EXPECT_FALSE(std::isnan(active) || std::isnan(done));
  const Recording s(o.report_folder);
  // The switches: the commanded pose (the tool's admittance) across each, one recorded period
  // (10 ms) either side.
  for (const double t : {active, done}) {
    const auto& before = s.at(t - 0.011);
    const auto& after = s.at(t + 0.011);
    f.switch_step = std::max(f.switch_step, (s.position(after, P + "Admittance.admPose") -
                                             s.position(before, P + "Admittance.admPose")).Norm());
    f.switch_turn = std::max(f.switch_turn, (s.orientation(after, P + "Admittance.admPose") *
                                             s.orientation(before, P + "Admittance.admPose").Inverse()).GetRot().Norm());
  }
  // The contact, felt: from 0.3 s into the teleoperation (the link's delay, the coupling settled)
  // to its end, the force the coupling gives the master along the contact's force on the tool.
  int n = 0;
  for (const auto& row : s.rows) {
    if (row[0] < active + 0.3 || row[0] >= done) continue;
    const KDL::Vector contact = s.force(row, robot.contact), felt = s.force(row, felt_port);
    if (!(contact.Norm() > 0.05)) continue;  // N: no contact force to feel (NaN: none recorded yet)
    f.force_along_contact += KDL::dot(felt, contact / contact.Norm());
    f.contact_force += contact.Norm();
    ++n;
  }
  EXPECT_GT(n, 20);
  if (n > 0) {
    f.force_along_contact /= n;
    f.contact_force /= n;
  }
  for (const auto& row : s.rows) {
    if (row[0] < active || row[0] > done) continue;
    f.lowest_tank = std::min({f.lowest_tank, row[s.column(P + "MasterPassivity.tankEnergy")],
                              row[s.column(P + "SlavePassivity.tankEnergy")]});
  }
  // The master's motion (mapped onto the tool by the clutch) from just before the hand moved to
  // 2.9 s into the teleoperation (drawn back, turned, settled: the rest length gone 2 s after the
  // engagement), against the tool's measured motion; the orientations then.
  const auto& start = s.at(moved - 0.02);
  const auto& end = s.at(active + 2.9);
  const KDL::Vector master_motion = s.position(end, P + "Clutch.desPose") - s.position(start, P + "Clutch.desPose");
  const KDL::Vector needle_motion = s.position(end, robot.measured) - s.position(start, robot.measured);
  f.master_motion = master_motion.Norm();
  f.follow_error = (needle_motion - master_motion).Norm();
  f.master_turn = (s.orientation(end, P + "Clutch.desPose") * s.orientation(start, P + "Clutch.desPose").Inverse())
                      .GetRot()
                      .Norm();
  f.orientation_error =
      (s.orientation(end, P + "Clutch.desPose") * s.orientation(end, robot.measured).Inverse()).GetRot().Norm();
  std::printf("%s, %s%s: master force along the contact's %.2f N (contact %.2f N); master moved %.2f mm, the tool %.2f mm "
              "off that; lowest tank %.2f J; at the switches %.3f mm, %.3f deg; master turned %.2f deg, the tool "
              "%.2f deg off it\n",
              P.c_str(), device.c_str(), link.empty() ? "" : " (impaired link)", f.force_along_contact, f.contact_force,
              1000.0 * f.master_motion, 1000.0 * f.follow_error, f.lowest_tank, 1000.0 * f.switch_step,
              f.switch_turn * 180.0 / M_PI, f.master_turn * 180.0 / M_PI, f.orientation_error * 180.0 / M_PI);
  std::filesystem::remove_all(o.report_folder);
  return f;
}

/// What every take-over must show; `follow` (m): the tool's motion may miss the master's by at
/// most this; `felt` (N): the master's least mean force along the contact's.
void expectCoupled(const Figures& f, double follow, double felt) {
  EXPECT_GT(f.contact_force, 0.2);         // N: the tissue or the skin held the tool while felt
  EXPECT_GT(f.force_along_contact, felt);  // N: the master is pushed the way the contact pushes the tool
  // m: of the hand's 2 mm, what reached the tool's side (the Omni's stylus gives way to the
  // contact's force rendered on the hand: about half of it in the tissue, more against the skin;
  // the Leap's hand does not)
  EXPECT_GT(f.master_motion, 0.0005);
  EXPECT_LT(f.follow_error, follow);
  EXPECT_GT(f.lowest_tank, 1.0);          // J: above the tanks' minimum ε
  EXPECT_LT(f.switch_step, 1e-3);         // m
  EXPECT_LT(f.switch_turn, M_PI / 180.0);
  EXPECT_NEAR(f.master_turn, 10.0 * M_PI / 180.0, 0.5 * M_PI / 180.0);  // the hand's 10 degrees
  EXPECT_LT(f.orientation_error, M_PI / 180.0);                         // followed within 1
}

/// One take-over: the robot, the device, the link ("" = none), and the bounds of expectCoupled.
struct TakeOver {
  const char* name;
  const Robot* robot;
  const char* device;
  const char* link;
  double follow;  // m
  double felt;    // N
};

class PuncturingTeleoperation : public ::testing::TestWithParam<TakeOver> {};

TEST_P(PuncturingTeleoperation, TheMasterFeelsTheContactAndTheToolFollowsItsMotionAndTurn) {
  const TakeOver& t = GetParam();
  expectCoupled(takeOver(*t.robot, t.device, t.link), t.follow, t.felt);
}

// The needle in the tissue with each device, without and with 100 ms one way and 10 % of the
// packets lost each way (the coupling at 300 N/m, controller.lua: the needle gives way to the
// tissue by about 1 mm, 0.3 N / 300 N/m); the probe on the skin with its Omni.
const char* const kImpaired = "{ delay = 0.1, loss = 0.1, seed = 3 }";
INSTANTIATE_TEST_SUITE_P(
    Devices, PuncturingTeleoperation,
    ::testing::Values(TakeOver{"NeedleOmni", &kNeedleRobot, "omni", "", 0.001, 0.2},
                      TakeOver{"NeedleLeapMotion", &kNeedleRobot, "leap", "", 0.001, 0.2},
                      TakeOver{"NeedleOmniOverADelayedLossyLink", &kNeedleRobot, "omni", kImpaired, 0.002, 0.15},
                      TakeOver{"NeedleLeapMotionOverADelayedLossyLink", &kNeedleRobot, "leap", kImpaired, 0.002, 0.15},
                      TakeOver{"ProbeOmni", &kProbeRobot, "omni", "", 0.001, 0.2}),
    [](const ::testing::TestParamInfo<TakeOver>& take_over) { return std::string(take_over.param.name); });

/// The message of the error a run of the task with `settings` (Lua) throws while loading.
std::string loadError(const std::string& settings) {
  RunOptions o = options("two_needles");
  o.before_lua = settings;
  o.time_limit = 0.01;  // s: a run that loads is no use here
  try {
    (void)runApp(o);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(loaded)";
}

// A master the coupling cannot use is refused while loading, in one line naming the setting and
// the rule: its pose must have six DoF (a 1-DoF position has no orientation to follow), its twist
// be a twist; an unknown device is named.
TEST(PuncturingTeleoperationSettings, AMasterWithoutSixDegreesOfFreedomIsRefusedNamingTheSettingAndTheRule) {
  const std::string one_dof = loadError("teleop_device = { needle = { pose = 'Patient.needleDepth' } }");
  EXPECT_NE(one_dof.find("teleop_device.needle: pose port Patient.needleDepth is a double; the coupling needs a pose "
                         "of six DoF (position and orientation): a KDL.Frame as NeedleLink.masterPose takes"),
            std::string::npos)
      << one_dof;
  EXPECT_EQ(one_dof.find('\n'), std::string::npos) << one_dof;
  const std::string twist = loadError(
      "teleop_device = { probe = { pose = 'UR5.measCartPose', twist = 'UR5.measJointPosition' } }");
  EXPECT_NE(twist.find("teleop_device.probe: twist port UR5.measJointPosition is a "), std::string::npos) << twist;
  EXPECT_NE(twist.find("; the coupling needs a twist of six DoF (linear and angular velocity): a KDL.Twist as "
                       "ProbeLink.masterTwist takes"),
            std::string::npos)
      << twist;
  const std::string missing = loadError("teleop_device = { needle = { pose = 'Nobody.pose' } }");
  EXPECT_NE(missing.find("teleop_device.needle: pose = 'Nobody.pose' names no port of a component created before it"),
            std::string::npos)
      << missing;
  const std::string unknown = loadError("teleop_device = 'falcon'");
  EXPECT_NE(unknown.find("teleop_device must be omni, leap or a table { needle = master, probe = master }, not falcon"),
            std::string::npos)
      << unknown;
}

}  // namespace
}  // namespace cobra::run::testing
