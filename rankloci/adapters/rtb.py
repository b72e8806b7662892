"""Robotics Toolbox for Python's DH robots as rankloci models.

rankloci's ``dh`` and ``mdh`` conventions are the toolbox's standard and
modified DH (``T = Rz(theta) Tz(d) Tx(a) Rx(alpha)`` and
``T = Rx(alpha) Tx(a) Rz(theta) Tz(d)``), so a ``DHRobot`` is written as a
model file and read back by :func:`rankloci.io.toml_model.parse_model`: its
numbers become exact as a file's do (decimals are the rationals of their
shortest form, twists within 1e-12 of a multiple of pi/12 that multiple).
"""

from __future__ import annotations

import json
import re

from ..errors import ModelError
from .transforms import is_identity, length_text, xyz_rpy

__all__ = ["from_rtb"]


def _number(value, what: str) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ModelError(f"{what} is {value!r}, not a number; give the robot numeric "
                         "parameters") from None


def _angle(value, what: str) -> str:
    """An angle as model files write it: an exact multiple of pi/12 when it is one."""
    import sympy as sp

    from ..expr import snap_angle

    x = _number(value, what)
    exact = snap_angle(x)
    return json.dumps(sp.sstr(exact)) if exact is not None else repr(x)


def _name(robot) -> str:
    text = re.sub(r"[^a-z0-9_-]+", "_", str(getattr(robot, "name", "") or "robot").lower())
    text = text.strip("_-") or "robot"
    return text[:64] if text[0].isalnum() else f"r{text[:63]}"


def _transform_table(key, T) -> str:
    xyz, rpy = xyz_rpy(T)
    return (f"[{key}]\nxyz = [{', '.join(length_text(x) for x in xyz)}]\n"
            f"rpy = [{', '.join(_angle(a, f'{key} rotation') for a in rpy)}]\n")


def model_text(robot, *, symbolic: bool = True) -> str:
    """The model file of a ``DHRobot`` (see :func:`from_rtb`)."""
    links = getattr(robot, "links", None)
    if links is None or not hasattr(robot, "mdh") or not all(hasattr(L, "sigma") for L in links):
        raise ModelError(f"from_rtb takes a roboticstoolbox DHRobot (standard or modified DH); "
                         f"{type(robot).__name__} is not one (for an ERobot, read its URDF "
                         f"file with rankloci.load_model)")
    params, joints = {}, []
    for i, L in enumerate(links, 1):
        if getattr(L, "isflip", False):
            raise ModelError(f"link {i} is flipped (flip=True), which model files cannot say")
        kind = "prismatic" if L.isprismatic else "revolute"
        fields = {"kind": json.dumps(kind), "alpha": _angle(L.alpha, f"link {i} alpha")}
        lengths = {"a": _number(L.a, f"link {i} a")}
        if kind == "revolute":
            lengths["d"] = _number(L.d, f"link {i} d")
            fields["theta"] = _angle(L.offset, f"link {i} offset")
        else:
            lengths["d"] = _number(L.offset, f"link {i} offset")
            fields["theta"] = _angle(L.theta, f"link {i} theta")
        for key, value in lengths.items():
            if symbolic and value != 0 and not (kind == "prismatic" and key == "d"):
                params[f"{key}{i}"] = value
                fields[key] = json.dumps(f"{key}{i}")
            else:
                fields[key] = repr(value)
        qlim = getattr(L, "qlim", None)
        if qlim is not None and len(qlim) == 2 and all(abs(float(x)) < 1e6 for x in qlim) \
                and float(qlim[0]) < float(qlim[1]):
            fields["limits"] = f"[{float(qlim[0])!r}, {float(qlim[1])!r}]"
        joints.append("[[joint]]\n" + "".join(f"{k} = {v}\n" for k, v in fields.items()))
    title = str(getattr(robot, "name", "") or "robot")
    maker = str(getattr(robot, "manufacturer", "") or "")
    source = ("Robotics Toolbox for Python DHRobot " + title + (", " + maker if maker else "")).strip()
    text = (f"name = {json.dumps(_name(robot))}\ntitle = {json.dumps(title)}\n"
            f"source = {json.dumps(source)}\n"
            f"convention = {json.dumps('mdh' if robot.mdh else 'dh')}\n")
    for key in ("base", "tool"):
        T = getattr(robot, key, None)
        T = getattr(T, "A", T)
        if T is not None and not is_identity(T):
            text += _transform_table(key, T)
    if params:
        text += "[parameters]\n" + "".join(f"{k} = {v!r}\n" for k, v in params.items())
    return text + "\n".join(joints)


def from_rtb(robot, *, symbolic: bool = True):
    """A rankloci model of a Robotics Toolbox for Python ``DHRobot``.

    Parameters
    ----------
    robot : roboticstoolbox.DHRobot
        Standard (``RevoluteDH``, ``PrismaticDH``) or modified DH
        (``RevoluteMDH``, ``PrismaticMDH``) links, with its ``base`` and ``tool``.
    symbolic : bool, default True
        Name every nonzero link length ``a<i>`` / ``d<i>`` (joint i, 1-based) as a
        parameter with the robot's value, as rankloci's own model files do, so
        the locus says which lengths it depends on and where it changes.  With
        False the lengths are numbers.

    Returns
    -------
    RobotModel
        Joint variables ``q1..qn`` are the toolbox's ``q`` (its offsets are
        part of the model); the task is the full 6-row Jacobian of the tool
        point in the base frame, the toolbox's ``jacob0``.

    Raises
    ------
    rankloci.errors.ModelError
        Not a DH robot, a flipped joint, or symbolic link values.  A twist that
        is not a multiple of pi/12 is kept as written, and the locus computation
        refuses it (its cosine is not an exact number).

    Examples
    --------
    >>> import roboticstoolbox as rtb
    >>> from_rtb(rtb.models.DH.Puma560())
    <RobotModel 'puma_560': 6 revolute joints, standard DH, parameters a2, a3, d1, d3, d4>
    """
    import warnings

    from ..expr import AngleSnapWarning
    from ..io.toml_model import parse_model

    text = model_text(robot, symbolic=symbolic)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AngleSnapWarning)  # exact multiples are written as such
        return parse_model(text)
