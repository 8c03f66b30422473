-- No goal the needle planner can reach: 0.5 m of clearance required from the needle robot's first
-- motion (MakeRoomForProbe: none of its needle change poses can be taken) on, never restored; the reaction's retry fails the same way: both charts end in their safe stop.
return {
  { on = { state = "needle:root.MakeRoomForProbe" },
    lua = "stopComponents({'NeedlePlanner'}) cleanupComponents({'NeedlePlanner'}) "
       .. "NeedlePlanner.min_collision_distance = 0.5 "
       .. "configureComponents({'NeedlePlanner'}) startComponents({'NeedlePlanner'})" },
}
