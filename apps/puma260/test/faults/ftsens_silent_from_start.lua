-- The FTSens is silent from the start (never connected): the tare in B_Ready is never answered;
-- after the chart's device_timeout it stops safely, naming e_sensor_timeout.
return {
  { on = { time = 0 }, call = "FTSensSim.setSilent", args = { true } },
}
