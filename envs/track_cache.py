"""What a process keeps of the reference tracks its environments use, shared by all of them.

A :class:`envs.mimic.MimicEnv` turns each reference it tracks (a clip, or a corrupted variant of one,
prepared as its :class:`envs.config.ArtefactMix` says) into a :class:`envs.reference.ReferenceTrack`
in two costly steps: making the reference (corrupting, denoising, setting on the floor: most of the
cost, ``bench/track_rebuild.py``) and precomputing the track from it (~25 ms, ~5 kB a frame). A
process keeps both by content in two least-recently-used caches shared by all its environments, so
what they keep is bounded per process, whatever the number of environments:

- :data:`TRACKS`: the tracks (``MimicConfig.track_cache_size``; ~5 kB a frame, ~3 MB for a
  602-frame training clip);
- :data:`REFERENCES`: the references they were built from (``MimicConfig.reference_cache_size``;
  a :class:`reference_motion.motion.Motion`, ``qpos`` only: ~0.4 kB a frame, each ~12x smaller
  than its track), so that a track dropped for room is rebuilt without corrupting and denoising
  again (``bench/track_rebuild.py``).

A value dropped for room that some environment still holds (the tracks of its running episode) is
still found by content until nobody holds it, so environments never hold two copies of one; memory
is the cache's capacity plus what the running episodes hold (about two tracks per environment). The
tracks' arrays are read only; the references are read by the tracks built from them and must not be
written to.
"""

from __future__ import annotations

import weakref
from collections import OrderedDict
from collections.abc import Hashable
from typing import Generic, TypeVar

V = TypeVar("V")


class LruCache(Generic[V]):
    """At most :attr:`capacity` values by key, the least recently used dropped first; a dropped
    value is still found while something else holds it (values must be weak-referenceable).

    The capacity starts at 0 (nothing kept) and only grows (:meth:`reserve`): each environment of a
    process reserves what its configuration asks for, and the largest request holds; only
    :meth:`clear` with ``release`` gives it back."""

    def __init__(self) -> None:
        self._items: OrderedDict[Hashable, V] = OrderedDict()
        self._alive: weakref.WeakValueDictionary = weakref.WeakValueDictionary()
        """Every value put, while anything holds it."""
        self.capacity = 0
        """Most values kept."""

    def reserve(self, capacity: int) -> None:
        """Keep at least ``capacity`` values from now on (``>= 0``)."""
        if capacity < 0:
            raise ValueError(f"LruCache.reserve: capacity must be >= 0, got {capacity}")
        self.capacity = max(self.capacity, int(capacity))

    def get(self, key: Hashable) -> V | None:
        """The value kept for ``key``, or still held elsewhere (either way now the most recently
        used), or ``None``."""
        value = self._items.get(key)
        if value is not None:
            self._items.move_to_end(key)
            return value
        value = self._alive.get(key)
        return None if value is None else self.put(key, value)

    def put(self, key: Hashable, value: V) -> V:
        """Keep ``value`` for ``key`` as the most recently used, dropping the least recently used
        beyond :attr:`capacity` (with capacity 0, nothing is kept); returns ``value``."""
        self._items[key] = value
        self._items.move_to_end(key)
        self._alive[key] = value
        while len(self._items) > self.capacity:
            self._items.popitem(last=False)
        return value

    def clear(self, release: bool = False) -> None:
        """Drop every value kept, as a measurement that starts cold needs; the capacity reserved stays,
        unless ``release``, which leaves the cache as a new process has it (capacity 0)."""
        self._items.clear()
        self._alive.clear()
        if release:
            self.capacity = 0

    def __len__(self) -> int:
        return len(self._items)

    def __contains__(self, key: Hashable) -> bool:
        return key in self._items


TRACKS: LruCache = LruCache()
"""This process's reference tracks (:class:`envs.reference.ReferenceTrack`) by content: model, clip
content, corruption, denoiser and its slowing, preparation steps, cube size. Clip names are not part
of the key (an environment reports its own clip's name)."""

REFERENCES: LruCache = LruCache()
"""This process's prepared references (:class:`reference_motion.motion.Motion`) by the same content
as :data:`TRACKS`, less the cube size."""
