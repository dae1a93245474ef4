-- Fixture: half of a require cycle (bad_cycle_a -> bad_cycle_b -> bad_cycle_a).
return require("bad_cycle_b")
