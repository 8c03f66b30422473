-- The kinematics solver is held to 0.2 % of its joint speeds while the tool rides on the surface:
-- the next command is out of its reach (e_ik_discontinuity); the chart stops and tries the retreat,
-- whose first step the slowed solver refuses too (the wrist still hunts), so the master's own
-- joint-space move to the ready position lifts the tool off instead (root.ToReady), then SafeStop.
return {
  { on = { state = "puma:root.F_FollowingSurface" }, after = 0.2, set = { property = "Kin.speed_scaling", value = 0.002 } },
}
