-- The image processing loses the needle 0.3 s after the probe tracks it (no distance counts as
-- visible), and sees it again 1 s after the insertion paused.
return {
  { on = { state = "us:root.USPositioned.NeedleTracked" }, after = 0.3,
    set = { property = "USMonitor.visible_distance", value = -1 } },  -- m
  { on = { state = "us:root.USPositioned.NeedleTracked" }, after = 0.3,
    set = { property = "USMonitor.lost_distance", value = -1 } },     -- m
  { on = { state = "needle:root.InsertingNeedles.MoveToTumor.Paused" }, after = 1.0,
    set = { property = "USMonitor.visible_distance", value = 0.002 } },
  { on = { state = "needle:root.InsertingNeedles.MoveToTumor.Paused" }, after = 1.0,
    set = { property = "USMonitor.lost_distance", value = 0.003 } },
}
