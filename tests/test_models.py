import mujoco
import numpy as np
import pytest

from reference_motion.humanoid import builder
from reference_motion.humanoid.model import CONTACT_CHANNELS, HumanoidModel


def test_committed_models_match_generator():
    for name in builder.MODEL_NAMES:
        assert (builder.ASSET_DIR / f"{name}.xml").read_text() == builder.build(name), (
            f"{name}.xml is stale: run python -m reference_motion.humanoid.builder")


@pytest.mark.parametrize("name,bodies,actuated", [("humanoid_1seg", 20, 43), ("humanoid_2seg", 22, 45)])
def test_counts_mass_height(name, bodies, actuated):
    hm = HumanoidModel(name)
    assert len(hm.body_names) == bodies
    assert hm.model.nu == actuated == len(hm.hinge_names)
    assert hm.nq == 7 + actuated
    assert 65.0 <= hm.total_mass <= 75.0
    d = mujoco.MjData(hm.model)
    mujoco.mj_forward(hm.model, d)
    head = hm.model.geom("head_geom").id
    height = d.geom_xpos[head][2] + hm.model.geom_size[head][0]
    assert 1.65 <= height <= 1.85
    three = [b for b, j in hm.body_joints.items() if len(j.axes) == 3]
    one = [b for b, j in hm.body_joints.items() if len(j.axes) == 1]
    assert len(three) == 13 and len(one) == (4 if name == "humanoid_1seg" else 6)
    # ADAPT topology: the wrists are not actuated
    assert "l_hand" not in hm.body_joints and "r_hand" not in hm.body_joints


def test_two_segment_toe_joint_at_80_percent():
    hm = HumanoidModel("humanoid_2seg")
    m = hm.model
    toe = m.body("l_toe").pos[0]
    heel_end = builder.A.FOOT_HEEL_X
    assert np.isclose((toe - heel_end) / builder.A.FOOT_LENGTH, 0.8)




@pytest.mark.parametrize("name", ["humanoid_1seg", "humanoid_2seg"])
def test_insole_cells_read_vertical_force(name):
    hm = HumanoidModel(name)
    m, d = hm.model, mujoco.MjData(hm.model)
    d.qpos[2] -= 0.005  # soles 5 mm into the floor: every cell sphere is in contact
    mujoco.mj_forward(m, d)
    assert d.ncon == 32, "one contact per insole cell sphere, 16 per sole"
    for c in d.contact[: d.ncon]:
        sole = c.geom2 if m.geom(c.geom1).name == "floor" else c.geom1
        assert hm.cell_of_point(d, sole, c.pos) == int(m.geom(sole).name[-2:])
    cells = hm.cell_forces(d)
    assert cells.shape == (2, 16) and cells.sum() > 0
    assert np.allclose(cells[0], cells[1], rtol=1e-6, atol=1e-9), "left and right feet symmetric"
    assert CONTACT_CHANNELS == ("left_toe", "right_toe", "left_heel", "right_heel")


def test_insole_total_is_body_weight_in_quiet_stance():
    hm = HumanoidModel("humanoid_1seg")
    m, d = hm.model, mujoco.MjData(hm.model)
    for _ in range(int(1.0 / m.opt.timestep)):
        d.ctrl[:] = 0.0
        mujoco.mj_step(m, d)
    total = hm.cell_forces(d).sum()
    assert 0.9 <= total <= 1.1, f"feet carry {total:.3f} body weights standing still"


def test_collision_filter_leg_leg_and_arm_torso_only():
    hm = HumanoidModel("humanoid_1seg")
    m = hm.model

    def collide(a, b):
        ga, gb = m.geom(a).id, m.geom(b).id
        return bool((m.geom_contype[ga] & m.geom_conaffinity[gb]) or (m.geom_contype[gb] & m.geom_conaffinity[ga]))

    assert collide("l_thigh_geom", "r_shin_geom")
    assert collide("l_foot_geom", "r_foot_geom")
    assert collide("l_forearm_geom", "pelvis_geom")
    assert not collide("l_forearm_geom", "r_forearm_geom")
    assert not collide("l_hand_geom", "l_thigh_geom")
    assert not collide("l_foot_geom", "floor") and collide("l_sole00", "floor")
    assert collide("head_geom", "floor") and collide("pelvis_geom", "floor")
