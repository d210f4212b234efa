"""The per-process caches of reference tracks and prepared references (envs.track_cache)."""

import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401  (registers the ids)
import envs.mimic
from envs import ArtefactMix
from envs.config import MimicConfig
from envs.track_cache import LruCache


def test_lru_cache_drops_the_least_recently_used_beyond_its_capacity():
    cache = LruCache()
    assert cache.put("a", 1) == 1 and len(cache) == 0  # capacity 0 keeps nothing
    cache.reserve(2)
    cache.put("a", 1)
    cache.put("b", 2)
    assert cache.get("a") == 1  # "a" is now the most recently used ...
    cache.put("c", 3)  # ... so "b" goes
    assert "b" not in cache and cache.get("b") is None and cache.get("a") == 1 and cache.get("c") == 3
    cache.reserve(1)  # a smaller request does not shrink it
    assert cache.capacity == 2 and len(cache) == 2
    cache.reserve(3)
    cache.put("d", 4)
    assert len(cache) == 3 and [cache.get(k) for k in "acd"] == [1, 3, 4]
    cache.clear()
    assert len(cache) == 0 and cache.capacity == 0 and cache.get("a") is None
    with pytest.raises(ValueError, match="capacity must be >= 0"):
        cache.reserve(-1)


@pytest.fixture
def fresh_caches(monkeypatch):
    """Empty process caches, so that this test's capacities hold."""
    tracks, references = LruCache(), LruCache()
    monkeypatch.setattr(envs.mimic, "TRACKS", tracks)
    monkeypatch.setattr(envs.mimic, "REFERENCES", references)
    return tracks, references


def test_a_process_keeps_at_most_its_budget_of_tracks_whatever_its_envs(fresh_caches):
    """Two envs of one process, each asking for one track: the process keeps one, not one per env; an
    env's running episode keeps its own track."""
    tracks, _ = fresh_caches
    mix = ArtefactMix(fraction=1.0, variants_per_clip=2, seed=7)
    config = MimicConfig(track_cache_size=1, reference_cache_size=4)
    a, b = (gym.make("MimicIMU-v0", clips=["deepmimic:walk"], artefacts=mix, config=config).unwrapped
            for _ in range(2))
    a.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    running = a.current_track
    b.reset(options={"clip": 0, "start_frame": 0, "corrupted": False})
    assert len(tracks) == 1 and tracks.capacity == 1
    assert a.current_track is running and b.current_track is b.track(0, -1)
    a.step(np.zeros(a.action_space.shape))  # the dropped track is still the one a tracks


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
    assert corruptions == [1] and len(references) == 2  # the clip and its variant
    env.track(0, 0, as_given=True)  # another variant's track takes the one place ...
    assert len(tracks) == 1 and corruptions == [1, 1]
    again = env.track(0, 1)  # ... and variant 1's comes back from its kept reference: not corrupted again
    assert again is not first and corruptions == [1, 1] and again.motion is first.motion
    for name, value in vars(first).items():
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(getattr(again, name), value, err_msg=name)
            assert not getattr(again, name).flags.writeable


@pytest.mark.parametrize("field, value", [("track_cache_size", 0), ("reference_cache_size", -1),
                                          ("track_cache_size", 2.5)])
def test_cache_sizes_are_checked(field, value):
    with pytest.raises(ValueError, match="track_cache_size must be a whole number >= 1"):
        MimicConfig(**{field: value})
