-- Free motion, away from the part: the trajectory generator's speeds for approach and retreat.
-- The robot's servos lag about 10 ms behind their command: at 0.1 m/s per axis (0.17 m/s on a
-- diagonal) that is below the 2 mm of tracking error the test accepts; 0.15 m/s gave 2.04 mm.
return {
  TrajGen = {
    max_vel = 0.1,      -- m/s per Cartesian axis
    max_ang_vel = 0.5,  -- rad/s
  },
}
