-- The analytic world of the Puma 260 task, without contact (scenarios/no_contact): the arm with its
-- six Elmo drives on a simulated EtherCAT bus (sim::Puma260Arm) and the FTSens on a simulated CAN
-- bus, nothing in the workspace. The drivers of
-- deployment/controller.lua find them by name (Puma.bus = "sim:World", FTSens.bus =
-- "sim:FTSensSim"); on the real set-up this file goes and those two properties name the real
-- buses. Sets `world`: the names the controller and the run table use for the world's outputs.
initConfigurator({ "cobra_sim" }, {
  { peer_name = "World", component_type = "SimulatedPuma260" },
  { peer_name = "FTSensSim", component_type = "SimulatedFTSens" },
})
getReferences()
FTSensSim.seed = 260

setActivities({ { peer_name = "World", period = 0.001 }, { peer_name = "FTSensSim", period = 0.001 } })  -- s
configureComponents({ "World", "FTSensSim" })  -- before their drivers: each registers its bus at configure
startComponents({ "World", "FTSensSim" })
world = { bus = "sim:World", ftsens = "sim:FTSensSim", record = {} }
