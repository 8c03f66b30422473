#pragma once
/// @file
/// The simulated patient of the puncturing task (thesis §4.2): the abdomen phantom
/// (sim::PhantomScenario), the needle-tissue interaction with the cryoablation iceball
/// (sim::NeedleTissueModel), the ultrasound probe on the skin (sim::observe) and its B-mode image
/// (sim::UltrasoundImager), behind ports.

#include <cstdint>
#include <kdl/frames.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/sim/needle_tissue.hpp"
#include "cobra/sim/ultrasound.hpp"
#include "cobra/sim/ultrasound_image.hpp"
#include "cobra/types/gray_image.hpp"

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
/// Outputs (all pure data), each update but the image:
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
///  - `usImage` (Imaging.GrayImage): the probe's B-mode image (sim::UltrasoundImager: layers,
///    tumour, vessels, ribs, the needle where it lies in the beam, speckle), `image_rate` times per
///    s; its `pose` is the centre of pixel (0, 0) in the world (m; x along the array, y along the
///    beam, as types::GrayImage places pixels), spacing `image_spacing` (m per pixel). It is
///    of the probe and needle poses this component reads (`probePose`, `needleTipPose`, as for
///    the other ultrasound outputs) at the update its rendering starts, and is published when its
///    last band of columns is done (see "The image's cost").
/// The image's cost: a 128 x 128 image costs about 1.4 ms of CPU (sim/README.md), more than a
/// 1 ms tick of the real-time executor holds (every component of a deployment steps in one tick).
/// So each update renders one band of whole columns (scan lines) of at most
/// `image_pixels_per_step` pixels (default 1024: 0.09 ms, about 0.17 ms for the central columns,
/// which hold the most tissue; bench/sim_bench.cpp, group PatientUpdate), and the image is
/// published with its last band: 16 updates for 128 x 128. A band of columns renders exactly
/// what the whole image would (sim::UltrasoundImager::renderColumns). Configure refuses a rate the
/// bands cannot keep at the activity's period; a rate set while running is not checked, and an
/// image due while the previous one is still being rendered is skipped. `image_rate` may change
/// while the patient runs (a configuration turns the images on and off); the image's size, seed
/// and bands are fixed at configure. No probe pose yet, or no connection reading usImage: no image
/// (rendering one nobody reads would cost a lockstep world most of its CPU time); the first
/// starts in the update that has both.
/// Read-only properties, set at configure from the phantom scenario (what cobra studio draws):
/// `tumour` (vector<double>, m: the tumour's centre x y z in the world, then its radius) and
/// `layer_depths` (vector<double>, m: each layer's top and bottom depth below the skin along -z of
/// phantom_pose, skin first).
/// Operations: `startFreeze()` starts a freeze cycle around the tip (thawing by itself after
/// `freeze_duration` s when that is > 0), `startThaw()` stops it. updateHook allocates nothing
/// (the image's buffers are allocated at construction, the imager at configure).
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
  bool configureImage();
  void stepImage(std::int64_t now_ns) noexcept;

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

  // The rendered image (usImage); its field of view is the imager's (a convex probe's sector),
  // distinct from image_depth / image_half_width above, which decide the needle's visibility.
  core::Property<double> image_rate_{"image_rate", 10.0, "Hz",
                                     "usImage images per second, 0..1000 (0: none); may change while running"};
  core::Property<int> image_seed_{"image_seed", 1, "1",
                                  "seed of the image's speckle (same seed and poses, same image; fixed at configure)"};
  core::Property<int> image_width_{"image_width", 128, "px",
                                   "usImage columns, along the probe's array, 1..256 (fixed at configure)"};
  core::Property<int> image_height_{"image_height", 128, "px",
                                    "usImage rows, along the beam (depth), 1..256 (fixed at configure)"};
  core::Property<double> image_spacing_{"image_spacing", 0.0008, "m/px",
                                        "usImage pixel size along the array and the beam, 1e-6..0.01 (fixed at configure)"};
  core::Property<int> image_pixels_per_step_{"image_pixels_per_step", 1024, "px",
                                             "most pixels rendered in one update (whole columns, at least one), "
                                             "0..65536; 0: the whole image at once (fixed at configure)"};

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
  core::OutputPort<types::GrayImage> us_image_{
      "usImage", "the probe's B-mode image, image_rate per s; pose: pixel (0, 0)'s centre in the world", "m"};

  std::optional<sim::NeedleTissueModel> tissue_;
  sim::UltrasoundProbeModel probe_model_;
  KDL::Frame world_to_phantom_;
  KDL::Frame needle_tip_, probe_;
  bool have_needle_ = false, have_probe_ = false;
  std::int64_t last_update_ns_ = -1;
  std::int64_t thaw_at_ns_ = -1;
  bool freeze_requested_ = false, thaw_requested_ = false;

  // The image: the imager (made at configure), the image being rendered (frame P) and the one
  // published (frame W), both allocated once here: 64 KiB each, kept off the update's stack.
  std::optional<sim::UltrasoundImager> imager_;
  std::unique_ptr<sim::UltrasoundImage> rendering_ = std::make_unique<sim::UltrasoundImage>();
  std::unique_ptr<types::GrayImage> published_ = std::make_unique<types::GrayImage>();
  int image_columns_per_step_ = 0;      // columns rendered per update
  std::int64_t next_image_ns_ = -1;     // when the next image starts (-1: at the first probe pose)
  int next_column_ = -1;                // next column of the image being rendered (-1: none)
  KDL::Frame image_probe_, image_tip_;  // P: the poses of the image being rendered
  bool image_has_tip_ = false;
};

}  // namespace cobra::components
