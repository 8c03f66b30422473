// The package's entry points: what the deployer calls after dlopen("libexample_filters.so").

#include <cstdint>

#include "cobra/deploy/package_registry.hpp"
#include "cobra/types/register_type.hpp"
#include "force_low_pass.hpp"
#include "force_sample.hpp"
#include "force_sample_hold.hpp"

extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion; }

extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
  // The package's own type, with every capability of the loading cobra: Lua, CSV, DDS.
  cobra::types::registerType<example::ForceSample>();
  package.component<example::ForceLowPass>("ForceLowPass", "first-order low-pass filter of a force (N)");
  package.component<example::ForceSampleHold>("ForceSampleHold", "holds the latest example.ForceSample it receives");
}
