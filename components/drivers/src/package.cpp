#include "cobra/components/drivers/package.hpp"

#include "cobra/components/drivers/ftsens_driver.hpp"
#include "cobra/components/drivers/leap_motion_driver.hpp"
#include "cobra/components/drivers/puma260_ethercat_master.hpp"
#include "cobra/fieldbus/socketcan_bus.hpp"

namespace cobra::components {

void registerDriversPackage(deploy::PackageBuilder& package) {
  package.component<Puma260EtherCATMaster>("Puma260EtherCATMaster", "Puma 260 EtherCAT/CiA 402 master (thesis §6.2.1)")
      .component<FTSensDriver>("FTSensDriver", "IIT FTSens force/torque sensor on CAN (thesis §6.2.2)")
      .component<LeapMotionDriver>("LeapMotionDriver", "Leap Motion hand tracker (thesis §5.4.4)")
      .backend<fieldbus::CanBus>("socketcan", "Linux SocketCAN: a raw CAN socket on the network interface named",
                                 [](const std::string& interface) {
                                   return std::make_unique<fieldbus::SocketCanBus>(interface);
                                 });
}

}  // namespace cobra::components
