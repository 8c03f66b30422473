// A shared-library package for the tests: "cobra_test_filters" with one component type,
// Offset (y = u + offset), loaded through dlopen by PackageRegistry.

#include <cstdint>

#include "cobra/core/component.hpp"
#include "cobra/deploy/package_registry.hpp"

namespace {

class Offset : public cobra::core::Component {
 public:
  explicit Offset(std::string name)
      : Component(std::move(name), cobra::core::Role::Calculation, "Adds a constant: y = u + offset") {
    addEventPort(in_);
    addPort(out_);
    addProperty(offset_);
  }

 protected:
  void updateHook() override {
    double u = 0.0;
    while (in_.read(u) == cobra::core::FlowStatus::NewData) out_.write(u + offset_());
  }

 private:
  cobra::core::InputPort<double> in_{"in", "signal u", "1"};
  cobra::core::OutputPort<double> out_{"out", "signal y = u + offset", "1"};
  cobra::core::Property<double> offset_{"offset", 0.0, "1", "value added to every sample"};
};

}  // namespace

extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion; }

extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
  package.component<Offset>("Offset", "adds a constant to a signal");
}
