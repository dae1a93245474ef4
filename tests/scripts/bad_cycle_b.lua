-- Fixture: the other half of the require cycle.
return require("bad_cycle_a")
