import numpy as np
import pytest

from reference_motion.artefacts import ARTEFACT_KINDS, ArtefactRecipe, corrupt
from reference_motion.quality import jitter, motion_quality, range_excursion


@pytest.fixture(scope="module")
def clean(walk):
    return walk, motion_quality(walk)


def test_same_seed_same_output_other_seed_differs(walk):
    a = corrupt(walk, ArtefactRecipe.imu(), seed=7)
    b = corrupt(walk, ArtefactRecipe.imu(), seed=7)
    c = corrupt(walk, ArtefactRecipe.imu(), seed=8)
    assert np.array_equal(a.qpos, b.qpos)
    assert not np.allclose(a.qpos, c.qpos)
    assert a.source["artefact_seed"] == 7


def test_zero_strength_is_identity(walk):
    assert np.array_equal(corrupt(walk, ArtefactRecipe(), seed=1).qpos, walk.qpos)


def test_foot_skate_synthesis_raises_skate_3x(clean):
    walk, q0 = clean
    for seed in range(3):
        q = motion_quality(corrupt(walk, ArtefactRecipe.only("skate"), seed))
        assert q.foot_skate_mps >= 3 * q0.foot_skate_mps, f"seed {seed}: {q.foot_skate_mps:.3f} vs {q0.foot_skate_mps:.3f}"


def test_height_offsets_raise_penetration_or_floating(clean):
    walk, q0 = clean
    raised = {"penetration": 0, "floating": 0}
    for seed in range(6):
        q = motion_quality(corrupt(walk, ArtefactRecipe.only("height"), seed))
        if q.penetration_max_m > q0.penetration_max_m + 0.03:
            raised["penetration"] += 1
        elif q.floating_m > q0.floating_m + 0.03:
            raised["floating"] += 1
    assert raised["penetration"] > 0 and raised["floating"] > 0
    assert sum(raised.values()) == 6


def test_adduction_raises_self_penetration(clean):
    walk, q0 = clean
    assert q0.self_penetration_frac == 0.0
    q = motion_quality(corrupt(walk, ArtefactRecipe.only("adduction"), 0))
    assert q.self_penetration_frac > 0.2


@pytest.mark.parametrize("kind", ["noise", "jitter"])
def test_noise_and_jitter_raise_jitter(clean, kind):
    walk, q0 = clean
    q = motion_quality(corrupt(walk, ArtefactRecipe.only(kind), 0))
    assert q.jitter > 2 * q0.jitter


def test_kinds_use_independent_streams(walk):
    both = corrupt(walk, ArtefactRecipe(skate=1.0, noise=1.0), seed=3)
    skate_only = corrupt(walk, ArtefactRecipe.only("skate"), seed=3)
    assert np.allclose(both.qpos[:, :2], skate_only.qpos[:, :2])


def test_bad_recipe():
    with pytest.raises(ValueError, match="unknown artefact kind 'wobble'"):
        ArtefactRecipe.only("wobble")
    with pytest.raises(ValueError, match="'noise' must be a finite number >= 0"):
        ArtefactRecipe(noise=-1)
    assert len(ARTEFACT_KINDS) == 7


def test_range_excursion_and_jitter_by_hand():
    ranges = np.array([[-1.0, 1.0], [0.0, 2.0]])
    angles = np.array([[1.5, 1.0], [0.0, -0.25], [-1.0, 2.5]])   # 0.5 over; 0.25 under; 0.5 over
    assert range_excursion(angles, ranges) == pytest.approx((0.5 + 0.25 + 0.5) / 3)
    assert range_excursion(np.zeros((4, 2)) + [0.0, 1.0], ranges) == 0.0
    cubic = (np.arange(6.0) / 10.0)[:, None] ** 3          # angle = t³ at 10 Hz: jerk 6 rad/s³
    assert jitter(cubic, fps=10.0) == pytest.approx(6.0)
