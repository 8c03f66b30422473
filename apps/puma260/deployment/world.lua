-- The simulated world of the Puma 260 task (thesis §6.1, §6.4), in MuJoCo: the arm with its six
-- Elmo drives on a simulated EtherCAT bus, the FTSens with the contact tool at the flange, and the
-- curved surface across the nominal path (world/puma260.xml, the Puma260World component). Its
-- wrench at the sensor feeds a simulated FTSens on a simulated CAN bus. The drivers of
-- deployment/controller.lua find them by name (Puma.bus = "sim:World", FTSens.bus =
-- "sim:FTSensSim"); on the real set-up this file goes and those two properties name the real
-- buses. Sets `world`: the buses, the ports of the world's ground truth the run records and the
-- property giving the contact surface.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
initConfigurator({ "cobra_sim" }, {
  { peer_name = "World", component_type = "Puma260World" },
  { peer_name = "FTSensSim", component_type = "SimulatedFTSens" },
})
getReferences()
World.model = here .. "../world/puma260.xml"
World.seed = 260
FTSensSim.seed = 260

setActivities({ { peer_name = "World", period = 0.001 }, { peer_name = "FTSensSim", period = 0.001 } })  -- s
connectPorts({ { output = "World.sensorWrench", input = "FTSensSim.trueWrench" } })
configureComponents({ "World", "FTSensSim" })  -- before their drivers: each registers its bus at configure
startComponents({ "World", "FTSensSim" })
world = { bus = "sim:World", ftsens = "sim:FTSensSim",
          record = { "World.toolPose", "World.contactForce", "World.penetration" },
          surface = "World.surface_cylinder" }  -- the contact surface (cobra studio draws it)
