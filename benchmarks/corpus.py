"""Corpus: every serial chain of example-robot-data's URDF files, graded against Pinocchio.

Each URDF file of the package is read as a link tree.  Every path from the root
link to a leaf link with 2 to 9 movable joints is a chain; its tip is the child
link of its last movable joint, so paths that differ only after that joint are
one chain (and chains with the same joints, origins and axes are kept once per
file).  The task is the tip position for chains of up to 3 joints and the full
6-row task otherwise.

For each chain, in its own process with a time limit, the locus is computed as
``rankloci locus FILE --base-link ROOT --tip TIP --task TASK --numeric``
does
(``task_matrix(model, frame="auto", numeric=True)``, the method of
``method_for``, seed 0) and graded against an independent Jacobian: Pinocchio's
``getFrameJacobian`` of the tip link, ``LOCAL_WORLD_ALIGNED`` (the linear rows
for the position task), built from a copy of the URDF whose angles are snapped
as rankloci snaps them (see :func:`snapped_urdf`).

- **mapping**: at random configurations rankloci's J in the base frame about the
  tip and Pinocchio's J have the same entries (so the same joints, in the same
  order, with the same signs) and the same rank;
- **sound**: at the sample point of every component that exists for the model,
  and at points solved onto it, Pinocchio's J is rank deficient;
- **complete**: every singular point found by minimising sigma_min/sigma_max of
  Pinocchio's J from random starts lies on some component.

A chain passes when all three hold.  The results go to ``benchmarks/corpus.md``
and ``benchmarks/corpus.json``.  Usage::

    python benchmarks/corpus.py [--timeout SECONDS] [--jobs N] [--robots a,b,...]
                                [--max-per-robot N] [--min-joints N] [--seed N]
                                [--output PATH] [--render]

``tests/io/test_corpus.py`` imports this module and grades a subset with the
same functions.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path

from rankloci.tolerances import COVER_DISTANCE, PROBE_DESCENT_RTOL

HERE = Path(__file__).resolve().parent

#: Chains with fewer or more movable joints than this are not part of the corpus.
MIN_JOINTS, MAX_JOINTS = 2, 9

#: URDF joint types that move (rankloci reads them; a fixed joint's axis is ignored).
MOVABLE_TYPES = ("revolute", "continuous", "prismatic")

#: Chains of up to this many joints are graded on the tip position, longer ones on the full task.
POSITION_TASK_MAX_JOINTS = 3

#: Pinocchio's J counts as rank deficient at a point solved onto a component when
#: sigma_min/sigma_max is at most this.  It is rankloci's RANK_RTOL: both Jacobians describe the
#: same snapped geometry to rounding (~1e-16), points are solved to a scaled residual of 1e-11, and
#: sigma_min is Lipschitz in q with a constant of order sigma_max, so on-locus points give ratios
#: of ~1e-11; random regular configurations give 1e-3 and more.
SOUND_RTOL = 1e-8

#: A minimum of Pinocchio's sigma_min/sigma_max counts as a singular point at or below this.
PROBE_SINGULAR_RTOL = 1e-8

# Such a minimum is then followed by Newton steps on the ratio (rankloci's
# ``descend_to_singular``, on Pinocchio's J) and counts as a singular point only where they
# bring it to rankloci's PROBE_DESCENT_RTOL, the threshold of ``rankloci check``: a minimum
# that stays far above it is nearly, not exactly, singular.  romeo_laas_small's gripper chain
# has one at 2e-9 that no bounded search within 0.01 rad brings lower, 4.4e-5 (scaled) off a
# component's equations; on tiago_dual's thumb chain one at 2.4e-9 lies 6.7e-4 rad from a
# component, along a direction where the ratio grows by only 3.5e-6 per radian.

#: A singular point lies on a component when all of the component's scaled equations (each divided
#: by the sum of the absolute values of its coefficients) are at most this at it.  The minimiser
#: stops within ~1e-8 rad of a smooth locus and ~1e-6 rad where components meet tangentially; scaled
#: trigonometric equations change by at most their degree per radian, so 1e-6 accepts those, while a
#: missing component leaves residuals of 1e-2 and more.  (rankloci's COVER_RESIDUAL, same reason.)
COVER_RESIDUAL = 1e-6

# A singular point farther than COVER_RESIDUAL from every component is still covered when
# solving a component's equations from it lands within rankloci's COVER_DISTANCE at a point
# where Pinocchio's J is singular (the reason is there).

#: rankloci's J (base frame, tip point) and Pinocchio's J agree entry by entry to this, relative to
#: their largest entry.  Both are products of ~20 transforms of the same snapped numbers in double
#: precision (errors ~1e-15); a wrong joint, sign or axis gives differences of order 1.
MAPPING_RTOL = 1e-9

#: Central-difference step for dJ/dq of Pinocchio's J in the completeness probes: the truncation
#: error h**2 ~ 1e-12 and the rounding error eps/h ~ 1e-10 are far below the O(1) derivatives.
FD_STEP = 1e-6

#: Random configurations of the mapping check, points solved onto each component, and starts of
#: the completeness probes per chain.
MAPPING_POINTS = 5
POINTS_PER_COMPONENT = 4
PROBE_STARTS = 24

#: The locus polls its time limit between steps; a process whose locus is not done this many
#: seconds after the limit (counted from the start of the process) is stopped: a time-out.
LOCUS_GRACE_S = 20.0

#: Once the locus is done, grading gets this many seconds before the process is stopped (and
#: as much again for each step of a failing chain's self-check, see self_checked).
GRADING_ALLOWANCE_S = 120.0


# --- the corpus -----------------------------------------------------------------------------

def robots_dir() -> Path | None:
    """The ``robots`` directory of the installed example-robot-data, or None."""
    from rankloci.io.urdf_chains import example_robot_data_dir

    return example_robot_data_dir()


@dataclass(frozen=True)
class Chain:
    """One serial chain of a URDF file: root link to the child link of its last movable joint."""

    robot: str          # the description package, without "_description" / "_data"
    file: str           # path relative to the robots directory
    base: str
    tip: str
    joints: tuple       # names of the movable joints, root to tip
    also: tuple = ()    # leaf links whose paths give the same chain

    @property
    def n(self) -> int:
        return len(self.joints)

    @property
    def task(self) -> str:
        return "position" if self.n <= POSITION_TASK_MAX_JOINTS else "full"

    @property
    def label(self) -> str:
        return f"{self.base} -> {self.tip}"


def robot_name(rel: Path) -> str:
    """``talos_data/robots/x.urdf`` -> ``talos``; ``ur_description/...`` -> ``ur``."""
    top = rel.parts[0]
    for suffix in ("_description", "_data"):
        if top.endswith(suffix):
            return top[: -len(suffix)]
    return top


def chains_of_urdf(text, *, robot: str, file: str) -> tuple[list[Chain], int]:
    """The chains of a URDF document and how many leaf paths were outside 2..9 movable joints.

    :func:`rankloci.io.urdf_chains.urdf_chains` finds them; this names their robot and file.
    Raises :class:`rankloci.errors.ModelError` when the document does not parse as a link tree.
    """
    from rankloci.io.urdf_chains import urdf_chains

    found, outside = urdf_chains(text, file=file, min_joints=MIN_JOINTS, max_joints=MAX_JOINTS)
    return [Chain(robot, file, c.base, c.tip, c.joints, c.also) for c in found], outside


def corpus(root: Path) -> tuple[list[Chain], list[dict], int]:
    """Every chain of the URDF files under ``root``; the files skipped, with why; paths outside."""
    from rankloci.errors import ModelError

    chains, skipped, outside = [], [], 0
    for path in sorted(p for p in root.rglob("*") if ".urdf" in p.name and p.is_file()):
        rel = path.relative_to(root)
        if path.suffix != ".urdf":
            kind = "".join(path.suffixes)
            skipped.append({"file": str(rel), "reason": f"not a URDF file ({kind}: xacro source)"})
            continue
        try:
            found, out = chains_of_urdf(path.read_bytes(), robot=robot_name(rel), file=str(rel))
        except ModelError as e:
            skipped.append({"file": str(rel), "reason": str(e)})
            continue
        if not found:
            skipped.append({"file": str(rel), "reason": f"no chain with {MIN_JOINTS} to "
                                                        f"{MAX_JOINTS} movable joints"})
        chains.extend(sorted(found, key=lambda c: c.joints))
        outside += out
    return chains, skipped, outside


# --- the reference: Pinocchio ---------------------------------------------------------------

def _snapped_angle(t: float) -> float:
    """``t`` as rankloci reads an rpy angle or a mimic offset: the nearest multiple of pi/12 when
    within the URDF snapping tolerance, else the angle of a short exact rational rotation within
    URDF_ROTATION_ATOL of it."""
    from rankloci.io.urdf_exact import read_angle

    return read_angle(t)


def _snapped_axis(v: tuple[float, ...]) -> tuple[float, ...]:
    """A unit axis as rankloci reads it: components snapped to 0, 1/2, sqrt(2)/2, sqrt(3)/2, 1
    when all of them snap to a unit vector, otherwise a short exact rational unit vector."""
    from rankloci.io.urdf_exact import read_axis

    return read_axis(v)


def _snapped_length(x: float) -> float:
    """A length as rankloci reads it: 0 within the URDF length snapping tolerance."""
    from rankloci.tolerances import URDF_LENGTH_SNAP_ATOL

    return 0.0 if abs(x) <= URDF_LENGTH_SNAP_ATOL else x


def snapped_urdf(text) -> str:
    """The URDF with its joint angles, axes and lengths as rankloci reads them, for Pinocchio.

    rankloci takes an rpy angle within URDF_ANGLE_SNAP_ATOL (1e-5) of a multiple of pi/12 as that
    exact multiple (``1.5708`` is pi/2) and any other one as a short rational rotation within
    URDF_ROTATION_ATOL (1e-9 rad), reads axes the same way and takes lengths within
    URDF_LENGTH_SNAP_ATOL (1e-6 m) of 0 as 0; Pinocchio reads the decimals literally.  The copy
    writes the snapped values at full precision, so both describe the same geometry to rounding.
    """
    import xml.etree.ElementTree as ET

    import defusedxml.ElementTree as SafeET

    root = SafeET.fromstring(text)
    for joint in root.findall("joint"):
        origin = joint.find("origin")
        if origin is not None and origin.get("rpy"):
            rpy = [_snapped_angle(float(x)) for x in origin.get("rpy").split()]
            origin.set("rpy", " ".join(repr(x) for x in rpy))
        if origin is not None and origin.get("xyz"):
            xyz = [_snapped_length(float(x)) for x in origin.get("xyz").split()]
            origin.set("xyz", " ".join(repr(x) for x in xyz))
        axis = joint.find("axis")
        if joint.get("type") in MOVABLE_TYPES and axis is not None and axis.get("xyz"):
            xyz = _snapped_axis(tuple(float(x) for x in axis.get("xyz").split()))
            axis.set("xyz", " ".join(repr(x) for x in xyz))
    return ET.tostring(root, encoding="unicode")


class PinocchioJacobian:
    """J(q) of a chain from Pinocchio: the tip link's frame Jacobian, LOCAL_WORLD_ALIGNED.

    ``q`` holds one value per chain joint without a ``<mimic>``, in chain order (rankloci's
    q1..qn).  A joint that mimics another (through any number of mimics) is set to
    ``multiplier * q + offset`` of the joint it ends at, the leader, and its column is added,
    times the multiplier, to the leader's column.  A leader off the chain has its variable in
    the place of its first follower on the chain with multiplier 1 or -1 (see
    :func:`_chain_leaders` for a leader without one).  Every other joint of the robot stays at
    Pinocchio's neutral configuration (it cannot move the tip).  The rows are (vx, vy, vz, wx,
    wy, wz), or the first three for the position task.
    """

    def __init__(self, urdf_text: str, joints, tip: str, task: str):
        import defusedxml.ElementTree as SafeET
        import numpy as np
        import pinocchio as pin

        self._pin, self._np = pin, np
        text = snapped_urdf(urdf_text)
        self.model = pin.buildModelFromXML(text)   # mimic joints as joints of their own
        self.data = self.model.createData()
        if not self.model.existFrame(tip, pin.FrameType.BODY):
            raise ValueError(f"Pinocchio has no body frame {tip!r}")
        self.frame = self.model.getFrameId(tip, pin.FrameType.BODY)
        # the robot's joints only: a <transmission> names joints in <joint> elements of its own
        elements = {j.get("name"): j for j in SafeET.fromstring(text).findall("joint")}
        leaders = _chain_leaders(joints, elements)
        free = []   # the variables: joints without a mimic, leaders off the chain
        for name, (leader, mult, _) in leaders.items():
            if leader == name or (leader not in joints and leader not in free and abs(mult) == 1):
                free.append(leader)
        #: "revolute" or "prismatic" per variable
        self.kinds = tuple("prismatic" if elements[n].get("type") == "prismatic" else "revolute"
                           for n in free)
        self.joints = []   # (idx_q, nq, idx_v, variable index, multiplier, offset)
        for name in joints:
            if not self.model.existJointName(name):
                raise ValueError(f"Pinocchio has no joint {name!r}")
            leader, mult, off = leaders[name]
            jm = self.model.joints[self.model.getJointId(name)]
            self.joints.append((jm.idx_q, jm.nq, jm.idx_v, free.index(leader), mult, off))
        self.rows = slice(0, 3) if task == "position" else slice(0, 6)
        self.q0 = pin.neutral(self.model)
        self._combine = np.zeros((self.model.nv, len(free)))
        for _, _, iv, k, mult, _ in self.joints:
            self._combine[iv, k] += mult

    def configuration(self, q):
        """Pinocchio's configuration vector for the chain's variables ``q``."""
        x = self.q0.copy()
        for iq, nq, _, k, mult, off in self.joints:
            v = mult * q[k] + off
            if nq == 2:   # a continuous joint: (cos, sin)
                x[iq], x[iq + 1] = math.cos(v), math.sin(v)
            else:
                x[iq] = v
        return x

    def __call__(self, q):
        pin = self._pin
        x = self.configuration(q)
        pin.computeJointJacobians(self.model, self.data, x)
        pin.updateFramePlacement(self.model, self.data, self.frame)
        J = pin.getFrameJacobian(self.model, self.data, self.frame,
                                 pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        return self._np.asarray(J[self.rows] @ self._combine)

    def derivatives(self, q):
        """dJ/dq_k by central differences (FD_STEP): shape (n, rows, cols)."""
        np = self._np
        q = np.asarray(q, dtype=float)
        out = []
        for k in range(len(q)):
            e = np.zeros_like(q)
            e[k] = FD_STEP
            out.append((self(q + e) - self(q - e)) / (2 * FD_STEP))
        return np.array(out)


# --- grading --------------------------------------------------------------------------------

def _followed(name: str, elements) -> tuple[str, float, float]:
    """``(leader, multiplier, offset)``: joint ``name`` moves by ``multiplier * q_leader +
    offset``, following its ``<mimic>`` elements to a joint without one.  A revolute offset is an
    angle, snapped as rankloci snaps angles."""
    mult, off = 1.0, 0.0
    follower, seen = name, {name}
    while (m := elements[name].find("mimic")) is not None:
        a, b = float(m.get("multiplier", "1")), float(m.get("offset", "0"))
        mult, off = mult * a, mult * b + off
        name = m.get("joint", "").strip()
        if name in seen or name not in elements:
            raise ValueError(f"the mimic of joint {follower!r} cannot be followed")
        seen.add(name)
    if off and elements[follower].get("type") != "prismatic":
        off = _snapped_angle(off)
    return name, mult, off


def _chain_leaders(joints, elements) -> dict[str, tuple[str, float, float]]:
    """``(leader, multiplier, offset)`` of each chain joint (:func:`_followed`), in chain order.

    A leader off the chain followed by no chain joint with multiplier 1 or -1 cannot give its
    variable to one of them: its one follower is then a joint of its own (``(name, 1, 0)``: its
    variable is its own position, as rankloci reads it).
    """
    leaders = {name: _followed(name, elements) for name in joints}
    off_chain: dict[str, list[str]] = {}
    for name, (leader, _, _) in leaders.items():
        if leader not in joints:
            off_chain.setdefault(leader, []).append(name)
    for leader, followers in off_chain.items():
        if all(abs(leaders[f][1]) != 1 for f in followers):
            if len(followers) > 1:
                raise ValueError(f"joints {followers} follow {leader!r}, which is off the chain, "
                                 f"none with multiplier 1 or -1")
            leaders[followers[0]] = (followers[0], 1.0, 0.0)
    return leaders


def sigma_ratio(J) -> float:
    """sigma_min / sigma_max (0 for a zero matrix)."""
    import numpy as np

    s = np.linalg.svd(J, compute_uv=False)
    return float(s[-1] / s[0]) if s[0] > 0 else 0.0


def _numeric_rank(J) -> int:
    import numpy as np

    from rankloci.tolerances import RANK_RTOL

    s = np.linalg.svd(J, compute_uv=False)
    return int(np.sum(s > RANK_RTOL * s[0])) if s[0] > 0 else 0


def random_configurations(kinds, rng, n: int):
    """n random configurations: revolute joints uniform in [-pi, pi), prismatic in [-1, 1)."""
    import numpy as np

    cols = [rng.uniform(-np.pi, np.pi, n) if k == "revolute" else rng.uniform(-1, 1, n)
            for k in kinds]
    return np.stack(cols, axis=-1)


def _q_text(q) -> str:
    return "[" + ", ".join(f"{x:+.4f}" for x in q) + "]"


def _short(text: str, limit: int = 160) -> str:
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _projects_onto(eqs, q, ref) -> bool:
    """Does solving ``eqs`` from ``q`` land within COVER_DISTANCE, at a singular point?"""
    import numpy as np
    from scipy.optimize import least_squares

    from rankloci.tolerances import ON_COMPONENT_RESIDUAL

    p = least_squares(eqs, q, method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15,
                      max_nfev=200 * len(q)).x
    return (eqs.residual(p) <= ON_COMPONENT_RESIDUAL and np.linalg.norm(p - q) <= COVER_DISTANCE
            and sigma_ratio(ref(p)) <= SOUND_RTOL)


def _in_base_frame(model, tm, nm):
    """The matrix the locus is computed on (``nm``, in ``tm``'s frame about ``tm``'s point),
    mapped to the base frame about the tool by the rigid velocity map of
    :func:`rankloci.kinematics.velocity_map` at each configuration (a rotation of both row
    blocks, and a shift of the point that adds angular rows to linear ones); None on a partial
    task about a point other than the tool, whose rows that shift would mix with the others.

    The symbolic base-frame Jacobian, expanded by sympy, took over 15 minutes on
    romeo_laas_small's 9-joint gripper chains (axes that do not snap); this takes
    milliseconds, and it checks the very matrix the locus is about.
    """
    import numpy as np

    from rankloci.kinematics import frame_position, velocity_map

    rows = list(tm.rows)
    if not rows or tm.frame is None:
        return None
    if len(rows) < 6 and frame_position(model, tm.point) != frame_position(model, "tool"):
        return None
    variables = list(tm.variables)

    def base_J(q):
        A = velocity_map(model, dict(zip(variables, q)), tm.frame, tm.point)
        return np.linalg.solve(A[np.ix_(rows, rows)], nm(q))

    return base_J


def probe_minimum(ref, q0):
    """A completeness probe from ``q0``: the point, its ratio, and whether it is singular.

    Pinocchio's sigma_min/sigma_max is minimised from ``q0`` (rankloci's minimiser only walks;
    what it walks on is ``ref``).  The third value is None for a minimum above
    PROBE_SINGULAR_RTOL, False for one that Newton steps do not bring down to
    PROBE_DESCENT_RTOL (nearly singular), True for a singular point.
    """
    from rankloci.numeric.equations import descend_to_singular, minimise_ratio

    q = minimise_ratio(ref, q0)
    r = float(sigma_ratio(ref(q)))
    if r > PROBE_SINGULAR_RTOL:
        return q, r, None
    q, r = descend_to_singular(ref, q)
    return q, r, bool(r <= PROBE_DESCENT_RTOL)


def grade(model, tm, locus, ref: PinocchioJacobian, rng) -> dict:
    """Grade a locus against Pinocchio's J: mapping, soundness, completeness (module docstring).

    Returns a dict with ``ok``, ``reason`` (the first problem found, "" when ok) and the
    figures of each check.
    """
    import numpy as np
    import sympy as sp

    from rankloci.jacobians import task_matrix
    from rankloci.numeric.equations import Equations, NumericMatrix, points_on

    kinds = ref.kinds
    problems = []

    # mapping: rankloci's J in the base frame about the tip against Pinocchio's, entry by entry
    nm = NumericMatrix(tm.matrix, tm.variables, tm.angles)
    base_J = _in_base_frame(model, tm, nm)
    if base_J is None:
        base_tm = task_matrix(model, task=tm.rows, frame="base", point="tool", numeric=True)
        base_J = NumericMatrix(base_tm.matrix, base_tm.variables, base_tm.angles)
    worst_dev, rank_mismatch = 0.0, []
    for q in random_configurations(kinds, rng, MAPPING_POINTS):
        A, B = base_J(q), ref(q)
        dev = float(np.max(np.abs(A - B)) / max(np.max(np.abs(B)), 1e-300))
        worst_dev = max(worst_dev, dev)
        if _numeric_rank(A) != _numeric_rank(B):
            rank_mismatch.append((q, _numeric_rank(A), _numeric_rank(B)))
    if worst_dev > MAPPING_RTOL:
        problems.append(f"mapping: rankloci's J and Pinocchio's differ by {worst_dev:.1e} "
                        f"(relative)")
    if rank_mismatch:
        q, a, b = rank_mismatch[0]
        problems.append(f"mapping: rank {a} in rankloci, {b} in Pinocchio at q={_q_text(q)}")
    mapping = {"ok": not (worst_dev > MAPPING_RTOL or rank_mismatch),
               "max_relative_deviation": worst_dev, "rank_mismatches": len(rank_mismatch)}

    # soundness: each component of the model's own locus is singular in Pinocchio's J
    names = [v.name for v in tm.variables]
    components = [c for c in locus.components if c.for_model]
    sound = []
    for i, c in enumerate(components, start=1):
        eqs = Equations(c.equations, tm.variables, tm.parameters, c.excluding)
        pts = []
        if c.sample and all(n in c.sample for n in names):
            pts.append(np.array([float(c.sample[n]) for n in names]))
        pts += points_on(eqs, nm, rng, POINTS_PER_COMPONENT)
        ratios = [sigma_ratio(ref(q)) for q in pts]
        for k, (q, r) in enumerate(zip(pts, ratios)):
            # a point regular in J is refined onto the equations first: near a multiple root
            # the solver stops far from the component for its residual (Equations.refined)
            p = eqs.settled(q) if r > SOUND_RTOL else None
            if p is not None:
                pts[k], ratios[k] = p, sigma_ratio(ref(p))
        bad = [(q, r) for q, r in zip(pts, ratios) if r > SOUND_RTOL]
        eq_text = _short("; ".join(sp.sstr(e) for e in c.equations) or "(no equation)")
        sound.append({"component": i, "equations": eq_text, "points": len(pts),
                      "max_ratio": max(ratios, default=None), "regular_points": len(bad)})
        if not pts:
            problems.append(f"component {i} ({eq_text}): no point found on it")
        elif bad:
            q, r = max(bad, key=lambda t: t[1])
            problems.append(f"unsound: component {i} ({eq_text}) is regular in Pinocchio's J at "
                            f"q={_q_text(q)} (ratio {r:.1e}; {len(bad)}/{len(pts)} points)")

    # completeness: singular minima of Pinocchio's ratio lie on some component
    closures = [Equations(c.equations, tm.variables, tm.parameters)
                for c in components]
    singular, nearly, near, uncovered = 0, 0, 0, []
    for q0 in random_configurations(kinds, rng, PROBE_STARTS):
        q, r, found = probe_minimum(ref, q0)
        if found is None:
            continue
        if not found:
            nearly += 1
            continue
        singular += 1
        if locus.degenerate:
            continue
        residuals = [e.residual(q) for e in closures]
        if min(residuals, default=math.inf) <= COVER_RESIDUAL:
            continue
        order = sorted(range(len(closures)), key=residuals.__getitem__)
        if any(_projects_onto(closures[k], q, ref) for k in order):
            near += 1
            continue
        uncovered.append({"q": [float(x) for x in q], "ratio": r,
                          "residual": min(residuals, default=math.inf)})
    if uncovered:
        u = min(uncovered, key=lambda d: d["ratio"])
        problems.append(f"incomplete: {len(uncovered)}/{singular} singular points on no "
                        f"component, e.g. q={_q_text(u['q'])} (ratio {u['ratio']:.1e}, smallest "
                        f"residual {u['residual']:.1e})")
    completeness = {"starts": PROBE_STARTS, "singular": singular, "nearly_singular": nearly,
                    "covered_by_projection": near, "uncovered": uncovered}
    return {"ok": not problems, "reason": "; ".join(problems), "mapping": mapping,
            "sound": sound, "completeness": completeness}


def _exception_text(e: BaseException) -> str:
    """``OverflowError at rankloci/methods/finalize.py:123 (_component): message``, shortened."""
    import traceback

    frames = [f for f in traceback.extract_tb(e.__traceback__) if "rankloci" in f.filename]
    where = ""
    if frames:
        f = frames[-1]
        path = f.filename[f.filename.rindex("rankloci"):]
        where = f" at {path}:{f.lineno} ({f.name})"
    return _short(f"{type(e).__name__}{where}: {e}", 300)


def run_case(chain: Chain, root: Path, *, time_limit: float | None = 60.0, seed: int = 0,
             emit=None) -> dict:
    """Compute and grade the locus of one chain in this process.

    ``status`` is ``pass``, ``fail`` (grading found a problem: ``reason``), ``timeout`` (the
    locus did not finish in ``time_limit`` seconds) or ``error`` (rankloci or Pinocchio refused
    the chain: ``reason``).  ``emit``, when given, is called with the partial result once the
    locus is done.
    """
    import numpy as np

    from rankloci.errors import LocusTimeout, RanklociError
    from rankloci.io import load_model
    from rankloci.jacobians import task_matrix
    from rankloci.methods import compute_locus, method_for

    out = {"status": "error", "reason": "", "components": None}
    path = root / chain.file
    t0 = time.perf_counter()
    try:
        model = load_model(str(path), base_link=chain.base, tip=chain.tip)
        tm = task_matrix(model, task=chain.task, frame="auto", numeric=True)
    except RanklociError as e:
        out["reason"] = f"rankloci: {e}"
        return out
    names = tuple(j.name for j in model.joints)
    if names != chain.joints:
        out["reason"] = f"rankloci's chain has joints {names}, expected {chain.joints}"
        return out
    try:
        ref = PinocchioJacobian(path.read_text(encoding="utf-8"), chain.joints, chain.tip,
                                chain.task)
    except (ValueError, RuntimeError) as e:
        out["reason"] = f"Pinocchio: {e}"
        return out
    if len(ref.kinds) != len(tm.variables):
        out["reason"] = (f"rankloci has {len(tm.variables)} variables, the reference "
                         f"{len(ref.kinds)}")
        return out
    method = method_for(tm.shape)
    end = None if not time_limit else time.monotonic() + time_limit
    t1 = time.perf_counter()
    try:
        locus = compute_locus(tm, method, rng=np.random.default_rng(seed),
                              should_stop=None if end is None else (lambda: time.monotonic() > end))
    except LocusTimeout:
        out.update(status="timeout", reason=f"no locus within {time_limit:g} s",
                   locus_s=time.perf_counter() - t1, shape=list(tm.shape), method=method)
        return out
    except RanklociError as e:
        out["reason"] = f"rankloci: {e}"
        return out
    except Exception as e:  # an engine failure is a result of the corpus, not a crash of the run
        out["reason"] = f"locus: {_exception_text(e)}"
        return out
    t2 = time.perf_counter()
    mine = [c for c in locus.components if c.for_model]
    out.update(shape=list(tm.shape), method=method, setup_s=t1 - t0, locus_s=t2 - t1,
               components=len(mine), other_components=len(locus.components) - len(mine),
               degenerate=locus.degenerate, nodes=locus.tree.number_of_nodes(),
               status="graded", reason="grading did not finish")
    if emit:
        emit(dict(out))
    try:
        g = grade(model, tm, locus, ref, np.random.default_rng(seed))
    except Exception as e:
        out.update(status="error", reason=f"grading: {_exception_text(e)}")
        return out
    out.update(status="pass" if g["ok"] else "fail", reason=g["reason"],
               grade_s=time.perf_counter() - t2,
               grading={k: v for k, v in g.items() if k not in ("ok", "reason")})
    if not g["ok"]:
        out["self_check"] = self_checked(model, tm, method, chain, ref, seed, emit=emit,
                                         partial=out)
    return out


def self_checked(model, tm, method, chain: Chain, ref, seed: int, *, emit=None,
                 partial=None) -> dict:
    """The locus as `rankloci locus` shows it (self-check, recomputation, hints), graded again.

    Run for the chains whose first computation fails grading: the table says whether the
    self-check catches the failure (``complete`` false: the locus is shown marked incomplete;
    null: not certified) or repairs it (the locus shown passes grading).  ``emit`` gets ``partial`` before each
    step, so that each step gets the grading allowance.
    """
    import numpy as np

    from rankloci.jacobians import task_matrix
    from rankloci.methods import compute_locus
    from rankloci.verify import verified_locus

    def compute(t, s, hints=()):
        return compute_locus(t, method, rng=np.random.default_rng(s), hints=hints)

    # the parent process restarts its grading allowance on a "graded" line; "after" keeps the
    # status that stands if this step is stopped
    mark = dict(partial or {}, status="graded", after=(partial or {}).get("status"))
    if emit:
        emit(mark)
    t0 = time.perf_counter()
    # the matrix `rankloci locus` checks: tm's, with the parameters symbolic
    reference = task_matrix(model, task=chain.task, frame=tm.frame, point=tm.point)
    locus, v = verified_locus(compute, tm, reference, seed=seed)
    t1 = time.perf_counter()
    if emit:
        emit(mark)
    g = grade(model, tm, locus, ref, np.random.default_rng(seed))
    return {"status": "pass" if g["ok"] else "fail", "reason": g["reason"],
            "complete": locus.complete, "attempts": list(v.attempts), "seconds": t1 - t0,
            "components": sum(c.for_model for c in locus.components)}


# --- running the corpus ---------------------------------------------------------------------

def _pump(stream, q) -> None:
    """Put each line of ``stream`` on ``q``, then None."""
    for line in stream:
        q.put(line)
    q.put(None)


def _run_child(chain: Chain, root: Path, time_limit: float, seed: int) -> dict:
    """run_case in a fresh process, stopped when it overruns.

    The locus polls its time limit only between steps, so a process whose locus is not done
    LOCUS_GRACE_S after the limit (counted from the start of the process: importing and
    building J are in it) is stopped; once the locus is done, grading gets
    GRADING_ALLOWANCE_S more.
    """
    import queue
    import threading

    cmd = [sys.executable, str(Path(__file__).resolve()), "--case",
           json.dumps({"chain": asdict(chain), "root": str(root), "time_limit": time_limit,
                       "seed": seed})]
    start = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines: queue.Queue = queue.Queue()
    err: list[str] = []
    threading.Thread(target=_pump, args=(proc.stdout, lines), daemon=True).start()
    err_reader = threading.Thread(target=err.extend, args=(proc.stderr,), daemon=True)
    err_reader.start()
    deadline = start + time_limit + LOCUS_GRACE_S
    res, stopped = None, False
    while True:
        try:
            line = lines.get(timeout=max(0.01, min(1.0, deadline - time.monotonic())))
        except queue.Empty:
            if time.monotonic() > deadline:
                proc.kill()
                stopped = True
                break
            continue
        if line is None:  # end of the child's output
            break
        if line.startswith("{"):
            res = json.loads(line)
            if res["status"] == "graded":
                deadline = time.monotonic() + GRADING_ALLOWANCE_S
    proc.wait()
    err_reader.join(timeout=5)
    wall = time.monotonic() - start
    res = res or {"status": "error", "reason": "", "components": None}
    if stopped and res.get("after"):
        # the chain failed grading and its self-check did not finish
        res.update(status=res.pop("after"), self_check={
            "status": "timeout", "reason": "", "complete": None, "attempts": [],
            "seconds": wall, "components": None})
    elif stopped:
        if res["status"] == "graded":
            res.update(status="timeout", reason=f"grading did not finish within "
                                                f"{GRADING_ALLOWANCE_S:g} s after the locus")
        else:
            res.update(status="timeout", reason=f"no locus within {time_limit:g} s (process "
                                                f"stopped after {wall:.0f} s)")
    elif proc.returncode != 0:
        tail = ("".join(err).strip().splitlines() or ["(no output)"])[-1]
        res.update(status="error", reason=_short(f"exit code {proc.returncode}: {tail}", 300))
    res["wall_s"] = wall
    return res


def _child_main(spec: str) -> int:
    args = json.loads(spec)
    chain = Chain(**{k: tuple(v) if isinstance(v, list) else v for k, v in args["chain"].items()})

    def emit(partial):
        print(json.dumps(partial), flush=True)

    res = run_case(chain, Path(args["root"]), time_limit=args["time_limit"], seed=args["seed"],
                   emit=emit)
    print(json.dumps(res), flush=True)
    return 0


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _self_check_text(r) -> str:
    """What the self-check of `rankloci locus` made of a failing chain, for the table."""
    sc = r.get("self_check")
    if not sc:
        return ""
    if sc["status"] == "pass":
        return (f"; the self-check of `rankloci locus` repairs it ({sc['seconds']:.0f} s, "
                f"{len(sc['attempts'])} computations): the locus shown passes grading "
                f"({sc['components']} components)")
    if sc["status"] == "timeout":
        return ("; the self-check of `rankloci locus` did not finish within the grading "
                "allowance")
    shown = "marked incomplete" if not sc["complete"] else "shown as complete"
    return (f"; after the self-check of `rankloci locus` ({sc['seconds']:.0f} s) the locus is "
            f"{shown} and fails grading: {_short(sc['reason'], 120)}")


def _whole_cells(w) -> str:
    """The whole-run cells of a chain's row (benchmarks/whole_runs.py), or *pending*."""
    if w is None:
        return " pending | | | | | | |"

    def f(x, digits=1):
        return "" if x is None else f"{x:.{digits}f}"

    complete = {True: "true", None: "null", False: "false"}.get(w.get("complete"), "")
    if w["status"] in ("timeout", "error"):
        complete = w["status"]
    shown = w.get("grade", "")
    return (f" {f(w.get('whole_s'))} | {f(w.get('engine_s'))} | {f(w.get('certificate_s'))} | "
            f"{f(w.get('peak_rss_mib'), 0)} | {complete} | {'yes' if w['within'] else 'no'} | "
            f"{shown} |")


def render_markdown(rows, skipped, outside, meta) -> str:
    """The corpus table as Markdown."""
    counts = {s: sum(r["status"] == s for r in rows) for s in ("pass", "fail", "timeout", "error")}
    lines = [
        "# URDF corpus: example-robot-data",
        "",
        f"Every serial chain with {MIN_JOINTS} to {MAX_JOINTS} movable joints in the URDF files "
        f"of example-robot-data {meta['example_robot_data']}, from the root link to the child "
        "link of the chain's last movable joint (paths that differ only after it, and chains "
        "with the same joints, origins and axes, kept once per file). Task: tip position for up "
        f"to {POSITION_TASK_MAX_JOINTS} joints, full otherwise. Each locus is computed as by "
        "`rankloci locus FILE --base-link ROOT --tip TIP --task TASK --numeric` and "
        f"graded against Pinocchio {meta['pinocchio']}'s frame Jacobian of the tip link "
        "(LOCAL_WORLD_ALIGNED), read from a copy of the URDF with the angles snapped as "
        "rankloci snaps them:",
        "",
        f"- *mapping*: at {MAPPING_POINTS} random configurations rankloci's J (base frame, tip "
        f"point) equals Pinocchio's to {MAPPING_RTOL:g} relative, and has the same rank;",
        f"- *sound*: at each component's sample point and up to {POINTS_PER_COMPONENT} points "
        f"solved onto it, Pinocchio's sigma_min/sigma_max <= {SOUND_RTOL:g};",
        f"- *complete*: of {PROBE_STARTS} minimisations of Pinocchio's sigma_min/sigma_max from "
        f"random starts (seed {meta['seed']}), every one that ends at a ratio <= "
        f"{PROBE_SINGULAR_RTOL:g} and that Newton steps bring to <= {PROBE_DESCENT_RTOL:g} (a "
        f"singular point, not a nearly singular one) lies on a component (scaled residual <= "
        f"{COVER_RESIDUAL:g}).",
        "",
        f"Python {meta['python']} on {meta['machine']}, one process per chain, "
        f"{meta['jobs']} at a time, locus time limit {meta['timeout_s']:g} s. "
        "'time' is the locus alone; 'components' counts those of the model's own locus. "
        "The locus graded is the engine's first computation, without the self-check that "
        "`rankloci locus` runs before it shows a locus (and that recomputes, or marks the "
        "locus incomplete, when it fails): a *fail* here is a locus that check has to catch. "
        "For those chains the table also says what `rankloci locus` shows: the locus after "
        "its self-check, graded the same way.",
        "",
    ]
    for note in meta.get("notes", ()):
        lines += [note, ""]
    if meta.get("min_joints", MIN_JOINTS) > MIN_JOINTS:
        lines += [f"Only the chains with {meta['min_joints']} or more joints.", ""]
    if meta.get("max_per_robot"):
        lines += [f"At most {meta['max_per_robot']} chains per robot (the shortest first).", ""]
    degenerate = sum(r["status"] == "pass" and bool(r.get("degenerate")) for r in rows)
    lines += [
        f"**{len(rows)} chains: {counts['pass']} pass, {counts['fail']} fail, "
        f"{counts['timeout']} time out, {counts['error']} error.**",
        "",
        f"{degenerate} of the passes are degenerate loci (J rank deficient everywhere, marked "
        "so): a chain graded on the position of the child link of its last joint loses that "
        "joint's column when the joint is revolute, since the link's origin lies on its axis. "
        "These check that rankloci and Pinocchio agree on it, no more.",
        "",
    ]
    others = [r for r in rows if r["status"] != "pass"]
    if others:
        lines += ["Chains that do not pass:", ""]
        lines += [f"- {r['status']}: `{r['file']}` {_cell(r['base'])} -> {_cell(r['tip'])} "
                  f"({r['n']} joints): {_cell(_short(r['reason'], 200))}{_self_check_text(r)}"
                  for r in others]
        lines += [""]
    # the whole runs of benchmarks/whole_runs.py, when they were merged into the rows
    whole = any("whole" in r for r in rows)
    extra_head = (" whole run (s) | engine (s) | certificate (s) | peak RSS (MiB) | complete | "
                  "within target | shown |") if whole else ""
    lines += [
        "| robot | file | chain | joints | task | time (s) | components | result | reason |"
        + extra_head,
        "| --- " * (9 + 7 * whole) + "|",
    ]
    for r in rows:
        t = f"{r['locus_s']:.2f}" if r.get("locus_s") is not None else ""
        if r["status"] == "timeout" and r.get("components") is None:
            t = f"> {meta['timeout_s']:g}"
        comps = "" if r.get("components") is None else str(r["components"])
        if r.get("degenerate"):
            comps += " (degenerate)"
        lines.append(f"| {r['robot']} | {r['file']} | {_cell(r['base'])} -> {_cell(r['tip'])} | "
                     f"{r['n']} | {r['task']} | {t} | {comps} | {r['status']} | "
                     f"{_cell(r['reason'])}{_cell(_self_check_text(r))} |"
                     + (_whole_cells(r.get("whole")) if whole else ""))
    lines += ["", "Files without chains in the corpus:", ""]
    lines += [f"- `{s['file']}`: {_cell(s['reason'])}" for s in skipped]
    lines += ["", f"{outside} root-to-leaf path(s) with fewer than {MIN_JOINTS} or more than "
                  f"{MAX_JOINTS} movable joints are not in the corpus.", ""]
    return "\n".join(lines)


def select_chains(chains, robots: str | None, min_joints: int, max_per_robot: int | None):
    """The chains of the robots named in ``robots`` (comma list; None: all) with at least
    ``min_joints`` joints, and of each robot at most ``max_per_robot``, the shortest first."""
    if robots:
        wanted = set(robots.split(","))
        chains = [c for c in chains if c.robot in wanted]
    chains = [c for c in chains if c.n >= min_joints]
    if max_per_robot:
        kept = []
        for robot in sorted({c.robot for c in chains}):
            mine = sorted((c for c in chains if c.robot == robot), key=lambda c: c.n)
            kept += mine[:max_per_robot]
        chains = [c for c in chains if c in kept]
    return chains


def main(argv=None) -> int:
    sys.path.insert(0, str(HERE.parent))
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--timeout", type=float, default=60.0, help="locus time limit per chain (s)")
    ap.add_argument("--jobs", type=int, default=2, help="chains computed at the same time")
    ap.add_argument("--robots", default="", help="comma-separated robot names (default: all)")
    ap.add_argument("--max-per-robot", type=int, default=0,
                    help="at most this many chains per robot, the shortest first (0: all)")
    ap.add_argument("--min-joints", type=int, default=MIN_JOINTS,
                    help="only the chains with at least this many movable joints (the frontier)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--output", default=str(HERE / "corpus"))
    ap.add_argument("--render", action="store_true",
                    help="only write OUTPUT.md again from OUTPUT.json (no computation)")
    ap.add_argument("--case", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.case:
        return _child_main(args.case)
    if args.render:
        data = json.loads(Path(args.output + ".json").read_text())
        Path(args.output + ".md").write_text(render_markdown(
            data["chains"], data["skipped_files"], data["paths_outside_joint_range"], data["meta"]))
        return 0

    from importlib.metadata import version

    root = robots_dir()
    if root is None:
        print("example-robot-data is not installed (pip install -e '.[test]')", file=sys.stderr)
        return 2
    chains, skipped, outside = corpus(root)
    chains = select_chains(chains, args.robots, args.min_joints, args.max_per_robot)
    print(f"{len(chains)} chains", file=sys.stderr, flush=True)

    def one(chain):
        res = _run_child(chain, root, args.timeout, args.seed)
        row = {"robot": chain.robot, "file": chain.file, "base": chain.base, "tip": chain.tip,
               "n": chain.n, "task": chain.task, "joints": list(chain.joints),
               "also_leaves": list(chain.also)} | res
        print(f"{row['status']:>7} {row['wall_s']:6.1f} s  {chain.file}: {chain.label}  "
              f"{row['reason'][:120]}", file=sys.stderr, flush=True)
        return row

    # longest chains first, so that the slow ones do not all end up at the end of the run
    order = sorted(range(len(chains)), key=lambda i: -chains[i].n)
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        done = dict(zip(order, pool.map(one, [chains[i] for i in order])))
    rows = [done[i] for i in range(len(chains))]
    meta = {"python": platform.python_version(), "machine": platform.machine(),
            "timeout_s": args.timeout, "jobs": args.jobs, "seed": args.seed,
            "max_per_robot": args.max_per_robot, "robots": args.robots or "all",
            "min_joints": args.min_joints,
            "example_robot_data": version("example-robot-data"), "pinocchio": version("pin"),
            "tolerances": {"SOUND_RTOL": SOUND_RTOL, "PROBE_SINGULAR_RTOL": PROBE_SINGULAR_RTOL,
                           "PROBE_DESCENT_RTOL": PROBE_DESCENT_RTOL,
                           "COVER_RESIDUAL": COVER_RESIDUAL, "MAPPING_RTOL": MAPPING_RTOL}}
    counts = {s: sum(r["status"] == s for r in rows) for s in ("pass", "fail", "timeout", "error")}
    Path(args.output + ".json").write_text(json.dumps(
        {"meta": meta, "summary": counts, "skipped_files": skipped,
         "paths_outside_joint_range": outside, "chains": rows}, indent=2) + "\n")
    Path(args.output + ".md").write_text(render_markdown(rows, skipped, outside, meta))
    print(f"{len(rows)} chains: " + ", ".join(f"{v} {k}" for k, v in counts.items()),
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
