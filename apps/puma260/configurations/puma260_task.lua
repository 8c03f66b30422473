-- The one configuration of the Puma 260 task (thesis §6.3: "the same set of parameters have been
-- kept during all its execution"), applied once by puma260.lua. The admittance reused from the
-- I-SUR (§4.5.3) needs only this tuning for the Puma's hardware (§6.4).
-- [translation; rotation]: kg, kg·m²; N·s/m, N·m·s/rad; N/m, N·m/rad.
return {
  -- Compliant along base z, stiff in x, y and orientation. Along z: 400 N/m (the 15 mm of surface
  -- above the path make 6 N; the FTSens' one-sample tare, off by up to its 0.25 N resolution,
  -- moves the tool 0.6 mm). The damping, not the mass, dominates along z: against the surface
  -- (4.4e4 N/m, world/puma260.xml) the force loop through the position-controlled arm crosses over
  -- at k/D; it must do so where the admittance is damping-like (k/D < D/M, i.e. D^2 > k M: here
  -- 1.6e5 > 4.4e4) or the tool bounces on the surface (with M = 2 kg, D = 63 N·s/m it does, up to
  -- 12 N). The price is D·ḣ: 400 N·s/m × the surface rising at up to 7.5 mm/s under the tool at
  -- 1 cm/s, 3 N where the surface meets the path.
  Admittance = {
    inertia = { 2, 2, 1, 0.1, 0.1, 0.1 },
    stiffness = { 3000, 3000, 400, 60, 60, 60 },
    damping = { 155, 155, 400, 4.9, 4.9, 4.9 },
  },
  -- 1 cm/s along each axis (s: the blends).
  TrajGen = { max_vel = 0.01, max_ang_vel = 0.5, time_acc = 0.3 },
  -- Contact from 2 N (the FTSens' noise, up to 3 quanta of 0.25 N per axis, makes up to 1.3 N),
  -- lost below 1 N for 0.1 s; the force limit; off the nominal path beyond 8 mm, back on it
  -- within 0.8 mm (the tare's offset, 0.6 mm, stays).
  Contact = { contact_force = 2.0, release_force = 1.0, release_time = 0.1, max_force = 10,
              off_path_distance = 0.008, on_path_distance = 0.0008 },
}
