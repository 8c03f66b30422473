-- Example 06's type between two processes over DDS: example.ForceSample (src/force_sample.hpp),
-- registered by the package with cobra::types::registerType<T>(), crosses on the dds transport of
-- the package cobra_dds. One file, two roles (FORCE_SAMPLE_ROLE), on DDS domain COBRA_DDS_DOMAIN:
--   writer: the filter's sample_out published on topic example/force_sample;
--   reader: Hold.sample_in subscribed to it (fed by Quiet, which writes nothing itself), Hold's
--           output recorded by a Reporter ($FORCE_SAMPLE_CSV or ./force_sample_dds.csv).
--   FORCE_SAMPLE_ROLE=reader cobra deploy force_sample_dds.lua --run-for 3 &
--   FORCE_SAMPLE_ROLE=writer cobra deploy force_sample_dds.lua --run-for 3
-- (wall clock: two lockstep simulations would each run at their own pace).

local role = os.getenv("FORCE_SAMPLE_ROLE") or "writer"
assert(role == "writer" or role == "reader", "FORCE_SAMPLE_ROLE is writer or reader, not " .. role)
local dds = { type = "data", transport = "dds", topic = "example/force_sample",
              qos = { reliability = "reliable", durability = "transient_local", depth = 1 } }

initConfigurator({ "cobra_signal", "cobra_reporting", "cobra_dds", "example_filters" },
                 { { peer_name = "Link", component_type = "DdsLink" } })
getReferences()
Link.domain = tonumber(os.getenv("COBRA_DDS_DOMAIN") or "0")
Link.participant = "force_sample_" .. role
configureComponents({ "Link" })  -- before any dds connection: its participant carries them
startComponents({ "Link" })

if role == "writer" then
  initConfigurator({}, {
    { peer_name = "Force", component_type = "Constant" },
    { peer_name = "Filter", component_type = "ForceLowPass" },
    { peer_name = "Hold", component_type = "ForceSampleHold" },
  })
  getReferences()
  Force.value = 10.0             -- N
  Filter.cutoff_frequency = 0.5  -- Hz
  setActivities({ { peer_name = "Force", period = 0.001 }, { peer_name = "Filter", period = 0.001 },
                  { peer_name = "Hold", period = 0.001 } })
  connectPorts({ { output = "Force.out", input = "Filter.force_in", conn_policy = rtt.Variable("ConnPolicy") },
                 { output = "Filter.sample_out", input = "Hold.sample_in", conn_policy = dds } })
  configureComponents({ "Force", "Filter", "Hold" })
  startComponents({ "Force", "Filter", "Hold" })
else
  initConfigurator({}, {
    { peer_name = "Quiet", component_type = "ForceSampleHold" },
    { peer_name = "Hold", component_type = "ForceSampleHold" },
    { peer_name = "Reporter", component_type = "Reporter" },
  })
  getReferences()
  Reporter.file_path = os.getenv("FORCE_SAMPLE_CSV") or "force_sample_dds.csv"
  addPeers({ { peer_name = "Reporter", peers_to_add = { "Hold" } } })
  setActivities({ { peer_name = "Quiet", period = 0.01 }, { peer_name = "Hold", period = 0.001 },
                  { peer_name = "Reporter", period = 0.01 } })
  connectPorts({ { output = "Quiet.sample_out", input = "Hold.sample_in", conn_policy = dds } })
  configureComponents({ "Quiet", "Hold", "Reporter" })
  startComponents({ "Quiet", "Hold", "Reporter" })
end
