-- A dds connection before the process's DdsLink is configured: refused, naming what to do.
initConfigurator({ "cobra_signal", "cobra_dds" }, {
  { peer_name = "Link", component_type = "DdsLink" },
  { peer_name = "Source", component_type = "Constant" },
  { peer_name = "Amp", component_type = "Gain" },
}, "")
connectPorts({
  { output = "Source.out", input = "Amp.in",
    conn_policy = { type = "data", transport = "dds", topic = "link/source" } },
})
