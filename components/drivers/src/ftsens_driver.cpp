#include "cobra/components/drivers/ftsens_driver.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cobra/core/activity.hpp"
#include "cobra/core/backend_registry.hpp"

namespace cobra::components {

FTSensDriver::FTSensDriver(std::string name)
    : Component(std::move(name), core::Role::Bridge, "IIT FTSens force/torque sensor on CAN (thesis §6.2.2)") {
  for (core::PropertyBase* p :
       std::initializer_list<core::PropertyBase*>{&bus_, &address_, &stream_period_, &timeout_, &tare_samples_})
    addProperty(*p);
  addPort(meas_wrench_);
  addOperation("tare", std::function<void()>([this] { tare_request_.ask(activity()); }),
               "the mean of the next tare_samples complete samples becomes the zero of measWrench; e_tared when "
               "taken");
  addOperation("clearTare", std::function<void()>([this] { clear_tare_request_.ask(activity()); }),
               "measWrench = raw sample again");
  addOperation("statistics", std::function<std::string()>([this] { return statistics(); }),
               "counts of samples and of frame errors");
}

bool FTSensDriver::configureHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: each update reads the CAN bus");
  const double ms = stream_period_() * 1e3;
  if (!std::isfinite(ms) || std::abs(ms - std::round(ms)) > 1e-6 || ms < 1 || ms > 255)
    return refuse("property stream_period = " + std::to_string(stream_period_()) +
                  " s; expected whole milliseconds from 0.001 to 0.255 s (the sensor's period command is 1-255 ms)");
  if (!(timeout_() > 0.0)) return refuse("property timeout = " + std::to_string(timeout_()) + " s; expected > 0 s");
  if (tare_samples_() < 1 || tare_samples_() > 10000)
    return refuse("property tare_samples = " + std::to_string(tare_samples_()) + "; expected 1 to 10000 samples");
  fieldbus::FtSensCodecConfig codec;
  codec.address = address_();
  try {
    decoder_.emplace(codec);
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  try {
    can_ = core::BackendRegistry<fieldbus::CanBus>::open(bus_());
  } catch (const std::exception& e) {
    decoder_.reset();
    return refuse("property bus = '" + bus_() + "': " + e.what());
  }
  tare_ = KDL::Wrench::Zero();
  tare_count_ = -1;
  tare_request_.clear();
  clear_tare_request_.clear();
  timed_out_ = false;
  seen_samples_ = timeouts_ = 0;
  return true;
}

bool FTSensDriver::startHook() {
  fieldbus::FtSensCodecConfig codec;
  codec.address = address_();
  const auto period_ms = static_cast<std::uint8_t>(std::lround(stream_period_() * 1e3));
  if (!can_->send(fieldbus::ftSensStreamCommand(codec, period_ms)))
    return refuse("the CAN transmit queue is full: the stream command was not sent");
  last_sample_ = now();
  return true;
}

void FTSensDriver::cleanupHook() {
  decoder_.reset();
  can_.reset();
}

std::string FTSensDriver::statistics() const {
  if (!decoder_) return "not configured";
  return "samples " + std::to_string(decoder_->samples()) + ", lost " + std::to_string(decoder_->lost()) +
         ", garbled " + std::to_string(decoder_->garbled()) + ", unpaired " + std::to_string(decoder_->unpaired()) +
         ", timeouts " + std::to_string(timeouts_);
}

void FTSensDriver::updateHook() {
  fieldbus::CanFrame frame;
  // Bounded: at most one receive queue's worth per update.
  for (int i = 0; i < 256 && can_->receive(frame); ++i) (void)decoder_->push(frame);
  if (clear_tare_request_.take()) tare_ = KDL::Wrench::Zero();
  if (tare_request_.take()) {
    tare_sum_ = KDL::Wrench::Zero();
    tare_count_ = 0;
  }
  if (decoder_->samples() != seen_samples_) {
    seen_samples_ = decoder_->samples();
    last_sample_ = now();
    if (tare_count_ >= 0) {
      tare_sum_ += decoder_->wrench();
      if (++tare_count_ == tare_samples_()) {
        tare_ = tare_sum_ / static_cast<double>(tare_count_);
        tare_count_ = -1;
        emitEvent("e_tared");
      }
    }
    meas_wrench_.write(decoder_->wrench() - tare_);
    if (timed_out_) {
      timed_out_ = false;
      emitEvent("e_comm_restored");
    }
  } else if (!timed_out_ && std::chrono::duration<double>(now() - last_sample_).count() > timeout_()) {
    timed_out_ = true;
    ++timeouts_;
    emitEvent("e_comm_timeout");
  }
}

}  // namespace cobra::components
