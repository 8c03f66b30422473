-- Tutorial 07: a new task written as files only, on cobra's existing components (README.md walks
-- through it). A simulated UR5 holding an ultrasound probe scans a part on a table: it approaches
-- the part, sweeps the probe over it in three lines, and goes back.
--   cobra run examples/07_task                      (runs until the chart is Done; writes a report)
--   cobra deploy examples/07_task/07_task.lua --sim --run-for 20   (deploys and steps it only)
-- World frame = the UR5's base: z up, the table top at z = 0; the part is a 0.2 x 0.3 x 0.1 m box
-- whose top is at z = 0.1 m. Units: m, rad, s.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
-- cobra's own charts (the deployment and configuration supervisors), wherever cobra is: the tool
-- sets COBRA_CHARTS (its build tree's or its installation's share/cobra/charts/), so this folder
-- can be copied anywhere and still run.
local charts = assert(COBRA_CHARTS, "cobra's charts folder is not found (COBRA_CHARTS): run with the cobra tool, or set "
  .. "COBRA_DATA_DIR to its share/cobra folder")

-- 1. Components: which packages to load, and the instances by type name.
initConfigurator({ "cobra_sim", "cobra_motion", "cobra_coordination" }, {
  { peer_name = "UR5", component_type = "SimulatedUR5Robot" },     -- the robot (a real one: its bridge)
  { peer_name = "TrajGen", component_type = "CartesianTrajectoryGenerator" },
  { peer_name = "ApproachPath", component_type = "WaypointPath" },  -- one path source per motion
  { peer_name = "ScanPath", component_type = "WaypointPath" },
  { peer_name = "RetreatPath", component_type = "WaypointPath" },
  { peer_name = "TaskSup", component_type = "Supervisor" },         -- the three supervisors of
  { peer_name = "DepSup", component_type = "Supervisor" },          -- thesis Fig. 2.6
  { peer_name = "ConfSup", component_type = "Supervisor" },
}, here .. "configurations")
getReferences()

-- 2. Properties.
UR5.tool_frame = { 0, 0, 0.12, 0, 0, 0, 1 }                      -- m: the probe's face, 12 cm out of the flange
UR5.initial_joints = { 0.0, -1.4495, -1.714, 1.5925, -1.571, 0 }  -- rad: probe down at (0.246, -0.109, 0.300) m
UR5.max_velocity = { 3.14, 3.14, 3.14, 3.14, 3.14, 3.14 }          -- rad/s: the UR5's joint limits (its
                                                                   -- defaults, stated for cobra run's joint-jump check)
TrajGen.arms_num = 1
TrajGen.time_acc = 0.2     -- s: blends at the waypoints
TrajGen.stop_time = 0.3    -- s
-- Poses: x, y, z [m], then the quaternion qx, qy, qz, qw of the probe: pointing down (z of the tool
-- along -z of the world), as the robot starts.
local down = { 0.70710678, 0.70710678, 0, 0 }
local function poses(list)
  local values = {}
  for _, p in ipairs(list) do
    for _, v in ipairs({ p[1], p[2], p[3], down[1], down[2], down[3], down[4] }) do values[#values + 1] = v end
  end
  return values
end
local scan_z = 0.15  -- m: 5 cm above the part's top
ApproachPath.waypoints = poses({ { 0.35, -0.15, 0.25 }, { 0.35, -0.15, scan_z } })
ScanPath.waypoints = poses({ { 0.35, 0.05, scan_z }, { 0.40, 0.05, scan_z }, { 0.40, -0.15, scan_z },
                             { 0.45, -0.15, scan_z }, { 0.45, 0.05, scan_z } })
RetreatPath.waypoints = poses({ { 0.45, 0.05, 0.25 }, { 0.246, -0.109, 0.300 } })
TaskSup.fsm_path = here .. "scan_task.lua"
DepSup.fsm_path = charts .. "deployment_supervisor.lua"
ConfSup.fsm_path = charts .. "configuration_supervisor.lua"

-- 3. Activities: everything at 1 kHz (on the lockstep clock when simulated).
local always = { "UR5", "TrajGen", "DepSup", "ConfSup", "TaskSup" }
local activities = {}
for _, name in ipairs({ "UR5", "TrajGen", "ApproachPath", "ScanPath", "RetreatPath", "TaskSup", "DepSup", "ConfSup" }) do
  activities[#activities + 1] = { peer_name = name, period = 0.001 }
end
setActivities(activities)
-- The task chart calls these by name (TrajGen:askStartMove(), ScanPath:askPath()).
addPeers({ { peer_name = "TaskSup", peers_to_add = { "TrajGen", "ApproachPath", "ScanPath", "RetreatPath" } } })
configureComponents({ "TrajGen" })  -- its desCartPose_1 port exists once configured

-- 4. Connections that never change: commands to the robot, measurements to the path sources,
-- every event to the task chart, the task chart's requests to the deployment and configuration
-- supervisors.
local buffered = { type = "buffer", size = 64 }
local connections = {
  { output = "TrajGen.desCartPose_1", input = "UR5.desCartPose" },
  -- The robot refusing a command holds: the motion ends at the held pose (ARCHITECTURE §7).
  { output = "UR5.heldCartPose", input = "TrajGen.heldPose_1" },
  { output = "TaskSup.outputEvents", input = "DepSup.inputEvents", conn_policy = buffered },
  { output = "TaskSup.outputEvents", input = "ConfSup.inputEvents", conn_policy = buffered },
  { output = "DepSup.outputEvents", input = "TaskSup.inputEvents", conn_policy = buffered },
  { output = "ConfSup.outputEvents", input = "TaskSup.inputEvents", conn_policy = buffered },
}
for _, source in ipairs({ "UR5", "TrajGen", "ApproachPath", "ScanPath", "RetreatPath" }) do
  connections[#connections + 1] = { output = source .. ".events", input = "TaskSup.inputEvents", conn_policy = buffered }
end
for _, path in ipairs({ "ApproachPath", "ScanPath", "RetreatPath" }) do
  connections[#connections + 1] = { output = "UR5.measCartPose", input = path .. ".measPose" }
end
connectPorts(connections)
configureComponents(always)
startComponents(always)

-- 5. Deployments, one per motion: which path source runs and feeds the trajectory generator.
-- The deployment supervisor applies them when the chart asks (e_deploy_<name>).
for _, d in ipairs({ { "approach", "ApproachPath" }, { "scan", "ScanPath" }, { "retreat", "RetreatPath" } }) do
  defineDeployment(d[1], { components = { d[2] }, connections = { { output = d[2] .. ".path", input = "TrajGen.plannedPath" } } })
end
-- Configurations (configurations/fast.lua, slow.lua) are found in the folder given to initConfigurator.

-- 6. What `cobra run` watches: the chart that ends the run, what it records and draws.
run = {
  title = "Tutorial 07: a probe scan on a simulated UR5",
  charts = { { name = "scan", supervisor = "TaskSup", done = "root.Done", safe_stop = "root.Failed" } },
  fold = { "Switching", "AskingPath", "Generating", "Moving" },  -- print each motion once, not its steps
  failures = { "e_ik_discontinuity", "e_ik_failed", "e_traj_failed", "e_no_data" },
  record = { period = 0.01, ports = { "UR5.measCartPose", "TrajGen.desCartPose_1" } },
  tracking = {
    { name = "UR5 probe", commanded = "TrajGen.desCartPose_1", measured = "UR5.measCartPose",
      joints = "UR5.measJointPosition", max_velocity = "UR5.max_velocity", chart = "scan" },
  },
  plots = {
    { title = "probe height", unit = "m", series = { "UR5.measCartPose.z", "TrajGen.desCartPose_1.z" } },
    { title = "the scan seen from above", unit = "m", x = "UR5.measCartPose.x", x_unit = "m",
      series = { "UR5.measCartPose.y" } },
  },
  summary = {
    { name = "refused commands", count = { "e_ik_discontinuity", "e_ik_failed" } },
  },
}
