#include "cobra/components/sim/patient_simulator.hpp"

#include <algorithm>
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
  addProperty(image_rate_.range(0.0, 1000.0));
  addProperty(image_seed_);
  addProperty(image_width_.range(1, 256));
  addProperty(image_height_.range(1, 256));
  addProperty(image_spacing_.range(1e-6, 0.01));
  addProperty(image_pixels_per_step_.range(0, 65536));
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
  addPort(us_image_);
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
  return configureImage();
}

bool PatientSimulator::configureImage() {
  imager_.reset();
  sim::UltrasoundImageModel model;
  model.width = image_width_();
  model.height = image_height_();
  model.spacing_x = model.spacing_y = image_spacing_();
  try {
    imager_.emplace(model, tissue_->scenario(), static_cast<std::uint64_t>(image_seed_()));
  } catch (const std::invalid_argument& e) {  // a phantom beyond the imager's tables (16 layers, 16 regions)
    return refuse(std::string("usImage: ") + e.what());
  }
  const int pixels = image_pixels_per_step_();
  image_columns_per_step_ = pixels == 0 ? model.width : std::max(1, pixels / model.height);
  // Each update renders one band: an image takes `steps` updates, which must fit in its interval
  // (a periodic activity; an event-driven one renders when it is triggered). A rate set later,
  // while running, is not checked: a due image that cannot start is skipped (stepImage).
  const int steps = (model.width + image_columns_per_step_ - 1) / image_columns_per_step_;
  const std::int64_t period_ns = activity().period().count();
  if (image_rate_() > 0.0 && period_ns > 0 && static_cast<double>(steps * period_ns) > 1e9 / image_rate_()) {
    const double period = static_cast<double>(period_ns) * 1e-9;
    return refuse("property image_rate is " + core::printValue(image_rate_()) + " Hz, but an image of " +
                  std::to_string(model.width) + " x " + std::to_string(model.height) + " px takes " +
                  std::to_string(steps) + " updates of " + core::printValue(period) + " s (image_pixels_per_step = " +
                  std::to_string(pixels) + " px); expected image_rate <= " +
                  core::printValue(1.0 / (steps * period)) + " Hz, or more image_pixels_per_step");
  }
  return true;
}

bool PatientSimulator::startHook() {
  last_update_ns_ = -1;
  next_image_ns_ = -1;  // the first image at the first update with a probe pose
  next_column_ = -1;    // an image stopped half-rendered is dropped
  return true;
}

void PatientSimulator::cleanupHook() {
  tissue_.reset();
  imager_.reset();
}

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
  stepImage(now_ns);
}

void PatientSimulator::stepImage(std::int64_t now_ns) noexcept {
  if (!imager_ || !have_probe_) return;
  if (next_column_ < 0) {
    // image_rate is read here, so that a configuration may turn the images on and off while the
    // patient runs (0: none start; an image being rendered is finished). Nor does one start while
    // nobody reads usImage: the images would be most of a lockstep world's CPU time for nothing.
    const double rate = image_rate_();
    if (rate <= 0.0 || !us_image_.hasReaders()) {
      next_image_ns_ = -1;  // turned on again, or connected: the first image at once
      return;
    }
    if (next_image_ns_ >= 0 && now_ns < next_image_ns_) return;
    // Images start 1 / rate apart on a fixed schedule; one that could not start when due (its
    // predecessor's bands ran late) is skipped, not caught up.
    const auto interval = static_cast<std::int64_t>(std::llround(1e9 / rate));
    next_image_ns_ = (next_image_ns_ < 0 ? now_ns : next_image_ns_) + interval;
    if (next_image_ns_ <= now_ns) next_image_ns_ = now_ns + interval;
    image_probe_ = probe_;
    image_tip_ = needle_tip_;
    image_has_tip_ = have_needle_;
    next_column_ = 0;
  }
  const int end = next_column_ + image_columns_per_step_;
  imager_->renderColumns(image_probe_, image_has_tip_ ? &image_tip_ : nullptr, *rendering_, next_column_, end);
  next_column_ = end;
  if (next_column_ < rendering_->width) return;
  next_column_ = -1;
  const sim::UltrasoundImage& done = *rendering_;
  types::GrayImage& out = *published_;
  out.width = done.width;
  out.height = done.height;
  out.spacing_x = done.spacing_x;
  out.spacing_y = done.spacing_y;
  // GrayImage's pose is pixel (0, 0)'s centre (gray_image.hpp; OpenIGTLink's IMAGE places voxel
  // centres), sim's frame I its outer corner: half a pixel along both axes, then from P to W by the
  // inverse of the map the probe's pose came through.
  const KDL::Frame centre(done.pose.M, done.pose * KDL::Vector(0.5 * done.spacing_x, 0.5 * done.spacing_y, 0.0));
  out.pose = kinematics::frameProduct(world_to_phantom_.Inverse(), centre);
  std::copy_n(done.pixels.begin(), std::size_t{done.width} * done.height, out.pixels.begin());
  us_image_.write(out);
}

}  // namespace cobra::components
