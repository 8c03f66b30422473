-- The suturing task (thesis §5.5, Fig. 5.11): the two-armed I-SUR's task chart, run by its task
-- Supervisor. Like the puncturing charts (apps/puncturing/charts), each state's entry asks the
-- deployment and configuration supervisors for what it needs by name (e_deploy_<name>,
-- e_configure_<name>) and its peers for services through void request operations; it advances on
-- their events. It never touches pure data. Its motions, waiting states and reactions are the
-- puncturing charts' (cobra's task_steps.lua, components/task/charts: on every chart's package.path).
--
-- Per stitch (§5.6 phases A-H): GetStitchTargetPose (the StitchPlanner plans it from the wound's
-- current edges), ApplyRightStitch (B over the wound, planned; C inside it; D to the right edge,
-- the Endo Stitch actuated: the robot answers e_endo_stitch_actuated; out of the skin), then the
-- thread: PullThread (E, the contact configuration), HookThread (F), PushThread (G, then the stick
-- lets the thread go), ApplyLeftStitch (H over the wound again, the same steps on the left edge),
-- and the thread again, which now closes the stitch; then the next stitch, until the plan has none.
-- The surgeon may take over at any time (e_take_over): TeleoperatedMode stops the motion
-- (StoppingMotion), switches to the teleoperated deployment with the haptic device
-- (InitHapticDevice) and runs it (TeleoperationActive: the couplings engaged) until e_teleop_done,
-- which resumes the interrupted state.
-- The end (e_stitches_done): Finishing waits for both tools to be at rest (the RestMonitor's
-- e_at_rest) before Done: the last push's e_motion_done says where the references stopped, and the
-- arms, let go of the thread's pull (the stick releases it), spring back onto their admittances'
-- references meanwhile (the stick 3.4 mm, the Endo Stitch 2.2 mm in the 0.75 s after the last push). Not at rest within `rest_timeout` s:
-- root.SafeStop with e_not_at_rest.

-- What the lead wires: the Supervisor's peers by role, and the names of the deployments and
-- configurations (thesis §5.5.1-5.5.2) its deployment and configuration supervisors know.
local peers = { frames = "SutureFrames", planner = "SuturePlanner", trajectory = "SutureTrajGen",
                stitches = "Stitches", right_coupling = "RightTransparency", left_coupling = "LeftTransparency",
                rest = "ArmsRest" }
local D = { planning = "suturing_autonomous_planning", primitives = "suturing_autonomous_primitives",
            teleoperated = "suturing_teleoperated" }
local C = { free = "suturing_free_motion", contact = "suturing_contact", teleoperation = "suturing_teleoperation" }
local arrival_grace = 1   -- s after a motion ends for the event that should have ended it
local plan_retry = 0.1    -- s between asks while the sensing module has no edges yet
-- s the chart waits in WaitReaction for the surgeon's decision (e_recover or e_take_over); then it
-- stops safely, emitting e_reaction_timeout (the run's safe stop names it).
local reaction_timeout = 120
-- s Finishing waits for both tools at rest (a critically damped admittance let go of a few N settles
-- within 1 s: free motion's 15.8 rad/s); then root.SafeStop with e_not_at_rest.
local rest_timeout = 5

local steps = require("task_steps") { chart = "suturing", peers = peers, goal_missed = "e_suture_goal_missed" }
local call, stop, waiting, motion = steps.call, steps.stop, steps.waiting, steps.motion

local half = "right"  -- the half-stitch being applied: right, then left

-- Failures the chart reacts to (task_steps.reactions: root.WaitReaction, the same one again
-- root.SafeStop). e_stitch_missed: the sensing module saw no stitch after an actuation.
local faults = { 'e_plan_failed', 'e_traj_failed', 'e_no_data', 'e_comm_timeout', 'e_ik_discontinuity',
                 'e_ik_failed', 'e_no_wound_data', 'e_stitch_missed', 'e_endo_stitch_busy' }
for _, d in pairs(D) do faults[#faults + 1] = 'e_deploy_failed_' .. d end
for _, c in pairs(C) do faults[#faults + 1] = 'e_configure_failed_' .. c end

-- The five steps of a half-stitch (ApplyRightStitch, ApplyLeftStitch).
local function applyStitch(side)
  local fqn = "root.AutonomousMode.Apply" .. side .. "Stitch."
  return rfsm.state {
    MoveOverWound = motion(fqn .. "MoveOverWound", D.planning, C.free, { planned = true }),
    MoveInsideWound = motion(fqn .. "MoveInsideWound", D.primitives, C.free),
    MoveToWoundEdge = motion(fqn .. "MoveToWoundEdge", D.primitives, C.free),
    -- The robot actuates the Endo Stitch (its inputEvents): the needle passes to the other jaw.
    ApplyStitch = waiting(fqn .. "ApplyStitch", D.primitives, C.free, function() emit("e_actuate_endo_stitch") end),
    DisengageNeedle = motion(fqn .. "DisengageNeedle", D.primitives, C.free),
    rfsm.trans { src = 'initial', tgt = 'MoveOverWound' },
    rfsm.trans { src = 'MoveOverWound', tgt = 'MoveInsideWound', events = { 'e_motion_done' } },
    rfsm.trans { src = 'MoveInsideWound', tgt = 'MoveToWoundEdge', events = { 'e_motion_done' } },
    rfsm.trans { src = 'MoveToWoundEdge', tgt = 'ApplyStitch', events = { 'e_motion_done' } },
    rfsm.trans { src = 'ApplyStitch', tgt = 'DisengageNeedle', events = { 'e_endo_stitch_actuated' },
                 effect = function() emit("e_half_stitch_" .. string.lower(side)) end },
  }
end

local chart = {
  -- A: both arms at their initial poses; the sensing module's edges give the plan.
  WaitStitchesPlan = waiting("root.WaitStitchesPlan", D.planning, C.free, function() call("stitches", "askStitch") end),
  RetryStitchesPlan = rfsm.state {},
  AutonomousMode = rfsm.state {
    GetStitchTargetPose = waiting("root.AutonomousMode.GetStitchTargetPose", D.planning, C.free,
                                  function() call("stitches", "askStitch") end),
    ApplyRightStitch = applyStitch("Right"),
    PullThread = motion("root.AutonomousMode.PullThread", D.primitives, C.contact),
    HookThread = motion("root.AutonomousMode.HookThread", D.primitives, C.free),
    PushThread = motion("root.AutonomousMode.PushThread", D.primitives, C.free),
    ApplyLeftStitch = applyStitch("Left"),

    rfsm.trans { src = 'initial', tgt = 'GetStitchTargetPose' },
    rfsm.trans { src = 'GetStitchTargetPose', tgt = 'ApplyRightStitch', events = { 'e_stitch_planned' },
                 effect = function() half = "right" end },
    rfsm.trans { src = 'root.AutonomousMode.ApplyRightStitch.DisengageNeedle', tgt = 'PullThread', events = { 'e_motion_done' } },
    rfsm.trans { src = 'root.AutonomousMode.ApplyLeftStitch.DisengageNeedle', tgt = 'PullThread', events = { 'e_motion_done' },
                 effect = function() half = "left" end },
    rfsm.trans { src = 'PullThread', tgt = 'HookThread', events = { 'e_motion_done' } },
    rfsm.trans { src = 'HookThread', tgt = 'PushThread', events = { 'e_motion_done' } },
    -- The thread pushed aside: the stick lets it go; on to the stitch's other half, or the next stitch.
    rfsm.trans { src = 'PushThread', tgt = 'ApplyLeftStitch', events = { 'e_motion_done' },
                 guard = function() return half == "right" end, effect = function() emit("e_release_thread") end },
    rfsm.trans { src = 'PushThread', tgt = 'GetStitchTargetPose', events = { 'e_motion_done' },
                 guard = function() return half == "left" end,
                 effect = function()
                   emit("e_release_thread")
                   emit("e_stitch_done")
                   call("stitches", "nextStitch")
                 end },
  },
  TeleoperatedMode = rfsm.state {
    StoppingMotion = rfsm.state { entry = stop },
    -- Not a task_steps waiting state: the state a teleoperation resumes stays the interrupted one.
    InitHapticDevice = rfsm.state { entry = function()
      emit("e_deploy_" .. D.teleoperated)
      emit("e_configure_" .. C.teleoperation)
    end },
    -- The two-layer couplings start (engage: the rest length takes the master-slave offset, which
    -- then shrinks to nothing, so that nothing jumps) and the surgeon drives both arms.
    TeleoperationActive = rfsm.state { entry = function()
      call("right_coupling", "engage")
      call("left_coupling", "engage")
      emit("e_teleoperation_active")
    end },
    rfsm.trans { src = 'initial', tgt = 'StoppingMotion' },
    rfsm.trans { src = 'StoppingMotion', tgt = 'InitHapticDevice', events = { 'e_motion_stopped', 'e_not_moving' } },
    rfsm.trans { src = 'InitHapticDevice', tgt = 'TeleoperationActive',
                 events = { 'e_deployed_' .. D.teleoperated } },
  },
  -- Something unexpected: the robot stops and the surgeon chooses (e_recover or e_take_over).
  WaitReaction = rfsm.state { entry = function() stop() emit("e_suture_reaction_needed") end },
  -- The same failure again after a reaction, or the thread broke: the motion stops, the
  -- admittances hold both arms where they are, and the procedure ends here.
  SafeStop = rfsm.state { entry = function() stop() emit("e_suture_safe_stop") end },
  -- Every stitch done: both tools come to rest before the procedure is.
  Finishing = rfsm.state { entry = function() call("rest", "askAtRest") end },
  Done = rfsm.state { entry = function() emit("e_suture_task_done") end },

  rfsm.trans { src = 'initial', tgt = 'WaitStitchesPlan' },
  rfsm.trans { src = 'WaitStitchesPlan', tgt = 'AutonomousMode.ApplyRightStitch', events = { 'e_stitch_planned' },
               effect = function() half = "right" end },
  rfsm.trans { src = 'WaitStitchesPlan', tgt = 'RetryStitchesPlan', events = { 'e_no_wound_data' } },
  rfsm.trans { src = 'RetryStitchesPlan', tgt = 'WaitStitchesPlan', events = { 'e_after(' .. plan_retry .. ')' } },
  rfsm.trans { src = 'WaitStitchesPlan', tgt = 'Finishing', events = { 'e_stitches_done' } },
  rfsm.trans { src = 'AutonomousMode.GetStitchTargetPose', tgt = 'Finishing', events = { 'e_stitches_done' } },
  rfsm.trans { src = 'Finishing', tgt = 'Done', events = { 'e_at_rest' } },
  steps.timeout('Finishing', rest_timeout, 'e_not_at_rest'),
  rfsm.trans { src = 'AutonomousMode', tgt = 'TeleoperatedMode', events = { 'e_take_over' }, pn = 5 },
  rfsm.trans { src = 'WaitReaction', tgt = 'TeleoperatedMode', events = { 'e_take_over' } },
  rfsm.trans { src = 'AutonomousMode', tgt = 'SafeStop', events = { 'e_thread_broken' }, pn = 10 },
  rfsm.trans { src = 'TeleoperatedMode', tgt = 'SafeStop', events = { 'e_thread_broken' }, pn = 10 },
  rfsm.trans { src = 'WaitReaction', tgt = 'SafeStop', events = { 'e_thread_broken' }, pn = 10 },
  steps.timeout('WaitReaction', reaction_timeout, 'e_reaction_timeout'),
}
for _, t in ipairs({ steps.reactions('AutonomousMode', faults) }) do chart[#chart + 1] = t end
-- A component in Exception (the runner's e_component_error), a non-finite input or command
-- refused: no reaction can mend a broken component; the safe stop, at once.
for _, state in ipairs({ 'WaitStitchesPlan', 'RetryStitchesPlan', 'AutonomousMode', 'TeleoperatedMode', 'WaitReaction' }) do
  chart[#chart + 1] = rfsm.trans { src = state, tgt = 'SafeStop',
                                   events = { 'e_component_error', 'e_input_not_finite', 'e_command_not_finite' }, pn = 10 }
end

-- Recovery (e_recover) and the end of a teleoperation (e_teleop_done) return to the state that
-- was interrupted; a motion starts again from where the arms are.
local resumable = { "root.AutonomousMode.GetStitchTargetPose", "root.AutonomousMode.PullThread",
                    "root.AutonomousMode.HookThread", "root.AutonomousMode.PushThread" }
for _, side in ipairs({ "Right", "Left" }) do
  for _, step in ipairs({ "MoveOverWound", "MoveInsideWound", "MoveToWoundEdge", "ApplyStitch", "DisengageNeedle" }) do
    resumable[#resumable + 1] = "root.AutonomousMode.Apply" .. side .. "Stitch." .. step
  end
end
steps.resumptions(chart, resumable, 'TeleoperatedMode.TeleoperationActive')

-- The Supervisor runs this when it goes to Exception (a callback failed or ran past its budget):
-- the motion stops and the admittances hold both arms where they are.
function exceptionHook() stop() end

return rfsm.state(chart)
