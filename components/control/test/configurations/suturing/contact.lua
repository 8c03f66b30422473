-- Suturing, contact (thesis §5.5.2: "a more stiff behavior of the robot ... used only while
-- pulling the thread in order to join the two edges of the wound"): stiffer than free motion, so
-- the pull keeps its line against the thread's tension. [translation; rotation]: N/m, N·m/rad;
-- kg, kg·m²; N·s/m, N·m·s/rad.
return {
  Admittance = {
    stiffness = { 3000, 3000, 3000, 60, 60, 60 },  -- stiffer than free motion (1000, 20)
    inertia = { 5, 5, 5, 0.25, 0.25, 0.25 },
    damping = { 245, 245, 245, 8, 8, 8 },          -- 2·sqrt(K·M): critically damped
  },
}
