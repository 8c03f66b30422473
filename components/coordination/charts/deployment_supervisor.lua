-- Deployment supervisor (thesis Fig. 2.6): e_deploy_<name> in, e_deployed_<name> or
-- e_deploy_failed_<name> out. See switch_supervisor.lua.
return require("switch_supervisor")("deployment")
