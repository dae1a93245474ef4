#!/usr/bin/env python3
"""python_example.py: a learner of our own on a stage of a curriculum, through the Python module
(docs/python.md). Q-learning over the controller-state vector in numpy, on the tutorial's stage
Look (docs/curricula.md): the same problem `roger train` solves, written in Python.

    PYTHONPATH=build/python python3 docs/examples/python_example.py
"""
import os

import numpy as np

import roger

# The tutorial's curriculum beside this file: docs/examples/, or share/doc/roger/examples/ installed.
CURRICULUM = os.path.join(os.path.dirname(os.path.abspath(__file__)), "curriculum_example.lua")
env = roger.make(CURRICULUM, stage="Look", context="Gaze")
print(env.actions, env.action_space.n, env.observation_space)

n = env.action_space.n
q = np.zeros((3 ** n, n))                 # one row per state: roger.state_index(obs)
rng = np.random.default_rng(1)
alpha, discount, episodes = 0.2, 0.95, 60

for e in range(episodes):
    epsilon = 1.0 - 0.95 * e / episodes    # 100% to 5%, as the paper's learner
    obs, info = env.reset(seed=roger.mix(1, e + 1))   # roger train's world of episode e
    done = False
    while not done:
        s = roger.state_index(obs)
        a = int(rng.integers(n)) if rng.random() < epsilon else int(np.argmax(q[s]))
        obs, reward, terminated, truncated, info = env.step(a)   # a runs until the state changes
        done = terminated or truncated
        target = reward if terminated else reward + discount * q[roger.state_index(obs)].max()
        q[s, a] += alpha * (target - q[s, a])

# The greedy policy on held-out worlds (the stage's checkpoint seeds).
successes, sim_s = 0, 0.0
for i in range(20):
    obs, info = env.reset(seed=1000000 + i)
    done = False
    while not done:
        obs, reward, terminated, truncated, info = env.step(int(np.argmax(q[roger.state_index(obs)])))
        done = terminated or truncated
    successes += info["success"]           # terminated: the goal, or the stage's time-out (info["time_out"])
    sim_s += info["sim_seconds"]
print(f"greedy policy: {successes}/20 episodes reached the goal, {sim_s / 20:.2f} simulated s each")

# Many worlds at once: C++ threads, numpy arrays, a finished world begins its next episode at its
# next step (Gymnasium's NEXT_STEP autoreset).
vec = roger.make_vec(CURRICULUM, "Look", "Gaze", num_envs=4, threads=2)
obs, info = vec.reset(seed=0)
ended, goals = 0, 0
for _ in range(10):
    actions = np.array([np.argmax(q[roger.state_index(o)]) for o in obs])
    obs, rewards, terminated, truncated, info = vec.step(actions)
    ended += int(np.count_nonzero(terminated | truncated))
    if "success" in info:  # as in Gymnasium's vector environments: there when some episode ended
        goals += int(np.count_nonzero(info["success"] & info["_success"]))
print(f"{ended} episodes ended in 10 steps of {vec.num_envs} worlds, {goals} at the goal")

# What the run must show (the tests run this file): the learner learned, and the batch ran.
assert successes >= 15, f"the greedy policy reached the goal in {successes} of 20 episodes"
assert 0 < goals <= ended, (goals, ended)
