-- Fixture: tries to run a shell command (line 2).
os.execute("echo pwned")  -- luacheck: ignore (the sandbox refusing os is the point)
