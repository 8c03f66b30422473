#pragma once
// The puncturing world of the cobra_sim tests, on the lockstep clock at 1 kHz: the I-SUR robot
// holding the needle, the UR5 holding the probe, the patient and the two monitors, wired as a
// deployment would wire them. The phantom is placed so that the skin is 5 mm ahead of the needle
// tip, its surface normal along the needle; the probe presses 2 mm into the skin 20 mm beside the
// entry point with the needle's line in its imaging plane.

#include <chrono>
#include <cmath>
#include <kdl/frames.hpp>
#include <string>
#include <vector>

#include "cobra/components/monitoring/needle_insertion_monitor.hpp"
#include "cobra/components/sim/patient_simulator.hpp"
#include "cobra/components/sim/simulated_robot.hpp"
#include "cobra/components/monitoring/ultrasound_monitor.hpp"
#include "cobra/core/core.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/ur5.hpp"

namespace cobra::components::test {

using namespace std::chrono_literals;

inline KDL::JntArray jointArray(const std::vector<double>& values) {
  KDL::JntArray q(static_cast<unsigned>(values.size()));
  for (unsigned i = 0; i < q.rows(); ++i) q(i) = values[i];
  return q;
}

/// Needle tip pose of the I-SUR at its default initial joints (world = robot base).
inline KDL::Frame isurStartPose() {
  kinematics::IsurPuncturingSolver solver;
  KDL::Frame pose;
  solver.forward(jointArray({0.1, 0.1, 0.1, 0.0, 0.0, 0.6, 0.6, 0.0}), pose);
  return pose;
}

struct PuncturingWorld {
  static constexpr double kSkinGap = 0.005;  // m, tip to skin at the start

  core::LockstepClock clock;
  SimulatedISURRobot isur{"isur"};
  SimulatedUR5Robot ur5{"ur5"};
  PatientSimulator patient{"patient"};
  NeedleInsertionMonitor needle_monitor{"needleMonitor"};
  UltrasoundMonitor us_monitor{"usMonitor"};

  core::OutputPort<KDL::Frame> needle_command{"needleCommand", "", "m"};
  core::OutputPort<KDL::Frame> probe_command{"probeCommand", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};
  core::InputPort<double> axial{"axial", "", "N"};
  core::InputPort<double> depth{"depth", "", "m"};
  core::InputPort<KDL::Wrench> needle_wrench{"needleWrench", "", "N"};
  core::InputPort<KDL::Frame> needle_pose{"needlePose", "", "m"};

  KDL::Frame needle_start = isurStartPose();
  KDL::Vector axis = needle_start.M.UnitX();  // the I-SUR needle is its tool's x axis
  KDL::Frame phantom;                         // world_T_phantom
  KDL::Frame probe;                           // world_T_probe

  explicit PuncturingWorld(int seed = 1, const std::string& scenario_file = "") {
    const KDL::Rotation needle_frame = needle_start.M * KDL::Rotation::RotY(std::acos(0.0));  // z = needle axis
    phantom = KDL::Frame(needle_frame * KDL::Rotation::RotX(std::acos(-1.0)), needle_start.p + axis * kSkinGap);
    // Probe frame in P: array along y_P, beam along -z_P; 20 mm beside the entry, 2 mm into the skin.
    probe = phantom * KDL::Frame(KDL::Rotation(0, 1, 0, 1, 0, 0, 0, 0, -1), KDL::Vector(0.0, 0.02, -0.002));
    kinematics::Ur5Solver ur5_solver;
    KDL::Frame flange;
    ur5_solver.forward(jointArray({0.0, -1.57, 1.57, -1.57, -1.57, 0.0}), flange);

    isur.setProperty("seed", seed);
    ur5.setProperty("seed", seed + 1000);
    ur5.setProperty("base_frame", probe * flange.Inverse());
    patient.setProperty("phantom_pose", phantom);
    patient.setProperty("scenario_file", scenario_file);
    for (core::Component* c : std::vector<core::Component*>{&isur, &ur5, &patient, &needle_monitor, &us_monitor})
      clock.add(*c, 1ms);
    core::connectPorts(needle_command, isur.port("desCartPose"));
    core::connectPorts(probe_command, ur5.port("desCartPose"));
    core::connectPorts(isur.port("trueCartPose"), patient.port("needleTipPose"));
    core::connectPorts(ur5.port("trueCartPose"), patient.port("probePose"));
    core::connectPorts(patient.port("needleWrench"), isur.port("contactWrench"));
    core::connectPorts(patient.port("probeWrench"), ur5.port("contactWrench"));
    core::connectPorts(isur.port("measWrench"), needle_monitor.port("measWrench"));
    core::connectPorts(isur.port("measCartPose"), needle_monitor.port("measCartPose"));
    core::connectPorts(patient.port("needlePlaneDistance"), us_monitor.port("needlePlaneDistance"));
    core::connectPorts(patient.port("needleInImage"), us_monitor.port("needleInImage"));
    core::connectPorts(patient.port("probeContactForce"), us_monitor.port("probeContactForce"));
    core::connectPorts(needle_monitor.port("events"), events, core::ConnPolicy::buffer(64));
    core::connectPorts(us_monitor.port("events"), events, core::ConnPolicy::buffer(64));
    core::connectPorts(patient.port("needleAxialForce"), axial);
    core::connectPorts(patient.port("needleDepth"), depth);
    core::connectPorts(patient.port("needleWrench"), needle_wrench);
    core::connectPorts(isur.port("measCartPose"), needle_pose);
  }

  /// Configures and starts every component; the message of the first refusal, or "".
  std::string start() {
    for (core::Component* c : std::vector<core::Component*>{&isur, &ur5, &patient, &needle_monitor, &us_monitor}) {
      if (core::Result r = c->configure(); !r) return r.message;
      if (core::Result r = c->start(); !r) return r.message;
    }
    return "";
  }

  /// The needle command `advance` (m) along the needle from the start pose.
  KDL::Frame needleAt(double advance) const { return KDL::Frame(needle_start.M, needle_start.p + axis * advance); }

  /// One 1 ms step with the needle commanded `advance` m along its axis and the probe held.
  void step(double advance) {
    needle_command.write(needleAt(advance));
    probe_command.write(probe);
    clock.advance(1ms);
  }

  std::vector<std::string> takeEvents() {
    std::vector<std::string> out;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) out.push_back(e.name.str());
    return out;
  }
  double read(core::InputPort<double>& port) {
    double v = NAN;
    (void)port.read(v);
    return v;
  }
};

}  // namespace cobra::components::test
