-- The package cobra_dds in a deployment file (dds_link CLI tests): a DdsLink configured first,
-- then a connection over the dds transport it carries (DDS domain 127, this test's own).
initConfigurator({ "cobra_signal", "cobra_dds" }, {
  { peer_name = "Link", component_type = "DdsLink" },
  { peer_name = "Source", component_type = "Constant" },
  { peer_name = "Amp", component_type = "Gain" },
}, "")
getReferences()
Link.domain = 127
Link.participant = "deploy_test"
Link.lease = 0.2
configureComponents({ "Link" })
Source.value = 2.5
connectPorts({
  { output = "Source.out", input = "Amp.in",
    conn_policy = { type = "data", transport = "dds", topic = "link/source",
                    qos = { reliability = "reliable", depth = 4 } } },
})
setActivities({ { peer_name = "Source", period = 0.001 }, { peer_name = "Amp", period = 0.001 } })
configureComponents({ "Source", "Amp" })
startComponents({ "Link", "Source", "Amp" })
