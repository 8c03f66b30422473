-- Suturing, free motion (thesis §5.5.2): both arms compliant, the admittance of
-- ../admittance/free_motion.lua on each arm's admittance.
local here = debug.getinfo(1, "S").source:match("^@(.*/)")
local free = dofile(here .. "../admittance/free_motion.lua").Admittance
return { RightAdmittance = free, LeftAdmittance = free }
