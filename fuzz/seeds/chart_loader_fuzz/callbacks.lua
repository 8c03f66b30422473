-- Every kind of callback, with rFSM's arguments, writing to the global `log`.
log = {}
local function note(text) log[#log + 1] = text end
return rfsm.state {
  idle = rfsm.state {
    entry = function(fsm, state, kind) note(kind .. " idle") end,
    exit = function(fsm, state, kind) note(kind .. " idle") end,
  },
  working = rfsm.state {
    doo = function(fsm, state, kind)
      for i = 1, 3 do
        note(kind .. " " .. i)
        rfsm.yield()
      end
    end,
  },
  waiting = rfsm.state {
    entry = function(fsm) rfsm.send_events(fsm, "e_self") end,
    doo = function() while true do rfsm.yield(true) end end,
  },
  done = rfsm.state {},
  rfsm.trans { src = 'initial', tgt = 'idle' },
  rfsm.trans { src = 'idle', tgt = 'working', events = { 'e_go' },
               guard = function(tr, events) note("guard " .. table.concat(events, ",")) return #events == 2 end,
               effect = function(fsm, tr, kind, events) note(kind .. " " .. events[1]) end },
  rfsm.trans { src = 'working', tgt = 'waiting', events = { 'e_done' } },
  rfsm.trans { src = 'waiting', tgt = 'done', events = 'e_self' },
}
