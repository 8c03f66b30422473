-- Puncturing, skin penetration (thesis §4.7: "while in contact with the skin the robot must be
-- stiff in order to be able to penetrate it"): the stiffest configuration, stiffest along the
-- needle (tool z) where the puncture force of the skin builds up; heavier and more damped so the
-- release after the puncture does not jerk. [translation; rotation]: N/m, N·m/rad; kg, kg·m²;
-- N·s/m, N·m·s/rad.
return {
  Admittance = {
    stiffness = { 3000, 3000, 4000, 80, 80, 80 },  -- stiff: the needle must not yield to the skin
    inertia = { 8, 8, 8, 0.3, 0.3, 0.3 },
    damping = { 310, 310, 360, 10, 10, 10 },       -- about 2·sqrt(K·M)
  },
}
