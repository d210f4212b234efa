"""bench/denoiser_styles.py: denoisers scored on the takes of named styles, on a hand-made library."""

import sys
from pathlib import Path

import pytest

from reference_motion.bvh_export import write_bvh
from reference_motion.importer import import_library
from reference_motion.library import load_motion

REPOSITORY = Path(__file__).resolve().parents[1]
sys.path.append(str(REPOSITORY / "bench"))
from denoiser_styles import main  # noqa: E402


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    """A library of DeepMimic's walk exported as two train takes of styles sad and chimpira."""
    root = tmp_path_factory.mktemp("styles")
    exported = write_bvh(load_motion("deepmimic:walk"), root / "walk.bvh").read_text()
    takes = root / "takes"
    takes.mkdir()
    for name in ("dataset-1_walk_sad_001", "dataset-1_walk_chimpira_001"):
        (takes / f"{name}.bvh").write_text(exported)
    import_library([takes], root / "lib", progress=False)
    return root / "lib"


def test_each_denoiser_scored_on_each_style_clean_and_corrupted(library):
    result = main(["--denoisers", f"soles={REPOSITORY / 'models/imu_denoiser_soles'}",
                   f"first={REPOSITORY / 'models/imu_denoiser'}", "--styles", "sad", "chimpira",
                   "--library", str(library), "--draws", "2"])
    table = result["table"]
    assert sorted(table) == sorted(f"{style}/{kind}/{label}" for style in ("sad", "chimpira")
                                   for kind in ("clean", "imu") for label in ("input", "soles", "first"))
    assert table["sad/imu/input"]["draws"] == 2 and table["sad/clean/input"]["draws"] == 1
    assert table["sad/clean/input"]["hinge_rms_deg"] == 0.0
    for style in ("sad", "chimpira"):  # the shipped denoiser undoes most of the hip offset and the soles' error
        before, after = table[f"{style}/imu/input"], table[f"{style}/imu/soles"]
        assert after["hip_offset_deg"] < 0.5 * before["hip_offset_deg"]
        assert after["sole_rms_cm"] < 0.6 * before["sole_rms_cm"]


def test_a_style_without_takes_is_named(library):
    with pytest.raises(SystemExit, match="no take of style 'giant'"):
        main(["--denoisers", f"soles={REPOSITORY / 'models/imu_denoiser_soles'}", "--styles", "giant",
              "--library", str(library)])


def test_a_denoiser_without_a_label_is_refused(library, capsys):
    with pytest.raises(SystemExit):
        main(["--denoisers", str(REPOSITORY / "models/imu_denoiser_soles"), "--styles", "sad"])
    assert "expected LABEL=DIR" in capsys.readouterr().err
