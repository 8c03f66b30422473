-- Suturing, free motion (thesis §5, §4.7): as stiff as the puncturing free motion.
return {
  Admittance = {
    stiffness = { 3000, 3000, 3000, 60, 60, 60 },
    inertia = { 4, 4, 4, 0.2, 0.2, 0.2 },
    damping = { 220, 220, 220, 7, 7, 7 },
  },
}
