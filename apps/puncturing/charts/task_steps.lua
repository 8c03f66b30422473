-- The steps both task charts are made of (needle_insertion.lua, us_positioning.lua): calling a
-- peer's void request, waiting in a deployment and configuration, and a motion. Each chart makes
-- its own set, bound to its peers:
--   local steps = require("task_steps") { chart = "us_positioning", peers = { frames = ..., ... },
--                                         goal_missed = "e_us_goal_missed" }
-- `steps.resume` is the fully qualified state a reaction returns to (the last waiting state or
-- motion entered), for the chart's recovery transitions.
return function(c)
  local steps = { resume = nil }

  -- Calls the void request operation `operation` of the peer playing `role`.
  function steps.call(role, operation)
    local name = assert(c.peers[role], c.chart .. ": no peer for role " .. tostring(role))
    local peer = _G[name]
    if peer == nil then error(c.chart .. ": peer '" .. name .. "' (" .. role .. ") is not a peer of this supervisor") end
    peer[operation](peer)
  end

  function steps.stop() steps.call("trajectory", "askStopMove") end

  -- A state that asks for its deployment and configuration on entry; `also` runs after.
  function steps.waiting(fqn, deployment, configuration, also)
    return rfsm.state { entry = function()
      steps.resume = fqn
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
        steps.resume = fqn
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
      s[#s + 1] = rfsm.trans { src = 'Arrived', tgt = 'root.WaitReaction', events = { 'e_after(' .. opts.grace .. ')' },
                               effect = function() emit(c.goal_missed) end }
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
