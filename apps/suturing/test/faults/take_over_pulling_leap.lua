-- As take_over_pulling_omni.lua with the Leap Motion: the surgeon's right hand, 20 cm above the
-- device (the simulator's scripted hand, LeapSim.right_hand), moves 8 mm along -y and 3 mm down
-- and turns 10 degrees about z 1 s into the teleoperation. The Leap renders no force: the force
-- the coupling computes for the master (RightPassivity.masterForce) is what a haptic device would
-- render.
return {
  { on = { state = "suture:root.AutonomousMode.PullThread.Moving" }, after = 1.3,
    call = "Surgeon.say", args = { "e_take_over" } },
  { on = { state = "suture:root.TeleoperatedMode.TeleoperationActive" }, after = 1,
    set = { property = "LeapSim.right_hand", value = { 0.050, -0.008, 0.197, 0, 0, 0.0871557, 0.9961947 } } },
  { on = { state = "suture:root.TeleoperatedMode.TeleoperationActive" }, after = 4,
    call = "Surgeon.say", args = { "e_teleop_done" } },
}
