-- The I-SUR slowed to 0.2 % of its joint speeds (a reduced mode) 1 s into the approach to the
-- skin: the robot refuses the next command, which it cannot reach in one step at that speed
-- (e_ik_discontinuity), and holds. The needle admittance and trajectory generator re-sync to the
-- held pose, so the command stays where the robot is while the chart waits for the surgeon; full
-- speed again 1 s later, the surgeon's recovery re-plans the approach from the held pose.
return {
  { on = { state = "needle:root.InsertingNeedles.MoveToSkin.Approach" }, after = 1.0,
    set = { property = "ISUR.speed_scaling", value = 0.002 } },
  { on = { state = "needle:root.WaitReaction" }, after = 1.0, set = { property = "ISUR.speed_scaling", value = 1 } },
}
