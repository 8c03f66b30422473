#pragma once
/// @file
/// The simulated patient of the puncturing task (thesis §4.2): the abdomen phantom
/// (sim::PhantomScenario), the needle-tissue interaction with the cryoablation iceball
/// (sim::NeedleTissueModel) and the ultrasound probe on the skin (sim::observe), behind ports.

#include <cstdint>
#include <kdl/frames.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/sim/needle_tissue.hpp"
#include "cobra/sim/ultrasound.hpp"

namespace cobra::components {

/// Bridge component (it stands for the physical world: poses in, forces and images out).
///
/// Frames: world W; phantom P placed at `phantom_pose` (W_T_P; skin z = 0, tissue below, see
/// sim/phantom.hpp). `needleTipPose` is the needle tip in W as the needle robot publishes it
/// (trueCartPose or measCartPose); `tip_to_needle` turns it into the model's needle frame, whose z
/// is the needle axis (default RotY(90°): the I-SUR tool's x axis is its needle). `probePose` is the
/// probe frame U in W (z = beam, x = array, origin at the face centre).
///
/// Inputs: `needleTipPose`, `probePose` (KDL::Frame, m). Until a pose has arrived its model is
/// not stepped and its outputs stay zero. `freezeCommand` (1: freeze, 0: thaw; from the
/// cryoablation console, CryoConsole): each new sample starts a freeze (> 0.5) or a thaw, as the
/// operations below do.
/// Outputs each update (all pure data):
///  - `needleWrench`: force of the tissue on the needle, W orientation, at the tip (N; torque 0):
///    wire it to the needle robot's contactWrench.
///  - `probeWrench`: force of the skin on the probe, W orientation, at the face centre (N):
///    wire it to the probe robot's contactWrench.
///  - `needleDepth` (m): depth of the tip below the undeformed skin (negative above it).
///  - `needleAxialForce` (N): true axial force on the needle, positive when it resists insertion.
///  - `needlePlaneDistance` (m): distance of the needle (tip and the shaft behind it) to the
///    imaging plane; `needleInImage` (0/1): the tip within the image's width and depth;
///    `needleVisible` (0/1): the model's verdict (coupled, in the plane, in the image);
///    `tumourVisible` (0/1); `probeContactForce` (N): how hard the probe presses on the skin.
///  - `iceballRadius` (m).
/// Read-only properties, set at configure from the phantom scenario (what cobra studio draws):
/// `tumour` (vector<double>, m: the tumour's centre x y z in the world, then its radius) and
/// `layer_depths` (vector<double>, m: each layer's top and bottom depth below the skin along -z of
/// phantom_pose, skin first).
/// Operations: `startFreeze()` starts a freeze cycle around the tip (thawing by itself after
/// `freeze_duration` s when that is > 0), `startThaw()` stops it. updateHook allocates nothing.
class PatientSimulator : public core::Component {
 public:
  explicit PatientSimulator(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  void startFreeze();
  void startThaw();

  core::Property<std::string> scenario_file_{
      "scenario_file", "", "", "phantom scenario file (sim/README.md format); empty: the default abdomen"};
  core::Property<KDL::Frame> phantom_pose_{"phantom_pose", KDL::Frame::Identity(), "m",
                                           "pose of the phantom frame (skin z = 0, tissue below) in the world"};
  core::Property<KDL::Frame> tip_to_needle_{"tip_to_needle", KDL::Frame(KDL::Rotation::RotY(1.5707963267948966)), "m",
                                            "needle frame (z = needle axis) in the frame of needleTipPose"};
  core::Property<double> iceball_max_radius_{"iceball_max_radius", 0.015, "m", "plateau radius of the iceball, > 0"};
  core::Property<double> freeze_time_constant_{"freeze_time_constant", 120.0, "s", "iceball growth time constant, > 0"};
  core::Property<double> thaw_time_constant_{"thaw_time_constant", 60.0, "s", "iceball thaw time constant, > 0"};
  core::Property<double> release_radius_{"release_radius", 0.002, "m", "iceball radius below which the needle is free"};
  core::Property<double> hold_stiffness_{"hold_stiffness", 2.0e4, "N/m", "iceball hold on the trapped needle, > 0"};
  core::Property<double> freeze_duration_{"freeze_duration", 0.0, "s",
                                          "a freeze cycle thaws by itself after this long, >= 0 (0: at startThaw)"};
  core::Property<double> probe_contact_stiffness_{"probe_contact_stiffness", 2000.0, "N/m", "skin push-back, > 0"};
  core::Property<double> probe_min_contact_force_{"probe_min_contact_force", 2.0, "N",
                                                  "below this the probe gives no image, >= 0"};
  core::Property<double> plane_tolerance_{"plane_tolerance", 0.002, "m", "half the elevational beam thickness, > 0"};
  core::Property<double> image_depth_{"image_depth", 0.15, "m", "image depth along the beam, > 0"};
  core::Property<double> image_half_width_{"image_half_width", 0.03, "m", "half the image width, > 0"};
  core::Property<double> needle_visible_length_{"needle_visible_length", 0.03, "m",
                                                "shaft length behind the tip that must lie in the plane, > 0"};

  core::Property<std::vector<double>> tumour_{"tumour", {}, "m",
                                              "set at configure: the tumour's centre (x y z, world) and radius"};
  core::Property<std::vector<double>> layer_depths_{
      "layer_depths", {}, "m", "set at configure: each layer's top and bottom depth below the skin (phantom frame)"};

  core::InputPort<KDL::Frame> needle_tip_pose_{"needleTipPose", "needle tip pose, world frame", "m"};
  core::InputPort<KDL::Frame> probe_pose_{"probePose", "ultrasound probe pose, world frame", "m"};
  core::InputPort<double> freeze_command_{"freezeCommand", "1: freeze around the tip, 0: thaw (from the console)",
                                          "1"};
  core::OutputPort<KDL::Wrench> needle_wrench_{"needleWrench",
                                               "tissue force on the needle, world orientation, at the tip", "N, N·m"};
  core::OutputPort<KDL::Wrench> probe_wrench_{"probeWrench", "skin force on the probe, world orientation, at the face",
                                              "N, N·m"};
  core::OutputPort<double> needle_depth_{"needleDepth", "tip depth below the undeformed skin", "m"};
  core::OutputPort<double> needle_axial_force_{"needleAxialForce", "axial force, positive resisting insertion", "N"};
  core::OutputPort<double> plane_distance_{"needlePlaneDistance", "needle distance to the imaging plane", "m"};
  core::OutputPort<double> needle_in_image_{"needleInImage", "1 when the tip is within the image width and depth", "1"};
  core::OutputPort<double> needle_visible_{"needleVisible", "1 when the needle is seen in the image", "1"};
  core::OutputPort<double> tumour_visible_{"tumourVisible", "1 when the tumour is seen in the image", "1"};
  core::OutputPort<double> probe_contact_force_{"probeContactForce", "probe force on the skin", "N"};
  core::OutputPort<double> iceball_radius_{"iceballRadius", "iceball radius", "m"};

  std::optional<sim::NeedleTissueModel> tissue_;
  sim::UltrasoundProbeModel probe_model_;
  KDL::Frame world_to_phantom_;
  KDL::Frame needle_tip_, probe_;
  bool have_needle_ = false, have_probe_ = false;
  std::int64_t last_update_ns_ = -1;
  std::int64_t thaw_at_ns_ = -1;
  bool freeze_requested_ = false, thaw_requested_ = false;
};

}  // namespace cobra::components
