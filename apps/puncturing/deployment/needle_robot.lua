-- The I-SUR robot's controller (thesis §4.6-4.8): deployments needle_autonomous_planning,
-- needle_autonomous_primitives and needle_teleoperated (scope "needle"), configurations
-- needle_free_motion, needle_penetration and needle_insertion (configurations/needle), the needle
-- insertion chart (Fig. 4.8). Needs the globals `scenario` and `phantom_pose` (puncturing.lua).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
local speeds = dofile(here .. "speeds.lua")
dofile(here .. "controller.lua") {
  prefix = "Needle", scope = "needle", robot = "ISUR", arm = 1,
  chart = here .. "../charts/needle_insertion.lua",
  configurations = here .. "configurations/needle",
  phantom_pose = phantom_pose,
  max_vel = speeds.needle.max_vel,  -- m/s per axis (speeds.lua)
  max_ang_vel = speeds.needle.max_ang_vel,  -- rad/s
  -- Its planner verifies the whole procedure before the first motion (chart: VerifyingProcedure);
  -- the probe's steps at the probe's speeds.
  planner_type = "PuncturingMotionPlanner",
  verifies_procedure = { other_max_vel = speeds.probe.max_vel, other_max_ang_vel = speeds.probe.max_ang_vel },
  event_sources = { "NeedleMonitor", "Cryo" },  -- Cryo: the console's e_cryo_done
  chart_peers = { "NeedleMonitor" },  -- the chart re-arms its skin detection for each new needle
  connections = {
    { output = "NeedleFrames.needleTarget", input = "NeedleMonitor.targetPose" },
    { output = "NeedleTaskSup.taskState", input = "Surgeon.needleTaskState", conn_policy = { type = "buffer", size = 64 } },
    { output = "NeedleTaskSup.outputEvents", input = "Cryo.inputEvents", conn_policy = { type = "buffer", size = 64 } },
  },
}
