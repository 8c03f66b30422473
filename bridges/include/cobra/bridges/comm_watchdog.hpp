#pragma once
/// @file
/// Decides when a link counts as lost and when as restored, from "fresh valid data arrived this
/// cycle" and the time. noexcept, allocation-free: for the bridges' update.

#include <cstdint>

namespace cobra::bridges {

class CommWatchdog {
 public:
  enum class Change { None, TimedOut, Restored };

  /// Starts a watch at `now_ns`: the timeout counts from here until the first valid data.
  void arm(std::int64_t now_ns) noexcept {
    last_valid_ns_ = now_ns;
    timed_out_ = false;
  }
  /// `fresh`: new valid data arrived since the last call. TimedOut once when `timeout_ns` passed
  /// without any; Restored once when data come back after that.
  Change update(bool fresh, std::int64_t now_ns, std::int64_t timeout_ns) noexcept {
    if (fresh) {
      last_valid_ns_ = now_ns;
      if (timed_out_) {
        timed_out_ = false;
        return Change::Restored;
      }
      return Change::None;
    }
    if (!timed_out_ && now_ns - last_valid_ns_ > timeout_ns) {
      timed_out_ = true;
      return Change::TimedOut;
    }
    return Change::None;
  }
  bool timedOut() const noexcept { return timed_out_; }

 private:
  std::int64_t last_valid_ns_ = 0;
  bool timed_out_ = false;
};

}  // namespace cobra::bridges
