-- The kinematics solver is held to 0.2 % of its joint speeds while the tool rides on the surface:
-- the next command is out of its reach (e_ik_discontinuity); the chart stops, retreats off the
-- surface slowly enough for the slowed solver (configurations/puma260_retreat.lua) and stops.
return {
  { on = { state = "puma:root.F_FollowingSurface" }, after = 0.2, set = { property = "Kin.speed_scaling", value = 0.002 } },
}
