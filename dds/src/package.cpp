// The package cobra_dds (libcobra_dds.so, `packages_list = { "cobra_dds" }`): loading it
// registers the transport "dds" and the component type DdsLink, whose participant the transport
// uses.
#include "cobra/dds/dds_link.hpp"
#include "cobra/deploy/package_registry.hpp"

extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion; }

extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
  cobra::dds::registerLinkedTransport();
  package.component<cobra::dds::DdsLink>(
      "DdsLink", "links this process to the others of a run over Fast DDS: the dds transport's participant, "
                 "peer liveliness (e_peer_lost, e_peer_joined), lockstep clock meetings");
}
