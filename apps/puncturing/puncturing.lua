-- The puncturing task (thesis ch. 4) in simulation: the world (deployment/world.lua), the I-SUR
-- robot's controller (deployment/needle_robot.lua) and the UR5's (deployment/probe_robot.lua),
-- coordinated only through events. Run it with `cobra run apps/puncturing` (what `./do demo` does;
-- the `run` table at the end says what ends the run and what to observe, run/README.md), or
-- browse it: cobra console apps/puncturing/puncturing.lua --sim.
-- `scenario` may be set before this file runs; default: scenarios/two_needles. `navigation` (a
-- table, deployment/navigation.lua), or the environment's COBRA_NAVIGATION_PORT: the plan and the
-- registration come from a navigation program over OpenIGTLink (README.md "Navigated puncturing").
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
scenario = scenario or (here .. "scenarios/two_needles")
local G = dofile(here .. "deployment/geometry.lua")
local abdomen = G.preoperative(scenario .. "/preoperative.txt").abdomen
-- The planning scene's phantom frame is 0.1 m under the skin's frame A (its box's top face at
-- z = 0.1 is the skin): place it 0.1 m below A along A's own z, so that a tilted registration
-- tilts the planner's skin with the patient's (not only about a point 0.1 m under it).
-- The probe pressed on the skin is an allowed contact of the scene (apps/puncturing/deployment/puncturing.scene).
-- The needle's motions near the skin are motion primitives, not planned.
local phantom_origin = G.apply(abdomen, { 0, 0, -0.1 })
phantom_pose = { phantom_origin[1], phantom_origin[2], phantom_origin[3], abdomen[4], abdomen[5], abdomen[6], abdomen[7] }
-- The needle frame of this application has z along the needle; the I-SUR kinematics' needle is its
-- tool's x axis. The robot bridge and the planners are told so.
needle_tool_frame = G.frame(0, 0, 0, 0, math.pi / 2, 0)

-- Split over two hosts, each robot controller on its own computer (thesis §4.4): `cobra run
-- apps/puncturing --host needle` and `--host probe` (README.md, "Two hosts"). Host needle runs the
-- world and the I-SUR's controller, host probe the UR5 and its controller; the connections
-- between them go over DDS. Without --host this table is ignored: one process runs everything.
placement = {
  hosts = {
    -- Navigation: the navigated run's OpenIGTLink bridge, beside the needle chart (a split
    -- navigated run is not tested: its plan and registration would cross to host probe over DDS).
    needle = { "ISUR", "Patient", "NeedleMonitor", "USMonitor", "Surgeon", "Cryo", "Needle*", "Navigation" },
    probe = { "UR5", "Probe*" },
  },
  everywhere = { "Link" },  -- each process's DDS link: its participant, the lockstep meeting, liveliness
  transport = "dds",
  -- A reader matched after its writer's first samples (discovery takes a moment at the start)
  -- still gets them: the writer keeps its last `size` samples for late readers.
  qos = { durability = "transient_local" },
}
if host then
  -- Before any connection between hosts: the link's participant carries them. The domain, the
  -- unicast peers (when multicast does not route, e.g. across a veth pair) and the fault
  -- injection come from the globals or the environment a test sets.
  initConfigurator({ "cobra_dds" }, { { peer_name = "Link", component_type = "DdsLink" } })
  getReferences()
  Link.domain = dds_domain or tonumber(os.getenv("COBRA_DDS_DOMAIN") or "0")
  Link.participant = host
  Link.peers = host == "needle" and "probe" or "needle"
  -- s of wall time: a peer whose liveliness (asserted by Fast DDS's own thread every lease / 4)
  -- lapses this long is lost, and the charts stop their robots. On the wall clock 0.1 s: a robot
  -- whose peer host is gone stops within 0.2 s. In lockstep 3 s: simulated runs are not bound to
  -- the wall clock, and the tests run two split runs at once on a 2-core machine, where a 0.2 s
  -- lease lost a live peer (its process starved for seconds).
  -- A lockstep meeting waits up to meeting_timeout for a live peer (one instant may take long).
  Link.lease = realtime and 0.1 or 3
  -- s: on the wall clock a lapsed peer is lost when its liveliness has not come back within
  -- 0.08 s more (a killed host is found within 0.2 s): a host stalled past the lease at its
  -- run's start was otherwise lost while alive (1 run in 10 on the loaded machine).
  Link.lapse_grace = realtime and 0.08 or 0
  -- On the wall clock DDS's threads run SCHED_FIFO 60, under the executor's 80: time-sharing, a
  -- loaded machine delayed them past the 0.1 s lease and a live peer was lost.
  Link.priority = realtime and 60 or 0
  Link.meeting_timeout = 10
  Link.join_timeout = 120  -- s: the other host may still be loading its half (its planning scenes)
  -- s: the hosts meet every 5th instant, so a port's sample or an event crosses within 5 ms (as
  -- over a network link) and the run pays a round trip between the processes 5 times less often.
  Link.meeting_period = 0.005
  Link.initial_peers = dds_initial_peers or os.getenv("COBRA_DDS_INITIAL_PEERS") or ""
  Link.drop_share = dds_drop_share or tonumber(os.getenv("COBRA_DDS_DROP_SHARE") or "0")  -- 1: tests only
  -- DDS Security (dds/README.md "Security"): `dds_security` or COBRA_DDS_SECURITY names a folder
  -- of the lab's certificates and signed documents (tools/make_test_pki.sh makes test ones; ./do
  -- makes them in build/pki). Host needle is the identity host_a, host probe host_b; each may
  -- publish only its own components' topics (dds/security/permissions_host_*.xml), everything on
  -- the wire is encrypted and a participant without a certificate of the CA is refused. Unset:
  -- no security.
  local pki = dds_security or os.getenv("COBRA_DDS_SECURITY") or ""
  if pki ~= "" then
    local id = host == "needle" and "host_a" or "host_b"
    Link.security_folder = pki
    Link.security_ca = "ca.crt"
    Link.security_certificate = id .. ".crt"
    Link.security_key = id .. ".key"
    Link.security_governance = "governance.p7s"
    Link.security_permissions = "permissions_" .. id .. ".p7s"
  end
  -- s: its events reach the charts within a step. Its own pace on the wall clock: there the hosts
  -- do not meet, and on the executor's lockstep schedule the link would put the transport in
  -- lockstep (samples held for meetings that never come); its work is on Fast DDS's threads and
  -- its writer ends' anyway (the link has no update hook).
  -- max_age (s): its thread steps every 1 ms; a stall as long as the lease is worth an event.
  setActivities({ { peer_name = "Link", period = 0.001, own_pace = true, max_age = 0.1 } })
  configureComponents({ "Link" })
  startComponents({ "Link" })
end

dofile(here .. "deployment/world.lua")
dofile(here .. "deployment/needle_robot.lua")
dofile(here .. "deployment/probe_robot.lua")
-- Navigated (README.md "Navigated puncturing"): the global `navigation`, or from the command line
-- COBRA_NAVIGATION_PORT=18944 cobra run apps/puncturing (the bridge's port; 0: an ephemeral one).
if navigation == nil and os.getenv("COBRA_NAVIGATION_PORT") then
  navigation = { port = tonumber(os.getenv("COBRA_NAVIGATION_PORT")) }
end
if navigation then dofile(here .. "deployment/navigation.lua") end
-- On the wall clock (cobra run --realtime) the real-time executor runs this deployment's schedule
-- every 1 ms on one SCHED_FIFO thread, memory locked; a missed period is an event in the log, and
-- 50 in a row (50 ms without the controllers keeping time) end the run in a safe stop.
setExecutor({ period = 0.001, priority = 80, on_deadline_miss = "event", safe_stop_after = 50 })
-- The two robots' only link: their task charts' events (thesis §4.4: coordinated through events).
connectPorts({
  { output = "NeedleTaskSup.outputEvents", input = "ProbeTaskSup.inputEvents", conn_policy = { type = "buffer", size = 64 } },
  { output = "ProbeTaskSup.outputEvents", input = "NeedleTaskSup.inputEvents", conn_policy = { type = "buffer", size = 64 } },
})
-- A lost peer host: each chart stops its robot and holds it (its SafeStop, charts/*.lua).
if host then
  connectPorts({
    { output = "Link.events", input = "NeedleTaskSup.inputEvents", conn_policy = { type = "buffer", size = 64 } },
    { output = "Link.events", input = "ProbeTaskSup.inputEvents", conn_policy = { type = "buffer", size = 64 } },
  })
end
applyDeployment("needle_autonomous_planning")
applyDeployment("probe_autonomous_planning")

-- What `cobra run` needs from this application (run/README.md).
-- The events the charts react to as failures (charts/*.lua): the last one is a safe stop's reason.
local failures = { "e_forbidden_region", "e_force_over_threshold", "e_plan_failed", "e_traj_failed", "e_no_data",
                   "e_comm_timeout", "e_ik_discontinuity", "e_probe_contact_lost", "e_needle_goal_missed",
                   "e_us_goal_missed", "e_us_needle_not_found", "e_peer_lost",
                   -- nobody answered in time (charts/waits.lua: the surgeon, the console, the other chart)
                   "e_reaction_timeout", "e_iceball_config_timeout", "e_needle_change_timeout", "e_cryo_timeout",
                   "e_peer_chart_timeout",
                   -- the whole procedure refused before any motion (NeedlePlanner.verifyProcedure)
                   "e_procedure_refused",
                   -- navigated: the plan or registration refused, or not come; the peer's ABORT
                   "e_navigation_refused", "e_navigation_timeout", "e_navigation_abort",
                   -- a component in Exception (the runner's), a non-finite input or command refused
                   "e_component_error", "e_input_not_finite", "e_command_not_finite" }
local detected = { "e_needle_trapped", "e_needle_lost", table.unpack(failures) }
run = {
  title = "Puncturing procedure",
  -- The task charts end the run: both done, or one in its safe stop (the other stops with it).
  charts = {
    { name = "needle", supervisor = "NeedleTaskSup", done = "root.Done", safe_stop = "root.SafeStop", scope = "needle" },
    { name = "us", supervisor = "ProbeTaskSup", done = "root.Done", safe_stop = "root.SafeStop", scope = "probe",
      sources = { "Probe", "UR5", "USMonitor" } },
  },
  -- A motion's internal steps are folded into the motion in the log and the timeline.
  fold = { "Switching", "AskingGoal", "Planning", "Generating", "Moving", "Arrived", "Paused" },
  failures = failures,
  explain = { e_plan_failed = "lastPlanResult", e_procedure_refused = "lastRefusal",
              e_navigation_refused = "navigationStatus", e_navigation_timeout = "navigationStatus" },
  safe_stop_reason = "the same failure again after the reaction to the first, no answer in time (charts/waits.lua), "
    .. "or the procedure refused before any motion (VerifyingProcedure)",
  record = { period = 0.01, ports = { "ISUR.measCartPose", "NeedleAdmittance.admPose", "Patient.needleAxialForce",
                                      "Patient.needleDepth", "NeedleAdmittance.tankEnergy", "ProbeAdmittance.tankEnergy",
                                      "NeedlePlanner.minDistance", "NeedlePlanner.allowedContactDistance",
                                      "NeedlePlanner.primitiveContactDistance" } },
  plots = {
    { title = "Needle-tip force against depth", unit = "N", x = "Patient.needleDepth", x_unit = "m",
      series = { "Patient.needleAxialForce" } },
    { title = "Commanded and measured needle tip height", unit = "m",
      series = { "NeedleAdmittance.admPose.z", "ISUR.measCartPose.z" } },
    { title = "Energy tanks of the variable admittances", unit = "J",
      series = { "NeedleAdmittance.tankEnergy", "ProbeAdmittance.tankEnergy" } },
  },
  summary = {
    -- Where the tip was during the freeze: when the chart leaves WaitCryoCycle.
    { name = "placement error per needle", unit = "mm", scale = 1000, say = true,
      distance = { "ISUR.measCartPose", "NeedleFrames.needleTarget" }, on_leave = "needle:root.WaitCryoCycle",
      of = "NeedleFrames.needleCount" },
    -- Events the nominal task causes itself are not faults: the ultrasound loses the needle as it
    -- is pulled out, and the probe leaves the skin as it moves to the next needle's pose. Heard
    -- there they are listed apart ("expected task events"); anywhere else they are faults.
    { name = "faults detected", count = detected,
      expected = { { event = "e_needle_lost", during = "needle:root.ExtractingNeedle" },
                   { event = "e_probe_contact_lost", during = "us:root.MoveToSkin" } } },
    { name = "surgeon reactions", count = { "e_recover", "e_take_over" } },
    { name = "IK discontinuity events", count = { "e_ik_discontinuity" } },
  },
  -- Fidelity: the robots do what they are told during their autonomous motions (the trajectory
  -- generator commands them); commanded = the variable admittance's output, measured = the robot's.
  tracking = {
    { name = "I-SUR needle", commanded = "NeedleAdmittance.admPose", measured = "ISUR.measCartPose",
      joints = "ISUR.measJointPosition", max_velocity = "ISUR.max_velocity", chart = "needle",
      counts_while = { scope = "needle", deployments = { "needle_autonomous_planning", "needle_autonomous_primitives" } } },
    { name = "UR5 probe", commanded = "ProbeAdmittance.admPose", measured = "UR5.measCartPose",
      joints = "UR5.measJointPosition", max_velocity = "UR5.max_velocity", chart = "us",
      counts_while = { scope = "probe", deployments = { "probe_autonomous_planning", "probe_autonomous_primitives" } } },
  },
  -- The measured state's clearance as the needle planner measures it, the whole run long, against
  -- its threshold; the contacts the task makes on purpose are left out of it and reported apart
  -- (apps/puncturing/deployment/puncturing.scene: `allow`, `primitive_contact`). Per pair of
  -- groups (the I-SUR's macro and micro parts, the UR5, the environment) too: which two come close.
  clearance = {
    port = "NeedlePlanner.minDistance", threshold = "NeedlePlanner.clearanceThreshold",
    pairs = "NeedlePlanner.pairDistances", pair_names = "NeedlePlanner.clearancePairs",
    contacts = { { name = "probe on skin", port = "NeedlePlanner.allowedContactDistance" },
                 { name = "needle in tissue", port = "NeedlePlanner.primitiveContactDistance" } },
  },
  -- cobra studio (studio/README.md): the needle planner's scene drawn with the robots' measured
  -- joints; the iceball at the needle tip; the ultrasound image plane (6 x 10 cm) on the probe
  -- face; the simulated patient's tumour and tissue layers (its phantom.txt, across the scene's
  -- phantom box) and the forbidden regions the needle monitor checks (preoperative.txt); the
  -- needle tip's and the probe's commanded and measured paths; the surgeon's confirmations as
  -- buttons (cobra run apps/puncturing --studio --interactive), each enabled while a chart waits
  -- for its event (the first argument): after a fault, Recover and Take over are the needle or
  -- ultrasound chart's choices.
  studio = {
    scene = "NeedlePlanner",
    robots = { isur = "ISUR.measJointPosition", ur5 = "UR5.measJointPosition" },
    extras = { iceball = { sphere = "ISUR.measCartPose", radius = "Patient.iceballRadius" },
               us_plane = { plane = "UR5.measCartPose", size = { 0.06, 0.1 } },
               tumour = { spheres = "Patient.tumour" },
               forbidden = { capsules = "NeedleMonitor.forbidden_regions" },
               layers = { slabs = "Patient.layer_depths", pose = "Patient.phantom_pose", size = "phantom" },
               needle_commanded = { points = "NeedleAdmittance.admPose" },
               needle_measured = { points = "ISUR.measCartPose" },
               probe_commanded = { points = "ProbeAdmittance.admPose" },
               probe_measured = { points = "UR5.measCartPose" } },
    signals = { "Patient.needleAxialForce", "Patient.needleDepth", "Patient.iceballRadius", "NeedlePlanner.minDistance" },
    inputs = {
      iceball_configured = { "Surgeon.say", "e_iceball_configured" },
      needle_mounted = { "Surgeon.say", "e_needle_mounted" },
      needle_removed = { "Surgeon.say", "e_needle_removed" },
      recover = { "Surgeon.say", "e_recover", label = "Recover (after a fault)" },
      take_over = { "Surgeon.say", "e_take_over", label = "Take over (teleoperation)" },
      teleop_done = { "Surgeon.say", "e_teleop_done", label = "Teleoperation done" },
    },
  },
}
