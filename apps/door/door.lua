-- The door task (thesis §2.2, Figs. 2.5 and 2.6): a simulated door, five deployments, two
-- configurations, and the three supervisors — task, deployment, configuration — as three
-- instances of the same Supervisor component with different charts.
-- Run: cobra run apps/door   (this file is the application's entry; `run` below says what to watch)
-- or deploy it only: cobra deploy apps/door/door.lua --sim --run-for 12

local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
local charts = assert(COBRA_CHARTS, "cobra's charts folder is not found (COBRA_CHARTS): run with the cobra tool, or set "
  .. "COBRA_DATA_DIR to its share/cobra folder")  -- the deployment and configuration supervisors

-- cobra_door: the task's own component, the simulated door (apps/door/components).
packages_list = { "cobra_signal", "cobra_coordination", "cobra_door" }
components_list = {
  { peer_name = "Door", component_type = "DoorSim" },
  -- set-points of the arm, gripper, handle torque and pull force (values from configurations)
  { peer_name = "ArmCmd", component_type = "Constant" },
  { peer_name = "GripCmd", component_type = "Constant" },
  { peer_name = "TorqueCmd", component_type = "Constant" },
  { peer_name = "PullCmd", component_type = "Constant" },
  -- situation awareness: Decision components turning measurements into events
  { peer_name = "AtHandle", component_type = "ThresholdDetector" },
  { peer_name = "Gripped", component_type = "ThresholdDetector" },
  { peer_name = "Unlatched", component_type = "ThresholdDetector" },
  { peer_name = "DoorOpen", component_type = "ThresholdDetector" },
  -- coordination
  { peer_name = "TaskSup", component_type = "Supervisor" },
  { peer_name = "DepSup", component_type = "Supervisor" },
  { peer_name = "ConfSup", component_type = "Supervisor" },
}
initConfigurator(packages_list, components_list, here .. "configurations")
getReferences()

TaskSup.fsm_path = here .. "door_task.lua"
DepSup.fsm_path = charts .. "deployment_supervisor.lua"
ConfSup.fsm_path = charts .. "configuration_supervisor.lua"
ArmCmd.value = 0.5      -- m: where the handle is
GripCmd.value = 1       -- close
-- m: the gripper closes on an arm at rest at the handle, within 0.1 mm of its set-point (the arm's
-- 0.1 s lag leaves it moving at 1 mm/s there). Gripped, the arm moves only with the handle: closed
-- 5 mm short (0.495 m), the arm's servo stayed 5 mm from its set-point the whole task, and once the
-- gripper let go it went on those 5 mm after the task was done (4 mm in the next second).
AtHandle.threshold = 0.4999
Gripped.threshold = 0.5
Unlatched.threshold = 0.7    -- rad
DoorOpen.threshold = 1.2     -- rad

-- Always running: the world, the detectors and the supervisors.
setActivities({
  { peer_name = "Door", period = 0.001 },
  { peer_name = "ArmCmd", period = 0.001 },
  { peer_name = "GripCmd", period = 0.001 },
  { peer_name = "TorqueCmd", period = 0.001 },
  { peer_name = "PullCmd", period = 0.001 },
  { peer_name = "TaskSup", period = 0.01 },
  { peer_name = "DepSup", period = 0.01 },
  { peer_name = "ConfSup", period = 0.01 },
})
-- On the wall clock (cobra run --realtime) the real-time executor runs this deployment's schedule
-- every 1 ms on one SCHED_FIFO thread, memory locked; a missed period is an event in the log, and
-- 50 in a row (50 ms without the controllers keeping time) end the run in a safe stop.
setExecutor({ period = 0.001, priority = 80, on_deadline_miss = "event", safe_stop_after = 50 })
local buffered = { type = "buffer", size = 32 }
connectPorts({
  { output = "Door.armPosition", input = "AtHandle.in" },
  { output = "Door.gripped", input = "Gripped.in" },
  { output = "Door.handleAngle", input = "Unlatched.in" },
  { output = "Door.doorAngle", input = "DoorOpen.in" },
  { output = "AtHandle.events", input = "TaskSup.inputEvents", conn_policy = buffered },
  { output = "Gripped.events", input = "TaskSup.inputEvents", conn_policy = buffered },
  { output = "Unlatched.events", input = "TaskSup.inputEvents", conn_policy = buffered },
  { output = "DoorOpen.events", input = "TaskSup.inputEvents", conn_policy = buffered },
  { output = "Door.events", input = "TaskSup.inputEvents", conn_policy = buffered },  -- e_command_not_finite
  { output = "TaskSup.outputEvents", input = "DepSup.inputEvents", conn_policy = buffered },
  { output = "TaskSup.outputEvents", input = "ConfSup.inputEvents", conn_policy = buffered },
  { output = "DepSup.outputEvents", input = "TaskSup.inputEvents", conn_policy = buffered },
  { output = "ConfSup.outputEvents", input = "TaskSup.inputEvents", conn_policy = buffered },
})
local always = { "Door", "AtHandle", "Gripped", "Unlatched", "DoorOpen", "DepSup", "ConfSup", "TaskSup" }
configureComponents(always)
startComponents(always)

-- One deployment per task state: which set-point sources run, and what they feed.
local function deployment(name, sources)
  local components, connections = {}, {}
  for source, input in pairs(sources) do
    components[#components + 1] = source
    connections[#connections + 1] = { output = source .. ".out", input = "Door." .. input }
  end
  table.sort(components)
  table.sort(connections, function(a, b) return a.output < b.output end)
  defineDeployment(name, { components = components, connections = connections })
end
deployment("approach", { ArmCmd = "armTarget" })
deployment("grasp", { ArmCmd = "armTarget", GripCmd = "gripCommand" })
deployment("turn", { GripCmd = "gripCommand", TorqueCmd = "handleTorque" })
deployment("pull", { GripCmd = "gripCommand", PullCmd = "pullForce" })
deployment("release", {})

-- What `cobra run apps/door` does with this deployment: it runs until the task chart is done (or
-- failed), records the door's measurements and draws them in the run's report.
run = {
  title = "The door task (thesis Figs. 2.5-2.6)",
  charts = {
    { name = "door", supervisor = "TaskSup", done = "root.done", safe_stop = "root.failed" },
  },
  -- What ends the task in root.failed (door_task.lua): a component in Exception (the runner's
  -- e_component_error), a non-finite set-point the door refused, a detector silent past the chart's
  -- detector_timeout; the last one is the reason.
  failures = { "e_component_error", "e_command_not_finite", "e_detector_timeout" },
  record = { period = 0.01, ports = { "Door.armPosition", "Door.gripped", "Door.handleAngle", "Door.doorAngle" } },
  plots = {
    { title = "arm and door", unit = "m, rad",
      series = { "Door.armPosition", "Door.handleAngle", "Door.doorAngle" } },
  },
  summary = {
    { name = "door opening when released", unit = "rad", port = "Door.doorAngle", on_enter = "door:root.release" },
  },
}
