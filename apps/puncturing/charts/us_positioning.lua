-- Ultrasound positioning (thesis §4.4.2, Fig. 4.9): the UR5's task chart, run by its task
-- Supervisor. Same pattern as needle_insertion.lua: each state's entry asks the deployment and
-- configuration supervisors by name and its peers for services through void request
-- operations; it advances on their events, on the UltrasoundMonitor's (e_probe_contact,
-- e_probe_contact_lost, e_needle_visible, e_needle_lost), the surgeon's and the needle chart's.
-- The two robots are coordinated only through events (README.md):
--   consumed from the needle chart: e_needle_procedure_verified (its planner's verdict),
--                                   e_needle_wait_us (the probe may move), e_needle_skin_reached,
--                                   e_needle_extracted, e_needle_next
--   emitted for it: e_us_procedure_verified, e_us_procedure_refused (this planner's verdict),
--                   e_us_positioned, e_us_needle_tracked, e_us_needle_lost

-- What the lead wires: the Supervisor's peers by role, and the names of the deployments and
-- configurations its deployment and configuration supervisors know.
local peers = { frames = "ProbeFrames", planner = "ProbePlanner", trajectory = "ProbeTrajGen",
                coupling = "ProbeTransparency" }
local D = { planning = "probe_autonomous_planning", primitives = "probe_autonomous_primitives",
            teleoperated = "probe_teleoperated" }
local C = { free = "probe_free_motion", contact = "probe_contact", teleoperation = "probe_teleoperation" }
local search_timeout = 60  -- s in SearchingNeedle before the surgeon is asked to react
local arrival_grace = 1    -- s after the descent ends for the contact that should have ended it

local waits = require("waits")  -- s before a wait on the surgeon or the needle's chart gives up
local steps = require("task_steps") { chart = "us_positioning", peers = peers, goal_missed = "e_us_goal_missed" }
local call, stop, waiting, motion = steps.call, steps.stop, steps.waiting, steps.motion

local faults = { 'e_plan_failed', 'e_traj_failed', 'e_no_data', 'e_comm_timeout', 'e_ik_discontinuity' }
for _, d in pairs(D) do faults[#faults + 1] = 'e_deploy_failed_' .. d end
for _, c in pairs(C) do faults[#faults + 1] = 'e_configure_failed_' .. c end
local contact_faults = { 'e_probe_contact_lost', table.unpack(faults) }

local chart = {
  -- The whole procedure verified by both planners before anything moves (README.md "Verified
  -- whole"): once the needle's planner passed it (e_needle_procedure_verified, from the needle
  -- chart's WaitProbeVerdict), this chart's walks it too (the same inputs, the probe's planner's
  -- own options and seed: its verdict can differ) and keeps the probe's verified paths to follow.
  -- Its verdict goes to the needle chart, which moves only after both passed:
  -- e_us_procedure_verified, or e_us_procedure_refused and both charts' safe stops.
  Idle = waiting("root.Idle", D.planning, C.free),
  VerifyingProcedure = rfsm.state { entry = function() call("planner", "verifyProcedure") end },
  Refused = rfsm.state { entry = function() emit("e_us_procedure_refused") end },
  Verified = waiting("root.Verified", D.planning, C.free, function() emit("e_us_procedure_verified") end),
  -- Above the planned pose, then down along the beam until the probe touches the skin.
  MoveToSkin = rfsm.state {
    Approach = motion("root.MoveToSkin.Approach", D.planning, C.free, { planned = true }),
    Descend = motion("root.MoveToSkin.Descend", D.primitives, C.free, { grace = arrival_grace }),
    rfsm.trans { src = 'initial', tgt = 'Approach' },
    rfsm.trans { src = 'Approach', tgt = 'Descend', events = { 'e_motion_done' } },
  },
  WaitNeedleSkinReached = waiting("root.WaitNeedleSkinReached", D.primitives, C.contact),
  -- Phase H: the Frame Generator moves on to the next needle and says whether there is one.
  NextProbePose = rfsm.state {},
  -- The probe presses on the skin (probe_contact configuration) while the needle goes in.
  USPositioned = rfsm.state {
    SearchingNeedle = motion("root.USPositioned.SearchingNeedle", D.primitives, C.contact, { arrive = true }),
    NeedleTracked = waiting("root.USPositioned.NeedleTracked", D.primitives, C.contact,
                            function() emit("e_us_needle_tracked") end),
    rfsm.trans { src = 'initial', tgt = 'SearchingNeedle' },
    rfsm.trans { src = 'SearchingNeedle', tgt = 'NeedleTracked', events = { 'e_needle_visible' }, effect = stop },
    rfsm.trans { src = 'NeedleTracked', tgt = 'SearchingNeedle', events = { 'e_needle_lost' },
                 effect = function() emit("e_us_needle_lost") end },
    rfsm.trans { src = 'SearchingNeedle', tgt = 'root.WaitReaction', events = { 'e_after(' .. search_timeout .. ')' },
                 effect = function() emit("e_us_needle_not_found") end },
  },
  WaitReaction = rfsm.state { entry = function() stop() emit("e_us_reaction_needed") end },
  -- The surgeon takes over the probe: InitHapticDevice, then TeleoperationActive (task_steps.teleoperation).
  USTeleoperation = rfsm.state(steps.teleoperation(D.teleoperated, C.teleoperation, { "coupling" })),

  -- The same failure again after a reaction (task_steps.lua), the needle chart stopped or its host lost: the
  -- motion stops, the admittance holds the probe where it is, and the procedure ends here.
  SafeStop = rfsm.state { entry = function() stop() emit("e_us_safe_stop") end },
  Done = rfsm.state { entry = function() emit("e_us_task_done") end },

  rfsm.trans { src = 'initial', tgt = 'Idle' },
  rfsm.trans { src = 'Idle', tgt = 'VerifyingProcedure', events = { 'e_needle_procedure_verified' } },
  rfsm.trans { src = 'VerifyingProcedure', tgt = 'Verified', events = { 'e_procedure_verified' } },
  rfsm.trans { src = 'VerifyingProcedure', tgt = 'Refused', events = { 'e_procedure_refused' } },
  rfsm.trans { src = 'Refused', tgt = 'SafeStop' },
  -- The needle robot waits where it leaves room for the probe (its MakeRoomForProbe, then
  -- WaitUSPositioning): the probe moves only then.
  rfsm.trans { src = 'Verified', tgt = 'MoveToSkin', events = { 'e_needle_wait_us' } },
  rfsm.trans { src = 'MoveToSkin', tgt = 'WaitNeedleSkinReached', events = { 'e_probe_contact' },
               effect = function() stop() emit("e_us_positioned") end },
  -- Phase H: on to the next needle's probe pose, once the Frame Generator has one; none after the
  -- last needle: the task is done (no approach, no switch).
  rfsm.trans { src = 'WaitNeedleSkinReached', tgt = 'NextProbePose', events = { 'e_needle_next' }, pn = 10,
               effect = function() call("frames", "nextNeedle") end },
  rfsm.trans { src = 'NextProbePose', tgt = 'MoveToSkin', events = { 'e_needle_selected' } },
  rfsm.trans { src = 'NextProbePose', tgt = 'Done', events = { 'e_all_needles_done' } },
  -- The needle chart waits for the probe: say it is in place (again).
  rfsm.trans { src = 'WaitNeedleSkinReached', tgt = 'WaitNeedleSkinReached', events = { 'e_needle_wait_us' },
               effect = function() emit("e_us_positioned") end },
  rfsm.trans { src = 'WaitNeedleSkinReached', tgt = 'USPositioned', events = { 'e_needle_skin_reached' } },
  rfsm.trans { src = 'USPositioned', tgt = 'WaitNeedleSkinReached', events = { 'e_needle_extracted' } },
  rfsm.trans { src = 'WaitReaction', tgt = 'USTeleoperation', events = { 'e_take_over' } },
  -- Nobody answers (waits.lua): the safe stop, naming what was waited for.
  steps.timeout('WaitReaction', waits.surgeon, 'e_reaction_timeout'),
  steps.timeout('Idle', waits.peer_chart, 'e_peer_chart_timeout'),
  steps.timeout('Verified', waits.peer_chart, 'e_peer_chart_timeout'),
  steps.timeout('WaitNeedleSkinReached', waits.peer_chart, 'e_peer_chart_timeout'),
  steps.timeout('USPositioned', waits.peer_chart, 'e_peer_chart_timeout'),
}
for _, reaction in ipairs({ { 'MoveToSkin', faults }, { 'WaitNeedleSkinReached', contact_faults },
                            { 'USPositioned', contact_faults } }) do
  for _, t in ipairs({ steps.reactions(reaction[1], reaction[2]) }) do chart[#chart + 1] = t end
end
-- The needle chart stopped safely, or its host was lost (the run split over two hosts, the DDS
-- link's e_peer_lost): this one stops too, from wherever it is.
for _, state in ipairs({ 'Idle', 'VerifyingProcedure', 'Verified', 'MoveToSkin', 'WaitNeedleSkinReached', 'NextProbePose', 'USPositioned', 'WaitReaction',
                         'USTeleoperation' }) do
  chart[#chart + 1] = rfsm.trans { src = state, tgt = 'SafeStop', events = { 'e_needle_safe_stop', 'e_peer_lost' }, pn = 20 }
  -- A component in Exception (the runner's e_component_error), a non-finite input or command refused.
  chart[#chart + 1] = rfsm.trans { src = state, tgt = 'SafeStop',
                                   events = { 'e_component_error', 'e_input_not_finite', 'e_command_not_finite' }, pn = 20 }
end

local resumable = { "root.MoveToSkin.Approach", "root.MoveToSkin.Descend", "root.WaitNeedleSkinReached",
                    "root.USPositioned.SearchingNeedle", "root.USPositioned.NeedleTracked" }
steps.resumptions(chart, resumable, 'USTeleoperation')

-- The Supervisor runs this when it goes to Exception (a callback failed or ran past its budget):
-- the motion stops, the admittance holds the probe where it is, and the needle chart is told, as by
-- this chart's SafeStop, so that it stops too.
function exceptionHook()
  stop()
  emit("e_us_safe_stop")
end

return rfsm.state(chart)
