-- The steps a task chart is made of: calling a peer's void request, waiting in a deployment and
-- configuration, and a motion. Each chart makes its own set, bound to its peers:
--   local steps = require("task_steps") { chart = "us_positioning", peers = { frames = ..., ... },
--                                         goal_missed = "e_us_goal_missed" }
-- `steps.resume` is the fully qualified state a reaction returns to (the last waiting state or
-- motion entered), which guards the chart's recovery transitions (steps.resumptions).
--
-- Reactions: a failure that ends a state (a fault event, a goal missed) is a reaction the first
-- time (root.WaitReaction: the robot stops, the surgeon recovers or takes over in teleoperation).
-- The same failure again in the same state, nothing achieved since (no other waiting state or
-- motion entered in between), cannot recover: the chart goes to root.SafeStop instead (motion
-- stopped, the admittance holding the robot where it is), and says which failure in which state.
return function(c)
  local steps = { resume = nil, failed = {} }

  -- A waiting state or motion is entered: progress, unless it is the one a reaction resumes.
  local function enter(fqn)
    if fqn ~= steps.resume then steps.failed = {} end
    steps.resume = fqn
  end
  local function key(failure) return tostring(steps.resume) .. " " .. failure end
  -- Whether `failure` already ended the state being resumed; remember that it did.
  function steps.again(failure) return steps.failed[key(failure)] == true end
  function steps.remember(failure) steps.failed[key(failure)] = true end

  -- The two transitions of the failure events `failures` leaving `src`: to root.SafeStop when one
  -- of them is a repeat, to root.WaitReaction otherwise.
  function steps.reactions(src, failures)
    local set = {}
    for _, name in ipairs(failures) do set[name] = true end
    local function repeated(events)
      for _, e in ipairs(events) do
        if set[e] and steps.again(e) then return true end
      end
      return false
    end
    return rfsm.trans { src = src, tgt = 'root.SafeStop', events = failures, pn = 1,
                        guard = function(_, events) return repeated(events) end },
           rfsm.trans { src = src, tgt = 'root.WaitReaction', events = failures,
                        effect = function(_, _, _, events)
                          for _, e in ipairs(events) do if set[e] then steps.remember(e) end end
                        end }
  end

  -- The recovery transitions, appended to `chart`: from WaitReaction (e_recover) and from the
  -- teleoperation state `teleop` (e_teleop_done) back to each fully qualified state of `targets`,
  -- each taken only for the state a reaction resumes (steps.resume).
  function steps.resumptions(chart, targets, teleop)
    for _, target in ipairs(targets) do
      for _, from in ipairs({ { 'WaitReaction', 'e_recover' }, { teleop, 'e_teleop_done' } }) do
        chart[#chart + 1] = rfsm.trans { src = from[1], tgt = target, events = { from[2] },
                                         guard = function() return steps.resume == target end }
      end
    end
  end

  -- Calls the void request operation `operation` of the peer playing `role`.
  function steps.call(role, operation)
    local name = assert(c.peers[role], c.chart .. ": no peer for role " .. tostring(role))
    local peer = _G[name]
    if peer == nil then error(c.chart .. ": peer '" .. name .. "' (" .. role .. ") is not a peer of this supervisor") end
    peer[operation](peer)
  end

  function steps.stop() steps.call("trajectory", "askStopMove") end

  -- The states of a take-over by the surgeon (thesis §4.6, §5.5: InitHapticDevice, then
  -- TeleoperationActive), the contents of an rfsm.state: the teleoperated deployment `deployment`
  -- with the configuration `configuration` (the clutch engages as the deployment starts: the tool
  -- follows the device's motion from where both are, so taking over moves nothing by itself),
  -- then the Transparency layers of the peers playing `couplings` (roles) engaged (the rest
  -- length takes the master-slave offset, which then shrinks to nothing: nothing jumps), and
  -- e_teleoperation_active.
  function steps.teleoperation(deployment, configuration, couplings)
    return {
      InitHapticDevice = rfsm.state { entry = function()
        emit("e_deploy_" .. deployment)
        emit("e_configure_" .. configuration)
      end },
      TeleoperationActive = rfsm.state { entry = function()
        for _, role in ipairs(couplings) do steps.call(role, "engage") end
        emit("e_teleoperation_active")
      end },
      rfsm.trans { src = 'initial', tgt = 'InitHapticDevice' },
      rfsm.trans { src = 'InitHapticDevice', tgt = 'TeleoperationActive', events = { 'e_deployed_' .. deployment } },
    }
  end

  -- The transition that ends a wait on an outside party (the surgeon, the cryoablation console,
  -- the other robot's chart) after `seconds` in `src` without its answer: root.SafeStop (the
  -- motion stopped, the admittance holding the robot), emitting `event`, which names what was
  -- waited for (e_reaction_timeout: the surgeon's reaction), so the run's safe stop says why.
  function steps.timeout(src, seconds, event)
    return rfsm.trans { src = src, tgt = 'root.SafeStop', events = { 'e_after(' .. seconds .. ')' }, pn = 1,
                        effect = function() emit(event) end }
  end

  -- A state that asks for its deployment and configuration on entry; `also` runs after.
  function steps.waiting(fqn, deployment, configuration, also)
    return rfsm.state { entry = function()
      enter(fqn)
      emit("e_deploy_" .. deployment)
      emit("e_configure_" .. configuration)
      if also then also() end
    end }
  end

  -- A motion: Switching (deployment and configuration asked, until both are answered), AskingGoal
  -- (the Frame Generator publishes this state's goal), Planning (with `opts.planned`), Generating,
  -- Moving. The transitions leaving it handle its end (e_motion_done or a Decision event). With
  -- `opts.arrive` or `opts.grace`, a motion that ends without that event waits in Arrived; with
  -- `opts.grace` s it then reacts (c.goal_missed, then root.WaitReaction). With
  -- `opts.pause = {stop, go}`, event `stop` halts Moving until event `go`.
  function steps.motion(fqn, deployment, configuration, opts)
    opts = opts or {}
    local want = {}
    local s = {
      Switching = rfsm.state { entry = function()
        enter(fqn)
        want = { ["e_deployed_" .. deployment] = true, ["e_configured_" .. configuration] = true }
        emit("e_deploy_" .. deployment)
        emit("e_configure_" .. configuration)
      end },
      AskingGoal = rfsm.state { entry = function() steps.call("frames", "askCurrentGoal") end },
      Generating = rfsm.state { entry = function() steps.call("trajectory", "askGenerateTraj") end },
      Moving = rfsm.state { entry = function() steps.call("trajectory", "askStartMove") end },
      rfsm.trans { src = 'initial', tgt = 'Switching' },
      rfsm.trans { src = 'Switching', tgt = 'AskingGoal', guard = function(tr, events)
        for _, e in ipairs(events) do want[e] = nil end
        return next(want) == nil
      end },
      rfsm.trans { src = 'Generating', tgt = 'Moving', events = { 'e_trajectory_ready' } },
    }
    if opts.planned then
      s.Planning = rfsm.state { entry = function() steps.call("planner", "askPlan") end }
      s[#s + 1] = rfsm.trans { src = 'AskingGoal', tgt = 'Planning', events = { 'e_goal_ready' } }
      s[#s + 1] = rfsm.trans { src = 'Planning', tgt = 'Generating', events = { 'e_path_ready' } }
    else
      s[#s + 1] = rfsm.trans { src = 'AskingGoal', tgt = 'Generating', events = { 'e_path_ready' } }
    end
    if opts.grace or opts.arrive then
      s.Arrived = rfsm.state {}
      s[#s + 1] = rfsm.trans { src = 'Moving', tgt = 'Arrived', events = { 'e_motion_done' } }
    end
    if opts.grace then
      local missed = { 'e_after(' .. opts.grace .. ')' }
      s[#s + 1] = rfsm.trans { src = 'Arrived', tgt = 'root.SafeStop', events = missed, pn = 1,
                               guard = function() return steps.again(c.goal_missed) end,
                               effect = function() emit(c.goal_missed) end }
      s[#s + 1] = rfsm.trans { src = 'Arrived', tgt = 'root.WaitReaction', events = missed,
                               effect = function() steps.remember(c.goal_missed) emit(c.goal_missed) end }
    end
    if opts.pause then
      s.Paused = rfsm.state {}
      s[#s + 1] = rfsm.trans { src = 'Moving', tgt = 'Paused', events = { opts.pause[1] }, effect = steps.stop }
      s[#s + 1] = rfsm.trans { src = 'Paused', tgt = 'Switching', events = { opts.pause[2] } }
    end
    return rfsm.state(s)
  end

  return steps
end
