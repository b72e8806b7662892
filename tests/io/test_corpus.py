"""Loci of real URDF chains, graded against Pinocchio: a subset of the corpus benchmark.

``benchmarks/corpus.py`` takes every serial chain with 2 to 9 movable joints in the URDF files
of example-robot-data and grades rankloci's locus of it against Pinocchio's frame Jacobian of
the tip link (LOCAL_WORLD_ALIGNED, from a copy of the URDF with the angles snapped as rankloci
snaps them):

- mapping: at random configurations rankloci's J (base frame, tip point) and Pinocchio's J
  have the same entries and rank;
- sound: at each component's sample point and points solved onto it, Pinocchio's J is singular;
- complete: every singular minimum of Pinocchio's sigma_min/sigma_max from random starts (fixed
  seed) lies on a component.

These tests run the same grading, with the same functions, on chains that finish in seconds:
one chain per robot, the longest one where it is fast and a shorter one otherwise; the others
and the chains rankloci does not finish or get right yet are in ``benchmarks/corpus.md``.  The
last tests check that the grading rejects a locus with a component removed, with a spurious
component, and a reference with its joints out of order.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from rankloci.tolerances import URDF_ROTATION_ATOL

pytest.importorskip("pinocchio", reason="Pinocchio (PyPI package 'pin', in the test extra) is "
                    "not installed: the corpus is graded against its Jacobian")

REPO = Path(__file__).resolve().parents[2]
SEED = 0
#: The slowest cases here (PR2's and panda's fingers, tiago_dual's arm) take 40-50 s alone; a
#: locus still running after this is a regression.
TIME_LIMIT_S = 120.0


def _load_corpus():
    """benchmarks/corpus.py as a module (benchmarks/ is no package)."""
    name = "benchmarks_corpus"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, REPO / "benchmarks" / "corpus.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module  # dataclasses look their module up while it executes
        spec.loader.exec_module(module)
    return sys.modules[name]


corpus = _load_corpus()


@pytest.fixture(scope="module")
def robots() -> Path:
    d = corpus.robots_dir()
    if d is None:
        pytest.fail("example-robot-data is not installed; it is a declared test dependency "
                    "(its URDFs are the test data)")
    return d


@pytest.fixture(scope="module")
def chains(robots):
    """Every chain of the corpus by (file, tip)."""
    found, _, _ = corpus.corpus(robots)
    return {(c.file, c.tip): c for c in found}


def slow(*values):
    return pytest.param(*values, marks=pytest.mark.slow)


# (file relative to example-robot-data's robots/, tip link): one or two chains per robot, its
# longest where that takes at most a few seconds here (locus and grading), else shorter ones.
# Cases above 3 s are marked slow.  Chains of up to 3 joints are graded on the position of the
# tip, which lies on the last joint's axis: their loci are degenerate (rank deficient
# everywhere), and these cases check that rankloci says so.
CASES = [
    ("a1_description/urdf/a1.urdf", "FL_calf"),
    ("alex_description/urdf/alex_nub_hands.urdf", "Head"),  # 8-joint arms: in the benchmark
    ("alex_description/urdf/alex_nub_hands.urdf", "LeftShoulderPitchLink"),
    ("alexander_description/urdf/alexander_v1.lowerBodyOnly.urdf", "LEFT_FOOT"),
    ("allegro_hand_description/urdf/allegro_left_hand.urdf", "link_15.0"),
    ("anymal_b_simple_description/robots/anymal-kinova.urdf", "j2s6s200_link_6"),
    ("anymal_c_simple_description/urdf/anymal.urdf", "LF_SHANK"),
    ("asr_twodof_description/urdf/TwoDofs.urdf", "Link2"),
    ("b1_description/urdf/b1.urdf", "FL_calf"),  # b1-z1's arm is the z1 below
    ("baxter_description/urdf/baxter.urdf", "left_upper_forearm"),
    ("baxter_description/urdf/baxter.urdf", "left_lower_elbow"),  # no singularity at all
    # the right finger moves by the left finger's variable, off the chain
    slow("baxter_description/urdf/baxter.urdf", "l_gripper_r_finger"),
    ("bolt_description/robots/bolt.urdf", "FL_LOWER_LEG"),
    ("borinot_description/urdf/borinot_flying_arm_2.urdf", "flying_arm_2__link2"),
    ("centauro_description/urdf/centauro.urdf", "wheel_1"),  # 7-joint arms: in the benchmark
    ("centauro_description/urdf/centauro.urdf", "ankle2_1"),
    ("double_pendulum_description/urdf/double_pendulum_continuous.urdf", "link2"),
    ("finger_edu_description/robots/finger_edu.urdf", "finger_lower_link"),
    slow("g1_description/urdf/g1_29dof_rev_1_0.urdf", "left_ankle_roll_link"),
    ("go1_description/urdf/go1.urdf", "FL_calf"),
    ("go2_description/urdf/go2.urdf", "FL_calf"),
    ("hextilt_description/urdf/hextilt_flying_arm_5.urdf", "flying_arm_5__link_5"),
    ("human_description/robots/human.urdf", "left_foot"),
    ("hyq_description/robots/hyq_no_sensors.urdf", "lf_lowerleg"),
    ("icub_description/robots/icub.urdf", "l_ankle_2"),  # 8-joint arms: in the benchmark
    ("icub_description/robots/icub.urdf", "head"),
    ("kinova_description/robots/kinova.urdf", "j2s6s200_link_6"),
    ("laikago_description/urdf/laikago.urdf", "FL_calf"),
    slow("panda_description/urdf/panda.urdf", "panda_link7"),
    # 8 joints, the last a prismatic finger: a branch's pair condition of 90 terms stays implicit
    # (rankloci.tree.branch.PAIR_MAX_TERMS); substituted, it made a 443072-term minor
    slow("panda_description/urdf/panda.urdf", "panda_leftfinger"),
    ("pr2_description/urdf/pr2.urdf", "l_forearm_roll_link"),  # prismatic torso + 5R
    # 9 joints with a mimic finger; leaves whose equations also hold on regular pieces
    # (cos q4 = cos q6 = 0, sin q4 = sin q6 = 0) must be split, not reported
    slow("pr2_description/urdf/pr2.urdf", "r_gripper_r_parallel_link"),
    ("quadruped_description/urdf/quadruped.urdf", "BL_shank"),
    ("romeo_description/urdf/romeo.urdf", "l_ankle"),
    ("romeo_description/urdf/romeo_laas_small.urdf", "HeadRoll_link"),
    ("simple_humanoid_description/urdf/simple_humanoid.urdf", "l_ankle"),
    ("so_arm_description/urdf/so101.urdf", "gripper_link"),
    slow("so_arm_description/urdf/so100.urdf", "jaw"),
    ("solo_description/robots/solo12.urdf", "FL_LOWER_LEG"),
    ("talos_data/robots/talos_left_arm.urdf", "arm_left_7_link"),
    # torso and arm, 9 joints: most of its branches are below the determinantal dimension
    # bound and pruned (rankloci.tree.prune.below_bound)
    slow("talos_data/robots/talos_reduced.urdf", "arm_left_7_link"),
    slow("talos_data/robots/talos_left_arm.urdf", "gripper_left_motor_double_link"),
    ("talos_data/robots/talos_reduced.urdf", "head_2_link"),
    ("tiago_description/robots/tiago.urdf", "head_2_link"),
    # a component through a multiple root of its equations (q4 = pi/2, q5 = pi, q6 = 0), where
    # points solved in double precision stay up to 0.05 rad off it: graded after refinement
    slow("tiago_description/robots/tiago_dual.urdf", "arm_left_7_link"),
    ("tiago_pro_description/robots/tiago_pro.urdf", "head_2_link"),
    ("ur_description/urdf/ur5_robot.urdf", "wrist_3_link"),
    slow("z1_description/urdf/z1.urdf", "gripperMover"),
]


@pytest.mark.parametrize("file, tip", CASES)
def test_locus_of_urdf_chain_agrees_with_pinocchio(robots, chains, file, tip):
    chain = chains[(file, tip)]
    res = corpus.run_case(chain, robots, time_limit=TIME_LIMIT_S, seed=SEED)
    assert res["status"] == "pass", f"{file}: {chain.label}: {res['status']}: {res['reason']}"
    grading = res["grading"]
    assert grading["mapping"]["max_relative_deviation"] <= corpus.MAPPING_RTOL
    assert all(c["points"] >= 1 for c in grading["sound"])
    if res["components"]:
        assert grading["completeness"]["singular"] >= 1, "no singular point probed: a weak test"


def test_chain_with_coefficients_past_a_float_is_computed_and_sound(robots, chains):
    """romeo_laas_small's elbow: its axes do not snap, and the equations of its locus carry
    integer coefficients of 300 digits and more; the locus is computed and graded, every
    component is singular for Pinocchio, and every singular point probed lies on one (the
    3-dimensional component whose exclusion is 1e-6 of its term size included)."""
    chain = chains[("romeo_description/urdf/romeo_laas_small.urdf", "LElbowYaw_link")]
    res = corpus.run_case(chain, robots, time_limit=TIME_LIMIT_S, seed=SEED)
    assert res["status"] == "pass", f"{res['status']}: {res['reason']}"
    grading = res["grading"]
    assert grading["mapping"]["ok"], res["reason"]
    assert res["components"] and all(c["points"] >= 1 and c["regular_points"] == 0
                                     for c in grading["sound"]), res["reason"]


@pytest.mark.slow
def test_regular_pieces_inside_an_excluded_set_are_kept_out(robots, chains):
    """romeo_laas_small's left wrist (8 joints, axes that do not snap): equations of two leaves
    also hold on regular pieces inside the zero set of an exclusion, pieces the sampler's solves
    (residuals scaled by term sizes) never reach.  The solves scaled by coefficients find them,
    the exclusions stay in the components, and the first computation passes grading."""
    chain = chains[("romeo_description/urdf/romeo_laas_small.urdf", "l_wrist")]
    res = corpus.run_case(chain, robots, time_limit=TIME_LIMIT_S, seed=SEED)
    assert res["status"] == "pass", f"{res['status']}: {res['reason']}"
    assert all(c["points"] >= 1 and c["regular_points"] == 0 for c in res["grading"]["sound"])


@pytest.mark.slow
def test_self_check_repairs_a_locus_with_regular_pieces(robots, chains, monkeypatch):
    """The same wrist without the solves scaled by coefficients (as the engine was before
    them): the first computation reports components whose equations also hold on regular
    pieces, and fails grading.  The locus `rankloci locus` shows, after its self-check fed the
    configurations where it found them regular back to the tree, is complete and passes the
    same grading: the self-check catches what the engine's own search misses."""
    from rankloci.tree.sampler import BranchSampler

    monkeypatch.setattr(BranchSampler, "coefficient_scaled_points", lambda self, branch: [])
    chain = chains[("romeo_description/urdf/romeo_laas_small.urdf", "l_wrist")]
    first = corpus.run_case(chain, robots, time_limit=TIME_LIMIT_S, seed=SEED)
    assert first["status"] == "fail" and "unsound" in first["reason"], first["reason"]
    got = first["self_check"]     # corpus.self_checked: the locus `rankloci locus` shows
    # an 8-joint chain: codimensions 3 and more are beyond the certificate's elimination, so
    # the locus is not certified (null), but nothing disproves it and the numeric check passes
    assert got["complete"] is None, got["attempts"]
    assert got["attempts"][-1].endswith("certificate undecided, numeric check passed")
    assert got["status"] == "pass", got["reason"]
    assert got["components"] >= 1
    assert any("configuration" in a for a in got["attempts"]), got["attempts"]


# --- the corpus itself ----------------------------------------------------------------------

def test_corpus_chains_of_known_files(robots, chains):
    ur5 = [c for c in chains.values() if c.file == "ur_description/urdf/ur5_robot.urdf"]
    assert [(c.base, c.tip, c.n, c.task) for c in ur5] == [("world", "wrist_3_link", 6, "full")]
    assert ur5[0].joints == ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                             "wrist_1_joint", "wrist_2_joint", "wrist_3_joint")
    # paths past the last movable joint (ee_link, tool0, ...) are the same chain
    assert set(ur5[0].also) >= {"ee_link", "tool0"}
    a1 = sorted((c.tip, c.n, c.task) for c in chains.values() if c.robot == "a1")
    assert a1 == [(f"{leg}_calf", 3, "position") for leg in ("FL", "FR", "RL", "RR")]
    assert all(2 <= c.n <= 9 for c in chains.values())


def test_corpus_records_why_files_are_skipped(robots):
    _, skipped, _ = corpus.corpus(robots)
    reasons = {s["file"]: s["reason"] for s in skipped}
    assert "xacro" in reasons["hector_description/robots/quadrotor_base.urdf.xacro"]
    assert "no <link>" in reasons["ur_description/urdf/ur3.urdf"]
    assert "no chain" in reasons["iris_description/robots/iris_simple.urdf"]


def test_snapped_urdf_writes_the_angles_rankloci_reads():
    text = """<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
      <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
        <origin xyz="0.1 0 0" rpy="1.5708 0.3 -3.14159"/><axis xyz="0 0.7071 0.7071"/></joint>
      <joint name="f" type="fixed"><parent link="b"/><child link="c"/><axis xyz="0 0 0"/></joint>
    </robot>"""
    out = corpus.snapped_urdf(text)
    import defusedxml.ElementTree as SafeET

    j1 = SafeET.fromstring(out).find("joint")
    rpy = [float(x) for x in j1.find("origin").get("rpy").split()]
    assert [rpy[0], rpy[2]] == [np.pi / 2, -np.pi]
    # 0.3 is no multiple of pi/12: a short rational rotation within URDF_ROTATION_ATOL of it
    assert 0 < abs(rpy[1] - 0.3) <= URDF_ROTATION_ATOL
    assert [float(x) for x in j1.find("origin").get("xyz").split()] == [0.1, 0, 0]
    axis = [float(x) for x in j1.find("axis").get("xyz").split()]
    assert axis == [0.0, np.sqrt(2) / 2, np.sqrt(2) / 2]


def test_reference_jacobian_follows_mimic_joints():
    # j2 mimics j1 twice over: link l2 turns by 3q about z, its origin moves on the unit circle
    text = """<robot name="r"><link name="b"/><link name="l1"/><link name="l2"/>
      <joint name="j1" type="continuous"><parent link="b"/><child link="l1"/>
        <axis xyz="0 0 1"/></joint>
      <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
        <origin xyz="1 0 0"/><axis xyz="0 0 1"/><mimic joint="j1" multiplier="2"/>
        <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
    </robot>"""
    ref = corpus.PinocchioJacobian(text, ("j1", "j2"), "l2", "full")
    assert ref.kinds == ("revolute",)
    q = 0.7
    expected = np.array([[-np.sin(q)], [np.cos(q)], [0], [0], [0], [3]])
    np.testing.assert_allclose(ref([q]), expected, atol=1e-14)


def test_reference_jacobian_of_a_leader_off_the_chain_is_pinocchios_mimic_column(robots, chains):
    """Baxter's right finger follows the left one (multiplier -1), which is on another branch:
    the chain's last variable is the left finger's position, and the reference's column for it
    is the one Pinocchio's own mimic joints give."""
    import pinocchio as pin

    file, tip = "baxter_description/urdf/baxter.urdf", "l_gripper_r_finger"
    chain = chains[(file, tip)]
    text = (robots / file).read_text(encoding="utf-8")
    ref = corpus.PinocchioJacobian(text, chain.joints, tip, chain.task)
    assert ref.kinds == ("revolute",) * 7 + ("prismatic",)
    model = pin.buildModelFromXML(corpus.snapped_urdf(text), mimic=True)
    data = model.createData()
    frame = model.getFrameId(tip, pin.FrameType.BODY)
    leaders = [model.joints[model.getJointId(name)]
               for name in chain.joints[:-1] + ("l_gripper_l_finger_joint",)]
    assert all(jm.nq == 1 for jm in leaders)
    for q in corpus.random_configurations(ref.kinds, np.random.default_rng(SEED), 3):
        x = pin.neutral(model)
        for jm, v in zip(leaders, q):
            x[jm.idx_q] = v
        pin.computeJointJacobians(model, data, x)
        pin.updateFramePlacement(model, data, frame)
        J = pin.getFrameJacobian(model, data, frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        np.testing.assert_allclose(ref(q), J[:, [jm.idx_v for jm in leaders]], rtol=0,
                                   atol=1e-12)


# --- the grading has teeth ------------------------------------------------------------------

@pytest.fixture(scope="module")
def ur5_case(robots, chains):
    from rankloci.io import load_model
    from rankloci.jacobians import task_matrix
    from rankloci.methods import compute_locus, method_for

    chain = chains[("ur_description/urdf/ur5_robot.urdf", "wrist_3_link")]
    path = robots / chain.file
    model = load_model(str(path), base_link=chain.base, tip=chain.tip)
    tm = task_matrix(model, task=chain.task, frame="auto", numeric=True)
    locus = compute_locus(tm, method_for(tm.shape), rng=np.random.default_rng(SEED))
    ref = corpus.PinocchioJacobian(path.read_text(encoding="utf-8"), chain.joints, chain.tip,
                                   chain.task)
    return chain, path, model, tm, locus, ref


def test_grading_passes_the_ur5_locus(ur5_case):
    _, _, model, tm, locus, ref = ur5_case
    g = corpus.grade(model, tm, locus, ref, np.random.default_rng(SEED))
    assert g["ok"], g["reason"]
    assert len(g["sound"]) == 3


@pytest.mark.parametrize("dropped", [0, 1, 2])
def test_grading_rejects_a_locus_without_one_component(ur5_case, dropped):
    _, _, model, tm, locus, ref = ur5_case
    rest = tuple(c for k, c in enumerate(locus.components) if k != dropped)
    g = corpus.grade(model, tm, dataclasses.replace(locus, components=rest), ref,
                     np.random.default_rng(SEED))
    assert not g["ok"] and g["reason"].startswith("incomplete:"), g["reason"]


def test_grading_rejects_a_spurious_component(ur5_case):
    from rankloci.loci import Component

    _, _, model, tm, locus, ref = ur5_case
    q1 = tm.variables[0]
    spurious = Component(equations=(sp.sin(q1),), free=tm.variables[1:], dimension=5)
    g = corpus.grade(model, tm, dataclasses.replace(locus, components=locus.components +
                                                    (spurious,)), ref, np.random.default_rng(SEED))
    assert not g["ok"] and "unsound: component 4 (sin(q1))" in g["reason"], g["reason"]


def test_grading_rejects_a_reference_with_joints_out_of_order(ur5_case):
    chain, path, model, tm, locus, _ = ur5_case
    swapped = (chain.joints[1], chain.joints[0]) + chain.joints[2:]
    ref = corpus.PinocchioJacobian(path.read_text(encoding="utf-8"), swapped, chain.tip,
                                   chain.task)
    g = corpus.grade(model, tm, locus, ref, np.random.default_rng(SEED))
    assert not g["ok"] and g["reason"].startswith("mapping:"), g["reason"]


class _Diagonal:
    """A 2x2 "Jacobian" diag(1, f(x)) with the derivative the probe's Newton steps use."""

    def __init__(self, f, df):
        self.f, self.df = f, df

    def __call__(self, q):
        return np.diag([1.0, self.f(q[0])])

    def derivatives(self, q):
        return np.array([np.diag([0.0, self.df(q[0])]), np.zeros((2, 2))])


def test_probe_minimum_tells_singular_from_nearly_singular_points():
    """x**2 + 1e-9 has a positive minimum below PROBE_SINGULAR_RTOL: nearly singular (as on
    romeo_laas_small's gripper chain); x - 0.3 vanishes: a singular point; with 1.5 + sin(x)/2
    the ratio is at least 1/2: regular."""
    nearly = _Diagonal(lambda x: x * x + 1e-9, lambda x: 2 * x)
    q, r, found = corpus.probe_minimum(nearly, np.array([0.7, 0.1]))
    assert found is False and 1e-9 <= r <= corpus.PROBE_SINGULAR_RTOL
    q, r, found = corpus.probe_minimum(_Diagonal(lambda x: x - 0.3, lambda x: 1.0),
                                       np.array([0.7, 0.1]))
    assert found is True and r <= corpus.PROBE_DESCENT_RTOL and abs(q[0] - 0.3) < 1e-12
    q, r, found = corpus.probe_minimum(_Diagonal(lambda x: 1.5 + np.sin(x) / 2,
                                                 lambda x: np.cos(x) / 2), np.array([0.7, 0.1]))
    assert found is None and r > corpus.PROBE_SINGULAR_RTOL


@pytest.mark.parametrize("file, tip", [("ur_description/urdf/ur5_robot.urdf", "wrist_3_link"),
                                       ("a1_description/urdf/a1.urdf", "FL_calf")])
def test_mapping_to_the_base_frame_equals_the_base_frame_jacobian(robots, chains, file, tip):
    """The grading maps the matrix of the locus (UR5: the middle link's frame about its origin;
    a1's leg: position rows in the middle frame) to the base frame about the tool numerically;
    it equals rankloci's symbolic Jacobian in the base frame about the tool."""
    from rankloci.io import load_model
    from rankloci.jacobians import task_matrix
    from rankloci.numeric.equations import NumericMatrix

    chain = chains[(file, tip)]
    model = load_model(str(robots / chain.file), base_link=chain.base, tip=chain.tip)
    tm = task_matrix(model, task=chain.task, frame="auto", numeric=True)
    assert tm.frame != "base"
    mapped = corpus._in_base_frame(model, tm, NumericMatrix(tm.matrix, tm.variables, tm.angles))
    base = task_matrix(model, task=chain.task, frame="base", point="tool", numeric=True)
    base_J = NumericMatrix(base.matrix, base.variables, base.angles)
    for q in np.random.default_rng(SEED).uniform(-np.pi, np.pi, (5, len(tm.variables))):
        want = base_J(q)
        assert np.max(np.abs(mapped(q) - want)) <= corpus.MAPPING_RTOL * np.max(np.abs(want))


def test_the_table_of_the_long_chains_says_it_holds_only_them():
    """``--min-joints 8`` runs only the frontier; its table must say so, the full one not."""
    meta = {"example_robot_data": "6.0.0", "pinocchio": "3", "seed": 0, "python": "3.11",
            "machine": "x86_64", "jobs": 2, "timeout_s": 60.0}
    row = {"robot": "tiago", "file": "t.urdf", "base": "b", "tip": "t", "n": 8, "task": "full",
           "status": "pass", "reason": "", "locus_s": 39.0, "components": 12}
    long = corpus.render_markdown([row], [], 0, meta | {"min_joints": 8})
    assert "Only the chains with 8 or more joints." in long
    full = corpus.render_markdown([row], [], 0, meta | {"min_joints": corpus.MIN_JOINTS})
    assert "or more joints" not in full


@pytest.mark.slow
def test_a_certified_eight_joint_locus_agrees_with_pinocchio(robots, chains):
    """pr2's left arm from its footprint (6 x 8, a prismatic lift and seven revolute joints):
    codimension 3 is decided on coordinate slices and the locus `rankloci locus` shows is
    certified complete.  Pinocchio's Jacobian, which nobody here wrote, agrees: every component
    is singular at its points, and every singular configuration probed lies on a component."""
    import rankloci
    from rankloci.api.calls import certified_locus

    chain = chains[("pr2_description/urdf/pr2.urdf", "l_wrist_roll_link")]
    path = robots / chain.file
    model = rankloci.load_model(path, base_link=chain.base, tip=chain.tip)
    locus, tm = certified_locus(model, task=chain.task, seed=SEED)
    assert locus.complete is True, locus.certificate.findings
    assert locus.certificate.witness_points[3] > 0
    ref = corpus.PinocchioJacobian(path.read_text(encoding="utf-8"), chain.joints, chain.tip,
                                   chain.task)
    graded = corpus.grade(model, tm, locus, ref, np.random.default_rng(SEED))
    assert graded["ok"], graded["reason"]
    assert graded["completeness"]["singular"] >= 1, "no singular point probed: a weak test"
