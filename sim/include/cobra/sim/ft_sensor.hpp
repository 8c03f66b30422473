#pragma once
/// @file
/// Six-axis force/torque sensor model: bias, optional first-order low-pass, Gaussian noise,
/// saturation and quantisation, with the thesis' sensors as presets (AtiNano17 §4.3.3,
/// AtiNano43 §5.3.2, IIT FTSens §6.1.2).

#include <array>
#include <cstdint>
#include <string>

#include <kdl/frames.hpp>

#include "cobra/sim/gaussian_noise.hpp"

namespace cobra::sim {

/// Axis order of every per-axis array: Fx, Fy, Fz (N), Tx, Ty, Tz (N·m), in the sensor frame.
using AxisArray = std::array<double, 6>;

/// Immutable description of a sensor. All wrenches are expressed in the sensor frame.
struct ForceTorqueSensorModel {
  std::string name = "sensor";       ///< used in error messages
  AxisArray saturation{};            ///< |reading| limit per axis (N, N·m), > 0; the output clips there
  AxisArray resolution{};            ///< quantisation step per axis (N, N·m), >= 0 (0 = none)
  AxisArray noise_std{};             ///< Gaussian noise standard deviation per axis (N, N·m), >= 0
  KDL::Wrench bias = KDL::Wrench::Zero();  ///< offset added to the true wrench (N, N·m)
  double filter_cutoff_hz = 0.0;     ///< first-order low-pass cutoff (Hz), >= 0 (0 = no filter)
  double max_rate_hz = 1000.0;       ///< the sensor's output rate (Hz), > 0; informative for bridges
};

/// ATI Nano17 (thesis §4.3.3, I-SUR micro-unit wrist). Saturation = the thesis' overloads.
ForceTorqueSensorModel atiNano17();
/// ATI Nano43 (thesis §5.3.2, suturing arm). Saturation = the thesis' overloads.
ForceTorqueSensorModel atiNano43();
/// IIT FTSens (thesis §6.1.2, Puma 260): range 2000 N / 40 / 30 N·m, resolution 0.25 N,
/// 0.049 / 0.037 N·m, up to 1 kHz.
ForceTorqueSensorModel ftSens();

/// Checks `model`.
/// @throws std::invalid_argument naming the sensor, the parameter, the axis and the expected range.
void validate(const ForceTorqueSensorModel& model);

/// One reading: the measured wrench and which axes saturated (bit i = axis i of AxisArray).
struct ForceTorqueReading {
  KDL::Wrench wrench = KDL::Wrench::Zero();  ///< measured (N, N·m), sensor frame
  std::uint8_t saturated = 0;                ///< bit i set when axis i clipped at its saturation
  bool anySaturated() const noexcept { return saturated != 0; }
};

/// A sensor instance: the model plus its state (filter, random generator seeded from `seed`).
/// `step` is noexcept and allocates nothing; identical seeds and inputs give identical readings.
class ForceTorqueSensor {
 public:
  /// @throws std::invalid_argument when the model is invalid (see validate).
  explicit ForceTorqueSensor(ForceTorqueSensorModel model, std::uint64_t seed = 0);

  /// Advances the sensor by `dt` (s, > 0; a non-positive or non-finite dt holds the filter) with
  /// `true_wrench` (N, N·m, sensor frame) acting on it, and returns the reading.
  const ForceTorqueReading& step(double dt, const KDL::Wrench& true_wrench) noexcept;

  const ForceTorqueReading& reading() const noexcept { return reading_; }
  const ForceTorqueSensorModel& model() const noexcept { return model_; }
  /// Restarts the filter from `wrench` (N, N·m) and reseeds the noise.
  void reset(std::uint64_t seed, const KDL::Wrench& wrench = KDL::Wrench::Zero()) noexcept;

 private:
  ForceTorqueSensorModel model_;
  GaussianNoise noise_;
  AxisArray filtered_{};
  double alpha_dt_ = -1.0;  // s: the dt alpha_ was computed for (a control loop's dt is constant)
  double alpha_ = 1.0;
  bool filter_started_ = false;
  ForceTorqueReading reading_;
};

}  // namespace cobra::sim
