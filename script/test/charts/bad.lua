return rfsm.state {
  busy = rfsm.state {
    inner = rfsm.state {},
    doo = function() end,
    rfsm.trans { src = 'initial', tgt = 'inner' },
  },
  rfsm.trans { src = 'initial', tgt = 'busy' },
  rfsm.trans { src = 'busy', tgt = 'nowhere', events = { 'e_x' } },
  rfsm.trans { src = 'busy', tgt = 'busy', event = 'e_y' },
  rfsm.trans { src = 'busy', tgt = 'busy', events = { function(e) return true end } },
}
