-- The Puma 260 task with KDL's kinematics solver (Newton-Raphson with joint limits, thesis §6.2.4).
kinematics_solver = "kdl_nr"
