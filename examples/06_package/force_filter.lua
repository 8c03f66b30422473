-- Example 06's deployment: a constant force set-point filtered by ForceLowPass, a component of
-- the package example_filters built outside cobra's tree (CMakeLists.txt here). The deployer
-- finds libexample_filters.so on COBRA_PACKAGE_PATH, or in <prefix>/lib/cobra/packages when the
-- package is installed beside cobra.
--   cobra deploy force_filter.lua --sim --run-for 1
--   cobra console force_filter.lua --sim     then: step 1, read Filter.force_out

packages_list = { "cobra_signal", "example_filters" }
components_list = {
  { peer_name = "Force", component_type = "Constant" },
  { peer_name = "Filter", component_type = "ForceLowPass" },
}
initConfigurator(packages_list, components_list)
getReferences()

Force.value = 10.0             -- N: a step of 10 N at start
Filter.cutoff_frequency = 0.5  -- Hz: time constant 1/(2π·0.5) ≈ 0.32 s
Filter.initial_force = 0.0     -- N

setActivities({
  { peer_name = "Force", period = 0.001, priority = 50, scheduler = rtt.globals.ORO_SCHED_RT },
  { peer_name = "Filter", period = 0.001, priority = 50, scheduler = rtt.globals.ORO_SCHED_RT },
})
connectPorts({ { output = "Force.out", input = "Filter.force_in", conn_policy = rtt.Variable("ConnPolicy") } })
configureComponents({ "Force", "Filter" })
startComponents({ "Force", "Filter" })
