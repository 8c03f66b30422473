-- Puncturing, needle insertion (thesis §4.7: "the needle must keep the orientation while being
-- compliant along the insertion axis in order to limit damages in the case in which forbidden
-- regions are touched"): compliant along the needle (tool z), stiff across it and in rotation so
-- that the needle keeps its line and orientation in the tissue. [translation; rotation]: N/m,
-- N·m/rad; kg, kg·m²; N·s/m, N·m·s/rad.
return {
  Admittance = {
    stiffness = { 3000, 3000, 1000, 80, 80, 80 },  -- z compliant (a forbidden region pushes back); x, y, rotation kept
    inertia = { 6, 6, 6, 0.3, 0.3, 0.3 },
    damping = { 270, 270, 155, 10, 10, 10 },       -- about 2·sqrt(K·M)
  },
}
