-- The two-armed I-SUR's controller for the suturing task (thesis §5.5.1-5.5.2, Fig. 5.12): the
-- three deployments (autonomous with motion planning, autonomous with motion primitives,
-- teleoperated with the State Validator between the admittances and the robot) of scope
-- "suture", the configurations suturing_free_motion, suturing_contact and suturing_teleoperation
-- (configurations/), and the task/deployment/configuration supervisors of the puncturing task,
-- reused unchanged. One variable admittance per arm, each with its energy tank.
-- Needs the globals `right_tool_frame`, `left_tool_frame`, `phantom_pose`, `teleop_device`
-- ("leap" or "omni": which haptic device the teleoperated deployment reads); optional
-- `teleop_link` = { delay = s, jitter = s, loss = 0..1, seed = n }: the impairment of the link
-- between the devices and the controller (each arm's LinkImpairment; default: none).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
local charts = assert(COBRA_CHARTS, "cobra's charts folder is not found (COBRA_CHARTS): run with the cobra tool, or set "
  .. "COBRA_DATA_DIR to its share/cobra folder")  -- the deployment and configuration supervisors
local buffered = { type = "buffer", size = 64 }
local couplings = dofile(charts .. "teleoperation_coupling.lua")  -- the two-layer coupling's wiring

local devices = {
  -- Leap Motion (§5.4.4): the simulated device and the driver reading it; both hands (the
  -- simulator's scripted hands: a fault script moves and turns them, LeapSim.right_hand). No
  -- twist and no force feedback: the device measures poses only and renders nothing.
  leap = { components = { { peer_name = "LeapSim", component_type = "SimulatedLeapMotion" },
                          { peer_name = "Leap", component_type = "LeapMotionDriver" } },
           right = "Leap.measRightPose", left = "Leap.measLeftPose" },
  -- Two Phantom Omnis, one per arm: pose and twist (six DoF: the gimbal is measured), and the
  -- force of the coupling rendered on the hand (desWrench).
  omni = { components = { { peer_name = "RightOmni", component_type = "SimulatedOmniPhantom" },
                          { peer_name = "LeftOmni", component_type = "SimulatedOmniPhantom" } },
           right = "RightOmni.measCartPose", left = "LeftOmni.measCartPose",
           right_twist = "RightOmni.measTwist", left_twist = "LeftOmni.measTwist",
           right_dissipation = "RightOmni.dissipatedPower", left_dissipation = "LeftOmni.dissipatedPower",
           right_feedback = "RightOmni.desWrench", left_feedback = "LeftOmni.desWrench",
           -- What the Omni renders (N, N·m): its saturation, and no wrist torque.
           max_force = 3.3, max_torque = 0.0 },
}
local device = assert(devices[teleop_device], "teleop_device must be leap or omni, not " .. tostring(teleop_device))

local controller = {
  { peer_name = "Stitches", component_type = "StitchPlanner" },
  { peer_name = "ArmsRest", component_type = "RestMonitor" },  -- the chart's Finishing: both tools at rest
  { peer_name = "SutureFrames", component_type = "SuturingFrameGenerator" },
  { peer_name = "SuturePlanner", component_type = "MotionPlanner" },
  { peer_name = "SutureTrajGen", component_type = "CartesianTrajectoryGenerator" },
  { peer_name = "RightWrench", component_type = "EquivalentWrench" },
  { peer_name = "LeftWrench", component_type = "EquivalentWrench" },
  { peer_name = "RightAdmittance", component_type = "VariableAdmittance" },
  { peer_name = "LeftAdmittance", component_type = "VariableAdmittance" },
  { peer_name = "Validator", component_type = "StateValidator" },
  { peer_name = "RightClutch", component_type = "TeleoperationClutch" },
  { peer_name = "LeftClutch", component_type = "TeleoperationClutch" },
  { peer_name = "RightLink", component_type = "LinkImpairment" },
  { peer_name = "LeftLink", component_type = "LinkImpairment" },
  { peer_name = "RightTransparency", component_type = "TransparencyLayer" },
  { peer_name = "LeftTransparency", component_type = "TransparencyLayer" },
  { peer_name = "RightMasterPassivity", component_type = "PassivityLayer" },  -- beside each device
  { peer_name = "LeftMasterPassivity", component_type = "PassivityLayer" },
  { peer_name = "RightSlavePassivity", component_type = "PassivityLayer" },   -- beside each admittance
  { peer_name = "LeftSlavePassivity", component_type = "PassivityLayer" },
  { peer_name = "TaskSup", component_type = "Supervisor" },
  { peer_name = "DepSup", component_type = "Supervisor" },
  { peer_name = "ConfSup", component_type = "Supervisor" },
}
for _, c in ipairs(device.components) do controller[#controller + 1] = c end
initConfigurator({ "cobra_motion", "cobra_control", "cobra_coordination", "cobra_planning", "cobra_sim", "cobra_drivers",
                   "cobra_suturing" }, controller, here .. "configurations")
getReferences()

SutureFrames.state_table_file = here .. "../state_table.txt"
-- m, stitch frames (x along the cut, z out of the skin): where each tool works, against the Endo
-- Stitch's 10 mm envelope and the stick (apps/suturing/deployment/suturing.scene; measured, README "Where the
-- stick works"). The Endo Stitch pulls the thread 8 mm ahead along the cut, 37 mm above the
-- stitch's centre (12 mm and 10 mm ahead, the +15 degree cut's first pull ended in
-- e_ik_discontinuity: the robot refused a pose off its IK branch). The stick hooks it 12 mm above
-- the last half's edge target, 3.5 mm ahead and 1.2 mm outward (on the free thread there), and pushes it 10 mm back
-- along the cut (16 mm folded the two upper arms to 1.7 mm on the +15 degree cut; the thread's
-- pull, up to 4.9 N on the compliant stick, stops it about 5 mm short anyway). Before each half it
-- waits aside, 16 mm back, 18 mm towards the left edge (its own side) and 15 mm above the stitch's
-- centre (state_table.txt, MoveOverWound: the same place for both halves, off the thread's line
-- and out of the Endo Stitch's way). Worst clearance 4.85 mm (the +15 degree cut) to 5.44 mm.
SutureFrames.pull_offset = { 0.008, 0.0, 0.037 }
SutureFrames.hook_offset = { 0.0035, 0.0012, 0.012 }
SutureFrames.push_offset = { -0.010, 0.0005, 0.012 }
SutureFrames.aside_offset = { -0.016, 0.018, 0.015 }
for _, p in ipairs({ SuturePlanner, Validator }) do
  p.scene_file = here .. "suturing.scene"
  p.phantom_pose = phantom_pose
  p.first_tool_frame = right_tool_frame    -- the scene's I-SUR tool 0: the Endo Stitch's tip (frames.lua)
  p.second_tool_frame = left_tool_frame    -- its tool 1: the stick's tip (frames.lua)
end
SuturePlanner.first_bounds_low = { 0.05, -0.12, 0.05 }    -- m: the Endo Stitch's tip over the phantom
SuturePlanner.first_bounds_high = { 0.3, 0.12, 0.3 }
SuturePlanner.second_bounds_low = { 0.05, -0.12, 0.05 }   -- m: the stick's tip
SuturePlanner.second_bounds_high = { 0.3, 0.12, 0.3 }
SuturePlanner.max_validity_checks = 20000  -- a work limit: the same plan on any machine
SuturePlanner.max_vel = 0.02                -- m/s: near the patient, slowly (the trajectory generator's)
SuturePlanner.max_ang_vel = 0.3             -- rad/s
SutureTrajGen.arms_num = 2                  -- 1: the Endo Stitch, 2: the stick
SutureTrajGen.max_vel = 0.02
SutureTrajGen.max_ang_vel = 0.3
for _, w in ipairs({ RightWrench, LeftWrench }) do
  w.invert_reference = true          -- the measured tool pose turns the sensor wrench
  w.change_application_point = false -- into world axes, at the tool point
end
-- A reference faster than 0.1 m/s / 1 rad/s between two steps is a jump the admittance rebases
-- (its output stays continuous) instead of the default 1 m/s / 3 rad/s: every motion's path
-- starts at the measured pose, which the thread's pull on an arm (the hooked stick's at
-- PushThread's start) displaces from its admittance's output by a few tenths of a mm, under the
-- default's 1 mm a step; unrebased, that step reached the robot as a command jump it refused
-- (e_ik_discontinuity). The paths themselves move the tools at most 0.02 m/s and 0.3 rad/s (the
-- gripper, 0.15 m behind the stick's tip, below 0.07 m/s); a teleoperation's device moving faster
-- is reached through the admittance's dynamics instead of step by step.
for _, a in ipairs({ RightAdmittance, LeftAdmittance }) do
  a.max_reference_speed = 0.1
  a.max_reference_angular_speed = 1.0
end
TaskSup.fsm_path = here .. "../charts/suturing.lua"
DepSup.fsm_path = charts .. "deployment_supervisor.lua"
ConfSup.fsm_path = charts .. "configuration_supervisor.lua"
if Leap then Leap.device = "sim:LeapSim" end
if LeapSim then LeapSim.scripted_hands = true end  -- the surgeon's hands above the device (fault scripts move them)
-- The Leap's 0.5 mm noise per sample: its clutches engage on the mean of 0.2 s of frames (40 at
-- 200 fps; 0.08 mm), else one sample's error would offset the tool for the whole teleoperation,
-- and smooth its positions over 0.05 s (about 0.1 mm left), else the jitter would shake the tools.
if Leap then
  for _, c in ipairs({ RightClutch, LeftClutch }) do
    c.engagement_time = 0.5
    c.smoothing_time = 0.1
  end
end
-- The two-layer coupling (thesis §4.5.4), per arm. N/m, N·s/m: stiffer than the layer's default
-- (50 N/m) so that the thread's pull (a few N) shows as a few mm between master and slave, not
-- cm; the slave's admittance (4 kg, 126 N·s/m in free motion) and this spring settle in about
-- 0.1 s. The Omni renders at most 3.3 N of it. Over a delayed link 30 N·s/m / (delay + jitter),
-- at most 1000 N/m, unless teleop_link.stiffness says (teleoperation_coupling.lua, M.stiffness:
-- the master's wrench comes a round trip late; 1000 N/m kept the device and the tool swinging by
-- mm at 100 ms, 300 N/m settles).
local coupling_stiffness = couplings.stiffness(teleop_link)
for _, t in ipairs({ RightTransparency, LeftTransparency }) do
  t.stiffness = coupling_stiffness
  t.damping = 20
  -- N·m/rad, N·m·s/rad: the tool's orientation follows the device's through the admittance's
  -- rotation (0.2 kg·m², 4 N·m·s/rad: critically damped at 20 N·m/rad, about 0.2 s). Nothing of
  -- it comes back over the link: neither device renders a torque.
  t.rotational_stiffness = 20
  t.rotational_damping = 0.5
end
-- The master tanks pay for the wrench the device renders, not for one it cannot exert (a device
-- that declares no limit: any wrench; the Leap, without feedback: none).
for _, side in ipairs({ "right", "left" }) do
  couplings.render((side == "right" and "Right" or "Left") .. "MasterPassivity",
                   { feedback = device[side .. "_feedback"], max_force = device.max_force, max_torque = device.max_torque })
end
-- The link between the devices and the controller: none unless `teleop_link` says so.
couplings.impair({ "RightLink", "LeftLink" }, teleop_link)  -- each link draws its own losses
addPeers({ { peer_name = "TaskSup", peers_to_add = { "SutureFrames", "SuturePlanner", "SutureTrajGen", "Stitches",
                                                     "RightTransparency", "LeftTransparency", "ArmsRest" } } })

local always = { "Stitches", "ArmsRest", "RightWrench", "LeftWrench", "RightAdmittance", "LeftAdmittance", "TaskSup",
                 "DepSup", "ConfSup" }
-- Event-driven, and on the wall clock on a thread of its own: a search takes longer than a period.
-- max_age (s): a search ends at the planner's time_limit (1 s) or its validity-check budget; an
-- answer twice that late means the planner is stuck: e_handover_stale_SuturePlanner from the executor.
local activities = { { peer_name = "SuturePlanner", period = 0, own_pace = true, max_age = 2.0 } }
for _, c in ipairs(controller) do
  if c.peer_name ~= "SuturePlanner" then activities[#activities + 1] = { peer_name = c.peer_name, period = 0.001 } end
end
setActivities(activities)

local connections = {
  { output = "Patient.woundEdges", input = "Stitches.woundEdges" },  -- the sensing module's stand-in
  { output = "Stitches.rightStitchPose", input = "SutureFrames.rightStitchPose" },
  { output = "Stitches.leftStitchPose", input = "SutureFrames.leftStitchPose" },
  { output = "ISUR.measRightCartPose", input = "SutureFrames.rightMeasPose" },
  { output = "ISUR.measLeftCartPose", input = "SutureFrames.leftMeasPose" },
  { output = "ISUR.measRightCartPose", input = "ArmsRest.rightMeasPose" },
  { output = "ISUR.measLeftCartPose", input = "ArmsRest.leftMeasPose" },
  { output = "TaskSup.taskState", input = "SutureFrames.currentTaskState" },
  { output = "ISUR.measRightCartPose", input = "SuturePlanner.isurMeasPose" },  -- the planner's first and
  { output = "ISUR.measLeftCartPose", input = "SuturePlanner.UR5MeasPose" },    -- second tool: right, left
  -- The start state and the measured clearance from the robot's joints (the path starts on its
  -- actual IK branches; the suturing scene's only robot is the I-SUR).
  { output = "ISUR.measJointPosition", input = "SuturePlanner.isurMeasJoints" },
  { output = "ISUR.measRightWrench", input = "RightWrench.inWrench" },
  { output = "ISUR.measRightCartPose", input = "RightWrench.referenceFrame" },
  { output = "ISUR.measLeftWrench", input = "LeftWrench.inWrench" },
  { output = "ISUR.measLeftCartPose", input = "LeftWrench.referenceFrame" },
  { output = "RightWrench.outWrench", input = "RightAdmittance.measWrench" },
  { output = "LeftWrench.outWrench", input = "LeftAdmittance.measWrench" },
  -- A refused command (the robot holds both tools): each admittance re-syncs to where its tool is,
  -- in every deployment (ARCHITECTURE §7, "Continuity in the control path").
  { output = "ISUR.heldRightCartPose", input = "RightAdmittance.heldPose" },
  { output = "ISUR.heldLeftCartPose", input = "LeftAdmittance.heldPose" },
  { output = "TaskSup.outputEvents", input = "DepSup.inputEvents", conn_policy = buffered },
  { output = "TaskSup.outputEvents", input = "ConfSup.inputEvents", conn_policy = buffered },
  { output = "TaskSup.outputEvents", input = "ISUR.inputEvents", conn_policy = buffered },     -- the Endo Stitch
  { output = "TaskSup.outputEvents", input = "Patient.inputEvents", conn_policy = buffered },  -- the stick lets go
}
for _, source in ipairs({ "SutureFrames", "SuturePlanner", "SutureTrajGen", "Stitches", "ArmsRest", "RightAdmittance",
                          "LeftAdmittance", "ISUR", "Patient", "Validator", "Surgeon", "DepSup", "ConfSup" }) do
  local port = (source == "DepSup" or source == "ConfSup") and ".outputEvents" or ".events"
  connections[#connections + 1] = { output = source .. port, input = "TaskSup.inputEvents", conn_policy = buffered }
end
connectPorts(connections)

-- The admittances run in every deployment (their commanded poses stay continuous across a
-- switch), and so does the planner, which measures the clearance of the measured state in all.
local follow = {
  { output = "SutureTrajGen.desCartPose_1", input = "RightAdmittance.refPose" },
  { output = "SutureTrajGen.desCartTwist_1", input = "RightAdmittance.refTwist" },
  { output = "SutureTrajGen.desCartPose_2", input = "LeftAdmittance.refPose" },
  { output = "SutureTrajGen.desCartTwist_2", input = "LeftAdmittance.refTwist" },
  { output = "RightAdmittance.admPose", input = "ISUR.desRightCartPose" },
  { output = "LeftAdmittance.admPose", input = "ISUR.desLeftCartPose" },
  -- The trajectory generator re-syncs to the admittances' re-synced references: the motion ends
  -- there, and the chart's recovery re-plans from it.
  { output = "RightAdmittance.heldRefPose", input = "SutureTrajGen.heldPose_1" },
  { output = "LeftAdmittance.heldRefPose", input = "SutureTrajGen.heldPose_2" },
}
local function with(list, more)
  local all = {}
  for _, x in ipairs(list) do all[#all + 1] = x end
  for _, x in ipairs(more) do all[#all + 1] = x end
  return all
end
local autonomous = { "SutureFrames", "SuturePlanner", "SutureTrajGen", "RightWrench", "LeftWrench", "RightAdmittance",
                     "LeftAdmittance" }
defineDeployment("suturing_autonomous_planning", {
  scope = "suture",
  components = autonomous,
  connections = with(follow, {
    { output = "SutureFrames.goalPoses", input = "SuturePlanner.goalPoses" },
    { output = "SuturePlanner.plannedPath", input = "SutureTrajGen.plannedPath" },
  }),
})
defineDeployment("suturing_autonomous_primitives", {
  scope = "suture",
  components = autonomous,
  connections = with(follow, { { output = "SutureFrames.desiredPoses", input = "SutureTrajGen.plannedPath" } }),
})
-- Fig. 5.12: the surgeon's hands (the device) drive the admittances through the two-layer
-- coupling, whose set-points reach the robot only through the State Validator (reachable and
-- collision-free, else the last valid pair). The clutches start with the deployment
-- (InitHapticDevice): each tool then follows its device's motion from where both were, so that
-- taking over moves nothing by itself; the chart engages the Transparency layers on entering
-- TeleoperationActive.
local teleoperated = { "SuturePlanner", "RightWrench", "LeftWrench", "RightAdmittance", "LeftAdmittance", "Validator" }
for _, side in ipairs({ "Right", "Left" }) do
  for _, c in ipairs({ "Link", "Clutch", "Transparency", "MasterPassivity", "SlavePassivity" }) do
    teleoperated[#teleoperated + 1] = side .. c
  end
end
for _, c in ipairs(device.components) do teleoperated[#teleoperated + 1] = c.peer_name end
-- One arm's coupling (Fig. 4.15 with the thesis §5.5 engagement): the device's pose and twist
-- cross the link to the controller, where the clutch maps the device's motion since the
-- engagement onto the tool's pose then (the tool's own pose until the first sample arrives), the
-- Transparency layer computes the coupling wrenches on that and the slave: the tool's
-- admittance, its output (the pose the robot is commanded; the robot tracks it, and where the
-- State Validator holds the robot, the coupling still holds the admittance to the device), the
-- Passivity layer of each side implements its wrench as far as its side's tank can pay: the
-- slave's on the tool through its admittance's extWrench, the master's on the device (the Omni's
-- desWrench) with the master's wrench as it arrives back across the link; the tanks trade energy
-- in the link's packets. The
-- admittance's reference stays where the autonomous motion stopped (nothing writes refPose) and
-- the configuration suturing_teleoperation has next to no translational stiffness (50 N/m against
-- the coupling's 1000): next to nothing holds the tool there, the coupling moves it, and the
-- thread's pull, measured by the tool's sensor, is what the coupling spring holds against: what
-- the surgeon feels.
local function coupling(side, arm)
  local lower = side:lower()
  return couplings.connections {
    link = side .. "Link", clutch = side .. "Clutch", transparency = side .. "Transparency",
    master_passivity = side .. "MasterPassivity", slave_passivity = side .. "SlavePassivity", admittance = arm,
    slave_pose = "ISUR.meas" .. side .. "CartPose",
    master = { pose = device[lower], twist = device[lower .. "_twist"], feedback = device[lower .. "_feedback"],
               dissipation = device[lower .. "_dissipation"] },
  }
end
defineDeployment("suturing_teleoperated", {
  scope = "suture",
  components = teleoperated,
  connections = with(with(coupling("Right", "RightAdmittance"), coupling("Left", "LeftAdmittance")), {
    { output = "RightAdmittance.admPose", input = "Validator.desPoseIn_1" },
    { output = "LeftAdmittance.admPose", input = "Validator.desPoseIn_2" },
    { output = "Validator.desPoseOut_1", input = "ISUR.desRightCartPose" },
    { output = "Validator.desPoseOut_2", input = "ISUR.desLeftCartPose" },
    -- The validator holding the last valid pair: the admittances re-sync to it instead of running
    -- on with the surgeon's hands into the refused region.
    { output = "Validator.heldPose_1", input = "RightAdmittance.heldPose" },
    { output = "Validator.heldPose_2", input = "LeftAdmittance.heldPose" },
  }),
})
configureComponents(always)
configureComponents({ "SutureTrajGen" })  -- its desCartPose_i ports exist once configured
startComponents(always)
