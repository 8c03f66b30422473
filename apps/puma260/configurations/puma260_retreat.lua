-- The retreat off the surface after a safe stop in contact (charts/puma260_task.lua, Retreating),
-- applied by the task chart once position_control runs: only the trajectory's speed changes.
-- 0.5 mm/s along each axis (m/s; the blends in s): 3 mm in about 6.3 s. Slow enough for an IK held
-- to 0.2 % of its joint speeds (Kin.speed_scaling = 0.002: 2 rad/s x 0.002 = 4 mrad/s per joint;
-- a vertical motion at D-H needs about 2.5 mrad/s per mm/s on the shoulder, elbow and wrist).
return {
  TrajGen = { max_vel = 0.0005, max_ang_vel = 0.05, time_acc = 0.3 },
}
