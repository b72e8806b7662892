"""What a locus says about its model beyond the algebra: read off the model, after the pipeline.

:func:`with_model_notes` is applied to the locus the pipeline returns (by the
Python API and by ``rankloci locus``), never inside it: the pipeline keeps loci
by the model's kinematics, and two URDF files can share those under other
joint names.

- an empty locus of a task with more rows than joints says so: J then has rank
  at most n and loses it only where every n x n minor vanishes, which most
  arms never do, so the empty answer is right but rarely the one wanted;
- the variables ``q1..qn`` of a URDF chain are given their joints' names.
"""

from __future__ import annotations

import dataclasses

__all__ = ["with_model_notes", "joint_names", "task_note"]


def joint_names(model) -> tuple[str, ...]:
    """The URDF joint name of each variable of ``model``, in order; () for other models.

    Mimic joints have no variable of their own and are left out.

    Examples
    --------
    >>> import rankloci
    >>> joint_names(rankloci.load_model("kinematics_models/extra/iiwa_offsets.urdf"))[:2]
    ('j1', 'j2')
    >>> joint_names(rankloci.load_model("puma560"))
    ()
    """
    from ..model import RobotModel

    if not isinstance(model, RobotModel) or model.convention != "urdf":
        return ()
    names = tuple(j.name for j in model.joints if j.mimic is None)
    return names if len(names) == len(model.variables) and all(names) else ()


def task_note(locus, model, task=None) -> str | None:
    """The note for an empty locus of a robot whose task has more rows than it has joints.

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.loci import Locus
    >>> m = rankloci.load_model("planar2r")
    >>> task_note(Locus("planar2r", m.variables, {}, (6, 2), "svm", ()), m, "full")[:60]
    'the task has 6 rows (vx, vy, vz, wx, wy, wz) and planar2r ha'
    """
    from ..model import RobotModel, task_rows

    if not isinstance(model, RobotModel) or locus.components:
        return None
    rows = model.task if task is None else task_rows(task)
    n = len(model.variables)
    if len(rows) <= n:
        return None
    labels = ", ".join(("vx", "vy", "vz", "wx", "wy", "wz")[r] for r in rows)
    better = 'task="position" (--task position)' if n >= 3 else 'task="planar" (--task planar)'
    return (f"the task has {len(rows)} rows ({labels}) and {model.name} has {n} joints: J has "
            f"rank at most {n} and loses it only where all its {n}x{n} minors vanish, which "
            f"they do nowhere here, hence no component; for the singularities of a task with "
            f"at most {n} rows, try {better}")


def with_model_notes(locus, model, task=None):
    """``locus`` with the notes and joint names it takes from ``model``.

    Parameters
    ----------
    locus : Locus
        As the pipeline returned it.
    model : RobotModel or MatrixModel
    task : optional
        The task the locus was computed for (None: the model's own).

    Returns
    -------
    Locus
        With :func:`task_note` appended to ``notes`` when it applies, and for
        a URDF chain ``joint_names`` set and a note naming the joint of each
        variable.
    """
    notes = list(locus.notes)
    names = joint_names(model)
    if names:
        notes.append("joint variables of the URDF joints: "
                     + ", ".join(f"{v} = {j}" for v, j in zip(locus.variables, names)))
    note = task_note(locus, model, task)
    if note:
        notes.append(note)
    if not names and len(notes) == len(locus.notes):
        return locus
    return dataclasses.replace(locus, notes=tuple(notes), joint_names=names)
