-- The Configurator listings of the thesis (§3.2.2), as printed there, on cobra's components: the
-- thesis' types map to cobra's as ISURMotPlan -> MotionPlanner (cobra_planning, §4.5.1),
-- CartesianTrajGen -> CartesianTrajectoryGenerator (cobra_motion, §4.5.2), OCL::LuaComponent ->
-- Supervisor (cobra_coordination: a Lua rFSM chart), OCL::FileReporting -> Reporter
-- (cobra_reporting: records its peers' ports to CSV). The thesis' packages "ocl" and
-- "kdl_typekit" are built into cobra. Where a value differs from the printed listing, a comment
-- says why. Run it: cobra deploy apps/examples/configurator_listing.lua --sim --run-for 1
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
cp = rtt.Variable("ConnPolicy")

packages_list = {
  "cobra_planning",
  "cobra_motion",
  "cobra_coordination",
  "cobra_reporting",
}
components_list = {
    { peer_name = "MotPlan", component_type = "MotionPlanner"},
    { peer_name = "TrajGen", component_type = "CartesianTrajectoryGenerator"},
    { peer_name = "TaskSup", component_type = "Supervisor"},
    { peer_name = "Reporter", component_type = "Reporter"},
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
  { peer_name = "TaskSup", peers_to_add = { "MotPlan", "TrajGen" } },  -- its chart calls TrajGen too
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
        period = 0,  -- s: the listing's 0.01 s would make it plan in a periodic real-time step;
                     -- cobra's planner runs when asked (askPlan), on its own non-real-time activity
        priority = 0,
        scheduler = rtt.globals.ORO_SCHED_OTHER
    },
    { peer_name = "TaskSup", period = 0.01 },   -- s: steps the chart (not in the printed listing)
    { peer_name = "Reporter", period = 0.01 },  -- s: one CSV row per 10 ms at most
}

-- The thesis' port names (path, events) are cobra's plannedPath, events and inputEvents.
connections_list = {
  { output = "MotPlan.plannedPath", input = "TrajGen.plannedPath", conn_policy = cp },
  { output = "MotPlan.events", input = "TaskSup.inputEvents", conn_policy = { type = "buffer", size = 16 } },
  { output = "TrajGen.events", input = "TaskSup.inputEvents", conn_policy = { type = "buffer", size = 16 } },
}

initConfigurator(packages_list, components_list, "")
getReferences()
-- Properties the printed listing leaves to configuration files (§2.2.3): the planning scene of the
-- puncturing task, the trajectory generator's two arms (needle, probe) and speeds, the chart.
MotPlan.scene_file = here .. "../puncturing/deployment/puncturing.scene"
TrajGen.arms_num = 2
TrajGen.max_vel = 0.05     -- m/s per Cartesian axis
TrajGen.max_ang_vel = 0.5  -- rad/s
TaskSup.fsm_path = here .. "configurator_listing_task.lua"
Reporter.file_path = (os.getenv("TMPDIR") or "/tmp") .. "/cobra_configurator_listing.csv"
addPeers(peers_list)
setActivities(activities_list)
connectPorts(connections_list)
configureComponents(configuration_list)
configureComponents({ "Reporter" })
startComponents(start_list)
startComponents({ "Reporter" })
getReferences()
