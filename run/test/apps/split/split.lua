-- The runner's test application split over two hosts (run/test/split_runner_test.cpp): host a runs
-- the threshold application (../threshold), host b a supervisor of its own, and Link (the test's
-- clock sync) runs on both. The test runs host a only.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
placement = {
  hosts = {
    a = { "Sine", "Gain", "Detector", "Recorder", "TaskSup" },
    b = { "RemoteSup" },
  },
  everywhere = { "Link" },
  transport = "split_test_wire",
}
dofile(here .. "../threshold/threshold.lua")
initConfigurator({ "split_test_parts" }, {
  { peer_name = "Link", component_type = "TestLink" },
  { peer_name = "RemoteSup", component_type = "Supervisor" },
})
connectPorts({
  { output = "Detector.events", input = "RemoteSup.inputEvents", conn_policy = { type = "buffer", size = 16 } },
})
run.charts[#run.charts + 1] = { name = "remote", supervisor = "RemoteSup", done = "root.done" }
getReferences()
RemoteSup.fsm_path = here .. "../threshold/threshold_task.lua"  -- the same task, on host b's events
setActivities({ { peer_name = "RemoteSup", period = 0.01 } })
configureComponents({ "RemoteSup" })
startComponents({ "RemoteSup" })
