-- The one configuration of the Puma 260 task (thesis §6.3: "the same set of parameters have been
-- kept during all its execution"), applied once by puma260.lua. The admittance reused from the
-- I-SUR (§4.5.3) needs only this tuning for the Puma's hardware (§6.4).
-- [translation; rotation]: kg, kg·m²; N·s/m, N·m·s/rad; N/m, N·m/rad.
return {
  -- Compliant along base z (500 N/m: the 15 mm of surface above the path make 7.5 N; the FTSens'
  -- 0.25 N resolution moves the tool 0.5 mm), stiff in x, y and orientation; each axis critically
  -- damped (D = 2 sqrt(K M)).
  Admittance = {
    inertia = { 2, 2, 2, 0.1, 0.1, 0.1 },
    stiffness = { 3000, 3000, 500, 60, 60, 60 },
    damping = { 155, 155, 63, 4.9, 4.9, 4.9 },
  },
  -- 2 cm/s along each axis (s: the blends).
  TrajGen = { max_vel = 0.02, max_ang_vel = 0.5, time_acc = 0.3 },
  -- Contact from 1 N (the FTSens resolves 0.25 N), lost below 0.5 N for 50 ms; the force limit;
  -- off the nominal path beyond 5 mm, back on it within 1 mm.
  Contact = { contact_force = 1.0, release_force = 0.5, release_time = 0.05, max_force = 10,
              off_path_distance = 0.005, on_path_distance = 0.001 },
}
