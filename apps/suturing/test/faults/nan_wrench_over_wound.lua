-- The Endo Stitch's wrench turns NaN 0.3 s into the first motion (the fault matrix's nan_input cell
-- at moment over_wound): its writer stopped, NaN written on its output; the admittance refuses it
-- (e_input_not_finite, its admPose held) and the chart stops safely at once.
return {
  { on = { state = "suture:root.AutonomousMode.ApplyRightStitch.MoveOverWound" }, after = 0.3,
    lua = "stopComponents({'RightWrench'}) RightWrench.outWrench:write({0/0, 0, 0, 0, 0, 0})" },
}
