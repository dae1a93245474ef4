-- Fixture: a misspelt field in a policy (line 9).
local phi0 = roger.primitive("phi0")
return {
  policies = {
    track = {
      action = phi0,
      goal = roger.converged(phi0),
      time_limit = 5,
      scenaro = "cluttered",
    },
  },
}
