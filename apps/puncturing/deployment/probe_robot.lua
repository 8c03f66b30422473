-- The UR5's controller (thesis §4.6-4.8, "the same structure has been replicated for the UR5"):
-- deployments probe_autonomous_planning, probe_autonomous_primitives and probe_teleoperated (scope
-- "probe"), configurations probe_free_motion and probe_contact (configurations/probe), the
-- ultrasound positioning chart (§4.4.2). Needs the globals `scenario` and `phantom_pose`.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
local speeds = dofile(here .. "speeds.lua")
dofile(here .. "controller.lua") {
  prefix = "Probe", scope = "probe", robot = "UR5", arm = 2,
  chart = here .. "../charts/us_positioning.lua",
  configurations = here .. "configurations/probe",
  phantom_pose = phantom_pose,
  max_vel = speeds.probe.max_vel,  -- m/s per axis (speeds.lua)
  max_ang_vel = speeds.probe.max_ang_vel,  -- rad/s
  -- Its planner walks the whole procedure too (the chart's Idle), so that it follows the probe's
  -- verified paths; the needle's steps at the needle's speeds.
  planner_type = "PuncturingMotionPlanner",
  verifies_procedure = { other_max_vel = speeds.needle.max_vel, other_max_ang_vel = speeds.needle.max_ang_vel },
  event_sources = { "USMonitor" },
  connections = {
    { output = "ProbeTaskSup.taskState", input = "Surgeon.usTaskState", conn_policy = { type = "buffer", size = 64 } },
  },
}
