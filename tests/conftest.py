import pytest

from reference_motion.library import load_motion


@pytest.fixture(scope="session")
def walk():
    """DeepMimic walk on humanoid_1seg, 60 Hz, looped to 5 s."""
    return load_motion("deepmimic:walk", min_frames=300)
