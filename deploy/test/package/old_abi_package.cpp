// A shared-library package built for another package ABI: loading it must be refused.

#include <cstdint>

#include "cobra/deploy/package_registry.hpp"

extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion + 1; }

extern "C" void cobra_register_package(cobra::deploy::PackageBuilder&) {}
