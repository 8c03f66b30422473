-- The FTSens stops sending (a pulled cable) while the tool is in contact: the driver raises
-- e_comm_timeout, the chart holds (root.Holding: the motion stopped); the sensor does not come
-- back, so after the hold time the chart stops (e_sensor_lost, root.SafeStop).
return {
  { on = { state = "puma:root.F_FollowingSurface" }, after = 0.2, call = "FTSensSim.setSilent", args = { true } },
}
