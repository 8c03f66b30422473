-- The two-layer teleoperation coupling's wiring (thesis §4.5.4, Fig. 4.15, with the engagement of
-- §5.5), for the applications' deployment files: one master (a haptic device or a hand tracker)
-- driving one slave (a tool's variable admittance) through
--   Link (LinkImpairment: the delay, jitter and loss between the device and the controller)
--   -> Clutch (TeleoperationClutch, package cobra_control: the device's motion since the
--      engagement, mapped onto the tool's pose then: taking over moves nothing by itself)
--   -> Transparency (TransparencyLayer: the coupling wrenches; the task chart engages it)
--   -> Passivity (PassivityLayer: as far as its tanks can pay) -> the admittance's extWrench,
-- and the master's wrench back across the link to the device (its desWrench, when it renders one).
--   local coupling = dofile(COBRA_CHARTS .. "teleoperation_coupling.lua")
--   coupling.check(master, "Link", "teleop_device")      -- after getReferences: six DoF or an error
--   connectPorts / defineDeployment(... coupling.connections{ ... } ...)
--   coupling.impair({ "Link" }, teleop_link)             -- the link's delay, jitter, loss, seed
-- A master is a table of port names: `pose` (a KDL.Frame port: six DoF), and when the device has
-- them `twist` (KDL.Twist, m/s and rad/s), `feedback` (the KDL.Wrench input it renders, N and
-- N·m), `dissipation` (W: what its backdrive friction dissipates; fills the master's tank),
-- `max_force` and `max_torque` (N, N·m: what it renders; see M.render).
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
-- `passivity` and `admittance` (the slave's VariableAdmittance), `slave_pose` (the tool's
-- measured pose port), `master` (as above).
function M.connections(c)
  local L, C, T, P, A = c.link, c.clutch, c.transparency, c.passivity, c.admittance
  local list = {
    { output = c.master.pose, input = L .. ".masterPose" },
    { output = L .. ".linkedMasterPose", input = C .. ".masterPose" },
    { output = c.slave_pose, input = C .. ".slavePose" },
    { output = C .. ".desPose", input = T .. ".masterPose" },
    { output = L .. ".linkedMasterTwist", input = T .. ".masterTwist" },
    { output = A .. ".admPose", input = T .. ".slavePose" },
    { output = A .. ".admTwist", input = T .. ".slaveTwist" },
    { output = T .. ".masterForceDesired", input = P .. ".masterForceDesired" },
    { output = T .. ".slaveForceDesired", input = P .. ".slaveForceDesired" },
    { output = L .. ".linkedMasterTwist", input = P .. ".masterTwist" },
    { output = A .. ".admTwist", input = P .. ".slaveTwist" },
    { output = P .. ".slaveForce", input = A .. ".extWrench" },
    { output = P .. ".masterForce", input = L .. ".slaveWrench" },
    -- The tanks fill with what the robots dissipate (eq. 4.19): the slave's admittance damping,
    -- the device's backdrive friction (reported beside the link: a figure for the tank, not a
    -- sample of the coupling).
    { output = A .. ".dissipatedPower", input = P .. ".slaveDissipation" },
  }
  if c.master.twist then list[#list + 1] = { output = c.master.twist, input = L .. ".masterTwist" } end
  if c.master.dissipation then list[#list + 1] = { output = c.master.dissipation, input = P .. ".masterDissipation" } end
  if c.master.feedback then list[#list + 1] = { output = L .. ".linkedSlaveWrench", input = c.master.feedback } end
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
-- saturation) and `master.max_torque` (N·m; 0: no actuated wrist) when the master declares them.
function M.render(passivity, master)
  local p = _G[passivity]
  if master.max_force then p.master_max_force = master.max_force end
  if master.max_torque then p.master_max_torque = master.max_torque end
end

-- N/m: the Transparency layer's stiffness over `link`: link.stiffness when given, else 1000 without
-- a lag and 30 N·s/m / (delay + jitter) with one, at most 1000 (both layers run on the controller's
-- side and the master's force crosses the link back: 1000 N/m oscillated by mm at 100 ms, 300 N/m
-- settled, measured on suturing).
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
