-- The drivers of the thesis' Puma 260 set-up (§6.2: the EtherCAT master of the six Elmo drives,
-- the FTSens on CAN, the Leap Motion) on simulated devices. Each driver names its device in ONE
-- property; the sim-world components provide the simulated ones as sim:<component name>. On the
-- real set-up the three sim-world components leave this file and the properties become e.g.
--   FTSens.bus = "socketcan:can0"   -- a real CAN adapter (SocketCAN)
--   Puma.bus = "soem:eth0"          -- once a package registers an EtherCAT master backend
-- Nothing else changes: ports, properties and operations of the drivers are the same.
-- Run it: cobra deploy apps/examples/puma260_drivers.lua --sim --run-for 0.1

initConfigurator({ "cobra_sim", "cobra_drivers" }, {
  -- the simulated world (configured first: each registers its device at configure)
  { peer_name = "PumaSim", component_type = "SimulatedPuma260" },
  { peer_name = "FTSensSim", component_type = "SimulatedFTSens" },
  { peer_name = "LeapSim", component_type = "SimulatedLeapMotion" },
  -- the drivers
  { peer_name = "Puma", component_type = "Puma260EtherCATMaster" },
  { peer_name = "FTSens", component_type = "FTSensDriver" },
  { peer_name = "Leap", component_type = "LeapMotionDriver" },
})
getReferences()

Puma.bus = "sim:PumaSim"
FTSens.bus = "sim:FTSensSim"
Leap.device = "sim:LeapSim"

local all = { "PumaSim", "FTSensSim", "LeapSim", "Puma", "FTSens", "Leap" }
local activities = {}
for _, name in ipairs(all) do activities[#activities + 1] = { peer_name = name, period = 0.001 } end  -- s
setActivities(activities)
configureComponents(all)
startComponents(all)
