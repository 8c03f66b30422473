-- The planner requires 0.5 m of clearance from the first motion on (every state is "too close":
-- the plan fails, a reaction), and the surgeon never answers: after the chart's reaction_timeout
-- (charts/suturing.lua) the procedure ends in its safe stop, naming e_reaction_timeout.
return {
  { on = { state = "suture:root.AutonomousMode.ApplyRightStitch.MoveOverWound" },
    lua = "stopComponents({'SuturePlanner'}) cleanupComponents({'SuturePlanner'}) "
       .. "SuturePlanner.min_collision_distance = 0.5 "
       .. "configureComponents({'SuturePlanner'}) startComponents({'SuturePlanner'})" },
}
