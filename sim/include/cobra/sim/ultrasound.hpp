#pragma once
/// @file
/// Ultrasound probe on the phantom (thesis §4.2: the probe is pressed on the skin and the needle
/// is guided in its image): contact force from a penalty stiffness on the skin, and what the
/// image shows.
///
/// Probe frame U: origin at the centre of the transducer face, z-axis into the body (the beam),
/// x-axis along the array; the imaging plane is U's x-z plane. Poses are given in the phantom
/// frame P (phantom.hpp: skin at z = 0, tissue below).

#include <kdl/frames.hpp>

#include "cobra/sim/phantom.hpp"

namespace cobra::sim {

/// Probe parameters. Values are ASSUMPTIONS of the order of a linear/convex abdominal probe.
struct UltrasoundProbeModel {
  double contact_stiffness = 2000.0;  ///< N/m, > 0: skin push-back per metre the face is below z = 0
  double min_contact_force = 2.0;     ///< N, >= 0: below this the coupling is too poor for an image
  double plane_tolerance = 0.002;     ///< m, > 0: half the elevational beam thickness
  double image_depth = 0.15;          ///< m, > 0: depth of the image along U's z
  double image_half_width = 0.03;     ///< m, > 0: half the image width along U's x
  double needle_visible_length = 0.03;  ///< m, > 0: shaft length behind the tip that must lie in the plane
};

/// @throws std::invalid_argument naming the parameter and its expected range.
void validate(const UltrasoundProbeModel& model);

/// What the probe feels and shows.
struct UltrasoundView {
  KDL::Vector contact_force;       ///< N, frame P: force of the skin on the probe (along +z)
  bool coupled = false;            ///< pressing with at least min_contact_force
  double needle_distance = 0.0;    ///< m: largest distance of the tip and of the shaft point behind it to the plane
  bool needle_visible = false;     ///< coupled, both points within plane_tolerance and inside the image
  bool tumour_visible = false;     ///< coupled and the plane cuts the tumour sphere inside the image
};

/// Stateless: noexcept, allocation-free. `needle_tip` as in NeedleTissueModel (z = needle axis).
UltrasoundView observe(const UltrasoundProbeModel& model, const PhantomScenario& phantom, const KDL::Frame& probe,
                       const KDL::Frame& needle_tip) noexcept;

}  // namespace cobra::sim
