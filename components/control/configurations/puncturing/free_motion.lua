-- Puncturing, free motion (thesis §4.7): stiff and well damped, to follow the planned trajectory
-- closely while nothing is touched. [translation; rotation]: N/m, N·m/rad; kg, kg·m²; N·s/m, N·m·s/rad.
return {
  Admittance = {
    stiffness = { 3000, 3000, 3000, 60, 60, 60 },
    inertia = { 4, 4, 4, 0.2, 0.2, 0.2 },
    damping = { 220, 220, 220, 7, 7, 7 },
  },
}
