-- Puncturing, skin penetration (thesis §4.7): stiff along the needle to build up the puncture
-- force of the skin, heavier and more damped so the release after the puncture does not jerk.
return {
  Admittance = {
    stiffness = { 2000, 2000, 4000, 80, 80, 80 },
    inertia = { 8, 8, 8, 0.3, 0.3, 0.3 },
    damping = { 300, 300, 400, 10, 10, 10 },
  },
}
