-- The one configuration of the Puma 260 task (thesis §6.3: "the same set of parameters have been
-- kept during all its execution"), applied once by puma260.lua. The admittance reused from the
-- I-SUR (§4.5.3) needs only this tuning for the Puma's hardware (§6.4).
-- [translation; rotation]: kg, kg·m²; N·s/m, N·m·s/rad; N/m, N·m/rad.
return {
  -- Compliant along base z, stiff in x, y and orientation; each axis critically damped
  -- (D = 2 sqrt(K M)). Along z 400 N/m: the 15 mm of surface above the path make 6 N, and the
  -- FTSens' one-sample tare, off by up to its 0.25 N resolution, moves the tool 0.6 mm.
  Admittance = {
    inertia = { 2, 2, 2, 0.1, 0.1, 0.1 },
    stiffness = { 3000, 3000, 400, 60, 60, 60 },
    damping = { 155, 155, 57, 4.9, 4.9, 4.9 },
  },
  -- 1 cm/s along each axis (s: the blends): the surface rises under the tool at up to 7.5 mm/s.
  TrajGen = { max_vel = 0.01, max_ang_vel = 0.5, time_acc = 0.3 },
  -- Contact from 2 N (the FTSens' noise, up to 3 quanta of 0.25 N per axis, makes up to 1.3 N),
  -- lost below 1 N for 0.1 s; the force limit; off the nominal path beyond 8 mm, back on it
  -- within 0.8 mm (the tare's offset, 0.6 mm, stays).
  Contact = { contact_force = 2.0, release_force = 1.0, release_time = 0.1, max_force = 10,
              off_path_distance = 0.008, on_path_distance = 0.0008 },
}
