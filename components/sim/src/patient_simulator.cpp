#include "cobra/components/sim/patient_simulator.hpp"

#include <cmath>
#include <stdexcept>

#include "cobra/core/activity.hpp"
#include "cobra/kinematics/frame_product.hpp"
#include "cobra/kinematics/kinematics_solver.hpp"

namespace cobra::components {

PatientSimulator::PatientSimulator(std::string name)
    : Component(
          std::move(name), core::Role::Bridge,
          "Simulated patient (thesis §4.2): abdomen phantom, needle-tissue forces, cryo iceball, ultrasound image") {
  addProperty(scenario_file_);
  addProperty(phantom_pose_);
  addProperty(tip_to_needle_);
  addProperty(iceball_max_radius_);
  addProperty(freeze_time_constant_);
  addProperty(thaw_time_constant_);
  addProperty(release_radius_);
  addProperty(hold_stiffness_);
  addProperty(freeze_duration_);
  addProperty(probe_contact_stiffness_);
  addProperty(probe_min_contact_force_);
  addProperty(plane_tolerance_);
  addProperty(image_depth_);
  addProperty(image_half_width_);
  addProperty(needle_visible_length_);
  addProperty(tumour_.readOnly());
  addProperty(layer_depths_.readOnly());
  addPort(needle_tip_pose_);
  addPort(probe_pose_);
  addPort(freeze_command_);
  addPort(needle_wrench_);
  addPort(probe_wrench_);
  addPort(needle_depth_);
  addPort(needle_axial_force_);
  addPort(plane_distance_);
  addPort(needle_in_image_);
  addPort(needle_visible_);
  addPort(tumour_visible_);
  addPort(probe_contact_force_);
  addPort(iceball_radius_);
  addOperation("startFreeze", &PatientSimulator::startFreeze, this,
               "starts a cryoablation freeze cycle around the needle tip (thaws after freeze_duration s when > 0)");
  addOperation("startThaw", &PatientSimulator::startThaw, this, "stops freezing: the iceball thaws");
}

bool PatientSimulator::configureHook() {
  tissue_.reset();
  if (!kinematics::validFrame(phantom_pose_()) || !kinematics::validFrame(tip_to_needle_()))
    return refuse("properties phantom_pose and tip_to_needle must be finite frames with an orthonormal rotation");
  if (!(freeze_duration_() >= 0.0) || !std::isfinite(freeze_duration_()))
    return refuse("property freeze_duration is " + std::to_string(freeze_duration_()) + " s; expected >= 0 s");
  try {
    sim::PhantomScenario scenario =
        scenario_file_().empty() ? sim::defaultAbdomen() : sim::loadScenario(scenario_file_());
    sim::NeedleModel needle;
    needle.iceball.max_radius = iceball_max_radius_();
    needle.iceball.freeze_time_constant = freeze_time_constant_();
    needle.iceball.thaw_time_constant = thaw_time_constant_();
    needle.iceball.release_radius = release_radius_();
    needle.iceball.hold_stiffness = hold_stiffness_();
    tissue_.emplace(std::move(scenario), needle);
    probe_model_ = sim::UltrasoundProbeModel{.contact_stiffness = probe_contact_stiffness_(),
                                             .min_contact_force = probe_min_contact_force_(),
                                             .plane_tolerance = plane_tolerance_(),
                                             .image_depth = image_depth_(),
                                             .image_half_width = image_half_width_(),
                                             .needle_visible_length = needle_visible_length_()};
    sim::validate(probe_model_);
  } catch (const std::invalid_argument& e) {
    tissue_.reset();
    return refuse(std::string(scenario_file_().empty() ? "" : "property scenario_file: ") + e.what());
  }
  world_to_phantom_ = phantom_pose_().Inverse();
  const sim::PhantomScenario& phantom = tissue_->scenario();
  const KDL::Vector centre = phantom_pose_() * phantom.tumour_center;
  tumour_.setFromOwner({centre.x(), centre.y(), centre.z(), phantom.tumour_radius});
  std::vector<double> depths;
  for (std::size_t i = 0; i < phantom.layers.size(); ++i) {
    const double top = sim::layerTop(phantom, i);
    depths.insert(depths.end(), {top, top + phantom.layers[i].thickness});
  }
  layer_depths_.setFromOwner(depths);
  have_needle_ = have_probe_ = false;
  freeze_requested_ = thaw_requested_ = false;
  thaw_at_ns_ = -1;
  return true;
}

bool PatientSimulator::startHook() {
  last_update_ns_ = -1;
  return true;
}

void PatientSimulator::cleanupHook() { tissue_.reset(); }

void PatientSimulator::startFreeze() {
  freeze_requested_ = true;
  thaw_requested_ = false;
}

void PatientSimulator::startThaw() {
  thaw_requested_ = true;
  freeze_requested_ = false;
}

void PatientSimulator::updateHook() {
  const std::int64_t now_ns = now().count();
  const double dt = last_update_ns_ < 0 ? std::chrono::duration<double>(activity().period()).count()
                                        : static_cast<double>(now_ns - last_update_ns_) * 1e-9;
  last_update_ns_ = now_ns;

  if (double command = 0.0; freeze_command_.read(command) == core::FlowStatus::NewData) {
    if (command > 0.5) {
      startFreeze();
    } else {
      startThaw();
    }
  }
  if (freeze_requested_) {
    freeze_requested_ = false;
    tissue_->startFreeze();
    thaw_at_ns_ = freeze_duration_() > 0.0 ? now_ns + static_cast<std::int64_t>(freeze_duration_() * 1e9) : -1;
  }
  if (thaw_requested_ || (thaw_at_ns_ >= 0 && now_ns >= thaw_at_ns_)) {
    thaw_requested_ = false;
    thaw_at_ns_ = -1;
    tissue_->startThaw();
  }

  KDL::Frame pose;
  if (needle_tip_pose_.read(pose) != core::FlowStatus::NoData) {
    needle_tip_ = kinematics::frameProduct(kinematics::frameProduct(world_to_phantom_, pose), tip_to_needle_());
    have_needle_ = true;
  }
  if (probe_pose_.read(pose) != core::FlowStatus::NoData) {
    probe_ = kinematics::frameProduct(world_to_phantom_, pose);
    have_probe_ = true;
  }
  const KDL::Rotation& to_world = phantom_pose_().M;
  if (have_needle_) {
    const sim::NeedleForces& f = tissue_->step(dt, needle_tip_);
    needle_wrench_.write(KDL::Wrench(to_world * f.force, KDL::Vector::Zero()));
    needle_axial_force_.write(f.axial);
    needle_depth_.write(-needle_tip_.p.z());
    iceball_radius_.write(f.iceball_radius);
  }
  if (have_probe_) {
    const sim::UltrasoundView view = sim::observe(probe_model_, tissue_->scenario(), probe_, needle_tip_);
    probe_wrench_.write(KDL::Wrench(to_world * view.contact_force, KDL::Vector::Zero()));
    probe_contact_force_.write(view.contact_force.z());
    tumour_visible_.write(view.tumour_visible ? 1.0 : 0.0);
    if (have_needle_) {
      const KDL::Vector tip_in_probe = probe_.Inverse(needle_tip_.p);
      const bool in_image = tip_in_probe.z() >= 0.0 && tip_in_probe.z() <= probe_model_.image_depth &&
                            std::abs(tip_in_probe.x()) <= probe_model_.image_half_width;
      plane_distance_.write(view.needle_distance);
      needle_in_image_.write(in_image ? 1.0 : 0.0);
      needle_visible_.write(view.needle_visible ? 1.0 : 0.0);
    }
  }
}

}  // namespace cobra::components
