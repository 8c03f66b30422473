-- The robots' trajectory generators' limits, one place for both controllers: each robot's own,
-- and its planner checks the other robot's steps of the whole procedure at the other's
-- (controller.lua: verifies_procedure).
return {
  -- m/s per axis: the needle moves slowly near the patient; rad/s: turning the needle about its
  -- tip moves the delta's platform, ~0.37 m up the arm, at 0.37 m/rad; its sliders run at 0.1 m/s
  needle = { max_vel = 0.04, max_ang_vel = 0.15 },
  probe = { max_vel = 0.08, max_ang_vel = 0.5 },  -- m/s per axis, rad/s
}
