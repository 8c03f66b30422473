-- Drive 3 (the elbow) reports an over-current fault while the tool follows the nominal path: the
-- master sees it (e_drive_fault), quick-stops the other five drives and enters Fault; the chart
-- stops the motion (root.SafeStop).
return {
  { on = { state = "puma:root.D_StartPose" }, after = 1.0, call = "World.injectFault", args = { 2 } },
}
