-- How long the puncturing task charts (needle_insertion.lua, us_positioning.lua) wait for an
-- outside party before their safe stop, in s: the one place the application declares them. Each
-- timeout emits an event naming what was waited for, which the run's safe stop names
-- (puncturing.lua, run.failures). The nominal scenarios' scripted surgeon answers within seconds.
return {
  -- The surgeon's decision in WaitReaction (e_recover or e_take_over): e_reaction_timeout; and
  -- the surgeon's actions: the iceball configured (e_iceball_config_timeout), the used needle
  -- removed or a new one mounted (e_needle_change_timeout).
  surgeon = 120,
  -- The cryoablation console's cycle in WaitCryoCycle (e_cryo_done): e_cryo_timeout. A clinical
  -- freeze-thaw-freeze cycle takes about 30 min; the simulated console's, seconds.
  cryo_console = 2700,
  -- The other robot's chart (the needle waiting for the probe's positioning, the probe for the
  -- needle's progress): e_peer_chart_timeout. Its own waits are bounded by the values above and
  -- its safe stop reaches this chart (e_needle_safe_stop, e_us_safe_stop, e_peer_lost): this is
  -- the backstop for a peer that is silent without being reported lost.
  peer_chart = 3600,
}
