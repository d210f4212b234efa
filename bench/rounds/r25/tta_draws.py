"""Prototype (round 25 probe): bench/imu_draws.py with the actor's action averaged over K copies of
its normalised observation with Gaussian noise (TTA). Usage: tta_draws.py K SIGMA -- <imu_draws args>"""
import os, sys
sys.path.insert(0, "."); sys.path.insert(0, "bench")
import numpy as np
import agents.policy as P

K, SIGMA = int(sys.argv[1]), float(sys.argv[2])
rng = np.random.default_rng(12345)
orig = P.MimicPolicy.mean_action

def mean_action(self, obs):
    x = np.asarray(self.normalizer.normalize_obs(obs), dtype=np.float32)
    xs = np.repeat(x[None], K, axis=0)
    xs[1:] += (SIGMA * rng.standard_normal(xs[1:].shape)).astype(np.float32)
    mean = P.mlp_mean_action(self.model.policy, xs).mean(axis=0)
    space = self.model.action_space
    return np.clip(mean, space.low, space.high)

P.MimicPolicy.mean_action = mean_action
sys.argv = ["imu_draws.py"] + sys.argv[4:]
import imu_draws
imu_draws.main()
