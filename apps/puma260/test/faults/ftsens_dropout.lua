-- The FTSens stops sending for 0.3 s while the tool is in contact: the driver raises
-- e_comm_timeout, the chart holds (root.Holding); the sensor comes back (e_comm_restored) within
-- the hold time and the nominal path resumes from where the tool is, to H.
return {
  { on = { state = "puma:root.F_FollowingSurface" }, after = 0.2, call = "FTSensSim.setSilent", args = { true } },
  { on = { state = "puma:root.Holding" }, after = 0.3, call = "FTSensSim.setSilent", args = { false } },
}
