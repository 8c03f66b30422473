#pragma once
/// @file
/// Recorder: a Bridge component that keeps (time, value) samples of a signal in memory.

#include <vector>

#include "cobra/core/component.hpp"

namespace cobra::components {

/// One recorded sample: time on the recorder's clock (s) and the value read.
struct Sample {
  double time;
  double value;
};

/// Appends every sample read on `in` (an event port) to a buffer preallocated at configure
/// time (`capacity` samples), so recording allocates nothing while running. When the buffer
/// is full, further samples are counted in `dropped` and not stored. Operations `count()` and
/// `clear()` run between two updates (own thread), so they are safe while it runs.
class Recorder : public core::Component {
 public:
  explicit Recorder(std::string name);

  /// The samples recorded so far. Read it when the recorder is not Running (or from its thread).
  const std::vector<Sample>& samples() const { return samples_; }

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  int count() const { return static_cast<int>(samples_.size()); }
  void clear();

  core::InputPort<double> in_{"in", "the recorded signal", "1"};
  core::Property<int> capacity_{"capacity", 10000, "1", "most samples kept (preallocated at configure)"};
  core::Property<int> dropped_{"dropped", 0, "1", "samples not stored because the buffer was full"};
  std::vector<Sample> samples_;
};

}  // namespace cobra::components
