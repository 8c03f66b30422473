-- Needle insertion (thesis §4.4.1, Fig. 4.8): the I-SUR robot's task chart, run by its task
-- Supervisor. Each state's entry asks the deployment and configuration supervisors for what it
-- needs by name (e_deploy_<name>, e_configure_<name>: components/coordination/charts) and asks
-- its peers for services through void request operations (askCurrentGoal, askPlan,
-- askGenerateTraj, askStartMove, askStopMove, nextNeedle); it advances on their events and on
-- the Decision components' (NeedleInsertionMonitor), the surgeon's, the cryoablation console's
-- (e_cryo_start asked, e_cryo_done answered) and the ultrasound chart's.
-- It never touches pure data. The two robots are coordinated only through events (README.md):
--   consumed from the ultrasound chart: e_us_positioned, e_us_needle_lost, e_us_needle_tracked
--   emitted for it: e_needle_wait_us, e_needle_skin_reached, e_needle_extracted, e_needle_next
-- First, before the probe moves, MakeRoomForProbe: to the needle change pose that leaves the
-- probe's first approach free (the state table lists the alternatives, the planner takes the
-- first that does; the surgeon mounts the needle there). Per needle: WaitUSPositioning, then
-- InsertingNeedles (to the needle change pose, the used needle removed, a new one mounted, to
-- the skin, through it, to the tumour), WaitCryoCycle, ExtractingNeedle (a short pull tells
-- whether the ice still holds the needle), back to the needle change pose (§4.9 phases G-H),
-- again one that leaves the probe's next approach free.

-- What the lead wires: the Supervisor's peers by role, and the names of the deployments and
-- configurations (thesis §4.6-4.7) its deployment and configuration supervisors know.
local peers = { frames = "NeedleFrames", planner = "NeedlePlanner", trajectory = "NeedleTrajGen",
                monitor = "NeedleMonitor", coupling = "NeedleTransparency" }
local D = { planning = "needle_autonomous_planning", primitives = "needle_autonomous_primitives",
            teleoperated = "needle_teleoperated" }
local C = { free = "needle_free_motion", penetration = "needle_penetration", insertion = "needle_insertion",
            teleoperation = "needle_teleoperation" }
local defrost_check = 10  -- s in WaitDefreezing before pulling again
local arrival_grace = 1   -- s after a motion ends for the event that should have ended it

local waits = require("waits")  -- s before a wait on the surgeon, the console or the probe's chart gives up
local steps = require("task_steps") { chart = "needle_insertion", peers = peers, goal_missed = "e_needle_goal_missed" }
local call, stop, waiting, motion = steps.call, steps.stop, steps.waiting, steps.motion

local needle_on_tool = false  -- a needle is mounted on the robot (new or used)
local at_change = false       -- the robot is at the needle change pose


-- e_ik_discontinuity: the robot refused a command it could not follow continuously (another IK
-- branch, or beyond its joint velocity limits in one period) and holds its last valid one.
local faults = { 'e_forbidden_region', 'e_plan_failed', 'e_traj_failed', 'e_no_data', 'e_comm_timeout',
                 'e_ik_discontinuity' }
for _, d in pairs(D) do faults[#faults + 1] = 'e_deploy_failed_' .. d end
for _, c in pairs(C) do faults[#faults + 1] = 'e_configure_failed_' .. c end
local insertion_faults = { 'e_force_over_threshold', table.unpack(faults) }

local chart = {
  WaitIceballConfig = waiting("root.WaitIceballConfig", D.planning, C.free),
  -- The plan and the registration, from the files or from the navigation peer over OpenIGTLink
  -- (the Frame Generator's plan_source; README.md "Navigated puncturing"): its awaitNavigation
  -- answers e_navigation_received once it has taken both (at once with files), or
  -- e_navigation_refused (a plan validate() refuses, a registration it cannot take) or
  -- e_navigation_timeout (what did not come), each named by its navigationStatus().
  WaitNavigation = rfsm.state { entry = function() call("frames", "awaitNavigation") end },
  -- The whole procedure verified before anything moves (the planner's verifyProcedure: every
  -- motion state of both charts for the plan and the registration, in their order, README.md
  -- "Verified whole"): e_procedure_verified, or e_procedure_refused naming the needle, the state,
  -- the datum and why (the planner's lastRefusal()).
  VerifyingProcedure = rfsm.state { entry = function() call("planner", "verifyProcedure") end },
  -- Refused before the first motion: the robots never moved; the procedure ends (the safe stop
  -- holds them where they are, the ultrasound chart follows).
  Refused = rfsm.state { entry = function() emit("e_needle_procedure_refused") end },
  -- This planner passed it: the probe's planner walks it now (us_positioning.lua); both must pass.
  WaitProbeVerdict = rfsm.state { entry = function() emit("e_needle_procedure_verified") end },
  MakeRoomForProbe = motion("root.MakeRoomForProbe", D.planning, C.free, { planned = true }),
  WaitUSPositioning = waiting("root.WaitUSPositioning", D.planning, C.free, function() emit("e_needle_wait_us") end),
  InsertingNeedles = rfsm.state {
    MoveToNeedleChange = motion("root.InsertingNeedles.MoveToNeedleChange", D.planning, C.free, { planned = true }),
    WaitNeedleRemoved = waiting("root.InsertingNeedles.WaitNeedleRemoved", D.planning, C.free),
    WaitNeedleMounted = waiting("root.InsertingNeedles.WaitNeedleMounted", D.planning, C.free),
    MoveToSkin = rfsm.state {
      Approach = motion("root.InsertingNeedles.MoveToSkin.Approach", D.planning, C.free, { planned = true }),
      Descend = motion("root.InsertingNeedles.MoveToSkin.Descend", D.primitives, C.free, { grace = arrival_grace }),
      rfsm.trans { src = 'initial', tgt = 'Approach' },
      rfsm.trans { src = 'Approach', tgt = 'Descend', events = { 'e_motion_done' } },
    },
    PenetratingSkin = motion("root.InsertingNeedles.PenetratingSkin", D.primitives, C.penetration,
                             { grace = arrival_grace }),
    MoveToTumor = motion("root.InsertingNeedles.MoveToTumor", D.primitives, C.insertion,
                         { grace = arrival_grace, pause = { 'e_us_needle_lost', 'e_us_needle_tracked' } }),

    rfsm.trans { src = 'initial', tgt = 'MoveToNeedleChange' },
    rfsm.trans { src = 'MoveToNeedleChange', tgt = 'WaitNeedleRemoved', events = { 'e_motion_done' },
                 guard = function() return needle_on_tool end, effect = function() at_change = true end },
    rfsm.trans { src = 'MoveToNeedleChange', tgt = 'WaitNeedleMounted', events = { 'e_motion_done' },
                 guard = function() return not needle_on_tool end, effect = function() at_change = true end },
    -- The used needle is off: the next one needs the probe at its next pose first (phase H).
    rfsm.trans { src = 'WaitNeedleRemoved', tgt = 'root.WaitUSPositioning', events = { 'e_needle_removed' },
                 effect = function()
                   needle_on_tool = false
                   call("frames", "nextNeedle")
                   emit("e_needle_next")
                 end },
    -- A new needle: the monitor's skin touch and puncture detection are re-armed for it.
    rfsm.trans { src = 'WaitNeedleMounted', tgt = 'MoveToSkin', events = { 'e_needle_mounted' },
                 effect = function() needle_on_tool, at_change = true, false call("monitor", "reset") end },
    rfsm.trans { src = 'MoveToSkin', tgt = 'PenetratingSkin', events = { 'e_skin_touched' },
                 effect = function() stop() emit("e_needle_skin_reached") end },
    rfsm.trans { src = 'PenetratingSkin', tgt = 'MoveToTumor', events = { 'e_skin_penetrated' },
                 effect = stop },
    rfsm.trans { src = 'MoveToTumor', tgt = 'root.WaitCryoCycle', events = { 'e_target_reached' },
                 effect = function() emit("e_needle_placed") end },
  },
  -- The needle placed: the cryoablation console (CryoConsole in deployment/world.lua) is asked for
  -- its freeze cycle and answers e_cryo_done once the iceball has thawed.
  WaitCryoCycle = waiting("root.WaitCryoCycle", D.primitives, C.insertion, function() emit("e_cryo_start") end),
  ExtractingNeedle = rfsm.state {
    VerifyingNeedleTrapped = motion("root.ExtractingNeedle.VerifyingNeedleTrapped", D.primitives, C.insertion),
    WaitDefreezing = waiting("root.ExtractingNeedle.WaitDefreezing", D.primitives, C.insertion),
    MoveToExtractionPoint = motion("root.ExtractingNeedle.MoveToExtractionPoint", D.primitives, C.insertion),

    rfsm.trans { src = 'initial', tgt = 'VerifyingNeedleTrapped' },
    -- The short pull met the ice's hold (the monitor's force estimate): wait for it to thaw.
    rfsm.trans { src = 'VerifyingNeedleTrapped', tgt = 'WaitDefreezing', events = { 'e_needle_trapped' },
                 effect = stop },
    rfsm.trans { src = 'VerifyingNeedleTrapped', tgt = 'MoveToExtractionPoint', events = { 'e_motion_done' } },
    rfsm.trans { src = 'WaitDefreezing', tgt = 'VerifyingNeedleTrapped',
                 events = { 'e_needle_free', 'e_after(' .. defrost_check .. ')' } },
    rfsm.trans { src = 'MoveToExtractionPoint', tgt = 'WaitDefreezing', events = { 'e_needle_trapped' }, effect = stop },
    rfsm.trans { src = 'MoveToExtractionPoint', tgt = 'root.InsertingNeedles', events = { 'e_motion_done' },
                 effect = function() emit("e_needle_extracted") end },
  },
  -- Something unexpected: the robot stops and the surgeon chooses (thesis §4.4.1).
  WaitReaction = rfsm.state { entry = function() stop() emit("e_needle_reaction_needed") end },
  -- The surgeon takes over (the robot stopped in WaitReaction): InitHapticDevice (the teleoperated
  -- deployment and configuration), then TeleoperationActive (the two-layer coupling engaged:
  -- task_steps.teleoperation); e_teleop_done resumes the interrupted state.
  NeedleTeleoperation = rfsm.state(steps.teleoperation(D.teleoperated, C.teleoperation, { "coupling" })),

  -- The same failure again after a reaction (task_steps.lua), the ultrasound chart stopped, or its host lost:
  -- the motion stops, the admittance holds the needle where it is, and the procedure ends here.
  SafeStop = rfsm.state { entry = function() stop() emit("e_needle_safe_stop") end },
  Done = rfsm.state { entry = function() emit("e_needle_task_done") end },

  rfsm.trans { src = 'initial', tgt = 'WaitIceballConfig' },
  rfsm.trans { src = 'WaitIceballConfig', tgt = 'WaitNavigation', events = { 'e_iceball_configured' } },
  rfsm.trans { src = 'WaitNavigation', tgt = 'VerifyingProcedure', events = { 'e_navigation_received' } },
  rfsm.trans { src = 'WaitNavigation', tgt = 'Refused', events = { 'e_navigation_refused', 'e_navigation_timeout' } },
  rfsm.trans { src = 'VerifyingProcedure', tgt = 'WaitProbeVerdict', events = { 'e_procedure_verified' } },
  rfsm.trans { src = 'WaitProbeVerdict', tgt = 'MakeRoomForProbe', events = { 'e_us_procedure_verified' } },
  rfsm.trans { src = 'VerifyingProcedure', tgt = 'Refused', events = { 'e_procedure_refused' } },
  rfsm.trans { src = 'Refused', tgt = 'SafeStop' },
  -- At a needle change pose: the probe may move (WaitUSPositioning says so), the needle is mounted there.
  rfsm.trans { src = 'MakeRoomForProbe', tgt = 'WaitUSPositioning', events = { 'e_motion_done' },
               effect = function() at_change = true end },
  rfsm.trans { src = 'WaitUSPositioning', tgt = 'InsertingNeedles.WaitNeedleMounted', events = { 'e_us_positioned' },
               guard = function() return at_change end },
  rfsm.trans { src = 'WaitUSPositioning', tgt = 'InsertingNeedles', events = { 'e_us_positioned' },
               guard = function() return not at_change end },
  rfsm.trans { src = 'WaitUSPositioning', tgt = 'Done', events = { 'e_all_needles_done' }, pn = 10 },
  rfsm.trans { src = 'WaitCryoCycle', tgt = 'ExtractingNeedle', events = { 'e_cryo_done' } },
  rfsm.trans { src = 'WaitReaction', tgt = 'NeedleTeleoperation', events = { 'e_take_over' } },
  -- Nobody answers (waits.lua): the safe stop, naming what was waited for.
  steps.timeout('WaitReaction', waits.surgeon, 'e_reaction_timeout'),
  steps.timeout('WaitIceballConfig', waits.surgeon, 'e_iceball_config_timeout'),
  steps.timeout('InsertingNeedles.WaitNeedleRemoved', waits.surgeon, 'e_needle_change_timeout'),
  steps.timeout('InsertingNeedles.WaitNeedleMounted', waits.surgeon, 'e_needle_change_timeout'),
  steps.timeout('WaitCryoCycle', waits.cryo_console, 'e_cryo_timeout'),
  steps.timeout('WaitUSPositioning', waits.peer_chart, 'e_peer_chart_timeout'),
}
for _, reaction in ipairs({ { 'MakeRoomForProbe', faults }, { 'InsertingNeedles', insertion_faults },
                            { 'ExtractingNeedle', faults }, { 'WaitUSPositioning', faults } }) do
  for _, t in ipairs({ steps.reactions(reaction[1], reaction[2]) }) do chart[#chart + 1] = t end
end
-- The ultrasound chart stopped safely, or its host was lost (the run split over two hosts, the
-- DDS link's e_peer_lost), or the navigation peer asked to abort: this one stops too, from
-- wherever it is. The navigation peer lost (e_igtl_peer_lost) is no reason to stop: the plan and
-- registration were taken and verified before the first motion, and the procedure goes on with
-- them (README.md "Navigated puncturing"); until they came, WaitNavigation's timeout bounds the wait.
for _, state in ipairs({ 'WaitIceballConfig', 'WaitNavigation', 'VerifyingProcedure', 'WaitProbeVerdict', 'MakeRoomForProbe',
                         'WaitUSPositioning', 'InsertingNeedles', 'WaitCryoCycle',
                         'ExtractingNeedle', 'WaitReaction', 'NeedleTeleoperation' }) do
  chart[#chart + 1] = rfsm.trans { src = state, tgt = 'SafeStop', events = { 'e_us_safe_stop', 'e_peer_lost' }, pn = 20 }
  -- The navigation peer's ABORT request (its IgtlBridge's `requests`): the same stop.
  chart[#chart + 1] = rfsm.trans { src = state, tgt = 'SafeStop', events = { 'e_navigation_abort' }, pn = 20 }
  -- A component in Exception (the runner's e_component_error), a non-finite input or command
  -- refused: no reaction can mend a broken component; the safe stop, at once.
  chart[#chart + 1] = rfsm.trans { src = state, tgt = 'SafeStop',
                                   events = { 'e_component_error', 'e_input_not_finite', 'e_command_not_finite' }, pn = 20 }
end

-- Recovery (e_recover) and the end of a teleoperation (e_teleop_done) return to the state that
-- was interrupted; a motion starts again from where the needle is.
local resumable = {
  "root.MakeRoomForProbe", "root.WaitUSPositioning", "root.InsertingNeedles.MoveToNeedleChange", "root.InsertingNeedles.WaitNeedleRemoved",
  "root.InsertingNeedles.WaitNeedleMounted", "root.InsertingNeedles.MoveToSkin.Approach",
  "root.InsertingNeedles.MoveToSkin.Descend", "root.InsertingNeedles.PenetratingSkin",
  "root.InsertingNeedles.MoveToTumor", "root.ExtractingNeedle.VerifyingNeedleTrapped",
  "root.ExtractingNeedle.WaitDefreezing", "root.ExtractingNeedle.MoveToExtractionPoint",
}
steps.resumptions(chart, resumable, 'NeedleTeleoperation')

-- The Supervisor runs this when it goes to Exception (a callback failed or ran past its budget):
-- the motion stops, the admittance holds the needle where it is, and the ultrasound chart is told, as by
-- this chart's SafeStop, so that it stops too.
function exceptionHook()
  stop()
  emit("e_needle_safe_stop")
end

return rfsm.state(chart)
