-- Puncturing, free motion (thesis §4.7: "for safety reasons, the robot is configured to have a
-- compliant behavior in order to reduce the possibility of damages to persons or objects in the
-- case of unexpected collisions"): the most compliant of the three, critically damped so that the
-- planned path is still followed without overshoot (nothing is touched: no deflection).
-- [translation; rotation]: N/m, N·m/rad; kg, kg·m²; N·s/m, N·m·s/rad.
return {
  Admittance = {
    stiffness = { 1000, 1000, 1000, 20, 20, 20 },  -- compliant: an unexpected contact yields
    inertia = { 4, 4, 4, 0.2, 0.2, 0.2 },
    damping = { 126, 126, 126, 4, 4, 4 },          -- 2·sqrt(K·M): critically damped
  },
}
