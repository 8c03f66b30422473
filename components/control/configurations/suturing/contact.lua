-- Suturing, contact (thesis §5): compliant in every direction while the stitching tool touches
-- the tissue.
return {
  Admittance = {
    stiffness = { 200, 200, 200, 10, 10, 10 },
    inertia = { 5, 5, 5, 0.25, 0.25, 0.25 },
    damping = { 120, 120, 120, 4, 4, 4 },
  },
}
