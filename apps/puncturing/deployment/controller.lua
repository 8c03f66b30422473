-- One robot's controller for the puncturing task (thesis §4.6-4.8), the same for both robots: the
-- three deployments of §4.6 (autonomous with motion planning, autonomous with motion primitives,
-- teleoperated with the two-layer passive coupling) as deployments of the robot's own scope, the
-- admittance configurations of §4.7, and the task/deployment/configuration supervisors (Fig. 4.21).
-- Its only links to the other robot are ports carrying events and measured poses.
--   local controller = dofile(here .. "controller.lua")
--   controller{ prefix = "Needle", scope = "needle", robot = "ISUR", arm = 1, chart = ..., ... }
-- Optional globals: `teleop_device`, the surgeon's master in the teleoperated deployment: "omni"
-- (the default: one Phantom Omni per robot, <prefix>Omni), "leap" (one Leap Motion: the right hand
-- drives the needle robot, the left the probe robot; it renders no force), or a table by scope
-- { needle = master, probe = master } of ports of components created before (teleoperation_coupling.lua
-- in cobra's charts: `pose` of six DoF, `twist`, `feedback`, `dissipation`; a scope without one
-- keeps its Omni); `teleop_link` = { delay = s, jitter = s, loss = 0..1, seed = n, stiffness = N/m }:
-- the impairment of the link between the device and the controller (default: none).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
local charts = assert(COBRA_CHARTS, "cobra's charts folder is not found (COBRA_CHARTS): run with the cobra tool, or set "
  .. "COBRA_DATA_DIR to its share/cobra folder")  -- the deployment and configuration supervisors
local buffered = { type = "buffer", size = 64 }
local coupling = dofile(charts .. "teleoperation_coupling.lua")

-- The surgeon's master for robot `scope` (prefix P; `hand` "Right" or "Left": its Leap hand): the
-- components to create, the master's ports, the setting's name, and whether the components run
-- always (the Leap, which both robots share) rather than in the teleoperated deployment (an Omni).
local function master(scope, P, hand)
  local setting = teleop_device or "omni"
  if type(setting) == "table" then
    if setting[scope] then return {}, setting[scope], "teleop_device." .. scope end
    setting = "omni"
  end
  if setting == "omni" then
    return { { peer_name = P .. "Omni", component_type = "SimulatedOmniPhantom" } },
           { pose = P .. "Omni.measCartPose", twist = P .. "Omni.measTwist", feedback = P .. "Omni.desWrench",
             dissipation = P .. "Omni.dissipatedPower", max_force = 3.3, max_torque = 0.0 }, "teleop_device"
  elseif setting == "leap" then
    -- One device for both robots: created by the first controller that needs it.
    local components = rawget(_G, "Leap") and {} or { { peer_name = "LeapSim", component_type = "SimulatedLeapMotion" },
                                                       { peer_name = "Leap", component_type = "LeapMotionDriver" } }
    return components, { pose = "Leap.meas" .. hand .. "Pose", twist = "Leap.meas" .. hand .. "Twist" }, "teleop_device",
           true
  end
  error("teleop_device must be omni, leap or a table { needle = master, probe = master }, not " .. tostring(setting), 0)
end

return function(c)
  local P = c.prefix
  local function n(role) return P .. role end
  local device, master_ports, setting, device_always = master(c.scope, P, c.arm == 1 and "Right" or "Left")
  local components = {
    { peer_name = n("Frames"), component_type = "PuncturingFrameGenerator" },
    { peer_name = n("Planner"), component_type = c.planner_type or "MotionPlanner" },
    { peer_name = n("TrajGen"), component_type = "CartesianTrajectoryGenerator" },
    { peer_name = n("Wrench"), component_type = "EquivalentWrench" },
    { peer_name = n("Admittance"), component_type = "VariableAdmittance" },
    { peer_name = n("Link"), component_type = "LinkImpairment" },
    { peer_name = n("Clutch"), component_type = "TeleoperationClutch" },
    { peer_name = n("Transparency"), component_type = "TransparencyLayer" },
    { peer_name = n("MasterPassivity"), component_type = "PassivityLayer" },  -- the master's side
    { peer_name = n("SlavePassivity"), component_type = "PassivityLayer" },   -- the tool's side
    { peer_name = n("TaskSup"), component_type = "Supervisor" },
    { peer_name = n("DepSup"), component_type = "Supervisor" },
    { peer_name = n("ConfSup"), component_type = "Supervisor" },
  }
  for _, d in ipairs(device) do components[#components + 1] = d end
  -- cobra_drivers: the Leap Motion's driver.
  initConfigurator({ "cobra_motion", "cobra_control", "cobra_coordination", "cobra_planning", "cobra_sim",
                     "cobra_drivers", "cobra_puncturing" }, components, c.configurations)
  getReferences()
  coupling.check(master_ports, n("Link"), setting)
  local frames, planner, trajgen = _G[n("Frames")], _G[n("Planner")], _G[n("TrajGen")]
  frames.arm = c.arm == 1 and "needle" or "probe"
  frames.preoperative_info_file = scenario .. "/preoperative.txt"
  frames.cryo_plan_file = scenario .. "/cryo_plan.txt"
  frames.US_pose_plan_file = scenario .. "/us_plan.txt"
  frames.state_table_file = here .. "../state_table.txt"
  planner.scene_file = here .. "puncturing.scene"
  if c.verifies_procedure then
    -- The whole procedure verified before the first motion (README.md, "Verified whole"): the
    -- Frame Generators' files, and the other robot's speeds for its steps.
    planner.preoperative_info_file = frames.preoperative_info_file
    planner.cryo_plan_file = frames.cryo_plan_file
    planner.US_pose_plan_file = frames.US_pose_plan_file
    planner.state_table_file = frames.state_table_file
    planner.arm = frames.arm
    planner.other_max_vel = c.verifies_procedure.other_max_vel                -- m/s
    planner.other_max_ang_vel = c.verifies_procedure.other_max_ang_vel or 0.5  -- rad/s
  end
  planner.phantom_pose = c.phantom_pose
  planner.first_tool_frame = needle_tool_frame  -- the needle frames of this application (puncturing.lua)
  -- A work limit, not a time limit, so that the procedure plans the same on any machine (simulated
  -- time does not advance while it plans). The way back to a needle change pose past the UR5's
  -- forearm is the hardest query: 1,209 and 2,276 validity checks in two_needles (replayed from
  -- the run's query log; formerly up to ~185,000), and a registration can make it a narrow passage
  -- (README.md, "Setups vary"); a goal alternative whose search fails costs the whole budget.
  planner.max_validity_checks = 600000
  planner.max_vel = c.max_vel   -- m/s and rad/s: the trajectory generator's, for the path's
  planner.max_ang_vel = c.max_ang_vel or 0.5  -- joint-velocity check
  trajgen.arms_num = 2          -- the pair (needle, probe); this robot follows its own arm
  trajgen.max_vel = c.max_vel   -- m/s
  trajgen.max_ang_vel = c.max_ang_vel or 0.5  -- rad/s
  _G[n("Wrench")].invert_reference = true          -- the measured tool pose turns the sensor wrench
  _G[n("Wrench")].change_application_point = false -- into world axes, at the tool point
  _G[n("TaskSup")].fsm_path = c.chart
  _G[n("DepSup")].fsm_path = charts .. "deployment_supervisor.lua"
  _G[n("ConfSup")].fsm_path = charts .. "configuration_supervisor.lua"
  addPeers({ { peer_name = n("TaskSup"), peers_to_add = { n("Frames"), n("Planner"), n("TrajGen"), n("Transparency"),
                                                         table.unpack(c.chart_peers or {}) } } })
  if rawget(_G, "LeapSim") then
    Leap.device = "sim:LeapSim"
    LeapSim.scripted_hands = true  -- the surgeon's hands above the device (fault scripts move them)
  end
  -- The two-layer coupling (thesis §4.5.4). N/m, N·s/m: the needle's admittance in teleoperation
  -- (configurations: 50 N/m, 4 kg, 126 N·s/m) follows 1000 / 1050 of the master's motion and
  -- settles in about 0.1 s; over a delayed link 30 N·s/m / (delay + jitter), at most 1000 N/m,
  -- unless teleop_link.stiffness says (teleoperation_coupling.lua, M.stiffness: the master's wrench
  -- comes a round trip late). N·m/rad, N·m·s/rad: the tool's orientation follows the
  -- master's (0.2 kg·m², 4 N·m·s/rad: critically damped at 20 N·m/rad, about 0.2 s); no device
  -- renders a torque.
  local transparency = _G[n("Transparency")]
  transparency.stiffness = coupling.stiffness(teleop_link)
  transparency.damping = 20
  transparency.rotational_stiffness = 20
  transparency.rotational_damping = 0.5
  coupling.render(n("MasterPassivity"), master_ports)  -- what the device renders; the Leap: nothing
  coupling.impair({ n("Link") }, teleop_link and {
    delay = teleop_link.delay, jitter = teleop_link.jitter, loss = teleop_link.loss,
    seed = (teleop_link.seed or 1) + 4 * (c.arm - 1) })  -- each robot's link draws its own losses
  -- The Leap's 0.5 mm noise per sample: the clutch engages on the mean of 0.5 s of frames, and
  -- smooths the positions over 0.1 s, else one sample's error would offset the tool and the
  -- jitter shake it (as the suturing task measured).
  if master_ports.pose:match("^Leap%.") then
    _G[n("Clutch")].engagement_time = 0.5
    _G[n("Clutch")].smoothing_time = 0.1
  end

  local always = { n("Wrench"), n("Admittance"), n("TaskSup"), n("DepSup"), n("ConfSup") }
  if device_always then
    for _, d in ipairs(device) do always[#always + 1] = d.peer_name end
  end
  local activities = {}
  for _, name in ipairs({ n("Frames"), n("TrajGen"), n("Wrench"), n("Admittance"), n("Link"), n("Clutch"),
                          n("Transparency"), n("MasterPassivity"), n("SlavePassivity"), n("TaskSup"), n("DepSup"),
                          n("ConfSup") }) do
    activities[#activities + 1] = { peer_name = name, period = 0.001 }  -- s: 1 kHz control and coordination
  end
  for _, d in ipairs(device) do activities[#activities + 1] = { peer_name = d.peer_name, period = 0.001 } end
  -- Event-driven, and on the wall clock on a thread of its own: a search takes longer than a period.
  -- max_age (s): an answer (or a clearance sample) that late means the planner is stuck:
  -- e_handover_stale_<planner> from the executor. A search ends at the planner's time_limit (1 s),
  -- but verifyProcedure walks the whole procedure in one step: 0.2-0.3 s nominally, 16-33 s in
  -- the registration sweep's slowest setup (three_needles seed 4: many searches fail before one
  -- passes), so 60 s.
  activities[#activities + 1] = { peer_name = n("Planner"), period = 0, own_pace = true, max_age = 60.0 }
  setActivities(activities)

  local robot, arm = c.robot, tostring(c.arm)
  local connections = {
    { output = "ISUR.measCartPose", input = n("Frames") .. ".needleMeasPose" },
    { output = "UR5.measCartPose", input = n("Frames") .. ".USMeasPose" },
    { output = n("TaskSup") .. ".taskState", input = n("Frames") .. ".currentTaskState" },
    { output = "ISUR.measCartPose", input = n("Planner") .. ".isurMeasPose" },
    { output = "UR5.measCartPose", input = n("Planner") .. ".UR5MeasPose" },
    { output = "ISUR.measJointPosition", input = n("Planner") .. ".isurMeasJoints" },  -- the start: the
    { output = "UR5.measJointPosition", input = n("Planner") .. ".UR5MeasJoints" },    -- robots' actual joints
    { output = robot .. ".measWrench", input = n("Wrench") .. ".inWrench" },
    { output = robot .. ".measCartPose", input = n("Wrench") .. ".referenceFrame" },
    { output = n("Wrench") .. ".outWrench", input = n("Admittance") .. ".measWrench" },
    { output = n("Admittance") .. ".admPose", input = robot .. ".desCartPose" },
    -- A refused command (the robot holds): the admittance re-syncs to where the robot is, in
    -- every deployment (ARCHITECTURE §7, "Continuity in the control path").
    { output = robot .. ".heldCartPose", input = n("Admittance") .. ".heldPose" },
    { output = n("TaskSup") .. ".outputEvents", input = n("DepSup") .. ".inputEvents", conn_policy = buffered },
    { output = n("TaskSup") .. ".outputEvents", input = n("ConfSup") .. ".inputEvents", conn_policy = buffered },
  }
  for _, source in ipairs({ n("Frames"), n("Planner"), n("TrajGen"), n("Admittance"), robot, "Surgeon",
                            n("DepSup"), n("ConfSup"), table.unpack(c.event_sources) }) do
    local port = (source == n("DepSup") or source == n("ConfSup")) and ".outputEvents" or ".events"
    connections[#connections + 1] = { output = source .. port, input = n("TaskSup") .. ".inputEvents",
                                      conn_policy = buffered }
  end
  for _, extra in ipairs(c.connections or {}) do connections[#connections + 1] = extra end
  connectPorts(connections)

  -- The three operative modes (§4.6). The admittance runs in all of them: its commanded pose stays
  -- continuous across a switch. So does the planner, which plans only in the first (its goal and
  -- path connections are that deployment's) but measures the measured state's clearance and the
  -- declared contacts in all of them (minDistance, allowedContactDistance,
  -- primitiveContactDistance): the needle's insertion and a teleoperation included.
  local follow = {
    { output = n("TrajGen") .. ".desCartPose_" .. arm, input = n("Admittance") .. ".refPose" },
    { output = n("TrajGen") .. ".desCartTwist_" .. arm, input = n("Admittance") .. ".refTwist" },
    -- ... and the trajectory generator to the admittance's re-synced reference: the motion ends
    -- there, and the chart's recovery re-plans from it.
    { output = n("Admittance") .. ".heldRefPose", input = n("TrajGen") .. ".heldPose_" .. arm },
  }
  local function with(list, more)
    local all = {}
    for _, x in ipairs(list) do all[#all + 1] = x end
    for _, x in ipairs(more) do all[#all + 1] = x end
    return all
  end
  defineDeployment(c.scope .. "_autonomous_planning", {
    scope = c.scope,
    components = { n("Frames"), n("Planner"), n("TrajGen"), n("Wrench"), n("Admittance") },
    connections = with(follow, {
      { output = n("Frames") .. ".goalPoses", input = n("Planner") .. ".goalPoses" },
      { output = n("Planner") .. ".plannedPath", input = n("TrajGen") .. ".plannedPath" },
    }),
  })
  defineDeployment(c.scope .. "_autonomous_primitives", {
    scope = c.scope,
    components = { n("Frames"), n("Planner"), n("TrajGen"), n("Wrench"), n("Admittance") },
    connections = with(follow, { { output = n("Frames") .. ".desiredPoses", input = n("TrajGen") .. ".plannedPath" } }),
  })
  -- The surgeon's master drives the admittance through the two-layer coupling (Fig. 4.15,
  -- teleoperation_coupling.lua): the device's pose and twist cross the link to the controller, the
  -- clutch maps the device's motion since the deployment started onto the tool's pose then (the
  -- tool's own pose until the first sample arrives), the Transparency layer (engaged by the chart
  -- once deployed) computes the coupling on that and the admittance's output; one Passivity layer
  -- per side implements it as far as its side's tank can pay: the slave's on the tool through the
  -- admittance's extWrench, the master's on the device (the Omni's desWrench) with the master's
  -- wrench as it arrives back across the link; the tanks trade energy in the link's packets. The
  -- admittance's reference stays
  -- where the motion stopped (nothing writes refPose) and the teleoperation configuration has
  -- next to no stiffness: the coupling moves the tool, and what resists it (the tissue on the
  -- needle, the skin on the probe), measured by the tool's sensor, is what the surgeon feels.
  local teleoperated = { n("Planner"), n("Wrench"), n("Admittance"), n("Link"), n("Clutch"), n("Transparency"),
                         n("MasterPassivity"), n("SlavePassivity") }
  if not device_always then
    for _, d in ipairs(device) do teleoperated[#teleoperated + 1] = d.peer_name end
  end
  defineDeployment(c.scope .. "_teleoperated", {
    scope = c.scope,
    components = teleoperated,
    connections = coupling.connections {
      link = n("Link"), clutch = n("Clutch"), transparency = n("Transparency"),
      master_passivity = n("MasterPassivity"), slave_passivity = n("SlavePassivity"), admittance = n("Admittance"),
      slave_pose = robot .. ".measCartPose", master = master_ports,
    },
  })
  configureComponents(always)
  configureComponents({ n("TrajGen") })  -- its desCartPose_i ports exist once configured
  startComponents(always)
end
