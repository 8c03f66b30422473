-- Puncturing, needle insertion (thesis §4.7): compliant sideways, so the needle follows the
-- tissue instead of tearing it, still stiff enough along the insertion axis to advance.
return {
  Admittance = {
    stiffness = { 300, 300, 1500, 20, 20, 20 },
    inertia = { 6, 6, 6, 0.3, 0.3, 0.3 },
    damping = { 150, 150, 250, 5, 5, 5 },
  },
}
