-- Suturing, free motion (thesis §5.5.2: "basically the same employed for the puncturing task"):
-- compliant, to reduce damage in an unexpected collision. [translation; rotation]: N/m, N·m/rad;
-- kg, kg·m²; N·s/m, N·m·s/rad.
return {
  Admittance = {
    stiffness = { 1000, 1000, 1000, 20, 20, 20 },
    inertia = { 4, 4, 4, 0.2, 0.2, 0.2 },
    damping = { 126, 126, 126, 4, 4, 4 },  -- 2·sqrt(K·M): critically damped
  },
}
