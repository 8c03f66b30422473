-- Opening the door firmly: enough torque to release the latch, a stronger pull.
return {
  TorqueCmd = { value = 2.0 },  -- N·m: the handle reaches 1 rad, past the latch (0.7 rad)
  PullCmd = { value = 6.0 },    -- N
}
