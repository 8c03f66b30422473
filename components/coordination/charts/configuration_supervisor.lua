-- Configuration supervisor (thesis Fig. 2.6): e_configure_<name> in, e_configured_<name> or
-- e_configure_failed_<name> out. See switch_supervisor.lua.
return require("switch_supervisor")("configuration")
