-- Fixture: a batch script that returns another one it requires, changed (the kind of a script
-- is that of the module it returns: roger check must read it as a batch script).
local batch = require("kill_batch")
batch.trials = 1
return batch
