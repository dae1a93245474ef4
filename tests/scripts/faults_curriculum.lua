-- Fixture of the [faults] tests (tests/test_batch.cpp): one sound stage and one stage per kind of
-- fault a Lua callback can commit while trials run. Each trial loads its own copy, so `calls`
-- counts the calls of one trial.
local p3 = roger.primitive("phi3")
local p0 = roger.primitive("phi0")
local calls = 0
bomb = {}  -- luacheck: ignore (a global: what the memory bomb holds stays held)

local function sound_reward(state, action, event)
  calls = calls + 1
  if event == "absorbing" then return 1 end
  return 0
end

local function late_loop(state, action, event)
  calls = calls + 1
  if calls > 1000 then
    while true do end  -- line 18: an infinite loop after 1,000 calls
  end
  return 0
end

local function memory_bomb(state, time)
  calls = calls + 1
  if calls > 50 then
    for i = 1, 64 do bomb[i] = string.rep("x", (16 << 20) + i) end  -- luacheck: ignore (line 26: 1 GiB wanted)
  end
  return false
end

local function late_nan(state, action, event)
  calls = calls + 1
  if calls > 20 then return 0 / 0 end  -- a NaN: the error names the function (line 31)
  return 0
end

local function wrong_type(state, time)
  return "yes"  -- a string, not a boolean: the error names the function (line 37)
end

local function late_finalizer(state, action, event)
  calls = calls + 1
  if calls > 10 then  -- a finalizer that never returns: refused at line 44
    setmetatable({}, { __gc = function() while true do end end })
  end
  return 0
end

local function late_pattern(state, time)
  calls = calls + 1
  if calls > 10 then  -- a pattern that backtracks for hours: stopped at line 52
    return string.rep("a", 30000):find(".-.-.-.-.-.-.-.-b") ~= nil
  end
  return false
end

local function late_chain(state, action, event)
  calls = calls + 1
  if calls > 10 then  -- an __index chain that loops: 2,000 links per read, stopped by time at line 61
    local mt = {} mt.__index = mt setmetatable(mt, mt)
    while true do pcall(function() return mt.x end) end
  end
  return 0
end

local function stage(name, fields)
  fields.name = name
  fields.time_limit = 1
  fields.budget = { episodes = fields.episodes or 6 }
  fields.episodes = nil
  fields.checkpoints = { every = 3, episodes = 2, final = 2 }
  fields.contexts = { { name = "A", actions = { p3, p0 } } }
  fields.absorbing = fields.absorbing or roger.converged(p3)
  return roger.stage(fields)
end

return {
  name = "faults",
  stages = {
    stage("sound", { reward = sound_reward }),
    stage("loop", { reward = late_loop, episodes = 2000 }),
    stage("bomb", { absorbing = memory_bomb, reward = sound_reward, episodes = 200 }),
    stage("nan", { reward = late_nan, episodes = 200 }),
    stage("type", { absorbing = wrong_type, reward = sound_reward }),
    stage("finalizer", { reward = late_finalizer, episodes = 200 }),
    stage("pattern", { absorbing = late_pattern, reward = sound_reward, episodes = 200 }),
    stage("chain", { reward = late_chain, episodes = 200 }),
    stage("compare", { scenario = "tests/scripts/faults_compare_scenario.lua", reward = sound_reward, episodes = 12 }),
    stage("escape", { scenario = "tests/scripts/faults_escape_scenario.lua", reward = sound_reward, episodes = 12 }),
    stage("unlucky", { scenario = "tests/scripts/faults_scenario.lua", reward = sound_reward, episodes = 12 }),
  },
}
