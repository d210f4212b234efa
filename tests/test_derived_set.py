"""bench/rounds/derived_set.py: a round's candidate set is its base with the named fields replaced, the rest kept."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench" / "rounds"))
from derived_set import main  # noqa: E402

from agents.policy_set import PolicySet, load_policy_set  # noqa: E402

MODELS = Path(__file__).resolve().parents[1] / "models"


def test_a_derived_set_replaces_the_named_fields_and_keeps_the_rest(tmp_path):
    base = PolicySet(tmp_path / "base", MODELS / "mimic_walk", MODELS / "mimic_imu", 0.3,
                     clips=(("*dash*", MODELS / "mimic_general"),), fast=MODELS / "mimic_general", fast_speed_mps=2.5)
    base.save()
    main([str(tmp_path / "base"), str(tmp_path / "new"), f"sideways={MODELS / 'mimic_walk_back'}",
          "sideways_speed_mps=0.25"])
    new = load_policy_set(tmp_path / "new")
    assert new.sideways == MODELS / "mimic_walk_back" and new.sideways_speed_mps == 0.25
    assert (new.default, new.backward, new.backward_speed_mps) == (MODELS / "mimic_walk", MODELS / "mimic_imu", 0.3)
    assert new.clips == (("*dash*", MODELS / "mimic_general"),)
    assert (new.fast, new.fast_speed_mps) == (MODELS / "mimic_general", 2.5)
    with pytest.raises(SystemExit, match="FIELD one of backward, .*turn_rate_rad_s, got 'path=x'"):
        main([str(tmp_path / "base"), str(tmp_path / "bad"), "path=x"])
    with pytest.raises(SystemExit, match="sideways_speed_mps is a number, got 'fast'"):
        main([str(tmp_path / "base"), str(tmp_path / "bad"), "sideways_speed_mps=fast"])
    with pytest.raises(SystemExit, match="fast_speed_mps must be a finite number >= 0"):
        main([str(tmp_path / "base"), str(tmp_path / "bad"), "fast_speed_mps=-1"])
    main([str(tmp_path / "new"), str(tmp_path / "turning"), f"turn={MODELS / 'mimic_walk'}", "turn_rate_rad_s=0.4"])
    turning = load_policy_set(tmp_path / "turning")
    assert (turning.turn, turning.turn_rate_rad_s, turning.sideways) == (MODELS / "mimic_walk", 0.4,
                                                                          MODELS / "mimic_walk_back")
    main([str(tmp_path / "turning"), str(tmp_path / "slowed"), "denoise_slow_s=fast:0.5"])
    slowed = load_policy_set(tmp_path / "slowed")
    assert slowed.denoise_slow_s == (("fast", 0.5),) and slowed.turn == MODELS / "mimic_walk"
    main([str(tmp_path / "slowed"), str(tmp_path / "kept"), "sideways_speed_mps=0.3"])
    assert load_policy_set(tmp_path / "kept").denoise_slow_s == (("fast", 0.5),)  # other fields keep the slowing
    main([str(tmp_path / "slowed"), str(tmp_path / "new_fast"), f"fast={MODELS / 'mimic_walk_back'}"])
    assert load_policy_set(tmp_path / "new_fast").denoise_slow_s == ()  # a new member does not inherit it
    main([str(tmp_path / "slowed"), str(tmp_path / "cleared"), "denoise_slow_s="])
    assert load_policy_set(tmp_path / "cleared").denoise_slow_s == ()
    with pytest.raises(SystemExit, match="denoise_slow_s is ROLE:SECONDS\\[,ROLE:SECONDS\\] with each ROLE once, "
                                         "got 'fast:0.5,fast:1'"):
        main([str(tmp_path / "turning"), str(tmp_path / "bad"), "denoise_slow_s=fast:0.5,fast:1"])
    with pytest.raises(SystemExit, match="denoise_slow_s is ROLE:SECONDS\\[,ROLE:SECONDS\\] with each ROLE once, got '0.5'"):
        main([str(tmp_path / "turning"), str(tmp_path / "bad"), "denoise_slow_s=0.5"])
    with pytest.raises(SystemExit, match="denoise_slow_s names 'dash', expected a role the set has a policy for"):
        main([str(tmp_path / "turning"), str(tmp_path / "bad"), "denoise_slow_s=dash:0.5"])
