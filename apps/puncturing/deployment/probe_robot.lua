-- The UR5's controller (thesis §4.6-4.8, "the same structure has been replicated for the UR5"):
-- deployments probe_autonomous_planning, probe_autonomous_primitives and probe_teleoperated (scope
-- "probe"), configurations probe_free_motion and probe_contact (configurations/probe), the
-- ultrasound positioning chart (§4.4.2). Needs the globals `scenario` and `phantom_pose`.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
dofile(here .. "controller.lua") {
  prefix = "Probe", scope = "probe", robot = "UR5", arm = 2,
  chart = here .. "../charts/us_positioning.lua",
  configurations = here .. "configurations/probe",
  phantom_pose = phantom_pose,
  max_vel = 0.08,  -- m/s per axis
  event_sources = { "USMonitor" },
  connections = {
    { output = "ProbeTaskSup.taskState", input = "Surgeon.usTaskState", conn_policy = { type = "buffer", size = 64 } },
  },
}
