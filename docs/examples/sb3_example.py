#!/usr/bin/env python3
"""sb3_example.py: Stable-Baselines3's PPO on the paper's search-grasp stage in DC2, from its
registered id alone, judged on held-out worlds as `roger eval` judges a policy (docs/python.md,
"With Stable-Baselines3"). Needs gymnasium, stable-baselines3 and torch besides the module.

    PYTHONPATH=build/python python3 docs/examples/sb3_example.py
"""
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.env_util import make_vec_env

import roger  # registers the roger/ ids with gymnasium

torch.set_num_threads(1)  # a small network: threads cost more than they give, and runs repeat exactly


def held_out(model, episodes=20):
    """Successes of the greedy policy in the stage's held-out worlds (roger train's checkpoints)."""
    env = roger.make("paper", stage="SG", context="DC2")
    first = env.stage_info["checkpoints"]["seeds"]
    successes = 0
    for i in range(episodes):
        obs, info = env.reset(seed=first + i)
        done = False
        while not done:
            action, _ = model.predict(obs, deterministic=True)
            obs, reward, terminated, truncated, info = env.step(int(action))
            done = terminated or truncated
        successes += info["is_success"]
    return successes


# Four environments, seeded 1, 2, 3, 4 and then each along its own stream of worlds (a Monitor
# each: SB3's episode statistics, and its success rate from info["is_success"]).
train = make_vec_env("roger/SG-DC2-v0", n_envs=4, seed=1)
model = PPO("MlpPolicy", train, n_steps=256, batch_size=64, learning_rate=1e-3, ent_coef=0.01, seed=1,
            device="cpu")
before = held_out(model)
model.learn(total_timesteps=8192)
after = held_out(model)
print(f"PPO on SG/DC2: {before}/20 held-out worlds grasped before training, {after}/20 after 8192 steps")

# What the run must show (the tests run this file where Stable-Baselines3 is installed).
assert after >= 18, f"the PPO policy grasped in {after} of 20 held-out worlds"
