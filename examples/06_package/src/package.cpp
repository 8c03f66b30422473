// The package's entry points: what the deployer calls after dlopen("libexample_filters.so").

#include <cstdint>

#include "cobra/deploy/package_registry.hpp"
#include "force_low_pass.hpp"

extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion; }

extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
  package.component<example::ForceLowPass>("ForceLowPass", "first-order low-pass filter of a force (N)");
}
