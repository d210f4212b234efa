"""Mocap as found in the wild: BVH rigs, units and axes, ASF/AMC, and the motion-library import.

Every file here is written by the test itself (from the DeepMimic walk, exported with our BVH
writer and then renamed, re-axed and re-scaled), so the tests run without ../shared/mocap.
"""

import json
import re

import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401  (registers the ids)
from reference_motion import asf_amc, bvh
from reference_motion.bvh_export import write_bvh
from reference_motion.humanoid.model import load_model
from reference_motion.importer import import_library
from reference_motion.library import expand_clips, load_motion, load_source_clip
from reference_motion.motion import MotionError
from reference_motion.motion_library import labels, read_manifest, split_of
from reference_motion.retarget import bone_direction_error, model_joint_positions, retarget, stance_sole_pitch
from reference_motion.rigs import RIGS, MocapOptions, canonical_positions, match_rig, unit_scale, up_axis
from reference_motion.source import CANONICAL_JOINTS, clip_from_joint_positions


@pytest.fixture(scope="module")
def walk():
    return load_motion("deepmimic:walk")


@pytest.fixture(scope="module")
def exported(walk, tmp_path_factory):
    return write_bvh(walk, tmp_path_factory.mktemp("bvh") / "walk.bvh")


def _world_joints(motion):
    hm = load_model(motion.model)
    return model_joint_positions(hm, hm.forward_kinematics(motion.qpos))


MIXAMO = {"pelvis": "Hips", "chest": "Spine2", "neck": "Neck", "head": "Head", "head_end": "HeadTop_End",
          **{f"{s[0]}_{body}": f"{side}{name}" for s, side in (("left", "Left"), ("right", "Right"))
             for body, name in (("thigh", "UpLeg"), ("shin", "Leg"), ("foot", "Foot"), ("foot_end", "Toe_End"),
                                ("upper_arm", "Arm"), ("forearm", "ForeArm"), ("hand", "Hand"))}}
"""Our export's joints → Mixamo's names (unlisted joints keep ours, as extra links do in the wild)."""


def _rewrite(text: str, names: dict[str, str], scale: float = 1.0, z_up: bool = False, six: bool = False,
             prefix: str = "") -> str:
    """Our exported BVH as another rig would write it: joints renamed (with a namespace prefix),
    lengths scaled, a Z-up file (a wrapping root turned +90° about x), 6 channels on every joint."""
    head, motion = text.split("MOTION")
    out, extra = [], []
    for line in head.splitlines():
        tok = line.split()
        if tok[:1] in (["ROOT"], ["JOINT"]):
            line = line.replace(tok[1], prefix + names.get(tok[1], tok[1]))
        elif tok[:1] == ["OFFSET"]:
            line = line.replace(" ".join(tok[1:]), " ".join(f"{float(v) * scale:.6f}" for v in tok[1:]))
        elif tok[:1] == ["CHANNELS"] and six and tok[1] == "3":
            offset = [ln for ln in out if "OFFSET" in ln][-1].split()[1:]
            line = line.replace("CHANNELS 3", "CHANNELS 6 Xposition Yposition Zposition")
            extra.append(offset)
        out.append(line)
    lines = motion.strip().splitlines()
    frames = []
    for row in lines[2:]:
        values = row.split()
        pos = [f"{float(v) * scale:.6f}" for v in values[:3]]
        rest = values[3:]
        if six:  # insert each joint's (constant) offset before its three rotations
            joints = [rest[i:i + 3] for i in range(3, len(rest), 3)]
            rest = rest[:3] + [v for off, rot3 in zip(extra, joints) for v in off + rot3]
        frames.append(" ".join(pos + rest))
    if z_up:  # a wrapping root that turns the y-up rig into a z-up one
        out = ["HIERARCHY", "ROOT Armature", "{", "OFFSET 0 0 0", "CHANNELS 3 Xrotation Yrotation Zrotation"] + \
              [ln.replace("ROOT", "JOINT") for ln in out[1:]] + ["}"]
        frames = ["90 0 0 " + f for f in frames]
    return "\n".join(out) + "\nMOTION\n" + "\n".join(lines[:2]) + "\n" + "\n".join(frames) + "\n"


@pytest.mark.parametrize("scale,units,z_up,six,prefix", [
    (1.0, 0.01, False, False, ""),  # Mixamo names, centimetres, y up
    (0.01, 1.0, True, True, "mixamorig:"),  # metres, z up, 6 channels on every joint, namespaced
    (1 / 2.54, 0.0254, True, False, "mixamorig:"),  # inches
])
def test_bvh_rigs_units_and_axes_are_detected(exported, walk, tmp_path, scale, units, z_up, six, prefix):
    path = tmp_path / "take.bvh"
    path.write_text(_rewrite(exported.read_text(), MIXAMO, scale, z_up, six, prefix))
    clip = bvh.load(path)
    assert clip.source["rig"] == "cmu_mixamo" and clip.source["units_m"] == pytest.approx(units)
    assert clip.source["up"] == ("z" if z_up else "y") and not clip.source["mirrored"]
    motion = retarget(clip, walk.model)
    assert bone_direction_error(clip, motion).mean() < 2.0  # degrees
    ours, theirs = _world_joints(walk), _world_joints(motion)
    assert np.abs((theirs - theirs[:1, :1]) - (ours - ours[:1, :1])).max() < 0.03  # m: the same walk


def test_mirrored_file_is_detected_and_mirrored_back(exported):
    """A left-handed file (every y negated) bends its knees forwards; it is mirrored back."""
    pos, _ = bvh.load(exported).global_pose()
    left_handed = pos * np.array([1.0, -1.0, 1.0])
    match = match_rig(list(CANONICAL_JOINTS), left_handed, "test", {c: c for c in CANONICAL_JOINTS})
    world, axes = canonical_positions(left_handed, match, "test", units="m", up="z")
    assert axes["mirrored"] and np.allclose(world, pos)
    _, axes = canonical_positions(pos, match, "test", units="m", up="z")
    assert not axes["mirrored"]


def test_unknown_rig_needs_a_joint_map_and_works_with_one(exported, tmp_path):
    odd = {"pelvis": "Becken", "l_thigh": "OberschenkelL", "r_thigh": "OberschenkelR"}
    path = tmp_path / "odd.bvh"
    path.write_text(_rewrite(exported.read_text(), odd))
    with pytest.raises(ValueError, match=r"odd\.bvh: unknown rig \(closest: physmimic, \d+ of 18 joints\); still "
                                         r"needed: root \(e\.g\. pelvis\).*Joints in the file: Becken, "):
        bvh.load(path)
    joint_map = {"root": "Becken", "left_hip": "OberschenkelL", "right_hip": "OberschenkelR"}
    clip = bvh.load(path, MocapOptions(joint_map=joint_map))
    assert clip.source["rig"] == "physmimic + joint map" and clip.n_frames == 76
    map_file = tmp_path / "map.json"
    map_file.write_text(json.dumps(joint_map))
    from reference_motion.__main__ import main
    assert main(["info", str(path), "--joint-map", str(map_file), "--json"]) == 0


def test_truncated_motion_and_bad_channels_are_named(exported, tmp_path):
    text = exported.read_text()
    cut = tmp_path / "cut.bvh"
    cut.write_text(text[: len(text) * 2 // 3])
    with pytest.raises(MotionError, match=r"cut\.bvh: expected 76 frames × \d+ channels .*truncated file\?"):
        bvh.load(cut)
    binary = tmp_path / "binary.bvh"
    binary.write_bytes(b"\xff\xfe\x00 not text")
    with pytest.raises(MotionError, match=r"binary\.bvh: not a BVH file"):
        bvh.load(binary)


def test_bvh_forward_kinematics_follows_the_channel_order(tmp_path):
    """A two-joint chain whose child rotates X then Y (intrinsic): hand-computed end position."""
    text = """HIERARCHY
ROOT a
{
  OFFSET 0 0 0
  CHANNELS 3 Xposition Yposition Zposition
  JOINT b
  {
    OFFSET 0 1 0
    CHANNELS 2 Xrotation Yrotation
    End Site
    {
      OFFSET 0 0 1
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.5
0 0 0 90 0
1 0 0 0 90
"""
    path = tmp_path / "chain.bvh"
    path.write_text(text)
    joints, frames, _ = bvh._parse(text, str(path))
    pos = bvh.joint_positions(joints, frames, str(path))  # (T, [a, b, b_end], 3)
    # frame 0: b at (0, 1, 0) turned 90° about x, so its end site (0, 0, 1) lands at (0, 1, 0) + (0, −1, 0)
    assert np.allclose(pos[0], [[0, 0, 0], [0, 1, 0], [0, 0, 0]], atol=1e-12)
    # frame 1: the root moved to x = 1; b turned 90° about y takes (0, 0, 1) to (1, 0, 0)
    assert np.allclose(pos[1], [[1, 0, 0], [1, 1, 0], [2, 1, 0]], atol=1e-12)


ASF = """:version 1.10
:name test
:units
  mass 1.0
  length 0.45
  angle deg
:root
   order TX TY TZ RX RY RZ
   axis XYZ
   position 0 0 0
   orientation 0 0 0
:bonedata
{bones}:hierarchy
  begin
    root lhipjoint rhipjoint lowerback
    lhipjoint lfemur
    lfemur ltibia
    ltibia lfoot
    lfoot ltoes
    rhipjoint rfemur
    rfemur rtibia
    rtibia rfoot
    rfoot rtoes
    lowerback upperback
    upperback thorax
    thorax head lclavicle rclavicle
    lclavicle lhumerus
    lhumerus lradius
    rclavicle rhumerus
    rhumerus rradius
  end
"""

BONES = {  # name: (direction (y up), length in ASF units (length 0.45: a unit is 1/0.45 inch), dof)
    "lhipjoint": ((1, -0.5, 0), 2.0, ""), "rhipjoint": ((-1, -0.5, 0), 2.0, ""),
    "lfemur": ((0, -1, 0), 7.0, "rx ry rz"), "rfemur": ((0, -1, 0), 7.0, "rx ry rz"),
    "ltibia": ((0, -1, 0), 7.0, "rx"), "rtibia": ((0, -1, 0), 7.0, "rx"),
    "lfoot": ((0, -0.3, 1), 2.0, "rx rz"), "rfoot": ((0, -0.3, 1), 2.0, "rx rz"),
    "ltoes": ((0, 0, 1), 1.0, ""), "rtoes": ((0, 0, 1), 1.0, ""),
    "lowerback": ((0, 1, 0), 2.0, "rx ry rz"), "upperback": ((0, 1, 0), 2.0, "rx ry rz"),
    "thorax": ((0, 1, 0), 4.0, "rx ry rz"), "head": ((0, 1, 0), 4.0, "rx ry rz"),
    "lclavicle": ((1, 0.2, 0), 3.0, ""), "rclavicle": ((-1, 0.2, 0), 3.0, ""),
    "lhumerus": ((1, 0, 0), 5.0, "rx ry rz"), "rhumerus": ((-1, 0, 0), 5.0, "rx ry rz"),
    "lradius": ((1, 0, 0), 4.0, "rx"), "rradius": ((-1, 0, 0), 4.0, "rx"),
}


def _write_asf_amc(tmp_path, frames=4, truncate=False):
    bones = "".join(f"  begin\n     name {n}\n     direction {d[0]} {d[1]} {d[2]}\n     length {ln}\n"
                    f"     axis 0 0 0 XYZ\n" + (f"    dof {dof}\n" if dof else "") + "  end\n"
                    for n, (d, ln, dof) in BONES.items())
    (tmp_path / "07.asf").write_text(ASF.format(bones=bones))
    lines = [":FULLY-SPECIFIED", ":DEGREES"]
    for t in range(frames):
        lines.append(str(t + 1))
        lines.append(f"root {t * 0.45} 17 0 0 0 0")  # walks 1 inch per frame along +x
        for n, (_, _, dof) in BONES.items():
            if dof:
                values = ["30" if (n.endswith("tibia") and t == 1) else "0" for _ in dof.split()]
                lines.append(f"{n} {' '.join(values)}")
    text = "\n".join(lines) + "\n"
    if truncate:
        text = text[: len(text) - 40]
    (tmp_path / "07_01.amc").write_text(text)
    return tmp_path / "07_01.amc"


def test_asf_amc_loads_with_units_and_the_skeleton_found_beside_it(tmp_path):
    clip = asf_amc.load(_write_asf_amc(tmp_path))
    assert clip.source["rig"] == "cmu_asf" and clip.source["up"] == "y" and clip.fps == 120.0
    inch = 0.0254
    assert clip.leg_length() == pytest.approx(14 / 0.45 * inch, rel=1e-6)  # femur + tibia: 14 units of 1/0.45 in
    assert np.allclose(np.diff(clip.root_pos[:, :2], axis=0), [[inch, 0]] * 3, atol=1e-9)  # +x stays +x, 1 in/frame
    motion = retarget(clip)
    knee = load_model(motion.model).body_joints["l_shin"].qpos_index[0]
    assert np.degrees(motion.qpos[1, knee] - motion.qpos[0, knee]) == pytest.approx(30.0, abs=1.0)


def test_truncated_amc_and_missing_asf_are_named(tmp_path):
    amc = _write_asf_amc(tmp_path, truncate=True)
    with pytest.raises(MotionError, match=r"07_01\.amc: frame 4 has \d values for '\w+', expected \d"):
        asf_amc.load(amc)
    lonely = tmp_path / "sub" / "09_01.amc"
    lonely.parent.mkdir()
    lonely.write_text("1\nroot 0 0 0 0 0 0\n")
    with pytest.raises(FileNotFoundError, match=r"09_01\.amc: no skeleton found .*pass --asf"):
        asf_amc.load(lonely)


def test_malformed_amc_names_its_line_frame_and_bone(tmp_path):
    amc = _write_asf_amc(tmp_path)
    lines = amc.read_text().splitlines()
    n = lines.index("2") + 3  # frame 2's second bone line, 1-based
    bone = lines[n - 1].split()[0]
    lines[n - 1] = f"{bone} abc " + " ".join(lines[n - 1].split()[2:])
    amc.write_text("\n".join(lines) + "\n")
    with pytest.raises(MotionError, match=rf"07_01\.amc: malformed AMC \(line {n}, frame 2, bone '{bone}': "
                                          r"could not convert string to float: 'abc'\)"):
        asf_amc.load(amc)
    amc.write_text(":DEGREES\nroot 0 0 0 0 0 0\n1\n")
    with pytest.raises(MotionError, match=r"malformed AMC \(line 2, 'root 0 0 0 0 0 0', comes before the first frame"):
        asf_amc.load(amc)


def test_units_and_up_axis_rules():
    assert unit_scale(1.55, "x") == 1.0 and unit_scale(155.0, "x") == 0.01
    assert unit_scale(61.0, "x") == 0.0254 and unit_scale(1550.0, "x") == 0.001
    assert unit_scale(100.0, "x") == 0.01  # a 1 m child in centimetres is not read as inches
    with pytest.raises(ValueError, match="cannot tell the length unit"):
        unit_scale(10000.0, "x")
    assert up_axis(np.array([[0.1, 1.5, 0.0]]), "x") == "y" and up_axis(np.array([[0.0, 0.2, 1.5]]), "x") == "z"
    with pytest.raises(ValueError, match="the head is below the feet"):
        up_axis(np.array([[0.0, -1.5, 0.0]]), "x")


def test_clip_from_joint_positions_recovers_a_bent_knee():
    """A hand-built standing pose, left knee bent 40° forwards: the retargeted knee hinge is 40°."""
    p = {"root": (0, 0, 0.9), "chest": (0, 0, 1.2), "neck": (0, 0, 1.45), "head_end": (0, 0, 1.7),
         "left_shoulder": (0, 0.18, 1.4), "right_shoulder": (0, -0.18, 1.4),
         "left_elbow": (0, 0.2, 1.12), "right_elbow": (0, -0.2, 1.12),
         "left_wrist": (0.02, 0.2, 0.88), "right_wrist": (0.02, -0.2, 0.88),
         "right_hip": (0, -0.09, 0.88), "right_knee": (0, -0.09, 0.47), "right_ankle": (0, -0.09, 0.06),
         "right_toe_end": (0.18, -0.09, 0.0), "left_hip": (0, 0.09, 0.88)}
    bend = np.radians(40.0)
    p["left_knee"] = (0.41 * np.sin(bend / 2), 0.09, 0.88 - 0.41 * np.cos(bend / 2))
    p["left_ankle"] = (0.0, 0.09, 0.88 - 2 * 0.41 * np.cos(bend / 2))
    p["left_toe_end"] = (0.18, 0.09, p["left_ankle"][2] - 0.06)
    pos = np.array([[p[n] for n in CANONICAL_JOINTS]] * 3, dtype=float)
    clip = clip_from_joint_positions("pose", 30.0, pos)
    motion = retarget(clip)
    hm = load_model(motion.model)
    knees = [hm.body_joints[b].qpos_index[0] for b in ("l_shin", "r_shin")]
    assert np.degrees(np.abs(motion.qpos[0, knees])) == pytest.approx([40.0, 0.0], abs=0.5)
    with pytest.raises(ValueError, match=r"joints 'left_knee' and 'left_ankle' are at the same place"):
        bad = pos.copy()
        bad[:, CANONICAL_JOINTS.index("left_ankle")] = bad[:, CANONICAL_JOINTS.index("left_knee")]
        clip_from_joint_positions("pose", 30.0, bad)


def test_rig_name_tables_cover_every_canonical_joint():
    for rig, table in RIGS.items():
        assert set(table) == set(CANONICAL_JOINTS), rig


def test_labels_and_split():
    assert labels("dataset-1_walk-back_old_001") == ("walk-back", "old")
    assert labels("02_03") == ("run", "cmu") and labels("mytake") == ("unknown", "unknown")
    assert split_of("dataset-1_walk_old_001", "old") == "test" and split_of("02_03", "cmu") == "test"
    assert split_of("dataset-1_walk_happy_001", "happy") == "val" and split_of("02_01", "cmu") == "train"


def test_import_builds_a_library_that_envs_and_cli_read(exported, tmp_path):
    takes = tmp_path / "takes"
    takes.mkdir()
    for name in ("dataset-1_walk_normal_001", "dataset-1_walk_old_001", "dataset-1_walk_happy_001"):
        (takes / f"{name}.bvh").write_text(exported.read_text())
    text = exported.read_text()
    (takes / "dataset-1_run_normal_001.bvh").write_text(text[: len(text) // 2])  # truncated: refused
    lib = tmp_path / "lib"
    manifest = import_library([takes], lib, progress=False)
    assert [t["name"] for t in manifest["takes"]] == ["dataset-1_walk_happy_001", "dataset-1_walk_normal_001",
                                                       "dataset-1_walk_old_001"]
    assert [t["split"] for t in manifest["takes"]] == ["val", "train", "test"]
    (refused,) = manifest["refused"]
    assert refused["file"].endswith("dataset-1_run_normal_001.bvh") and "truncated" in refused["reason"]
    entry = manifest["takes"][1]
    assert entry["rig"] == "physmimic" and entry["models"]["humanoid_2seg"]["bone_error_deg_mean"] < 2.0
    assert entry["models"]["humanoid_1seg"]["quality_after"]["foot_skate_mps"] <= \
        entry["models"]["humanoid_1seg"]["quality_before"]["foot_skate_mps"] + 1e-9
    again = import_library([takes], lib, progress=False)  # resumable: nothing redone
    assert again["wall_s"] == pytest.approx(manifest["wall_s"])
    assert expand_clips([f"library:{lib}/test"]) == [f"library:{lib}#dataset-1_walk_old_001"]
    take = load_motion(f"library:{lib}#dataset-1_walk_old_001", "humanoid_2seg")
    assert take.model == "humanoid_2seg" and take.fps == 60.0
    env = gym.make("MimicIMU-v0", clips=f"library:{lib}/train")
    _, info = env.reset(seed=0)
    assert info["clip"] == "bvh:dataset-1_walk_normal_001"
    with pytest.raises(KeyError, match=re.escape(f"library:{lib}#nope: no take 'nope'")):
        load_motion(f"library:{lib}#nope")


def test_source_clip_of_every_format(exported, tmp_path):
    assert load_source_clip(exported).source["format"] == "bvh"
    assert load_source_clip(_write_asf_amc(tmp_path)).source["format"] == "asf/amc"
    with pytest.raises(ValueError, match=r"expected deepmimic:NAME, library:DIR#TAKE, or a \.npz"):
        load_source_clip(tmp_path / "take.fbx")


def test_our_own_bvh_export_reads_back_through_the_commands(exported, tmp_path, capsys):
    """`info`, `perception contacts` and `clean.py` take the BVH that `make demo` writes, with no option."""
    from agents.clean import main as clean_main
    from perception.__main__ import main as perception_main
    from reference_motion.__main__ import main as motion_main

    assert motion_main(["info", str(exported), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["frames"] == 76
    result = perception_main(["contacts", str(exported), "--json", str(tmp_path / "c.json")])
    assert np.array(result["contacts"]).shape == (76, 4)
    out = tmp_path / "clean.npz"
    clean_main([str(exported), "--policy", "models/mimic_walk", "--out", str(out), "--no-adapt"])
    assert load_motion(out).n_frames == 76


def _feet(pitch_deg: float, lift_m: float, speed_mps: float, frames: int, fps: float = 60.0) -> np.ndarray:
    """Sole points (frames, 4, 3) (LT, RT, LH, RH) of two 26-cm feet side by side, pitched by
    ``pitch_deg`` (toe up positive), the lower point ``lift_m`` up, moving forwards at ``speed_mps``."""
    t = np.arange(frames) / fps
    a = np.radians(pitch_deg)
    heel_z = lift_m + max(0.0, -0.26 * np.sin(a))
    points = np.zeros((frames, 4, 3))
    for foot, y in ((0, 0.1), (1, -0.1)):
        heel = np.stack([speed_mps * t, np.full(frames, y), np.full(frames, heel_z)], axis=1)
        points[:, 2 + foot] = heel
        points[:, foot] = heel + [0.26 * np.cos(a), 0.0, 0.26 * np.sin(a)]
    return points


def test_stance_sole_pitch_is_the_most_common_over_planted_slow_frames():
    flat = _feet(10.0, 0.0, 0.0, 30)
    forefoot = np.concatenate([_feet(-45.0 + k, 0.0, 0.0, 1) for k in range(35)])  # spread: no mode there
    swing = _feet(-30.0, 0.10, 2.0, 30)  # lifted and fast: not stance, whatever its pitch
    pitch = np.degrees(stance_sole_pitch(np.concatenate([flat, forefoot, swing]), 60.0))
    assert pitch == pytest.approx(10.0, abs=1.0)  # the median of these 65 stance frames is -13
    short = np.concatenate([_feet(10.0, 0.0, 0.0, 5), _feet(-30.0, 0.10, 2.0, 55)])
    assert np.isnan(stance_sole_pitch(short, 60.0))  # 2 × 5 frames < 0.3 s of stance: unknown


def test_feet_levelled_for_a_rig_whose_foot_bone_ends_elsewhere(exported, tmp_path):
    """Our export with its foot bones ending level with the ankles (as Bandai Namco's and CMU's rigs
    differ from ours): retargeted as is, the soles would point 18.9 degrees up in stance."""
    text, n = re.subn(r"(JOINT [lr]_foot\s*\{[^}]*?End Site\s*\{\s*OFFSET )20\.500000 -7\.000000",
                      r"\g<1>21.662179 0.000000", exported.read_text())
    assert n == 2
    path = tmp_path / "level_foot_bones.bvh"
    path.write_text(text)
    motion = load_motion(path)
    assert motion.source["foot_level_deg"] == pytest.approx(-18.9, abs=1.5)
    kin = load_model(motion.model).forward_kinematics(motion.qpos)
    assert abs(np.degrees(stance_sole_pitch(kin.foot_points, motion.fps))) < 1.5
    assert np.percentile(kin.foot_points[:, 2:, 2], 10) < 0.01  # the heels touch down
    assert load_motion("deepmimic:walk").source["foot_level_deg"] == 0.0  # our own rig: left alone


def test_a_library_from_before_feet_were_levelled_asks_to_be_imported_again(tmp_path):
    (tmp_path / "manifest.json").write_text(json.dumps({"format": "physmimic.library/1", "takes": []}))
    with pytest.raises(ValueError, match="older import.*import again"):
        read_manifest(tmp_path)
