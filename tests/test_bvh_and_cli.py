import json
import subprocess
import sys

import numpy as np
import pytest

from reference_motion import deepmimic
from reference_motion import rotations as rot
from reference_motion.bvh import load as load_bvh
from reference_motion.bvh_export import write_bvh
from reference_motion.rigs import RIGS
from reference_motion.humanoid.model import load_model
from reference_motion.library import load_motion
from reference_motion.retarget import model_joint_positions, retarget
from reference_motion.source import CANONICAL_JOINTS, CANONICAL_PARENTS

Z_UP_TO_Y_UP = np.array([[1.0, 0, 0], [0, 0, 1.0], [0, -1.0, 0]])
CMU_NAME_MAP = {canon: names[0] for canon, names in RIGS["cmu_mixamo"].items()}


def _to_bvh(clip, scale_to_cm=100.0):
    """Write a SourceClip as a CMU-named BVH (y up, centimetres, ZXY Euler degrees)."""
    children = {j: [c for c, p in CANONICAL_PARENTS.items() if p == j] for j in CANONICAL_JOINTS}
    idx = CANONICAL_JOINTS.index
    order = []
    lines = ["HIERARCHY"]

    def emit(joint, depth):
        pad = "  " * depth
        off = Z_UP_TO_Y_UP @ clip.offsets[idx(joint)] * scale_to_cm
        if joint.endswith(("_end", "_wrist")):
            lines.extend([f"{pad}JOINT {CMU_NAME_MAP[joint]}", f"{pad}{{", f"{pad}  OFFSET {off[0]} {off[1]} {off[2]}",
                      f"{pad}  CHANNELS 3 Zrotation Xrotation Yrotation", f"{pad}  End Site", f"{pad}  {{",
                          f"{pad}    OFFSET 0 -5 0", f"{pad}  }}", f"{pad}}}"])
            order.append(joint)
            return
        head = "ROOT" if joint == "root" else "JOINT"
        chans = "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation" if joint == "root" \
            else "CHANNELS 3 Zrotation Xrotation Yrotation"
        lines.extend([f"{pad}{head} {CMU_NAME_MAP[joint]}", f"{pad}{{", f"{pad}  OFFSET {off[0]} {off[1]} {off[2]}",
                      f"{pad}  {chans}"])
        order.append(joint)
        for c in children[joint]:
            emit(c, depth + 1)
        lines.append(f"{pad}}}")

    emit("root", 0)
    rows = []
    for t in range(clip.n_frames):
        row = list(Z_UP_TO_Y_UP @ clip.root_pos[t] * scale_to_cm)
        for joint in order:
            q = clip.local_quats[t, idx(joint)]
            q_y = np.concatenate([q[:1], Z_UP_TO_Y_UP @ q[1:]])
            row += list(np.degrees(rot.to_hinges(q_y, "zxy")))
        rows.append(" ".join(f"{v:.6f}" for v in row))
    lines += ["MOTION", f"Frames: {clip.n_frames}", f"Frame Time: {1.0 / clip.fps:.8f}"] + rows
    return "\n".join(lines) + "\n"


def test_bvh_round_trip_reproduces_direct_retarget(tmp_path):
    """A CMU-named BVH of a DeepMimic clip retargets to the same motion as the clip itself: the
    same joint positions (what the rig-independent loader keeps) and the same knee angles."""
    clip = deepmimic.load("walk")
    path = tmp_path / "walk.bvh"
    path.write_text(_to_bvh(clip))
    loaded = load_bvh(path)
    assert loaded.source["rig"] == "cmu_mixamo" and loaded.source["units_m"] == 0.01 and loaded.source["up"] == "y"
    via_bvh, direct = retarget(loaded), retarget(clip)
    assert via_bvh.fps == direct.fps and via_bvh.n_frames == direct.n_frames
    hm = load_model(direct.model)
    joints = [model_joint_positions(hm, hm.forward_kinematics(m.qpos)) for m in (via_bvh, direct)]
    assert np.abs(joints[0] - joints[1]).max() < 0.02  # m
    knees = [hm.body_joints[b].qpos_index[0] for b in ("l_shin", "r_shin")]
    assert np.degrees(np.abs(via_bvh.qpos[:, knees] - direct.qpos[:, knees])).max() < 2.0


def _cli(*args):
    out = subprocess.run([sys.executable, "-m", "reference_motion", *args], capture_output=True, text=True, timeout=300)
    return out.returncode, out.stdout, out.stderr


def test_cli_quality_json_keys_and_corruption():
    rc, out, _ = _cli("quality", "deepmimic:walk", "--json")
    clean = json.loads(out)
    for key in ("frames", "fps", "foot_skate_mps", "penetration_max_m", "penetration_mean_m", "floating_m", "jitter",
                "self_penetration_frac"):
        assert key in clean
    assert rc == 0 and clean["fps"] == 60.0 and clean["frames"] == 76
    rc, out, _ = _cli("quality", "deepmimic:walk", "--model", "humanoid_2seg", "--corrupt", "imu", "--strength", "1",
                      "--seed", "3", "--json")
    bad = json.loads(out)
    assert bad["jitter"] > 1.1 * clean["jitter"] and bad["foot_skate_mps"] > 2 * clean["foot_skate_mps"]
    assert bad["seed"] == 3


def test_cli_info_and_clear_errors(tmp_path):
    rc, out, _ = _cli("info", "deepmimic:walker/turn_left0", "--json")
    assert rc == 0 and json.loads(out)["loop"] is True
    rc, _, err = _cli("info", "deepmimic:wlak")
    assert rc == 1 and "unknown DeepMimic clip 'wlak'" in err and "Traceback" not in err
    rc, _, err = _cli("quality", str(tmp_path / "missing.bvh"))
    assert rc == 1 and "missing.bvh: no such BVH file" in err


def test_cli_render_png(tmp_path):
    out = tmp_path / "walk.png"
    rc, _, err = _cli("render", "deepmimic:walk", "--out", str(out))
    assert rc == 0, err
    import imageio.v2 as imageio

    img = imageio.imread(out)
    assert img.shape == (360, 480, 3) and img.std() > 10


@pytest.mark.parametrize("model", ["humanoid_1seg", "humanoid_2seg"])
def test_written_bvh_reads_back_with_the_same_pose(tmp_path, model):
    motion = load_motion("deepmimic:walker/turn_left0", model)
    clip = load_bvh(write_bvh(motion, tmp_path / "walk.bvh"))  # no options: the rig is detected
    assert clip.source["rig"] == "physmimic" and not clip.source["mirrored"]
    assert clip.n_frames == motion.n_frames and clip.fps == pytest.approx(motion.fps, rel=1e-6)
    hm = load_model(model)
    pos, _ = clip.global_pose()
    # within 5 mm: the pelvis frame is built from hips and chest, which the spine hinges move apart
    assert np.abs(pos - model_joint_positions(hm, hm.forward_kinematics(motion.qpos))).max() < 0.005  # m
