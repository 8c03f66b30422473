-- The retreat off the surface after a safe stop in contact (charts/puma260_task.lua, Retreating),
-- applied by the task chart once position_control runs: only the trajectory generator changes.
-- 0.5 mm/s along each axis (m/s; the blends in s): 3 mm in 6.3 s, the tool unloading the contact
-- gradually (the measured tool within 0.5 mm of the set-point while it leaves). No continuing from
-- the last set-point (continue_tolerance, m): it is the admittance's reference, up to a few mm
-- inside the surface; the retreat starts where the tool is measured.
return {
  TrajGen = { max_vel = 0.0005, max_ang_vel = 0.05, time_acc = 0.3, continue_tolerance = 0 },
}
