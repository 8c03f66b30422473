#include "cobra/sim/ft_sensor.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace cobra::sim {
namespace {

constexpr const char* kAxisNames[6] = {"Fx", "Fy", "Fz", "Tx", "Ty", "Tz"};

AxisArray toArray(const KDL::Wrench& w) {
  return {w.force.x(), w.force.y(), w.force.z(), w.torque.x(), w.torque.y(), w.torque.z()};
}

void checkAxes(const ForceTorqueSensorModel& m, const AxisArray& values, const char* parameter, bool strictly_positive) {
  for (std::size_t i = 0; i < 6; ++i) {
    const double v = values[i];
    if (!std::isfinite(v) || v < 0.0 || (strictly_positive && v == 0.0)) {
      throw std::invalid_argument("force/torque sensor '" + m.name + "': " + parameter + "[" + kAxisNames[i] +
                                  "] = " + std::to_string(v) + ", expected a finite value " +
                                  (strictly_positive ? "> 0" : ">= 0") + " (N or N·m)");
    }
  }
}

}  // namespace

// Overloads are the thesis' tables. ATI resolution is the 16-bit DAQ figure from ATI's public
// F/T sensor datasheets (ati-ia.com) for the calibrations named below, as recalled, not re-checked
// against the current sheet. Noise std = half a resolution step is an ASSUMPTION (ATI states
// resolution as the noise-limited smallest step); FTSens noise = one resolution step is also an
// ASSUMPTION (the thesis gives no noise figure).
ForceTorqueSensorModel atiNano17() {
  ForceTorqueSensorModel m;
  m.name = "AtiNano17";
  m.saturation = {250.0, 250.0, 480.0, 1.6, 1.6, 1.8};  // thesis §4.3.3 overloads
  // ATI Nano17 SI-25-0.25: 1/160 N (Fx, Fy, Fz), 1/32 N·mm (Tx, Ty, Tz).
  m.resolution = {1.0 / 160, 1.0 / 160, 1.0 / 160, 1.0 / 32000, 1.0 / 32000, 1.0 / 32000};
  for (std::size_t i = 0; i < 6; ++i) m.noise_std[i] = 0.5 * m.resolution[i];
  m.max_rate_hz = 7000.0;  // ASSUMPTION: below the 7200 Hz resonance of the thesis table
  return m;
}

ForceTorqueSensorModel atiNano43() {
  ForceTorqueSensorModel m;
  m.name = "AtiNano43";
  m.saturation = {300.0, 300.0, 380.0, 3.2, 3.2, 4.6};  // thesis §5.3.2 overloads
  // ATI Nano43 SI-36-0.5: 1/128 N (Fx, Fy, Fz), 1/16 N·mm (Tx, Ty, Tz).
  m.resolution = {1.0 / 128, 1.0 / 128, 1.0 / 128, 1.0 / 16000, 1.0 / 16000, 1.0 / 16000};
  for (std::size_t i = 0; i < 6; ++i) m.noise_std[i] = 0.5 * m.resolution[i];
  m.max_rate_hz = 2000.0;  // ASSUMPTION: below the 2300 Hz resonance of the thesis table
  return m;
}

ForceTorqueSensorModel ftSens() {
  ForceTorqueSensorModel m;
  m.name = "FTSens";
  m.saturation = {2000.0, 2000.0, 2000.0, 40.0, 40.0, 30.0};  // thesis §6.1.2 measure range
  m.resolution = {0.25, 0.25, 0.25, 0.049, 0.049, 0.037};     // thesis §6.1.2
  m.noise_std = m.resolution;                                  // ASSUMPTION (see above)
  m.max_rate_hz = 1000.0;                                      // thesis §6.1.2: up to 1k messages/s
  return m;
}

void validate(const ForceTorqueSensorModel& m) {
  checkAxes(m, m.saturation, "saturation", true);
  checkAxes(m, m.resolution, "resolution", false);
  checkAxes(m, m.noise_std, "noise_std", false);
  for (std::size_t i = 0; i < 6; ++i) {
    if (!std::isfinite(toArray(m.bias)[i])) {
      throw std::invalid_argument("force/torque sensor '" + m.name + "': bias[" + kAxisNames[i] +
                                  "] is not finite, expected a finite offset (N or N·m)");
    }
  }
  if (!std::isfinite(m.filter_cutoff_hz) || m.filter_cutoff_hz < 0.0) {
    throw std::invalid_argument("force/torque sensor '" + m.name + "': filter_cutoff_hz = " +
                                std::to_string(m.filter_cutoff_hz) + ", expected >= 0 Hz (0 = no filter)");
  }
  if (!std::isfinite(m.max_rate_hz) || m.max_rate_hz <= 0.0) {
    throw std::invalid_argument("force/torque sensor '" + m.name + "': max_rate_hz = " +
                                std::to_string(m.max_rate_hz) + ", expected > 0 Hz");
  }
}

ForceTorqueSensor::ForceTorqueSensor(ForceTorqueSensorModel model, std::uint64_t seed)
    : model_(std::move(model)), noise_(seed) {
  validate(model_);
}

void ForceTorqueSensor::reset(std::uint64_t seed, const KDL::Wrench& wrench) noexcept {
  noise_.seed(seed);
  filtered_ = toArray(wrench + model_.bias);
  filter_started_ = true;
  reading_ = ForceTorqueReading{};
}

const ForceTorqueReading& ForceTorqueSensor::step(double dt, const KDL::Wrench& true_wrench) noexcept {
  const AxisArray input = toArray(true_wrench + model_.bias);
  // Exact discretisation of dy/dt = 2π fc (x - y) over dt for a held input.
  double alpha = 1.0;
  if (model_.filter_cutoff_hz > 0.0) {
    if (dt != alpha_dt_) {
      alpha_ = (std::isfinite(dt) && dt > 0.0) ? 1.0 - std::exp(-2.0 * std::numbers::pi * model_.filter_cutoff_hz * dt) : 0.0;
      alpha_dt_ = dt;
    }
    alpha = filter_started_ ? alpha_ : 1.0;
  }
  filter_started_ = true;
  AxisArray out{};
  std::uint8_t saturated = 0;
  for (std::size_t i = 0; i < 6; ++i) {
    filtered_[i] += alpha * (input[i] - filtered_[i]);
    double v = filtered_[i] + model_.noise_std[i] * noise_.sample();
    const double limit = model_.saturation[i];
    if (!(std::abs(v) <= limit)) {  // also catches NaN input: report it as saturated at +limit
      v = std::signbit(v) ? -limit : limit;
      saturated = static_cast<std::uint8_t>(saturated | (1U << i));
    }
    // The nearest count (rint: ties to even, inlined by the compiler; round is a libm call).
    if (model_.resolution[i] > 0.0) v = model_.resolution[i] * std::rint(v / model_.resolution[i]);
    out[i] = v;
  }
  reading_.wrench = KDL::Wrench(KDL::Vector(out[0], out[1], out[2]), KDL::Vector(out[3], out[4], out[5]));
  reading_.saturated = saturated;
  return reading_;
}

}  // namespace cobra::sim
