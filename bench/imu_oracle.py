"""How well could a *perfect* cleaner do on our synthetic IMU clips under ADAPT's termination rule?

Usage: ``python bench/imu_oracle.py [--strengths 0.25 0.5 0.75 1] [--seeds 20] [--json [OUT]]``

The "oracle" performs the clean clip exactly (the physically consistent motion the corrupted clip
was made from), started where the corrupted reference starts (reference state initialisation).
An episode still ends as soon as e_discount = clamp(1.3 − 1.4‖p_head − p̄_head‖, 0, 1) drops below
0.025 (adapt eqs. 9 and 11), i.e. once the corrupted reference's head is 0.91 m away. Only the
artefacts that move the whole body can do that: root drift (``skate``) above all. Reported per
artefact strength: the oracle's ELR and SR90 over 300-frame segments (5 start frames × ``--seeds``
seeds × ADAPT's three held-out walker clips plus walk and turn_left0), all kinds together and
``skate`` alone. An ELR goal above the oracle's cannot be met by any policy that does not skate.
"""

from __future__ import annotations

import argparse

import numpy as np

from envs.config import MimicConfig
from envs.rewards import fall_discount, lagging
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.library import load_motion

CLIPS = ("deepmimic:walker/0walk_forward", "deepmimic:walker/turn_left1", "deepmimic:walker/turn_right1",
         "deepmimic:walk", "deepmimic:walker/turn_left0")
STARTS = (0, 60, 120, 180, 240)


def oracle_elr(clean_head: np.ndarray, corrupted_head: np.ndarray, config: MimicConfig) -> float:
    """ELR of performing the clean clip (heads ``(T, 3)``) against the corrupted reference, both
    shifted to start at the same point."""
    performed = clean_head - clean_head[0] + corrupted_head[0]
    for t in range(1, len(performed)):
        if lagging(fall_discount(performed[t], corrupted_head[t]), config.discount_threshold):
            return (t - 1) / (len(performed) - 1)
    return 1.0


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--strengths", type=float, nargs="+", default=[0.25, 0.5, 0.75, 1.0])
    p.add_argument("--seeds", type=int, default=20)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    config = MimicConfig()
    hm = load_model("humanoid_1seg")
    head = hm.body_names.index("head")
    n = config.episode_frames + 1
    cleans = [load_motion(clip, min_frames=STARTS[-1] + n + 1) for clip in CLIPS]
    clean_heads = [hm.forward_kinematics(clean.qpos).body_pos[:, head] for clean in cleans]
    rows = []
    for recipe_name in ("imu", "skate"):
        for strength in args.strengths:
            elrs = []
            for c, (clean, clean_head) in enumerate(zip(cleans, clean_heads)):
                for seed in range(1000 + 100 * c, 1000 + 100 * c + args.seeds):
                    bad = corrupt(clean, ArtefactRecipe.named(recipe_name, strength), seed)
                    bad_head = hm.forward_kinematics(bad.qpos).body_pos[:, head]
                    elrs += [oracle_elr(clean_head[s:s + n], bad_head[s:s + n], config) for s in STARTS]
            elrs = np.array(elrs)
            rows.append({"artefacts": recipe_name, "strength": strength, "segments": len(elrs),
                         "oracle_ELR": float(elrs.mean()), "oracle_SR90": float((elrs >= 0.9).mean())})
            print(f"{recipe_name:>6} strength {strength:<5g} oracle ELR {rows[-1]['oracle_ELR']:.3f}  "
                  f"SR90 {rows[-1]['oracle_SR90']:.2f}  ({len(elrs)} segments)", flush=True)
    emit_json({"rows": rows, "clips": list(CLIPS), "starts": list(STARTS), "seeds": args.seeds}, args.json)


if __name__ == "__main__":
    main()
