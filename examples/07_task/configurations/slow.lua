-- Scanning: slow enough for the probe's images to overlap (an assumed 50 frames/s and 1 mm per
-- frame along the line: 0.05 m/s).
return {
  TrajGen = {
    max_vel = 0.05,     -- m/s per Cartesian axis
    max_ang_vel = 0.2,  -- rad/s
  },
}
