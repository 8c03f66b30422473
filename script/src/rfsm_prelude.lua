-- cobra's `rfsm` module: rFSM's model API (github.com/kmarkus/rFSM), run by cobra's C++ engine.
-- Embedded into the cobra_script library at build time (see CMakeLists.txt); `__cobra_rfsm` holds
-- the C functions it calls.
local C = ...
local rfsm = {}

local kind_of = {}  -- metatable -> 'state' | 'conn' | 'trans'

local function maker(kind)
  local methods = {}
  function methods:type() return kind == 'conn' and 'connector' or (kind == 'trans' and 'transition' or 'state') end
  local mt = { __index = methods }
  kind_of[mt] = kind
  return function(t)
    t = t or {}
    if type(t) ~= 'table' then error("rfsm." .. kind .. ": expected a table, got " .. type(t), 2) end
    -- Where the constructor was called (a tail call, `return rfsm.state{...}`, has no caller left).
    local info = debug.getinfo(2, "Sl")
    if info and info.currentline > 0 then
      local src = info.source:sub(1, 1) == '@' and info.source:sub(2) or info.short_src
      rawset(t, '_cobra_origin', src .. ":" .. info.currentline)
    end
    return setmetatable(t, mt)
  end
end

rfsm.state = maker('state')
rfsm.conn = maker('conn')
rfsm.trans = maker('trans')
rfsm.sista, rfsm.simple_state, rfsm.csta, rfsm.composite_state = rfsm.state, rfsm.state, rfsm.state, rfsm.state
rfsm.connector, rfsm.transition = rfsm.conn, rfsm.trans
rfsm.yield = coroutine.yield

local function kind(x) return type(x) == 'table' and kind_of[getmetatable(x)] or nil end
function rfsm.is_state(x) return kind(x) == 'state' end
function rfsm.is_conn(x) return kind(x) == 'conn' end
function rfsm.is_trans(x) return kind(x) == 'trans' end
function rfsm.is_node(x) return kind(x) == 'state' or kind(x) == 'conn' end
function rfsm.is_meta(key) return type(key) == 'string' and key:sub(1, 1) == '_' end
local function subnodes(s)
  local names = {}
  for k, v in pairs(s) do
    if type(k) == 'string' and not rfsm.is_meta(k) and rfsm.is_node(v) then names[#names + 1] = k end
  end
  table.sort(names)  -- a deterministic order (Lua's pairs has none)
  return names
end
function rfsm.is_composite(x) return rfsm.is_state(x) and #subnodes(x) > 0 end
function rfsm.is_leaf(x) return rfsm.is_state(x) and #subnodes(x) == 0 end

function rfsm.load(file)
  local model = dofile(file)
  if not rfsm.is_state(model) then error("rfsm.load: no valid rfsm in file '" .. tostring(file) .. "' found.", 2) end
  return model
end

-- The model as flat lists for the C++ builder. Nodes: {kind, parent, name, origin, entry, exit,
-- doo, table}; transitions: {scope, src, tgt, events, pn, guard, effect, origin, table}.
local function fields(t)
  local names = {}
  for k in pairs(t) do if type(k) == 'string' and not rfsm.is_meta(k) then names[#names + 1] = k end end
  table.sort(names)
  return table.concat(names, ", ")
end

function C.describe(root)
  local nodes, transitions, errors = {}, {}, {}
  local function problem(t, text) errors[#errors + 1] = (rawget(t, '_cobra_origin') or '?') .. ": " .. text end
  local function check_function(t, field, fqn)
    local f = rawget(t, field)
    if f ~= nil and type(f) ~= 'function' then problem(t, fqn .. ": " .. field .. " must be a function, got " .. type(f)) end
    return f
  end
  local function add_transition(tr, scope)
    local events = rawget(tr, 'events')
    if type(events) == 'string' then events = { events } end
    if events ~= nil and type(events) ~= 'table' then problem(tr, "transition in " .. scope .. ": events must be a list") events = {} end
    local names = {}
    for _, e in ipairs(events or {}) do
      if type(e) == 'string' then names[#names + 1] = e
      else problem(tr, "transition in " .. scope .. ": event " .. tostring(e) .. " is not a string (function events are not supported: use a guard)") end
    end
    if rawget(tr, 'event') ~= nil then problem(tr, "transition in " .. scope .. " has an 'event' field; rFSM reads 'events' (a list)") end
    local src, tgt = rawget(tr, 'src'), rawget(tr, 'tgt')
    if type(src) ~= 'string' then problem(tr, "transition in " .. scope .. " has no src (its fields: " .. fields(tr) .. ")") return end
    if type(tgt) ~= 'string' then problem(tr, "transition from '" .. src .. "' in " .. scope .. " has no tgt (its fields: " .. fields(tr) .. ")") return end
    if tgt == 'internal' then problem(tr, "transition from '" .. src .. "' in " .. scope .. ": internal transitions are not supported") return end
    local pn = rawget(tr, 'pn') or 0
    if type(pn) ~= 'number' or pn ~= math.floor(pn) then problem(tr, "transition in " .. scope .. ": pn must be an integer") pn = 0 end
    transitions[#transitions + 1] = { scope, src, tgt, names, pn, check_function(tr, 'guard', scope), check_function(tr, 'effect', scope),
                                      rawget(tr, '_cobra_origin') or '?', tr }
  end
  local function walk(state, fqn)
    for _, name in ipairs(subnodes(state)) do
      local child = state[name]
      local child_fqn = fqn .. "." .. name
      if rfsm.is_state(child) then
        nodes[#nodes + 1] = { 'state', fqn, name, rawget(child, '_cobra_origin') or '?', check_function(child, 'entry', child_fqn),
                              check_function(child, 'exit', child_fqn), check_function(child, 'doo', child_fqn), child }
        walk(child, child_fqn)
      else
        nodes[#nodes + 1] = { 'conn', fqn, name, rawget(child, '_cobra_origin') or '?', false, false, false, child }
      end
    end
    for _, v in ipairs(state) do
      if rfsm.is_trans(v) then add_transition(v, fqn) end
    end
    local keyed = {}
    for k, v in pairs(state) do
      if type(k) ~= 'number' and rfsm.is_trans(v) then keyed[#keyed + 1] = k end
    end
    table.sort(keyed, function(a, b) return tostring(a) < tostring(b) end)
    for _, k in ipairs(keyed) do add_transition(state[k], fqn) end
  end
  if not rfsm.is_state(root) then error("the chart must return an rfsm.state, got " .. type(root), 0) end
  walk(root, 'root')
  if #errors > 0 then error(table.concat(errors, "\n"), 0) end
  return { nodes, transitions, root, { 'entry', 'exit', 'doo', 'effect' }, {}, {},
           { check_function(root, 'entry', 'root'), check_function(root, 'exit', 'root') } }
end

-- Operational API: charts made by rfsm.init run on cobra's engine.
function rfsm.init(model)
  assert(rfsm.is_state(model), "invalid fsm model passed to rfsm.init")
  C.init(model)
  model._initialized = true
  return model
end
function rfsm.send_events(fsm, ...)
  for _, e in ipairs({ ... }) do C.send(fsm, e) end
end
function rfsm.get_actleaf_fqn(fsm) return C.leaf(fsm) end
function rfsm.get_active_conf(fsm) return C.configuration(fsm) end
function rfsm.reset(fsm) C.reset(fsm) end

local function hook_add(fsm, field, hook, where)
  local list = rawget(fsm, '_' .. field .. 's') or {}
  rawset(fsm, '_' .. field .. 's', list)
  if where == 'before' then table.insert(list, 1, hook) else list[#list + 1] = hook end
  rawset(fsm, field, function(...) for _, h in ipairs(list) do h(...) end end)
end
function rfsm.pre_step_hook_add(fsm, hook, where) hook_add(fsm, 'pre_step_hook', hook, where) end
function rfsm.post_step_hook_add(fsm, hook, where) hook_add(fsm, 'post_step_hook', hook, where) end

-- rFSM's step(fsm, n): n steps, where a step whose events triggered nothing does not count;
-- returns true when idle.
function rfsm.step(fsm, n)
  n = n or 1
  while true do
    if fsm.getevents then
      for _, e in ipairs(fsm.getevents() or {}) do C.send(fsm, e) end
    end
    if fsm.pre_step_hook then fsm.pre_step_hook(fsm) end
    local result = C.step(fsm)
    if fsm.post_step_hook then fsm.post_step_hook(fsm) end
    if result == 'cannot_enter' then return false end
    if result ~= 'events_ignored' then n = n - 1 end
    if result == 'idle' then return true end
    if n < 1 then return false end
  end
end
function rfsm.run(fsm) return rfsm.step(fsm, math.huge) end

package.loaded.rfsm = rfsm
package.loaded.rfsm_timeevent = {
  set_gettime_hook = function(f) C.gettime = f end,
  e_after = function(t) return "e_after(" .. tostring(t) .. ")" end,
  e_at = function(t) return "e_at(" .. tostring(t) .. ")" end,
}
return rfsm
