-- The task supervisor's chart of the Configurator listing (configurator_listing.lua): it follows
-- each plan of its peer MotPlan with the trajectory generator TrajGen, as the thesis' supervisors
-- do (§4.5): a plan done (e_plan_done) -> generate (askGenerateTraj) -> move (askStartMove) ->
-- Idle again at e_motion_done. A failure of either is reported and waits for the next plan.
return rfsm.state {
  Idle = rfsm.state {},
  Generating = rfsm.state { entry = function() TrajGen:askGenerateTraj() end },
  Moving = rfsm.state { entry = function() TrajGen:askStartMove() end },

  rfsm.trans { src = 'initial', tgt = 'Idle' },
  rfsm.trans { src = 'Idle', tgt = 'Generating', events = { 'e_path_ready' } },  -- TrajGen received the plan
  rfsm.trans { src = 'Generating', tgt = 'Moving', events = { 'e_trajectory_ready' } },
  rfsm.trans { src = 'Moving', tgt = 'Idle', events = { 'e_motion_done' } },
  rfsm.trans { src = 'Generating', tgt = 'Idle', events = { 'e_traj_failed' },
               effect = function() emit("e_task_failed") end },
}
