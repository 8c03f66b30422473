#include "cobra/components/signal/package.hpp"

#include "cobra/components/signal/constant.hpp"
#include "cobra/components/signal/gain.hpp"
#include "cobra/components/signal/recorder.hpp"
#include "cobra/components/signal/sine_generator.hpp"
#include "cobra/components/signal/threshold_detector.hpp"

namespace cobra::components {

void registerSignalPackage(deploy::PackageBuilder& package) {
  package.component<SineGenerator>("SineGenerator", "y(t) = offset + amplitude·sin(2π·frequency·t + phase)")
      .component<Gain>("Gain", "y = k·u on every sample")
      .component<ThresholdDetector>("ThresholdDetector", "events when a signal crosses a threshold")
      .component<Recorder>("Recorder", "keeps (time, value) samples in memory")
      .component<Constant>("Constant", "writes the value of a property at every update");
}

}  // namespace cobra::components
