-- Puncturing, teleoperation (the two-layer coupling drives the tool, thesis §4.5.4): translational
-- stiffness at the admittance's constant floor (50 N/m: the least it ever implements), so that
-- next to nothing holds the tool where the motion stopped: the coupling's spring to the surgeon's
-- device (1000 N/m without a delayed link) moves it, through free motion's inertia and damping (it
-- settles in about 0.1 s without overshoot); what the tool meets (the tissue, the skin) is held by
-- the coupling alone, and felt. The rotation likewise: its stiffness at the floor (1 N·m/rad)
-- against the coupling's 20 N·m/rad (the tool turns 20 / 21 of the device's turn).
-- [translation; rotation]: N/m, N·m/rad; kg, kg·m²; N·s/m, N·m·s/rad.
-- The inertia and damping are free motion's (free_motion.lua): critically damped at its 1000 N/m.
return {
  Admittance = {
    stiffness = { 50, 50, 50, 1, 1, 1 },        -- the floor: the coupling holds the tool
    inertia = { 4, 4, 4, 0.2, 0.2, 0.2 },
    damping = { 126, 126, 126, 4, 4, 4 },
  },
}
