-- The surgeon takes over mid-stitch: 0.2 s into the Endo Stitch's move to the right edge of the
-- first stitch, then gives the arms back after 2 s of teleoperation (the interrupted motion resumes).
return {
  { on = { state = "suture:root.AutonomousMode.ApplyRightStitch.MoveToWoundEdge.Moving" }, after = 0.2,
    call = "Surgeon.say", args = { "e_take_over" } },
  { on = { state = "suture:root.TeleoperatedMode.TeleoperationActive" }, after = 2,
    call = "Surgeon.say", args = { "e_teleop_done" } },
}
