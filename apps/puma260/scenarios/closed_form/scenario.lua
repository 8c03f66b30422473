-- The Puma 260 task with the closed-form kinematics solver (thesis §6.2.4), in the MuJoCo world.
kinematics_solver = "closed_form"
