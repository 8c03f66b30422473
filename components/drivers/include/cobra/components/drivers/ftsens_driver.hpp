#pragma once
/// @file
/// The FTSens driver (thesis §6.2.2) as a component: the CAN frame codec of
/// cobra::fieldbus::FtSensDecoder on a cobra::fieldbus::CanBus found by name.

#include <kdl/frames.hpp>
#include <memory>
#include <optional>
#include <string>

#include "cobra/core/component.hpp"
#include "cobra/core/request.hpp"
#include "cobra/fieldbus/ftsens_codec.hpp"
#include "cobra/fieldbus/can_bus.hpp"

namespace cobra::components {

/// Bridge (the thesis calls it a Driver). Needs a periodic activity. At start it commands the
/// sensor to stream every `stream_period`; each update it takes every frame waiting on the bus and
/// publishes the newest complete sample minus the tare.
///
/// Properties: `bus` (the CAN backend, core::BackendRegistry<fieldbus::CanBus>:
/// `socketcan:<interface>` for a real adapter, e.g. socketcan:can0, or `sim:<component>` for the
/// simulated FTSens of that sim-world component, e.g. a SimulatedFTSens; moving to hardware
/// changes this property only), `address` (board address, 0-15), `stream_period` (s, whole
/// milliseconds 1-255 ms), `timeout` (s, > 0: no complete sample for that long raises
/// e_comm_timeout), `tare_samples` (1-10000: how many consecutive samples a tare averages; one
/// sample carries the sensor's noise and its 0.25 N resolution into every later measurement).
///
/// Ports: out `measWrench` (N, N·m, sensor frame).
///
/// Operations: `tare()` (the mean of the next `tare_samples` complete samples becomes the zero;
/// e_tared when taken; the tool must be still meanwhile),
/// `clearTare()`, `statistics()` ("samples N, lost N, garbled N, unpaired N, timeouts N").
///
/// Events: e_comm_timeout, e_comm_restored, e_tared.
class FTSensDriver : public core::Component {
 public:
  explicit FTSensDriver(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  std::string statistics() const;

  core::Property<std::string> bus_{"bus", "", "",
                                   "CAN backend: socketcan:<interface> (e.g. socketcan:can0) or sim:<component>"};
  core::Property<int> address_{"address", 0, "1", "the sensor's board address, 0-15"};
  core::Property<double> stream_period_{"stream_period", 1e-3, "s", "sample period asked of the sensor, 1-255 ms"};
  core::Property<double> timeout_{"timeout", 0.01, "s", "no complete sample for this long raises e_comm_timeout"};
  core::Property<int> tare_samples_{"tare_samples", 100, "1", "consecutive samples a tare averages, 1-10000"};
  core::OutputPort<KDL::Wrench> meas_wrench_{"measWrench", "measured wrench minus the tare, sensor frame", "N, N·m"};

  std::shared_ptr<fieldbus::CanBus> can_;
  std::optional<fieldbus::FtSensDecoder> decoder_;
  KDL::Wrench tare_ = KDL::Wrench::Zero();
  KDL::Wrench tare_sum_ = KDL::Wrench::Zero();
  int tare_count_ = -1;  // samples summed for the tare under way; -1: none
  core::PendingRequest tare_request_, clear_tare_request_;
  bool timed_out_ = false;
  std::uint64_t seen_samples_ = 0, timeouts_ = 0;
  std::chrono::nanoseconds last_sample_{0};
};

}  // namespace cobra::components
