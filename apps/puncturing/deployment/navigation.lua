-- Navigated puncturing (README.md "Navigated puncturing"): the registration and the cryoablation
-- plan come from a navigation program (3D Slicer, PLUS) over OpenIGTLink instead of the scenario's
-- cryo_plan.txt and us_plan.txt. An IgtlBridge `Navigation` serves it and sends back the tool
-- poses, the needle chart's task state and events, and any refusal. Run by puncturing.lua after
-- both controllers are loaded and before their first deployment, with the global `navigation`:
--   navigation = { port = 18944, send_period = 0.05, timeout = 120 }
-- port: TCP port the bridge listens on (0: an ephemeral one, Navigation:localPort() tells);
-- send_period (s): the tool poses' period (0.05: 20 Hz); timeout (s): how long the needle chart's
-- WaitNavigation waits for the plan and the registration before its safe stop; max_message_bytes:
-- a received message bigger than this is dropped (counted).
local nav = assert(navigation, "navigation.lua needs the global `navigation`")
initConfigurator({ "cobra_bridges" }, { { peer_name = "Navigation", component_type = "IgtlBridge" } })
getReferences()
Navigation.role = "server"
Navigation.port = nav.port or 18944
Navigation.send_period = nav.send_period or 0.05                          -- s: 20 Hz
Navigation.max_message_bytes = nav.max_message_bytes or 1048576           -- bytes: bigger ones are dropped
-- World poses of the tools (m in cobra, mm on the wire).
Navigation.send_transforms = "NeedleTip=needleTip, Probe=probePose"
-- Frame A (the abdomen) registered in the world: the Frame Generators' and planners' abdomenFrame.
Navigation.receive_transforms = "Registration=registration"
-- Points `<needle>.entry`, `<needle>.target` in frame A (mm on the wire, m on the port).
Navigation.plan_device = "Plan"
-- The peer's requests that the application declares: ABORT stops the procedure (the charts' safe stop).
Navigation.requests = "ABORT=e_navigation_abort"
-- Why the plan, its registration or the procedure was refused: a STRING of device "Refusal".
Navigation.send_strings = "Refusal=refusal"
-- The simulated ultrasound image, once the Patient has it (an IMAGE of device "USImage").
local has_image = pcall(function() return Patient.usImage end)
if has_image then Navigation.images = "USImage=usImage" end
configureComponents({ "Navigation" })
-- Where the navigation program connects (the ephemeral port when port is 0).
io.stderr:write(("[cobra] 'Navigation': OpenIGTLink server on port %d\n"):format(Navigation:localPort()))

-- The plan comes from the navigation, read by both Frame Generators and both planners alike.
for _, name in ipairs({ "NeedleFrames", "ProbeFrames", "NeedlePlanner", "ProbePlanner" }) do
  _G[name].plan_source = "navigation"
end
NeedleFrames.navigation_timeout = nav.timeout or 120                   -- s
local buffered = { type = "buffer", size = 64 }
local connections = {
  { output = "ISUR.measCartPose", input = "Navigation.needleTip" },
  { output = "UR5.measCartPose", input = "Navigation.probePose" },
  { output = "NeedleTaskSup.taskState", input = "Navigation.taskState", conn_policy = buffered },
  { output = "NeedleTaskSup.outputEvents", input = "Navigation.inputEvents", conn_policy = buffered },
  { output = "NeedleFrames.refusal", input = "Navigation.refusal", conn_policy = { type = "buffer", size = 4 } },
  { output = "NeedlePlanner.refusal", input = "Navigation.refusal", conn_policy = { type = "buffer", size = 4 } },
  -- e_navigation_abort: the needle chart's safe stop (the ultrasound chart follows it, as it
  -- follows every safe stop of the needle chart); e_igtl_connected and e_igtl_peer_lost are in the
  -- log, and no chart reacts to them (the procedure goes on with the plan it verified).
  { output = "Navigation.events", input = "NeedleTaskSup.inputEvents", conn_policy = buffered },
}
for _, name in ipairs({ "NeedleFrames", "ProbeFrames", "NeedlePlanner", "ProbePlanner" }) do
  connections[#connections + 1] = { output = "Navigation.registration", input = name .. ".abdomenFrame" }
  connections[#connections + 1] = { output = "Navigation.plan", input = name .. ".plan" }
end
if has_image then connections[#connections + 1] = { output = "Patient.usImage", input = "Navigation.usImage" } end
connectPorts(connections)
-- s: 1 ms like the world: each pose sent is the one measured in the step it is sent.
setActivities({ { peer_name = "Navigation", period = 0.001 } })
startComponents({ "Navigation" })
