-- The surgeon takes over with the Omnis while the Endo Stitch pulls the thread (1.3 s into the
-- first PullThread: the thread tensioned, a few N): through the two-layer coupling the right
-- Omni feels the thread's pull. 1 s into the teleoperation his right hand moves the stylus 8 mm
-- along -y (away from the stick) and 3 mm down (towards the wound: the thread slackens) and turns
-- it 10 degrees about z; 3 s later he gives the arms back and the pull resumes.
local ten_degrees_about_z = { 0, 0, 0.0871557, 0.9961947 }  -- quaternion x, y, z, w
return {
  { on = { state = "suture:root.AutonomousMode.PullThread.Moving" }, after = 1.3,
    call = "Surgeon.say", args = { "e_take_over" } },
  { on = { state = "suture:root.TeleoperatedMode.TeleoperationActive" }, after = 1,
    set = { property = "RightOmni.hand_motion",
            value = { 0, -0.008, -0.003, ten_degrees_about_z[1], ten_degrees_about_z[2], ten_degrees_about_z[3],
                      ten_degrees_about_z[4] } } },
  { on = { state = "suture:root.TeleoperatedMode.TeleoperationActive" }, after = 4,
    call = "Surgeon.say", args = { "e_teleop_done" } },
}
