-- The "door task" of the thesis (§2.2, Fig. 2.5) as the task supervisor's rFSM chart. Each state
-- asks the deployment supervisor for the deployment that provides its actions (e_deploy_<name>)
-- and the configuration supervisor for how to perform them (e_configure_<name>); the task
-- advances on the events of the Decision components (ThresholdDetectors named AtHandle, Gripped,
-- Unlatched, DoorOpen). It knows nothing of ports, gains or forces: that is the point.
--
-- No state waits for ever: a detector that stays silent for `detector_timeout` s in the state that
-- waits for it (a stopped detector, a sensor gone quiet, a handle that does not give) is a failure:
-- the chart goes to root.failed with e_detector_timeout (the run's safe stop names the state, hence
-- the detector). root.failed keeps the deployment it was in: the gripper keeps what it holds, the
-- arm (moved by the handle while it grips it) stays where it is.

-- s a state waits for its detector's event before root.failed. The slowest wait of a nominal run
-- is the pull (the door from 0 to 1.2 rad: about 2.5 s at the gentle 3 N, DoorSim's inertia and
-- damping); the turn has its own 2 s before it turns firmly, then this again.
local detector_timeout = 5
local firm_after = 2  -- s: a handle that does not give within this is turned harder (the firm configuration)

local function ask(deployment, configuration)
  return function()
    emit("e_deploy_" .. deployment)
    if configuration then emit("e_configure_" .. configuration) end
  end
end

local silent = { 'e_after(' .. detector_timeout .. ')' }
local function timedOut() emit("e_detector_timeout") end

return rfsm.state {
  opening = rfsm.state {
    approach = rfsm.state { entry = ask("approach", "gentle") },
    grasp = rfsm.state { entry = ask("grasp") },
    turn = rfsm.state { entry = ask("turn") },
    -- A handle that does not give within `firm_after` s is turned harder: same deployment, firm configuration.
    turn_firmly = rfsm.state { entry = function() emit("e_configure_firm") end },
    pull = rfsm.state { entry = ask("pull") },

    rfsm.trans { src = 'initial', tgt = 'approach' },
    rfsm.trans { src = 'approach', tgt = 'grasp', events = { 'e_above_threshold@AtHandle' } },
    rfsm.trans { src = 'grasp', tgt = 'turn', events = { 'e_above_threshold@Gripped' } },
    rfsm.trans { src = 'turn', tgt = 'pull', events = { 'e_above_threshold@Unlatched' } },
    rfsm.trans { src = 'turn', tgt = 'turn_firmly', events = { 'e_after(' .. firm_after .. ')' } },
    rfsm.trans { src = 'turn_firmly', tgt = 'pull', events = { 'e_above_threshold@Unlatched' } },
    -- The gripper slipped: grasp again.
    rfsm.trans { src = 'pull', tgt = 'grasp', events = { 'e_below_threshold@Gripped' } },
  },
  release = rfsm.state { entry = ask("release") },
  done = rfsm.state {},
  failed = rfsm.state { entry = function() emit("e_door_task_failed") end },

  rfsm.trans { src = 'initial', tgt = 'opening' },
  rfsm.trans { src = 'opening', tgt = 'release', events = { 'e_above_threshold@DoorOpen' } },
  rfsm.trans { src = 'release', tgt = 'done', events = { 'e_below_threshold@Gripped' } },
  -- Outer transitions win over inner ones: a failed switch ends the task wherever it is.
  rfsm.trans { src = 'opening', tgt = 'failed', events = { 'e_deploy_failed_approach', 'e_deploy_failed_grasp',
                                                          'e_deploy_failed_turn', 'e_deploy_failed_pull' } },
  -- A component in Exception (the runner's e_component_error) or a non-finite set-point the door
  -- refused (e_command_not_finite): the task ends in its safe stop.
  rfsm.trans { src = 'opening', tgt = 'failed', events = { 'e_component_error', 'e_command_not_finite' } },
  rfsm.trans { src = 'release', tgt = 'failed', events = { 'e_component_error', 'e_command_not_finite' } },
  -- Each wait on a detector, bounded.
  rfsm.trans { src = 'opening.approach', tgt = 'failed', events = silent, effect = timedOut },
  rfsm.trans { src = 'opening.grasp', tgt = 'failed', events = silent, effect = timedOut },
  rfsm.trans { src = 'opening.turn_firmly', tgt = 'failed', events = silent, effect = timedOut },
  rfsm.trans { src = 'opening.pull', tgt = 'failed', events = silent, effect = timedOut },
  rfsm.trans { src = 'release', tgt = 'failed', events = silent, effect = timedOut },
}
