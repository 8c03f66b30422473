-- The controller of the Puma 260 task (thesis §6.3, Fig. 6.5): the EtherCAT master of the six
-- drives, the FTSens driver, the equivalent wrench (the measured wrench to the tool tip, eq. 6.1),
-- the kinematics solver, the Cartesian trajectory generator fed by three fixed paths (and the
-- retreat off the surface after a safe stop in contact, relative to the tool's pose), the variable
-- admittance, a contact monitor and the task and deployment supervisors. Two deployments, one
-- configuration (configurations/puma260_task.lua):
--   position_control   the trajectory's set-point goes straight to the inverse kinematics (B -> C)
--   compliant_control  through the variable admittance, with the measured wrench (C -> H)
-- Needs the globals `world` (deployment/world.lua) and `kinematics_solver` (the kinematics solver's
-- `solver`: the scenario's kinematics.lua).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
local charts = assert(COBRA_CHARTS, "cobra's charts folder is not found (COBRA_CHARTS): run with the cobra tool, or set "
  .. "COBRA_DATA_DIR to its share/cobra folder")  -- the deployment and configuration supervisors
local T = dofile(here .. "task_geometry.lua")
local buffered = { type = "buffer", size = 64 }

initConfigurator({ "cobra_drivers", "cobra_motion", "cobra_control", "cobra_monitoring", "cobra_coordination" }, {
  { peer_name = "Puma", component_type = "Puma260EtherCATMaster" },
  { peer_name = "FTSens", component_type = "FTSensDriver" },
  { peer_name = "SensorToTip", component_type = "EquivalentWrench" },
  { peer_name = "TipToBase", component_type = "EquivalentWrench" },
  { peer_name = "Kin", component_type = "KinematicsSolver" },
  { peer_name = "ToTaskPose", component_type = "WaypointPath" },
  { peer_name = "ToStartPose", component_type = "WaypointPath" },
  { peer_name = "NominalPath", component_type = "WaypointPath" },
  { peer_name = "Retreat", component_type = "WaypointPath" },
  { peer_name = "TrajGen", component_type = "CartesianTrajectoryGenerator" },
  { peer_name = "Admittance", component_type = "VariableAdmittance" },
  { peer_name = "Contact", component_type = "ContactMonitor" },
  { peer_name = "TaskSup", component_type = "Supervisor" },
  { peer_name = "DepSup", component_type = "Supervisor" },
}, here .. "../configurations")
getReferences()

Puma.bus = world.bus
Puma.control_mode = "position"
Puma.ready_position = T.ready_joints   -- rad; the nest is the master's default (Corke's qn)
Puma.move_speed = 1.0                  -- rad/s: peak joint speed of the nest and ready moves
FTSens.bus = world.ftsens
FTSens.timeout = 0.01                  -- s without a sample: e_comm_timeout
-- Eq. 6.1 twice: the sensor's wrench (sensor frame, at its origin) to the tool tip 0.10 m along
-- its z axis; then into base axes with the measured tool pose, keeping the tip as application point.
SensorToTip.reference_frame = { 0, 0, T.sensor_to_tip, 0, 0, 0, 1 }
TipToBase.invert_reference = true
TipToBase.change_application_point = false
-- The closed form or KDL's solver (§6.2.4: interchangeable): one property, set by the scenario
-- (scenarios/closed_form, scenarios/kdl: "closed_form", "kdl_nr" or "kdl_lma").
Kin.robot = "puma260"
Kin.solver = kinematics_solver
Kin.tool_frame = { 0, 0, T.flange_to_sensor + T.sensor_to_tip, 0, 0, 0, 1 }  -- m: flange to tool tip
Kin.max_joint_velocity = { 2, 2, 2, 2, 2, 2 }  -- rad/s: the master's max_velocity, per joint
ToTaskPose.waypoints = T.task_pose
ToStartPose.waypoints = T.start_pose
NominalPath.waypoints = T.final_pose
-- Stopped in contact (charts/puma260_task.lua, Retreating): T.retreat m up from wherever the tool
-- is, its orientation kept, at the speed of configurations/puma260_retreat.lua.
Retreat.relative = true
Retreat.waypoints = { 0, 0, T.retreat, 0, 0, 0, 1 }
TrajGen.arms_num = 1
-- The smallest inertia and stiffness the admittance ever implements (fixed at configure; the
-- configuration's are above them, the tank pays the difference) and its tank, J.
Admittance.constant_inertia = { 1, 1, 1, 0.05, 0.05, 0.05 }
Admittance.constant_stiffness = { 1500, 1500, 250, 30, 30, 30 }
Admittance.tank_initial = 2
Admittance.tank_max = 5
Admittance.tank_min = 0.5
-- s: a silent FTSens (no sample for 5 ms) makes the admittance hold where it is instead of pushing
-- on with the last force; the chart's Holding (the driver's e_comm_timeout, 10 ms) then stops the path.
Admittance.wrench_timeout = 0.005
TaskSup.fsm_path = here .. "../charts/puma260_task.lua"
DepSup.fsm_path = charts .. "deployment_supervisor.lua"
addPeers({ { peer_name = "TaskSup",
             peers_to_add = { "Puma", "FTSens", "ToTaskPose", "ToStartPose", "NominalPath", "Retreat", "TrajGen" } } })

local activities = {}
for _, name in ipairs({ "Puma", "FTSens", "SensorToTip", "TipToBase", "Kin", "ToTaskPose", "ToStartPose", "NominalPath",
                        "Retreat", "TrajGen", "Admittance", "Contact", "TaskSup", "DepSup" }) do
  activities[#activities + 1] = { peer_name = name, period = 0.001 }  -- s: the 1 kHz bus cycle
end
setActivities(activities)

local always = { "Puma", "FTSens", "SensorToTip", "TipToBase", "Kin", "TaskSup", "DepSup" }
configureComponents(always)
configureComponents({ "TrajGen" })  -- its desCartPose_1 and desCartTwist_1 exist once configured
local connections = {
  { output = "Puma.measJointPosition", input = "Kin.jointPositions" },
  { output = "Kin.desJointPositions", input = "Puma.desJointPosition" },
  -- The drives quick-stopped (Fault): the kinematics solver takes the held joints as its reference
  -- and passes them on as heldCartPose, as for a refused command (ARCHITECTURE §7).
  { output = "Puma.heldJointPosition", input = "Kin.heldJointPositions" },
  { output = "FTSens.measWrench", input = "SensorToTip.inWrench" },
  { output = "SensorToTip.outWrench", input = "TipToBase.inWrench" },
  { output = "Kin.cartPose", input = "TipToBase.referenceFrame" },
  { output = "TaskSup.outputEvents", input = "DepSup.inputEvents", conn_policy = buffered },
  { output = "DepSup.outputEvents", input = "TaskSup.inputEvents", conn_policy = buffered },
}
for _, path in ipairs({ "ToTaskPose", "ToStartPose", "NominalPath", "Retreat" }) do
  connections[#connections + 1] = { output = "Kin.cartPose", input = path .. ".measPose" }
  connections[#connections + 1] = { output = path .. ".path", input = "TrajGen.plannedPath", conn_policy = buffered }
end
for _, source in ipairs({ "Puma", "FTSens", "Kin", "ToTaskPose", "ToStartPose", "NominalPath", "Retreat", "TrajGen", "Admittance",
                          "Contact" }) do
  connections[#connections + 1] = { output = source .. ".events", input = "TaskSup.inputEvents",
                                    conn_policy = buffered }
end
connectPorts(connections)

-- The retreat runs in position_control only: the admittance and the FTSens may be what failed.
local paths = { "ToTaskPose", "ToStartPose", "NominalPath", "Retreat", "TrajGen" }
defineDeployment("position_control", {
  components = paths,
  connections = {
    { output = "TrajGen.desCartPose_1", input = "Kin.desCartPose" },
    -- Held (a refused command, a quick stop): the trajectory generator's motion ends at the held pose.
    { output = "Kin.heldCartPose", input = "TrajGen.heldPose_1" },
  },
})
defineDeployment("compliant_control", {
  components = { "ToTaskPose", "ToStartPose", "NominalPath", "TrajGen", "Admittance", "Contact" },
  connections = {
    { output = "TrajGen.desCartPose_1", input = "Admittance.refPose" },
    { output = "TrajGen.desCartTwist_1", input = "Admittance.refTwist" },
    { output = "TipToBase.outWrench", input = "Admittance.measWrench" },
    { output = "Admittance.admPose", input = "Kin.desCartPose" },
    -- Held: the admittance re-syncs to the held pose, the trajectory generator to its reference.
    { output = "Kin.heldCartPose", input = "Admittance.heldPose" },
    { output = "Admittance.heldRefPose", input = "TrajGen.heldPose_1" },
    { output = "TipToBase.outWrench", input = "Contact.measWrench" },
    { output = "Kin.cartPose", input = "Contact.measPose" },
    { output = "TrajGen.desCartPose_1", input = "Contact.nominalPose" },
  },
})
applyConfiguration("puma260_task")
startComponents(always)
applyDeployment("position_control")
