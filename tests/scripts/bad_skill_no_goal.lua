-- Fixture: a policy without a goal (the policy starts on line 7).
local phi0 = roger.primitive("phi0")
local search = roger.primitive("search")
return {
  name = "no goal",
  policies = {
    track = {
      action = roger.sequence("Track", { search, phi0 }),
      time_limit = 5,
    },
  },
}
