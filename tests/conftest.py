import os

# Torch's OpenMP threads wait for work passively (they sleep instead of spinning): with another job on the cores
# (a training run, a second test session) spinning threads took VGRFNet's small convolutions 2-3 times longer on 2
# threads than on 1, and the footskate cleanup tests from 17 s to 110 s each; passive waiting costs about 10% on an idle
# machine. Set before torch is imported, since OpenMP reads it once.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import pytest  # noqa: E402
import torch  # noqa: E402

from agents.physics_dataset import DatasetConfig, generate  # noqa: E402
from reference_motion.library import load_motion  # noqa: E402

TINY = DatasetConfig(policies=("models/mimic_walk",),
                     clips=("deepmimic:walk", "deepmimic:walker/0walk_forward", "deepmimic:walker/turn_left0"),
                     splits={"val": ["deepmimic:walker/0walk_forward"], "test": ["deepmimic:walker/turn_left0"]},
                     variants=1, episodes=1, min_episode_s=1.0, corrupted_share=0.0)
"""A tiny physics-labelled dataset: one walk episode per split, performed by the shipped walk policy."""


@pytest.fixture(scope="session")
def walk():
    """DeepMimic walk on humanoid_1seg, 60 Hz, looped to 5 s."""
    return load_motion("deepmimic:walk", min_frames=300)


@pytest.fixture(scope="session")
def dataset(tmp_path_factory):
    """:data:`TINY` generated once per test session."""
    root = tmp_path_factory.mktemp("physics")
    generate(root, TINY, progress=False)
    return root


@pytest.fixture(scope="session")
def tiny_config():
    """The configuration :func:`dataset` was generated with."""
    return TINY


@pytest.fixture(scope="module")
def one_thread():
    """Torch on one thread for a test module (``pytestmark = pytest.mark.usefixtures("one_thread")``):
    small batched linear algebra is fastest so and does not fight other jobs for cores."""
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)
