-- The needle planner requires 0.5 m of clearance from its first motion (MakeRoomForProbe) on (every state is "too
-- close": the plan fails); the reaction restores its distance, so the retry succeeds. The
-- property is read at configure: the planner is reconfigured through the deployer.
return {
  { on = { state = "needle:root.MakeRoomForProbe" },
    lua = "saved_distance = NeedlePlanner.min_collision_distance "
       .. "stopComponents({'NeedlePlanner'}) cleanupComponents({'NeedlePlanner'}) "
       .. "NeedlePlanner.min_collision_distance = 0.5 "
       .. "configureComponents({'NeedlePlanner'}) startComponents({'NeedlePlanner'})" },
  { on = { state = "needle:root.WaitReaction" }, after = 0.5,
    lua = "stopComponents({'NeedlePlanner'}) cleanupComponents({'NeedlePlanner'}) "
       .. "NeedlePlanner.min_collision_distance = saved_distance "
       .. "configureComponents({'NeedlePlanner'}) startComponents({'NeedlePlanner'})" },
}
