-- Opening the door gently: a light torque on the handle (may not be enough) and a light pull.
return {
  TorqueCmd = { value = 1.2 },  -- N·m: the handle's spring (2 N·m/rad) stops it at 0.6 rad, below the latch
  PullCmd = { value = 3.0 },    -- N
}
