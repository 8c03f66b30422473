-- The Endo Stitch's admittance throws in its update hook 0.3 s into the first motion (the fault
-- matrix's update_exception cell at moment over_wound): the component goes to Exception, the
-- runner tells the chart (e_component_error), the chart stops safely at once.
return {
  { on = { state = "suture:root.AutonomousMode.ApplyRightStitch.MoveOverWound" }, after = 0.3,
    throw = "RightAdmittance" },
}
