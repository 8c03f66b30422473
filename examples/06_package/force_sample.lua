-- Example 06 with the package's own type, example.ForceSample (src/force_sample.hpp): the
-- filter's `sample_out` recorded by a Reporter, one column per field with its unit
-- (Filter.sample_out.force [N], Filter.sample_out.filtered [N], Filter.sample_out.count), and a
-- property of that type set from Lua (Hold.sample, a table of its fields).
--   cobra deploy force_sample.lua --sim --run-for 1      (the CSV: $FORCE_SAMPLE_CSV or ./force_sample.csv)
--   cobra console force_sample.lua --sim                 then: get Hold.sample

packages_list = { "cobra_signal", "cobra_reporting", "example_filters" }
components_list = {
  { peer_name = "Force", component_type = "Constant" },
  { peer_name = "Filter", component_type = "ForceLowPass" },
  { peer_name = "Hold", component_type = "ForceSampleHold" },
  { peer_name = "Reporter", component_type = "Reporter" },
}
initConfigurator(packages_list, components_list)
getReferences()

Force.value = 10.0             -- N
Filter.cutoff_frequency = 0.5  -- Hz
Filter.initial_force = 0.0     -- N
Hold.sample = { force = 1.5, filtered = 2.25, count = 3 }  -- an example.ForceSample from Lua
Reporter.file_path = os.getenv("FORCE_SAMPLE_CSV") or "force_sample.csv"

addPeers({ { peer_name = "Reporter", peers_to_add = { "Filter" } } })
setActivities({
  { peer_name = "Force", period = 0.001 },
  { peer_name = "Filter", period = 0.001 },
  { peer_name = "Hold", period = 0.001 },
  { peer_name = "Reporter", period = 0.1 },  -- s: a row every 100 ms
})
connectPorts({ { output = "Force.out", input = "Filter.force_in", conn_policy = rtt.Variable("ConnPolicy") } })
configureComponents({ "Force", "Filter", "Hold", "Reporter" })
startComponents({ "Force", "Filter", "Hold", "Reporter" })
