-- The two-layer teleoperation coupling's wiring (thesis §4.5.4, Fig. 4.15, with the engagement of
-- §5.5; one Passivity layer per side as Franken, Stramigioli, Misra, Secchi, Macchelli, IEEE T-RO
-- 2011 place them), for the applications' deployment files: one master (a haptic device or a
-- hand tracker) driving one slave (a tool's variable admittance):
--   master side: the device -> Link (LinkImpairment: the delay, jitter and loss between the
--     device and the controller); MasterPassivity (PassivityLayer with the master's tank, next to
--     the device) renders the desired master wrench arriving over the link as far as its tank
--     pays, with the device's own twist -> the device's desWrench (when it renders one);
--   slave side: Link -> Clutch (TeleoperationClutch, package cobra_control: the device's motion
--     since the engagement, mapped onto the tool's pose then: taking over moves nothing by
--     itself) -> Transparency (TransparencyLayer: both coupling wrenches from the master's state
--     as it arrives and the slave's own; the task chart engages it) -> SlavePassivity
--     (PassivityLayer with the slave's tank, paying with the admittance's own twist) -> the
--     admittance's extWrench; the desired master wrench crosses the link back to MasterPassivity.
-- The Transparency layer runs on the slave's side only: it needs the clutch's mapping of the
-- master onto the tool, and the master's side needs only the wrench to render (Franken et al.
-- leave the Transparency layer free: what the Passivity layers implement is passive whatever it
-- computes). The tanks exchange energy only in packets riding the link with the samples: what a
-- lost packet carried is gone, never created.
--   local coupling = dofile(COBRA_CHARTS .. "teleoperation_coupling.lua")
--   coupling.check(master, "Link", "teleop_device")      -- after getReferences: six DoF or an error
--   connectPorts / defineDeployment(... coupling.connections{ ... } ...)
--   coupling.impair({ "Link" }, teleop_link)             -- the link's delay, jitter, loss, seed
--   coupling.render("MasterPassivity", master)           -- what the device renders (or nothing)
-- A master is a table of port names: `pose` (a KDL.Frame port: six DoF), and when the device has
-- them `twist` (KDL.Twist, m/s and rad/s; needed with `feedback`: the master's tank pays with it),
-- `feedback` (the KDL.Wrench input it renders, N and N·m), `dissipation` (W: what its backdrive
-- friction dissipates; fills the master's tank), `max_force` and `max_torque` (N, N·m: what it
-- renders; see M.render).
local M = {}

-- The type a port of `name` ("Component.port") has, from the component's Lua reference.
local function portType(name)
  local component, port = name:match("^([^.]+)%.(.+)$")
  local c = component and rawget(_G, component)
  if not c then return nil end
  local ok, p = pcall(function() return c[port] end)
  if not ok or type(p) ~= "userdata" then return nil end
  return p:type()
end

-- Refuses (one line, naming `setting` and the rule) a master whose ports the coupling cannot use:
-- its pose must be a pose of six DoF, as the link's masterPose is (a 1-DoF position or a 3-DoF
-- point has no orientation for the tool to follow); its twist a twist, its feedback a wrench.
function M.check(master, link, setting)
  local rules = { { "pose", "masterPose", "a pose of six DoF (position and orientation)" },
                  { "twist", "masterTwist", "a twist of six DoF (linear and angular velocity)" },
                  { "feedback", "linkedSlaveWrench", "a wrench of six DoF (force and torque)" } }
  if type(master) ~= "table" or type(master.pose) ~= "string" then
    error(setting .. ": the master needs a `pose` port (Component.port) of " .. rules[1][3], 0)
  end
  if master.feedback and not master.twist then
    error(setting .. ": a master with `feedback` needs its `twist` port: the master's tank pays for the wrench it "
          .. "renders with the device's own twist", 0)
  end
  for _, r in ipairs(rules) do
    local name = master[r[1]]
    if name then
      local expected = portType(link .. "." .. r[2])
      local got = portType(name)
      if got == nil then
        error(setting .. ": " .. r[1] .. " = '" .. name .. "' names no port of a component created before it", 0)
      end
      if got ~= expected then
        error(setting .. ": " .. r[1] .. " port " .. name .. " is a " .. got .. "; the coupling needs " .. r[3] ..
              ": a " .. expected .. " as " .. link .. "." .. r[2] .. " takes", 0)
      end
    end
  end
  return master
end

-- The connections of one coupling. `c`: the components `link`, `clutch`, `transparency`,
-- `master_passivity` and `slave_passivity` (PassivityLayers, one per side), `admittance` (the
-- slave's VariableAdmittance), `slave_pose` (the tool's measured pose port), `master` (as above).
function M.connections(c)
  local L, C, T, PM, PS, A = c.link, c.clutch, c.transparency, c.master_passivity, c.slave_passivity, c.admittance
  local list = {
    -- Master -> slave: the device's pose (and twist, below) over the link to the clutch.
    { output = c.master.pose, input = L .. ".masterPose" },
    { output = L .. ".linkedMasterPose", input = C .. ".masterPose" },
    { output = c.slave_pose, input = C .. ".slavePose" },
    -- The slave's side: the Transparency layer on the master as it arrived and the admittance's
    -- own state; the slave's layer pays with the admittance's twist.
    { output = C .. ".desPose", input = T .. ".masterPose" },
    { output = L .. ".linkedMasterTwist", input = T .. ".masterTwist" },
    { output = A .. ".admPose", input = T .. ".slavePose" },
    { output = A .. ".admTwist", input = T .. ".slaveTwist" },
    { output = T .. ".slaveForceDesired", input = PS .. ".forceDesired" },
    { output = A .. ".admTwist", input = PS .. ".twist" },
    { output = PS .. ".force", input = A .. ".extWrench" },
    -- The slave's tank fills with what the admittance's damping dissipates (eq. 4.19).
    { output = A .. ".dissipatedPower", input = PS .. ".dissipation" },
    -- Slave -> master: the desired master wrench over the link to the master's layer.
    { output = T .. ".masterForceDesired", input = L .. ".slaveWrench" },
    { output = L .. ".linkedSlaveWrench", input = PM .. ".forceDesired" },
    -- The tanks' exchange, in the link's packets both ways.
    { output = PM .. ".energyOut", input = L .. ".masterEnergy" },
    { output = PM .. ".request", input = L .. ".masterRequest" },
    { output = L .. ".linkedMasterEnergy", input = PS .. ".energyIn" },
    { output = L .. ".linkedMasterRequest", input = PS .. ".peerRequest" },
    { output = PS .. ".energyOut", input = L .. ".slaveEnergy" },
    { output = PS .. ".request", input = L .. ".slaveRequest" },
    { output = L .. ".linkedSlaveEnergy", input = PM .. ".energyIn" },
    { output = L .. ".linkedSlaveRequest", input = PM .. ".peerRequest" },
  }
  if c.master.twist then
    list[#list + 1] = { output = c.master.twist, input = L .. ".masterTwist" }
    list[#list + 1] = { output = c.master.twist, input = PM .. ".twist" }  -- the device's own, undelayed
  end
  -- The device's backdrive friction fills the master's tank (a figure beside the device).
  if c.master.dissipation then list[#list + 1] = { output = c.master.dissipation, input = PM .. ".dissipation" } end
  if c.master.feedback then list[#list + 1] = { output = PM .. ".force", input = c.master.feedback } end
  return list
end

-- The links' impairment from `link` = { delay = s, jitter = s, loss = 0..1, seed = n } (nil:
-- none); each link draws its own losses (a link uses seed and seed + 1).
function M.impair(links, link)
  link = link or {}
  for i, name in ipairs(links) do
    local l = _G[name]
    l.delay = link.delay or 0.0
    l.jitter = link.jitter or 0.0
    l.loss = link.loss or 0.0
    l.seed = (link.seed or 1) + 2 * (i - 1)
  end
end

-- The master's tank pays for the wrench the device renders: `master.max_force` (N, its
-- saturation) and `master.max_torque` (N·m; 0: no actuated wrist) when the master declares them;
-- a master without `feedback` renders nothing (a hand tracker has no actuator): 0 and 0, so its
-- tank pays for nothing and only exchanges energy with the slave's.
function M.render(passivity, master)
  local p = _G[passivity]
  if not master.feedback then
    p.max_force = 0.0
    p.max_torque = 0.0
    return
  end
  if master.max_force then p.max_force = master.max_force end
  if master.max_torque then p.max_torque = master.max_torque end
end

-- N/m: the Transparency layer's stiffness over `link`: link.stiffness when given, else 1000 without
-- a lag and 30 N·s/m / (delay + jitter) with one, at most 1000. A bound on performance, not on
-- passivity: the per-side layers keep the loop passive at any stiffness (their tanks pay every
-- joule), but the master's wrench acts a round trip after the motion it answers, and a spring K
-- seen late by 2d behaves like K with a negative damping of about 2dK; the device, the hand and B
-- must out-damp it, else master and tool swing within what the tanks, refilled by that very
-- motion's dissipation, can pay (measured on the puncturing take-over at 100 ms + 10 % loss with
-- the per-side layers: 1000 N/m left the tool 5 mm off the master, 300 N/m within 2 mm).
function M.stiffness(link)
  local lag = M.lag(link)
  return (link and link.stiffness) or (lag > 0 and math.min(1000, 30 / lag) or 1000)
end

-- s: the link's worst one-way lag (delay + jitter), 0 without a link setting.
function M.lag(link)
  link = link or {}
  return (link.delay or 0.0) + (link.jitter or 0.0)
end

return M
