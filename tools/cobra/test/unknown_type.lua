-- A deployment with a typo in a component type: the CLI must name the file and line.
initConfigurator({ "cobra_signal" }, {
  { peer_name = "Sine", component_type = "SineGenerator" },
  { peer_name = "Amp", component_type = "Gian" },
})
