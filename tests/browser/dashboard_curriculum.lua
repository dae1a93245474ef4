-- The curriculum of dashboard_batch.lua: a sound stage, and one whose reward raises after 4 calls;
-- each's contexts are not in alphabetical order.
local p3 = roger.primitive("phi3")
local p0 = roger.primitive("phi0")
local calls = 0
local function sound_reward(state, action, event)
  if event == "absorbing" then return 1 end
  return 0
end
local function boom_reward(state, action, event)
  calls = calls + 1
  -- Markup and quotes in the message: the page must show them as text.
  if calls > 4 then error("reward exploded after 4 calls <b>bold</b> & \"quotes\"") end
  if event == "absorbing" then return 1 end
  return 0
end
local function stage(name, reward, context)
  return roger.stage{ name = name, time_limit = 1, budget = { episodes = 9 },
    checkpoints = { every = 3, episodes = 2, final = 2 },
    -- "B" first: the contexts are not in the order of their names, which the page must keep.
    contexts = { { name = "B", actions = { p3 } }, { name = context, actions = { p3, p0 } } },
    absorbing = roger.converged(p3), reward = reward }
end
return { name = "dashboard", stages = {
  stage("sound", sound_reward, "A_context_with_a_rather_long_name_to_see_how_the_dashboard_copes_0123456789"),
  stage("boom", boom_reward, "A"),
} }
