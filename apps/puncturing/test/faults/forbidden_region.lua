-- The needle "near" the rib: the insertion monitor's margin grows to 10 cm 0.5 s into MoveToTumor
-- (a forbidden region is reported), and is back to 1 mm once the surgeon has the needle in
-- teleoperation (with take_over_surgeon.txt, the first reaction is a take-over).
return {
  { on = { state = "needle:root.InsertingNeedles.MoveToTumor" }, after = 0.5,
    set = { property = "NeedleMonitor.forbidden_margin", value = 0.1 } },   -- m
  { on = { state = "needle:root.NeedleTeleoperation" }, after = 0.1,
    set = { property = "NeedleMonitor.forbidden_margin", value = 0.001 } }, -- m
}
