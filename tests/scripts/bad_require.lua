-- Fixture: require calls that must be refused. `which` is set by the test.
return function(which)
  if which == "dots" then return require("../../etc/passwd") end
  if which == "missing" then return require("no.such.module") end
  if which == "cycle" then return require("bad_cycle_a") end
  return require(which)
end
