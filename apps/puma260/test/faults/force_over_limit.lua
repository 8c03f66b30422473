-- The admittance is made stiff along z while the tool rides on the surface (a wrong configuration:
-- 3000 N/m instead of 300 N/m): the contact force rises through the configured limit, the contact
-- monitor raises e_force_over_limit and the chart stops (root.SafeStop).
return {
  { on = { state = "puma:root.F_FollowingSurface" }, after = 0.1,
    set = { property = "Admittance.stiffness", value = { 3000, 3000, 3000, 60, 60, 60 } } },
}
