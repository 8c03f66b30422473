-- The planner requires 0.5 m of clearance from the first motion on (every state is "too close":
-- the plan fails, a reaction); the surgeon restores its distance and recovers, the retry succeeds.
-- The property is read at configure: the planner is reconfigured through the deployer.
return {
  { on = { state = "suture:root.AutonomousMode.ApplyRightStitch.MoveOverWound" },
    lua = "saved_distance = SuturePlanner.min_collision_distance "
       .. "stopComponents({'SuturePlanner'}) cleanupComponents({'SuturePlanner'}) "
       .. "SuturePlanner.min_collision_distance = 0.5 "
       .. "configureComponents({'SuturePlanner'}) startComponents({'SuturePlanner'})" },
  { on = { state = "suture:root.WaitReaction" }, after = 0.5,
    lua = "stopComponents({'SuturePlanner'}) cleanupComponents({'SuturePlanner'}) "
       .. "SuturePlanner.min_collision_distance = saved_distance "
       .. "configureComponents({'SuturePlanner'}) startComponents({'SuturePlanner'})" },
  { on = { state = "suture:root.WaitReaction" }, after = 1, call = "Surgeon.say", args = { "e_recover" } },
}
