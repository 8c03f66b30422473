-- The Configurator listing of the thesis (§3.2.2) with signal components standing in for its
-- four (SineGenerator for MotPlan, Gain for TrajGen, ThresholdDetector for TaskSup, Recorder for
-- Reporter): a playground whose components need no configuration, for the console
-- (`cobra console apps/examples/signal_listing.lua --sim`: `cd TrajGen`, `set k 2`, `trace out 5`,
-- `Reporter.count()`), `cobra describe`'s round trip and the tool's tests. The listing on the real
-- components is configurator_listing.lua.
cp = rtt.Variable("ConnPolicy")

packages_list = {
  "cobra_signal",
}
components_list = {
    { peer_name = "MotPlan", component_type = "SineGenerator"},
    { peer_name = "TrajGen", component_type = "Gain"},
    { peer_name = "TaskSup", component_type = "ThresholdDetector"},
    { peer_name = "Reporter", component_type = "Recorder"},
}

configuration_list = {
  "MotPlan",
  "TrajGen",
  "TaskSup"
}

start_list = {
  "MotPlan",
  "TrajGen",
  "TaskSup"
}

peers_list = {
  { peer_name = "TaskSup", peers_to_add = { "MotPlan" } },
  { peer_name = "Reporter", peers_to_add = { "MotPlan" } }
}

activities_list = {
    {
        peer_name = "TrajGen",
        period = 0.001,
        priority = 95,
        scheduler = rtt.globals.ORO_SCHED_RT
    },
    {
        peer_name = "MotPlan",
        period = 0.01,
        priority = 0,
        scheduler = rtt.globals.ORO_SCHED_RT
    }
}

connections_list = {
  { output = "MotPlan.out", input = "TrajGen.in", conn_policy = cp },
  { output = "TrajGen.out", input = "TaskSup.in", conn_policy = cp },
  { output = "TrajGen.out", input = "Reporter.in", conn_policy = cp },
}

initConfigurator(packages_list, components_list, "")
addPeers(peers_list)
setActivities(activities_list)
connectPorts(connections_list)
configureComponents(configuration_list)
configureComponents({ "Reporter" })
startComponents(start_list)
startComponents({ "Reporter" })
getReferences()
