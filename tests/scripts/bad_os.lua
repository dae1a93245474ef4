-- Fixture: tries to run a shell command (line 2).
os.execute("echo pwned")
