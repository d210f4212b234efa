"""PPO training, evaluation and clip cleaning — built in the PPO issue."""
