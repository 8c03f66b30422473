#pragma once
/// @file
/// A CAN bus with a simulated IIT FTSens on it (thesis §6.1.2): sim::ForceTorqueSensor with the
/// `ftSens()` preset behind the frame layout of fieldbus/ftsens_codec.hpp, with fault injection:
/// dropped samples, garbled frames, silence. The host side is fieldbus::CanBus (what the FTSens
/// driver uses); the world side takes the true wrench and advances time. See device_link.hpp for
/// when each side sees the other's frames.

#include <array>
#include <cstdint>

#include "cobra/fieldbus/can_bus.hpp"
#include "cobra/fieldbus/ftsens_codec.hpp"
#include "cobra/sim/device_link.hpp"
#include "cobra/sim/ft_sensor.hpp"

namespace cobra::sim {

/// The simulated sensor streams nothing until the host sends the stream command
/// (fieldbus::ftSensStreamCommand); then one sample (two frames) every period. Frames the host has
/// not taken wait in a receive queue of 64 frames; frames that find it full are lost and counted
/// as overruns (as a controller's receive FIFO overruns). Every call is noexcept and
/// allocation-free after construction.
class FtSensCanBus final : public fieldbus::CanBus {
 public:
  /// @throws std::invalid_argument when the sensor model or the codec configuration is invalid.
  FtSensCanBus(const ForceTorqueSensorModel& sensor, const fieldbus::FtSensCodecConfig& codec, std::uint64_t seed);

  /// Host side. The sensor takes the frame at the world's next step; false when 16 frames are
  /// already waiting for it, or the sensor is unplugged (the world side detached).
  bool send(const fieldbus::CanFrame& frame) noexcept override;
  /// Host side. False when no frame the host may see is waiting, or the sensor is unplugged.
  bool receive(fieldbus::CanFrame& frame) noexcept override;

  /// World side: the clock and connection state (attach the world component's clock).
  DeviceLink& link() noexcept { return link_; }
  /// World side: the wrench acting on the sensor (N, N·m, sensor frame).
  void setTrueWrench(const KDL::Wrench& wrench) noexcept { truth_ = wrench; }
  /// World side: takes the host's commands, then advances time by `dt` (s), producing the samples
  /// that fall due.
  void advance(double dt) noexcept;
  /// World side: the next `count` samples are not sent (lost on the bus).
  void dropSamples(int count) noexcept { drop_ = count; }
  /// World side: the next `count` frames get a flipped data bit (the checksum no longer matches).
  void garbleFrames(int count) noexcept { garble_ = count; }
  /// World side: a silent sensor sends nothing (cable pulled) until set back.
  void setSilent(bool silent) noexcept { silent_ = silent; }
  double streamingPeriod() const noexcept { return period_; }  ///< s; 0 = not streaming
  std::uint64_t overruns() const noexcept { return overruns_; }
  const ForceTorqueSensor& sensor() const noexcept { return sensor_; }

 private:
  struct StampedFrame {
    fieldbus::CanFrame frame;
    std::int64_t stamp = 0;  // ns
  };
  void enqueue(fieldbus::CanFrame frame, std::int64_t stamp) noexcept;

  DeviceLink link_;
  ForceTorqueSensor sensor_;
  fieldbus::FtSensCodecConfig codec_;
  KDL::Wrench truth_ = KDL::Wrench::Zero();
  SpscQueue<StampedFrame, 64> to_host_;
  SpscQueue<StampedFrame, 16> to_sensor_;
  double period_ = 0.0, since_sample_ = 0.0;  // s
  std::uint8_t sequence_ = 0;
  int drop_ = 0, garble_ = 0;
  bool silent_ = false;
  std::uint64_t overruns_ = 0;
};

}  // namespace cobra::sim
