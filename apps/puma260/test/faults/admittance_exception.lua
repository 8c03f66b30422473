-- The admittance's update hook throws (a bug) while the tool rides on the surface: it goes to
-- Exception and its admPose stops; the runner tells the chart (e_component_error), which stops, then
-- retreats off the surface without it (root.Retreating: position_control) and stops (root.SafeStop).
return {
  { on = { state = "puma:root.F_FollowingSurface" }, after = 0.2, throw = "Admittance" },
}
