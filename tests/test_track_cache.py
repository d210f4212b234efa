"""The per-process caches of reference tracks and prepared references (envs.track_cache)."""

import gc
from dataclasses import replace

import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401  (registers the ids)
import envs.mimic
from agents.sidecar import EnvSpec
from envs import ArtefactMix
from envs.config import MimicConfig
from envs.track_cache import LruCache


class Value:
    """A weak-referenceable value for the cache."""

    def __init__(self, n):
        self.n = n


def test_lru_cache_drops_the_least_recently_used_beyond_its_capacity():
    cache = LruCache()
    a, b, c, d = map(Value, range(4))
    assert cache.put("a", a) is a and len(cache) == 0  # capacity 0 keeps nothing
    cache.reserve(2)
    cache.put("a", a)
    cache.put("b", b)
    assert cache.get("a") is a  # "a" is now the most recently used ...
    cache.put("c", c)  # ... so "b" goes
    assert "b" not in cache and "a" in cache and "c" in cache
    cache.reserve(1)  # a smaller request does not shrink it
    assert cache.capacity == 2 and len(cache) == 2
    cache.reserve(3)
    cache.put("d", d)
    assert len(cache) == 3 and [cache.get(k) for k in "acd"] == [a, c, d]
    cache.clear()
    assert len(cache) == 0 and cache.capacity == 3 and "a" not in cache
    cache.put("a", a)
    cache.clear(release=True)  # as a new process has it
    assert len(cache) == 0 and cache.capacity == 0 and cache.put("a", a) is a and "a" not in cache
    with pytest.raises(ValueError, match="capacity must be >= 0"):
        cache.reserve(-1)


def test_a_dropped_value_is_found_while_something_else_holds_it():
    cache = LruCache()
    cache.reserve(1)
    held = cache.put("held", Value(1))
    cache.put("other", Value(2))  # "held" is dropped for room ...
    assert "held" not in cache and len(cache) == 1
    assert cache.get("held") is held  # ... but found while held, and kept again (the most recent)
    assert "held" in cache and "other" not in cache
    cache.put("other", Value(3))  # dropped again, and now nobody else holds it
    del held
    gc.collect()
    assert cache.get("held") is None


@pytest.fixture
def fresh_caches(monkeypatch):
    """Empty process caches, so that this test's capacities hold."""
    tracks, references = LruCache(), LruCache()
    monkeypatch.setattr(envs.mimic, "TRACKS", tracks)
    monkeypatch.setattr(envs.mimic, "REFERENCES", references)
    return tracks, references


def test_a_process_keeps_its_budget_of_tracks_whatever_its_envs_and_episodes_run_on(fresh_caches):
    """Two envs of one process, each asking for one track: the process keeps one, not one per env, and
    the episode whose track was dropped steps on it as an env that kept it does."""
    tracks, _ = fresh_caches
    mix = ArtefactMix(fraction=1.0, variants_per_clip=2, seed=7)
    a, b = (gym.make("MimicIMU-v0", clips=["deepmimic:walk"], artefacts=mix,
                     config=MimicConfig(track_cache_size=1, reference_cache_size=4)).unwrapped for _ in range(2))
    start = {"clip": 0, "start_frame": 0, "corrupted": True}
    a.reset(seed=0, options=start)
    b.reset(seed=0, options={**start, "corrupted": False})
    assert len(tracks) == 1 and tracks.capacity == 1
    assert a._plans[(0, a.variant_index, False, ())].track_key not in tracks  # a's track is no longer kept ...
    twin = gym.make("MimicIMU-v0", clips=["deepmimic:walk"], artefacts=mix).unwrapped
    twin.reset(seed=0, options=start)
    assert twin.current_track is a.current_track  # found while a holds it: one copy, not two
    action = np.full(a.action_space.shape, 0.1)
    for _ in range(3):  # ... yet a steps on it as its twin does
        _, reward, *_ = a.step(action)
        _, twin_reward, *_ = twin.step(action)
        assert reward == twin_reward


def test_a_dropped_track_is_rebuilt_from_its_kept_reference_without_corrupting_again(fresh_caches, monkeypatch):
    tracks, references = fresh_caches
    corruptions = []
    real_corrupt = envs.mimic.corrupt
    monkeypatch.setattr(envs.mimic, "corrupt", lambda *a, **k: corruptions.append(1) or real_corrupt(*a, **k))
    mix = ArtefactMix(fraction=1.0, variants_per_clip=2, seed=7)
    env = gym.make("MimicIMU-v0", clips=["deepmimic:walk"], artefacts=mix,
                   config=MimicConfig(track_cache_size=1, reference_cache_size=4)).unwrapped
    env.reset(seed=0, options={"clip": 0, "corrupted": False})
    first = env.track(0, 1)
    first_arrays = {k: v.copy() for k, v in vars(first).items() if isinstance(v, np.ndarray)}
    first_motion = id(first.motion)
    assert corruptions == [1] and len(references) == 2  # the clip and its variant
    del first
    env.track(0, 0, as_given=True)  # another variant's track takes the one place ...
    gc.collect()
    assert len(tracks) == 1 and corruptions == [1, 1]
    again = env.track(0, 1)  # ... and variant 1's comes back from its kept reference: not corrupted again
    assert corruptions == [1, 1] and id(again.motion) == first_motion
    for name, value in first_arrays.items():
        np.testing.assert_array_equal(getattr(again, name), value, err_msg=name)
        assert not getattr(again, name).flags.writeable


def test_envs_differing_in_cube_size_share_the_reference_but_not_the_track(fresh_caches):
    one, half = (gym.make("MimicIMU-v0", clips=["deepmimic:walk"], config=MimicConfig(cube_size_m=size)).unwrapped
                 for size in (1.0, 0.5))
    assert one.track(0) is not half.track(0) and one.track(0).motion is half.track(0).motion
    assert not np.allclose(one.track(0).faces_rel_root, half.track(0).faces_rel_root)


def test_variants_of_an_earlier_seed_come_back_from_the_cache(fresh_caches):
    env = gym.make("MimicIMU-v0", clips=["deepmimic:walk"], artefacts=ArtefactMix(fraction=1.0, variants_per_clip=1),
                   config=MimicConfig(track_cache_size=8)).unwrapped
    env.reset(seed=1)
    first = env.track(0, 0)
    env.reset(seed=2)
    assert not np.allclose(env.track(0, 0).motion.qpos, first.motion.qpos)  # the new seed's variant
    env.reset(seed=1)
    assert env.track(0, 0) is first


def test_envs_made_from_a_sidecar_keep_the_default_cache_sizes():
    """The cache sizes are how the training process spent its memory, not part of the task."""
    spec = EnvSpec(env_id="MimicIMU-v0", config={"track_cache_size": 1200, "reference_cache_size": 16000,
                                                 "cube_size_m": 0.5})
    config = spec.make(["deepmimic:walk"]).unwrapped.config
    assert config == replace(spec.mimic_config(), track_cache_size=MimicConfig().track_cache_size,
                             reference_cache_size=MimicConfig().reference_cache_size)
    assert config.cube_size_m == 0.5


@pytest.mark.parametrize("field, value", [("track_cache_size", 0), ("track_cache_size", 2.5),
                                          ("reference_cache_size", -1), ("reference_cache_size", True)])
def test_cache_sizes_are_checked(field, value):
    with pytest.raises(ValueError, match=f"{field} must be a whole number >= {int(field == 'track_cache_size')}"):
        MimicConfig(**{field: value})
