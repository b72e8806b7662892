"""The symbolic matrix whose rank is studied, built from any model.

:func:`task_matrix` turns a :class:`RobotModel` (through its geometric
Jacobian) or a :class:`MatrixModel` into a :class:`TaskMatrix`, optionally
augmented with the gradients of constraint functions g(q) and with the
parameters replaced by their numeric values.  :func:`pivot_constant_columns`
takes out the constant pivot columns (a prismatic base joint in the base
frame, say) before a locus is computed.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np
import sympy as sp

from .errors import ExpressionError, ModelError
from .expr import parse_expression
from .kinematics import augmented_rows, geometric_jacobian, turns_about_z
from .model import MatrixModel, RobotModel, task_rows

__all__ = ["TaskMatrix", "task_matrix", "parse_constraints", "pivot_constant_columns",
           "lift_directions"]

_ROW_NAMES = ("vx", "vy", "vz", "wx", "wy", "wz")


@dataclass(frozen=True)
class TaskMatrix:
    """A symbolic matrix with what is needed to study its rank.

    Attributes
    ----------
    name : str
        Model name.
    matrix : sympy.ImmutableMatrix
    variables : tuple of Symbol
        Column variables (joint variables).
    angles : tuple of Symbol
        The variables that enter only through sin and cos.
    parameters : dict
        Symbol -> numeric value, for the parameters still symbolic in ``matrix``.
    row_labels : tuple of str
        What each row is (``vx``, ``wz``, or the name of a constraint).
    n_constraint_rows : int
        How many trailing rows are constraint gradients.
    """

    name: str
    matrix: sp.ImmutableMatrix
    variables: tuple[sp.Symbol, ...]
    angles: tuple[sp.Symbol, ...]
    parameters: Mapping[sp.Symbol, sp.Expr] = field(default_factory=dict)
    row_labels: tuple[str, ...] = ()
    n_constraint_rows: int = 0
    frame: object = None     # frame and reference point the Jacobian rows use
    point: object = None
    rows: tuple = ()         # the selected rows of the 6-row Jacobian
    notes: tuple = ()        # what building the matrix changed (constant angles made exact)

    @property
    def shape(self) -> tuple[int, int]:
        return self.matrix.shape

    def evaluate(self, q) -> np.ndarray:
        """The matrix at configurations, as numbers (the parameters at their values).

        Parameters
        ----------
        q : array_like or mapping
            One configuration (the values of :attr:`variables` in order, or a
            mapping from variable name or symbol to value), or N of them as an
            (N, n) array.

        Returns
        -------
        numpy.ndarray
            Shape (rows, cols) for one configuration, (N, rows, cols) for N.

        Raises
        ------
        rankloci.errors.ArgumentError
            A value that is not a finite number (NaN), or the wrong number of values.

        Examples
        --------
        >>> import rankloci
        >>> J = rankloci.jacobian("planar2r")
        >>> [int(np.linalg.matrix_rank(Jq)) for Jq in J.evaluate([[0.3, 0.0], [0.3, 1.0]])]
        [1, 2]
        >>> J.evaluate(np.zeros((5, 2))).shape
        (5, 2, 2)
        """
        from .numeric.equations import NumericMatrix
        from .numeric.points import configurations

        X, single = configurations(q, self.variables)
        numeric = self.__dict__.get("_numeric")
        if numeric is None:
            M = sp.Matrix(self.matrix).subs(self.parameters)
            numeric = self.__dict__.setdefault("_numeric",
                                               NumericMatrix(M, self.variables, self.angles))
        values = numeric.batch(X)
        return values[0] if single else values

    def __getstate__(self):
        # the function cached by evaluate() is lambdified: not pickled
        return {k: v for k, v in self.__dict__.items() if k != "_numeric"}

    def numeric_parameters(self) -> "TaskMatrix":
        """The same matrix with every parameter replaced by its value."""
        if not self.parameters:
            return self
        import dataclasses

        M, notes = exact_constant_angles(sp.Matrix(self.matrix.subs(self.parameters)))
        return dataclasses.replace(self, matrix=sp.ImmutableMatrix(M), parameters={},
                                   notes=tuple(dict.fromkeys(self.notes + notes)))


def _small_frame(model: RobotModel, rows, point):
    """A frame (and point) in which the Jacobian has the smallest entries, same rank.

    A rotation of the frame multiplies the linear and the angular rows by the
    same invertible matrix, so it keeps the rank for the full, position and
    orientation tasks; moving the reference point adds angular rows to linear
    ones, which keeps the rank only for the full task.  A middle link's frame
    halves the length of the chains of transforms on either side.
    """
    middle = model.dof // 2
    kinds = [j.kind for j in model.joints]
    if kinds[:2] == ["prismatic", "prismatic"]:
        # a mobile base: in the base frame its columns are constant and are pivoted out
        return "base", point
    if kinds and kinds[0] == "prismatic" and tuple(rows) == (0, 1, 2, 3, 4, 5):
        # one lift before an arm: the middle of the arm, as for an arm alone (measured,
        # full task: tiago's torso and 7R arm 35 s there against over 300 s in the base
        # frame, PR2's 9 s against 10 s; a planar base, above, is the other way round)
        middle = 1 + (model.dof - 1) // 2
        return middle, middle
    if tuple(rows) == (0, 1, 2, 3, 4, 5):
        return middle, middle
    if tuple(rows) in ((0, 1, 2), (3, 4, 5)):
        return middle, point
    if set(rows) <= {0, 1, 5} and turns_about_z(model, middle):
        # a planar arm: vx, vy (and wz) of the middle frame are those of the model's
        # frame turned about z, so the rank is the same
        return middle, point
    return model.frame, point


def parse_constraints(model, texts: Sequence[str], *,
                      flag: str = "--augment") -> tuple[tuple[str, sp.Expr], ...]:
    """Parse ``--augment`` expressions in the model's variables and parameters.

    Errors name ``flag`` (``"augment"`` for the Python API).
    """
    names = {v.name: v for v in model.variables} | {p.name: p for p in model.parameters}
    out = []
    for t in texts:
        try:
            out.append((t, parse_expression(t, names)))
        except ExpressionError as e:
            raise ModelError(f"{flag}: {e}") from None
    return tuple(out)


def task_matrix(model, *, task=None, frame=None, point="tool", augment: Sequence = (),
                use_model_augment: bool = True, numeric: bool = False) -> TaskMatrix:
    """Build the matrix to study from a model.

    Parameters
    ----------
    model : RobotModel or MatrixModel
    task, frame, point
        Passed to :func:`~rankloci.kinematics.geometric_jacobian` (robots only).
        ``frame="auto"`` picks a frame (and, for the full task, a reference
        point) in which the entries are small and the rank is the same; for
        an arm whose first joint is prismatic (a mobile base), the base frame,
        where the base's columns are constant.
    augment : sequence of (name, expr)
        Extra constraint functions; their gradients are stacked under J.
    use_model_augment : bool, default True
        Also stack the model's own ``[[augment]]`` rows.
    numeric : bool, default False
        Replace the parameters by their numeric values.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> tm = task_matrix(load_model("planar2r"))
    >>> tm.shape, tm.row_labels
    ((2, 2), ('vx', 'vy'))
    """
    constraints = (tuple(model.augment) if use_model_augment else ()) + tuple(augment)
    if isinstance(model, RobotModel):
        rows = model.task if task is None else task_rows(task)
        if frame == "auto":
            frame, point = _small_frame(model, rows, point)
        frame = model.frame if frame is None else frame
        J = geometric_jacobian(model, frame=frame, point=point, task=task)
        labels = tuple(_ROW_NAMES[r] for r in rows)
        angles = model.angle_variables
    elif isinstance(model, MatrixModel):
        if task is not None or frame not in (None, "auto"):
            raise ModelError("--task and --frame apply to robot models, not to a raw matrix",
                             file=model.name)
        J = sp.Matrix(model.matrix)
        labels = tuple(f"row{i + 1}" for i in range(J.rows))
        angles = model.angle_variables
    else:
        raise TypeError(f"model must be a RobotModel or MatrixModel, got {type(model).__name__}")
    if constraints:
        J = J.col_join(augmented_rows(model, [g for _, g in constraints]))
        labels += tuple(name for name, _ in constraints)
    robot = isinstance(model, RobotModel)
    J, notes = exact_constant_angles(J)
    tm = TaskMatrix(model.name, sp.ImmutableMatrix(J), tuple(model.variables), angles,
                    dict(model.parameters), labels, len(constraints),
                    frame=frame if robot else None, point=point if robot else None,
                    rows=tuple(rows) if robot else (), notes=notes)
    return tm.numeric_parameters() if numeric else tm


def _constant_part(arg):
    """The constant angle in a sine or cosine argument whose value has no exact radical form
    (``3/10``, ``2*pi/7``; not ``pi/4``), or None."""
    const = sp.Add(*[t for t in sp.Add.make_args(arg) if t.is_number])
    if const == 0 or not const.is_real:
        return None
    if not (sp.cos(const).has(sp.cos) or sp.sin(const).has(sp.sin)):
        return None
    return const


def exact_constant_angles(M):
    """``M`` with the sines and cosines of constant angles made exact, and notes saying how.

    One policy for every input format (DH tables, raw matrices, sympy, Robotics Toolbox and
    Pinocchio robots), the one URDF angles get (:mod:`rankloci.io.urdf_exact`): a constant
    angle within 1e-5 of a multiple of pi/12 is that multiple, whose sine and cosine are exact
    square roots; any other (a twist of 0.3 rad, 2*pi/7) becomes the exactly orthogonal
    rotation by ``2*atan(u)`` with ``u`` the shortest rational within 1e-9 rad of it, so that
    cos**2 + sin**2 = 1 holds exactly.  Angles that already have exact radical values
    (``pi/4``) are left as they are.

    Examples
    --------
    >>> q = sp.Symbol("q", real=True)
    >>> M, notes = exact_constant_angles(sp.Matrix([[sp.cos(q + sp.Rational(3, 10))]]))
    >>> M[0, 0].atoms(sp.cos)
    {cos(q)}
    >>> len(notes)
    1
    """
    from .io.urdf_exact import cos_sin

    found = {}
    for a in M.atoms(sp.sin, sp.cos):
        const = _constant_part(a.args[0])
        if const is not None and const not in found:
            found[const] = cos_sin(float(const))
    if not found:
        return M, ()

    def rewrite(f, arg):
        const = _constant_part(arg)
        if const is None:
            return f(arg)
        c, s_ = found[const]
        rest = arg - const
        if f is sp.cos:
            return sp.cos(rest) * c - sp.sin(rest) * s_
        return sp.sin(rest) * c + sp.cos(rest) * s_

    out = M.applyfunc(lambda e: e.replace(
        lambda x: isinstance(x, (sp.sin, sp.cos)) and _constant_part(x.args[0]) is not None,
        lambda x: rewrite(type(x), x.args[0])))
    out = out.applyfunc(sp.expand)
    notes = []
    for const, (c, s_) in sorted(found.items(), key=lambda kv: float(kv[0])):
        err = abs(float(sp.atan2(s_, c)) - ((float(const) + np.pi) % (2 * np.pi) - np.pi))
        notes.append(f"the constant angle {sp.sstr(const)} has no exact radical sine and "
                     f"cosine: it was read as the exact rotation with cos = {sp.sstr(c)}, "
                     f"sin = {sp.sstr(s_)}, {err:.1e} rad from it")
    return out, tuple(notes)


def pivot_constant_columns(tm):
    """``tm`` without the rows and columns of constant pivot columns, and the pivots.

    A column whose entries in the remaining rows are numbers, exactly one of
    them nonzero (a prismatic base joint in the base frame, say), is a pivot:
    column operations clear its row elsewhere, so rank J = 1 + rank of J
    without that row and column.  Only for matrices with at least as many
    columns as rows (then the left null vectors of the rest, with zeros in
    the pivot rows, are those of J).

    Returns
    -------
    TaskMatrix, list of (row, column)
    """
    J = tm.matrix
    if J.rows > J.cols:
        return tm, []
    rows, cols = list(range(J.rows)), list(range(J.cols))
    pivots = []
    found = True
    while found and rows:
        found = False
        for j in cols:
            entries = [J[i, j] for i in rows]
            if all(e.is_number for e in entries):
                nonzero = [i for i, e in zip(rows, entries) if e != 0]
                if len(nonzero) == 1:
                    pivots.append((nonzero[0], j))
                    rows.remove(nonzero[0])
                    cols.remove(j)
                    found = True
                    break
    if not pivots:
        return tm, []
    labels = tuple(tm.row_labels[i] for i in rows) if tm.row_labels else ()
    return dataclasses.replace(tm, matrix=sp.ImmutableMatrix(J.extract(rows, cols)),
                               row_labels=labels), pivots


def lift_directions(comp, pivot_rows, n_rows):
    """``comp`` with the lost directions of the reduced matrix made directions of J.

    The pivot rows of :func:`pivot_constant_columns` get zeros.
    """
    if not pivot_rows:
        return comp
    keep = [i for i in range(n_rows) if i not in pivot_rows]

    def lift(vec, zero):
        out = [zero] * n_rows
        for i, x in zip(keep, vec):
            out[i] = x
        return tuple(out)

    return dataclasses.replace(
        comp, direction=tuple(lift(v, sp.Integer(0)) for v in comp.direction),
        direction_at_sample=tuple(lift(v, 0.0) for v in comp.direction_at_sample))
