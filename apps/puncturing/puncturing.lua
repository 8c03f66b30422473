-- The puncturing task (thesis ch. 4) in simulation: the world (deployment/world.lua), the I-SUR
-- robot's controller (deployment/needle_robot.lua) and the UR5's (deployment/probe_robot.lua),
-- coordinated only through events. Run it with `./do demo` (build/release/apps/puncturing/
-- cobra-puncturing), or browse it: cobra console apps/puncturing/puncturing.lua --sim.
-- `scenario` may be set before this file runs; default: scenarios/two_needles.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
scenario = scenario or (here .. "scenarios/two_needles")
local G = dofile(here .. "deployment/geometry.lua")
local abdomen = G.preoperative(scenario .. "/preoperative.txt").abdomen
-- The planning scene's phantom sits at the nominal abdomen pose (0, 0, 0.1); move it to this one.
-- The probe pressed on the skin is an allowed contact of the scene (planning/scenes/puncturing.scene).
-- The needle's motions near the skin are motion primitives, not planned.
phantom_pose = { abdomen[1], abdomen[2], abdomen[3] - 0.1, abdomen[4], abdomen[5], abdomen[6], abdomen[7] }
-- The needle frame of this application has z along the needle; the I-SUR kinematics' needle is its
-- tool's x axis. The robot bridge and the planners are told so.
needle_tool_frame = G.frame(0, 0, 0, 0, math.pi / 2, 0)

dofile(here .. "deployment/world.lua")
dofile(here .. "deployment/needle_robot.lua")
dofile(here .. "deployment/probe_robot.lua")
-- The two robots' only link: their task charts' events (thesis §4.4: coordinated through events).
connectPorts({
  { output = "NeedleTaskSup.outputEvents", input = "ProbeTaskSup.inputEvents", conn_policy = { type = "buffer", size = 64 } },
  { output = "ProbeTaskSup.outputEvents", input = "NeedleTaskSup.inputEvents", conn_policy = { type = "buffer", size = 64 } },
})
applyDeployment("needle_autonomous_planning")
applyDeployment("probe_autonomous_planning")
