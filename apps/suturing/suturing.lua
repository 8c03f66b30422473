-- The suturing task (thesis ch. 5) in simulation: the world (deployment/world.lua: the two-armed
-- I-SUR and the wound) and the robot's controller (deployment/controller.lua: the deployments of
-- §5.5.1, the configurations of §5.5.2, the supervisors, the chart of Fig. 5.11). Run it with
-- `cobra run apps/suturing` (what `./do demo suturing` does; the `run` table at the end says what
-- ends the run and what to observe, run/README.md).
-- `scenario` may be set before this file runs; default: scenarios/straight_cut.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
scenario = scenario or (here .. "scenarios/straight_cut")
wound = dofile(scenario .. "/wound.lua")

-- The haptic device of the teleoperated deployment: "leap" (Leap Motion, both hands) or "omni" (two
-- Phantom Omnis). Switching is this one line.
teleop_device = teleop_device or "leap"

-- This application's tool frames (frames.lua, the one place they are given): the Endo Stitch's tip
-- (right) and the stick's tip (left), in which the robot, the planner, the State Validator, the
-- Frame Generator and the wound all see the tools.
local frames = dofile(here .. "frames.lua")
right_tool_frame = frames.right_tool
left_tool_frame = frames.left_tool
-- The suturing scene's phantom (0.25 x 0.2 x 0.06 m) centred under the wound.
phantom_pose = { wound.wound_pose[1], wound.wound_pose[2], 0, 0, 0, 0, 1 }

dofile(here .. "deployment/world.lua")
dofile(here .. "deployment/controller.lua")
-- On the wall clock (cobra run --realtime) the real-time executor runs this deployment's schedule
-- every 1 ms on one SCHED_FIFO thread, memory locked; a missed period is an event in the log, and
-- 50 in a row (50 ms without the controllers keeping time) end the run in a safe stop.
setExecutor({ period = 0.001, priority = 80, on_deadline_miss = "event", safe_stop_after = 50 })
applyDeployment("suturing_autonomous_planning")

-- What `cobra run` needs from this application (run/README.md).
local failures = { "e_plan_failed", "e_traj_failed", "e_no_data", "e_comm_timeout", "e_ik_discontinuity", "e_ik_failed",
                   "e_no_wound_data", "e_stitch_missed", "e_endo_stitch_busy", "e_thread_broken",
                   "e_reaction_timeout",  -- the surgeon did not react in time (charts/suturing.lua)
                   "e_not_at_rest",       -- the tools did not come to rest at the end (charts/suturing.lua)
                   -- a component in Exception (the runner's), a non-finite input or command refused
                   "e_component_error", "e_input_not_finite", "e_command_not_finite" }
run = {
  title = "Suturing procedure",
  charts = {
    { name = "suture", supervisor = "TaskSup", done = "root.Done", safe_stop = "root.SafeStop", scope = "suture" },
  },
  fold = { "Switching", "AskingGoal", "Planning", "Generating", "Moving", "Arrived" },
  failures = failures,
  explain = { e_plan_failed = "lastPlanResult" },
  safe_stop_reason = "the same failure again after the reaction to the first, the thread broke, no reaction in time, or "
    .. "the tools not at rest at the end",
  record = { period = 0.01, ports = { "ISUR.measRightCartPose", "ISUR.measLeftCartPose", "RightAdmittance.admPose",
                                      "Patient.threadTension", "Patient.maxStitchGap", "Patient.maxGap",
                                      "RightAdmittance.tankEnergy", "LeftAdmittance.tankEnergy",
                                      "SuturePlanner.minDistance", "SuturePlanner.primitiveContactDistance",
                                      "Patient.stickWrench", "ISUR.measLeftWrench", "LeftAdmittance.admPose",
                                      "ISUR.measLeftCartPose" } },
  plots = {
    { title = "Thread tension", unit = "N", series = { "Patient.threadTension" } },
    { title = "The wound's gap: widest along the cut, widest at a stitch", unit = "m",
      series = { "Patient.maxGap", "Patient.maxStitchGap" } },
    { title = "Endo Stitch tip height, commanded and measured", unit = "m",
      series = { "RightAdmittance.admPose.z", "ISUR.measRightCartPose.z" } },
    { title = "Energy tanks of the variable admittances", unit = "J",
      series = { "RightAdmittance.tankEnergy", "LeftAdmittance.tankEnergy" } },
  },
  summary = {
    { name = "half-stitches applied", count = { "e_stitch_applied" } },
    { name = "stitches completed", count = { "e_stitch_done" } },
    -- After each stitch (the thread pulled, hooked and pushed): the widest gap at any stitch so far.
    { name = "gap at the stitches after each stitch", unit = "mm", scale = 1000, say = true,
      port = "Patient.maxStitchGap", on_enter = "suture:root.AutonomousMode.GetStitchTargetPose" },
    { name = "thread tension at the end of each pull", unit = "N", port = "Patient.threadTension",
      on_leave = "suture:root.AutonomousMode.PullThread" },
    -- The energy tanks around the work against the thread (README.md, "Energy tanks"): the Endo
    -- Stitch's over each pull (the contact configuration), the stick's over each hook and push.
    { name = "Endo Stitch tank at the start of each pull", unit = "J", port = "RightAdmittance.tankEnergy",
      on_enter = "suture:root.AutonomousMode.PullThread" },
    { name = "Endo Stitch tank at the end of each pull", unit = "J", port = "RightAdmittance.tankEnergy",
      on_leave = "suture:root.AutonomousMode.PullThread" },
    { name = "stick tank before each hook", unit = "J", port = "LeftAdmittance.tankEnergy",
      on_enter = "suture:root.AutonomousMode.HookThread" },
    { name = "stick tank after each push", unit = "J", port = "LeftAdmittance.tankEnergy",
      on_leave = "suture:root.AutonomousMode.PushThread" },
    { name = "widest gap along the cut at the end", unit = "mm", scale = 1000, port = "Patient.maxGap",
      on_enter = "suture:root.Done" },
    { name = "faults detected", count = failures },
    { name = "surgeon reactions", count = { "e_recover", "e_take_over" } },
  },
  -- The arms do what they are told during the autonomous motions; commanded = each admittance's output.
  tracking = {
    { name = "Endo Stitch", commanded = "RightAdmittance.admPose", measured = "ISUR.measRightCartPose",
      joints = "ISUR.measJointPosition", max_velocity = "ISUR.max_velocity", chart = "suture",
      counts_while = { scope = "suture", deployments = { "suturing_autonomous_planning", "suturing_autonomous_primitives" } } },
    { name = "stick", commanded = "LeftAdmittance.admPose", measured = "ISUR.measLeftCartPose",
      joints = "ISUR.measJointPosition", max_velocity = "ISUR.max_velocity", chart = "suture",
      counts_while = { scope = "suture", deployments = { "suturing_autonomous_planning", "suturing_autonomous_primitives" } } },
  },
  -- The measured state's clearance as the planner measures it (apps/suturing/deployment/suturing.scene),
  -- the whole run long; the Endo Stitch in the wound (a contact only the motion primitives make,
  -- `primitive_contact`) is left out of it and reported apart; per pair of groups too.
  clearance = {
    port = "SuturePlanner.minDistance", threshold = "SuturePlanner.clearanceThreshold",
    pairs = "SuturePlanner.pairDistances", pair_names = "SuturePlanner.clearancePairs",
    contacts = { { name = "Endo Stitch in the wound", port = "SuturePlanner.primitiveContactDistance" } },
  },
  -- cobra studio (studio/README.md): the planner's scene with the two-armed I-SUR's measured joints,
  -- the wound's edges (woundEdges: right and left point at each sample, two lines), the thread's
  -- path, the stitches in the tissue (at most 16 stitches: 34 thread points, 96 stitch points), the
  -- Endo Stitch's commanded and measured paths.
  studio = { scene = "SuturePlanner", robots = { isur = "ISUR.measJointPosition" },
             extras = { wound_edges = { polyline = "Patient.woundEdges", strands = 2, max = 400 },
                        thread = { polyline = "Patient.threadPath", max = 34 },
                        stitches = { segments = "Patient.stitchLines", max = 96 },
                        endo_stitch_commanded = { points = "RightAdmittance.admPose" },
                        endo_stitch_measured = { points = "ISUR.measRightCartPose" } },
             signals = { "Patient.threadTension", "Patient.maxGap" } },
}
