-- The probe on the skin (thesis §4.4.2, USPositioned: "the probe applies a constant force to the
-- surface of the skin"): the set-point lies a few mm inside the skin and the vertical stiffness
-- turns that into the pressing force (about 1000 N/m x 4 mm = 4 N, above the image's 2 N).
-- [translation; rotation]: N/m, N·m/rad; kg, kg·m²; N·s/m, N·m·s/rad.
return {
  ProbeAdmittance = {
    stiffness = { 3000, 3000, 1000, 60, 60, 60 },
    inertia = { 4, 4, 4, 0.2, 0.2, 0.2 },
    damping = { 220, 220, 150, 7, 7, 7 },
  },
}
