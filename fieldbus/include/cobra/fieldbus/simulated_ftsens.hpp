#pragma once
/// @file
/// A CAN bus with a simulated FTSens on it (sim::ForceTorqueSensor with the `ftSens()` preset
/// behind the frame layout of ftsens_codec.hpp), with fault injection for tests: dropped
/// samples, garbled frames, silence.

#include <array>
#include <cstdint>

#include "cobra/fieldbus/can_bus.hpp"
#include "cobra/fieldbus/ftsens_codec.hpp"
#include "cobra/sim/ft_sensor.hpp"

namespace cobra::fieldbus {

/// The simulated sensor streams nothing until the host sends the stream command
/// (ftSensStreamCommand); then one sample (two frames) every period. Frames the host has not
/// taken wait in a receive queue of 64 frames; beyond that the oldest are overwritten (as a
/// controller's receive FIFO overruns). noexcept and allocation-free after construction.
class SimulatedFtSensBus final : public CanBus {
 public:
  /// @throws std::invalid_argument when the sensor model or the codec configuration is invalid.
  SimulatedFtSensBus(const sim::ForceTorqueSensorModel& sensor, const FtSensCodecConfig& codec, std::uint64_t seed);

  bool send(const CanFrame& frame) noexcept override;
  bool receive(CanFrame& frame) noexcept override;

  /// The wrench acting on the sensor (N, N·m, sensor frame): the simulated world's input.
  void setTrueWrench(const KDL::Wrench& wrench) noexcept { truth_ = wrench; }
  /// Advances time by `dt` (s), producing the samples that fall due.
  void advance(double dt) noexcept;

  /// The next `count` samples are not sent (lost on the bus).
  void dropSamples(int count) noexcept { drop_ = count; }
  /// The next `count` frames get a flipped data bit (the checksum no longer matches).
  void garbleFrames(int count) noexcept { garble_ = count; }
  /// A silent sensor sends nothing (cable pulled) until set back.
  void setSilent(bool silent) noexcept { silent_ = silent; }
  double streamingPeriod() const noexcept { return period_; }  ///< s; 0 = not streaming
  std::uint64_t overruns() const noexcept { return overruns_; }
  const sim::ForceTorqueSensor& sensor() const noexcept { return sensor_; }

 private:
  void enqueue(CanFrame frame) noexcept;

  sim::ForceTorqueSensor sensor_;
  FtSensCodecConfig codec_;
  KDL::Wrench truth_ = KDL::Wrench::Zero();
  std::array<CanFrame, 64> queue_{};
  std::size_t head_ = 0, size_ = 0;
  double period_ = 0.0, since_sample_ = 0.0;  // s
  std::uint8_t sequence_ = 0;
  int drop_ = 0, garble_ = 0;
  bool silent_ = false;
  std::uint64_t overruns_ = 0;
};

}  // namespace cobra::fieldbus
