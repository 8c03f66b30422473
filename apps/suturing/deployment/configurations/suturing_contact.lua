-- Suturing, contact (thesis §5.5.2: stiffer, used while pulling the thread to join the edges):
-- ../admittance/contact.lua on the Endo Stitch arm, which pulls; the
-- stick's arm, holding still meanwhile, stays compliant.
local here = debug.getinfo(1, "S").source:match("^@(.*/)")
local C = "../admittance/"
return { RightAdmittance = dofile(here .. C .. "contact.lua").Admittance,
         LeftAdmittance = dofile(here .. C .. "free_motion.lua").Admittance }
