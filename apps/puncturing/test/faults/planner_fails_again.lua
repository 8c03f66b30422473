-- A goal the needle planner cannot reach: 0.5 m of clearance required from MoveToNeedleChange
-- on, never restored; the reaction's retry fails the same way: both charts end in their safe stop.
return {
  { on = { state = "needle:root.InsertingNeedles.MoveToNeedleChange" },
    lua = "stopComponents({'NeedlePlanner'}) cleanupComponents({'NeedlePlanner'}) "
       .. "NeedlePlanner.min_collision_distance = 0.5 "
       .. "configureComponents({'NeedlePlanner'}) startComponents({'NeedlePlanner'})" },
}
