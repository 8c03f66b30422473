-- Suturing, teleoperation (the two-layer coupling drives the tools, thesis §4.5.4): translational
-- stiffness at the admittance's constant floor (constant_stiffness, 50 N/m: the least it ever
-- implements), so that next to nothing holds a tool where the autonomous motion left it: the
-- coupling's 1000 N/m spring to the surgeon's device moves it (a tool follows 1000 / 1050 of the
-- device's motion, 0.5 mm short per 10 mm), through free motion's inertia and damping (4 kg,
-- 126 N·s/m: it settles in about 0.1 s without overshoot). The rotation likewise: its stiffness
-- at the constant floor (1 N·m/rad) against the coupling's 20 N·m/rad, free motion's inertia and
-- damping (a tool turns 20 / 21 of the device's turn: 0.5 degree short of 10 degrees).
-- [translation; rotation]: N/m, N·m/rad; kg, kg·m²; N·s/m, N·m·s/rad.
local free = dofile((debug.getinfo(1, "S").source:match("^@(.*/)") or "./") .. "free_motion.lua").Admittance
return {
  Admittance = {
    stiffness = { 50, 50, 50, 1, 1, 1 },
    inertia = free.inertia,
    damping = free.damping,
  },
}
