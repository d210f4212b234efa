"""Gymnasium environments (MimicIMU-v0, ablations, MimicGait-v0) — built in the environments issue."""
