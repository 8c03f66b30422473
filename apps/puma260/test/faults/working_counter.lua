-- The EtherCAT frame comes back with a wrong working counter for 5 cycles (the last slave did not
-- process its datagram) during the nominal path: the master emits e_bus_fault, quick-stops the
-- drives and enters Fault; the chart stops (root.Stopping, root.SafeStop).
return {
  { on = { state = "puma:root.D_StartPose" }, after = 1.0, call = "World.injectWorkingCounterFault", args = { 5 } },
}
