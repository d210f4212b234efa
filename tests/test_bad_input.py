import json

import numpy as np
import pytest

from reference_motion import bvh, deepmimic
from reference_motion.library import load_motion
from reference_motion.motion import Motion, MotionError


def _walk_frames():
    return json.loads(deepmimic.clip_path("walk").read_text())


def _write(tmp_path, text, name="clip.txt"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_truncated_json(tmp_path):
    text = deepmimic.clip_path("walk").read_text()
    p = _write(tmp_path, text[: len(text) // 2])
    with pytest.raises(MotionError, match=r"clip\.txt: not valid JSON \(truncated"):
        deepmimic.load(p)


def test_frame_with_wrong_value_count(tmp_path):
    doc = _walk_frames()
    doc["Frames"][7] = doc["Frames"][7][:40]
    with pytest.raises(MotionError, match="clip.txt: frame 7 has 40 values, expected 44"):
        deepmimic.load(_write(tmp_path, json.dumps(doc)))


def test_nan_in_frame(tmp_path):
    doc = _walk_frames()
    text = json.dumps(doc).replace(str(doc["Frames"][3][10]), "NaN", 1)
    with pytest.raises(MotionError, match="clip.txt: frame 3 value 10 is not finite"):
        deepmimic.load(_write(tmp_path, text))


def test_empty_file(tmp_path):
    with pytest.raises(MotionError, match="clip.txt: file is empty"):
        deepmimic.load(_write(tmp_path, ""))


def test_binary_deepmimic_file(tmp_path):
    p = tmp_path / "clip.txt"
    p.write_bytes(b"\xff\xfe\x00 not text")
    with pytest.raises(MotionError, match=r"clip\.txt: not a DeepMimic clip \(binary data\)"):
        deepmimic.load(p)


def test_unknown_clip_name_lists_the_valid_ones():
    with pytest.raises(KeyError, match="unknown DeepMimic clip 'wlak'; available: backflip"):
        load_motion("deepmimic:wlak")


def test_bvh_of_an_unknown_rig_lists_its_joints_and_the_missing_ones(tmp_path):
    p = _write(tmp_path, BVH_TWO_FRAMES, "tiny.bvh")
    with pytest.raises(ValueError, match=r"tiny\.bvh: unknown rig \(closest: cmu_mixamo, 2 of 18 joints\); still needed: "
                                         r"neck \(e\.g\. Neck\).*Joints in the file: Hips, Spine1, Spine1_end\. Pass --joint-map"):
        bvh.load(p)


def test_truncated_bvh(tmp_path):
    p = _write(tmp_path, BVH_TWO_FRAMES.rsplit("\n", 2)[0], "cut.bvh")
    with pytest.raises(MotionError, match="cut.bvh"):
        bvh.load(p)


def test_motion_saved_for_other_model(tmp_path, walk):
    path = walk.save(tmp_path / "walk.npz")
    with pytest.raises(MotionError, match=r"walk\.npz: motion was saved for model humanoid_1seg \(nq=50\) but "
                                          r"humanoid_2seg was requested"):
        Motion.load(path, model="humanoid_2seg")
    with pytest.raises(MotionError, match="walk.npz"):
        load_motion(path, model="humanoid_2seg")


def test_motion_rejects_nan_and_wrong_width(walk):
    bad = walk.qpos.copy()
    bad[5, 12] = np.nan
    with pytest.raises(MotionError, match="NaN/inf .*frame 5, column 12"):
        walk.with_qpos(bad)
    with pytest.raises(MotionError, match=r"shape \(T, 50\)"):
        walk.with_qpos(walk.qpos[:, :49])


def test_corrupt_npz(tmp_path):
    p = tmp_path / "broken.npz"
    p.write_bytes(b"PK\x03\x04 not really a zip")
    with pytest.raises(MotionError, match="broken.npz: not a readable .npz"):
        Motion.load(p)


BVH_TWO_FRAMES = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine1
  {
    OFFSET 0 20 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 10 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.033333
0 90 0 0 0 0 0 0 0
0 90 0 0 0 0 0 0 0
"""


@pytest.mark.parametrize("text, reason", [
    (BVH_TWO_FRAMES[:BVH_TWO_FRAMES.index("End Site")], r"the file ends inside its HIERARCHY, before MOTION"),
    (BVH_TWO_FRAMES.replace("ROOT Hips\n{", "ROOT Hips\n}"), r"'\}' outside any joint's braces in HIERARCHY"),
    (BVH_TWO_FRAMES.replace("Frame Time:", "Frametime:"), r"expected 'Frames: N' and 'Frame Time: S' after MOTION, "
                                                          r"found 'Frames: 2 Frametime: 0\.033333 0'"),
    (BVH_TWO_FRAMES.replace("0 20 0", "0 twenty 0"), r"a HIERARCHY value is not a number: .*'twenty'"),
    (BVH_TWO_FRAMES.replace("0 90 0 0 0 0 0 0 0\n0 90", "0 90 0 0 0 0 0 0 0\n0 ninety"),
     r"a MOTION value is not a number: .*'ninety'"),
])
def test_malformed_bvh_says_where(tmp_path, text, reason):
    """Each way a BVH can be malformed is named, after the file, in one line (not a bare IndexError)."""
    p = _write(tmp_path, text, "bad.bvh")
    with pytest.raises(MotionError, match=r"bad\.bvh: malformed or truncated BVH \(" + reason):
        bvh.load(p)
