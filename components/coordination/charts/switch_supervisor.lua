-- The reusable deployment and configuration supervisors of the three-supervisor pattern (thesis
-- §2.2.3, Fig. 2.6), as one rFSM chart made for either kind:
--   require("switch_supervisor")("deployment")     -- see deployment_supervisor.lua
--   require("switch_supervisor")("configuration")  -- see configuration_supervisor.lua
-- Run by a cobra Supervisor component. A request event e_deploy_<name> (e_configure_<name>) on
-- its inputEvents makes it ask the Configurator for deployment (configuration) <name>; it answers
-- e_deployed_<name> or e_deploy_failed_<name> (e_configured_<name>, e_configure_failed_<name>)
-- on its outputEvents. Requests that arrive while one is being applied wait their turn.

local words = {
  deployment = { request = "e_deploy_", done = "e_deployed_", failed = "e_deploy_failed_", apply = "applyDeployment" },
  configuration = { request = "e_configure_", done = "e_configured_", failed = "e_configure_failed_",
                    apply = "applyConfiguration" },
}

return function(kind)
  local w = assert(words[kind], "switch_supervisor: kind must be 'deployment' or 'configuration'")
  local pending = {}   -- requested names, oldest first
  local current = nil  -- the name being applied

  -- The Supervisor raises each input event twice, as NAME and as NAME@SOURCE: a request is
  -- taken from its plain form only (the other would ask for a deployment "NAME@SOURCE").
  -- The guards run on every event the supervisor gets: they compare without making strings.
  local function take_requests(events)
    for _, e in ipairs(events) do
      if e:find(w.request, 1, true) == 1 and not e:find("@", 1, true) then
        pending[#pending + 1] = e:sub(#w.request + 1)
      end
    end
    return #pending > 0
  end

  -- The Supervisor answers a switch with e_<kind>_done@<name> or e_<kind>_failed@<name>; the
  -- two answers to wait for are made once, when the switch is asked.
  local answer = { done = nil, failed = nil }
  local function answered(events, verdict)
    local expected = answer[verdict]
    for _, e in ipairs(events) do
      if e == expected then return true end
    end
    return false
  end

  return rfsm.state {
    idle = rfsm.state {},
    applying = rfsm.state {
      entry = function()
        current = table.remove(pending, 1)
        answer.done = "e_" .. kind .. "_done@" .. current
        answer.failed = "e_" .. kind .. "_failed@" .. current
        _G[w.apply](current)
      end,
    },

    rfsm.trans { src = 'initial', tgt = 'idle' },
    rfsm.trans { src = 'idle', tgt = 'applying', guard = function(tr, events) return take_requests(events) end },
    rfsm.trans { src = 'applying', tgt = 'idle',
                 guard = function(tr, events) take_requests(events) return answered(events, "done") end,
                 effect = function() emit(w.done .. current) end },
    rfsm.trans { src = 'applying', tgt = 'idle',
                 guard = function(tr, events) take_requests(events) return answered(events, "failed") end,
                 effect = function() emit(w.failed .. current) end },
    -- Back in idle with requests that came while applying: on to the next one.
    rfsm.trans { src = 'idle', tgt = 'applying', events = { 'e_done@root.idle' },
                 guard = function() return #pending > 0 end },
  }
end
