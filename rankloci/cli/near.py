"""The ``ik`` and ``manipulability`` subcommands: what a robot does near its locus.

``ik`` follows a task-space line or polyline and writes the joint rates
(minimum two-norm, minimum infinity-norm or mixed), the discontinuity
indices and the distance to the nearest locus component at every step, as
CSV or JSON, with an optional figure.  ``manipulability`` gives the
manipulability ellipsoid and polytope at one configuration, the nearest
locus component and sigma_min/sigma_max, with an optional 2-D or 3-D figure.
Both compute the locus of the model's Jacobian (parameters at their values)
in a child process under ``--timeout`` and ``--memory``.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

from .output import output_target, progress_printer, write_atomic
from ..errors import UsageError
from .arguments import memory_arg, seed_arg, timeout_arg
from .running import command_deadline, limited
from ..process_limits import DEFAULT_MEMORY_MB

__all__ = ["add_parsers", "cmd_ik", "cmd_manipulability", "parse_vector", "parse_waypoints"]

EXIT_OK, EXIT_FAILED = 0, 1

#: Largest waypoint file read by ``ik --path`` (bytes) and most waypoints in it.
MAX_PATH_BYTES = 1 << 20
MAX_WAYPOINTS = 10000
#: Most time steps of ``ik``.
MAX_STEPS = 100000

EPILOG_IK = """examples:
  rankloci ik planar4r --q0 "0.62 0.23 1.0 0.46" --line "0.524572,3.032596 -> -1.475428,3.032596"
  rankloci ik planar4r --q0 "0.2 0.6 0.6 0.6" --line "1.430594,2.810773 -> 1.81366,3.56351" --norm 2
  rankloci ik pa10 --line "0.4,0.1,0.8 -> 0.5,-0.2,0.7" --norm mixed --format json -o rates.json
  rankloci ik planar4r --path examples/waypoints.csv --restrict 1 --plot rates.png

The path is in the position rows of the model's task (x, y for a planar arm,
x, y, z otherwise), traversed at constant speed in --duration; rows of angular
velocity hold the starting orientation.  Without --q0 the start is solved from
the first point.  Each step solves J(q) qdot = xdot: --norm 2 (pseudo-inverse),
inf (Ha and Lee's minimum infinity-norm algorithm), or mixed (r x_inf + (1 - r)
x_2, r = 1 - exp(-gain d) with d the discontinuity index).  The table has t,
q, the applied rates, the discontinuity index, the index formed with J (0 on
the locus), Gravagne's index over every face, the mixing ratio, sigma_min/sigma_max, the tracking error and the
distance to the nearest locus component.  The path stops early, saying so,
when J comes within 1e-6 (sigma_min/sigma_max) of losing rank.  Paths in these
examples are files of rankloci's source tree.
"""

EPILOG_MANIP = """examples:
  rankloci manipulability planar2r --q "pi/4 pi/4" --plot planar2r.png
  rankloci manipulability pa10 --q "0 pi/4 0 pi/4 0 pi/4 0" --format json
  rankloci manipulability puma560 --q "pi/4 pi/4 pi/4 pi/4 pi/4 pi/4" --plot puma.png

Prints the ellipsoid (semi-axes, w = sqrt(det J J')), the polytope (vertices,
facets, volume, cone-cell index w_p) for the task rows and for the position
rows, sigma_min/sigma_max, and the nearest locus component with the distance
to it and sigma_min/sigma_max at its nearest point.  The figure shows the
position rows: 2-D for two of them, 3-D for three.
"""


def _common(p):
    p.add_argument("model", metavar="MODEL|FILE",
                   help="a built-in model name (see 'rankloci models') or a .toml/.urdf file")
    p.add_argument("--base-link", dest="base_link", help="URDF only: first link of the chain")
    p.add_argument("--tip", dest="tip_link", help="URDF only: last link of the chain")
    p.add_argument("--plot", metavar="FILE.png",
                   help="write the figure to FILE.png (or .pdf, .svg)")
    p.add_argument("--no-locus", dest="locus", action="store_false",
                   help="skip the locus and the distance to its components")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the locus probes (default 0)")
    p.add_argument("--timeout", type=timeout_arg, default=600.0,
                   help="give up after this many seconds (default 600; 0 = never)")
    p.add_argument("--memory", type=memory_arg, default=DEFAULT_MEMORY_MB, metavar="MIB",
                   help=f"memory limit in MiB (default {DEFAULT_MEMORY_MB}; 0 = none)")
    p.add_argument("--quiet", action="store_true", help="no progress messages on stderr")


def add_parsers(sub, formatter_class) -> None:
    """Add the ``ik`` and ``manipulability`` subcommands to the subparsers ``sub``."""
    p = sub.add_parser("ik", help="joint rates along a task-space path (2-norm, inf-norm, mixed)",
                       epilog=EPILOG_IK, formatter_class=formatter_class)
    _common(p)
    where = p.add_mutually_exclusive_group(required=True)
    where.add_argument("--line", metavar='"X0 -> X1"',
                       help="a straight line between two task points, coordinates separated by "
                            "commas or spaces")
    where.add_argument("--path", metavar="FILE",
                       help="waypoints, one task point per line (commas or spaces; # comments)")
    p.add_argument("--norm", choices=("2", "inf", "mixed"), default="inf",
                   help="joint rates of least 2-norm, least infinity-norm, or mixed (default inf)")
    p.add_argument("--restrict", type=int, nargs="+", metavar="J", default=[],
                   help="joints (1-based) held still")
    p.add_argument("--q0", metavar='"Q1 Q2 ..."',
                   help="start configuration (numbers or expressions in pi); default: solved "
                        "from the first point")
    p.add_argument("--steps", type=int, default=200, help="time steps (default 200)")
    p.add_argument("--duration", type=float, default=1.0,
                   help="time to traverse the path (default 1)")
    p.add_argument("--gain", type=float, default=None,
                   help="gain a of the mixing ratio r = 1 - exp(-a d) (default 20)")
    p.add_argument("--format", choices=("csv", "json"), default="csv")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="write the table to FILE (default stdout)")

    p = sub.add_parser("manipulability",
                       help="manipulability ellipsoid and polytope at a configuration",
                       epilog=EPILOG_MANIP, formatter_class=formatter_class)
    _common(p)
    p.add_argument("--q", required=True, metavar='"Q1 Q2 ..."',
                   help="the configuration (numbers or expressions in pi)")
    p.add_argument("--format", choices=("text", "json"), default="text")


def parse_vector(text: str, n: int | None, what: str):
    """Numbers (or expressions in pi) separated by commas or spaces; ``n`` of them if given.

    Examples
    --------
    >>> parse_vector("0, pi/2 1e-3", 3, "--q")
    [0.0, 1.5707963267948966, 0.001]
    """
    import math

    from ..errors import ExpressionError
    from ..expr import parse_expression

    items = [t for t in re.split(r"[,\s]+", text.strip()) if t]
    if n is not None and len(items) != n:
        raise UsageError(f"{what}: expected {n} values, got {len(items)} in {text[:60]!r}")
    if not items:
        raise UsageError(f"{what}: no values in {text[:60]!r}")
    out = []
    for t in items:
        try:
            value = float(parse_expression(t).evalf())
        except (ExpressionError, TypeError, ValueError, OverflowError):
            raise UsageError(f"{what}: {t[:40]!r} is not a number or an expression in pi") from None
        if not math.isfinite(value):
            raise UsageError(f"{what}: {t[:40]!r} is not finite")
        out.append(value)
    return out


def parse_waypoints(text: str, k: int, what: str):
    """Rows of ``k`` numbers, one per line; blank lines and ``#`` comments are skipped."""
    rows = []
    for i, line in enumerate(text.splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        if len(rows) >= MAX_WAYPOINTS:
            raise UsageError(f"{what}: more than {MAX_WAYPOINTS} waypoints")
        rows.append(parse_vector(line, k, f"{what}: line {i}"))
    if len(rows) < 2:
        raise UsageError(f"{what}: a path needs at least 2 waypoints, got {len(rows)}")
    return rows


def _robot(args):
    from ..io import load_model
    from ..model import RobotModel

    model = load_model(args.model, base_link=args.base_link, tip=args.tip_link)
    if not isinstance(model, RobotModel):
        raise UsageError(f"{args.command} needs a robot model; {args.model!r} is a raw matrix")
    if any(getattr(j, "mimic", None) is not None for j in model.joints):
        raise UsageError(f"{args.command}: {model.name} has mimic joints, which are not "
                         "supported here")
    return model


def _check_out(option, path, suffixes):
    if path is None:
        return
    if option == "--plot":
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            from ..extras import install_command

            raise UsageError(f"--plot needs matplotlib ({install_command('report')})") from None
    output_target(path, option, suffixes)     # before the computation, not after it


def _locus_distance(model, args, tell):
    """The model's locus (the one ``rankloci locus`` shows) and a ComponentDistance over it."""
    from ..api.calls import certified_locus
    from ..near.nearest import ComponentDistance

    if tell:
        tell(f"{model.name}: computing the locus of its Jacobian (the locus rankloci locus "
             "shows)")
    stop = command_deadline(args.timeout, getattr(args, "started", None))
    locus, tm = certified_locus(model, seed=args.seed, should_stop=stop, progress=tell)
    labels = [", ".join(f"{e} = 0" for e in c.equations) for c in locus.components]
    return ComponentDistance(locus, tm.angles), labels


def _start(kin, args, first):
    import numpy as np
    from scipy.optimize import least_squares

    from ..tolerances import IK_START_RTOL

    n = len(kin.model.variables)
    scale = 1.0 + float(np.linalg.norm(first))
    if args.q0 is not None:
        q0 = np.array(parse_vector(args.q0, n, "--q0"))
        gap = float(np.linalg.norm(kin.position(q0) - first))
        if gap > IK_START_RTOL * scale:
            raise UsageError(f"--q0 puts the tool at {np.round(kin.position(q0), 6).tolist()}, "
                             f"{gap:.3g} from the path's first point")
        return q0
    res = least_squares(lambda q: kin.position(q) - first, np.full(n, 0.3), method="trf",
                        xtol=1e-15, ftol=1e-15, gtol=1e-15)
    if np.linalg.norm(res.fun) > IK_START_RTOL * scale:
        raise UsageError(f"the first point {list(first)} is out of reach from q = 0.3 (each "
                         f"joint); give --q0")
    return res.x


def cmd_ik(args) -> int:
    import numpy as np

    from ..near.discontinuity import DEFAULT_MIXING_GAIN
    from ..near.path import Kinematics, joint_rates_along
    from ..tolerances import REGULAR_MIN_RATIO

    if not 1 <= args.steps <= MAX_STEPS:
        raise UsageError(f"--steps must be between 1 and {MAX_STEPS}, got {args.steps}")
    if not (np.isfinite(args.duration) and args.duration > 0):
        raise UsageError(f"--duration must be a positive number, got {args.duration}")
    gain = DEFAULT_MIXING_GAIN if args.gain is None else args.gain
    if not (np.isfinite(gain) and gain > 0):
        raise UsageError(f"--gain must be a positive number, got {args.gain}")
    _check_out("-o", args.output, ())
    _check_out("--plot", args.plot, (".png", ".pdf", ".svg"))
    model = _robot(args)
    kin = Kinematics(model)
    k = len(kin.position_rows)
    if k == 0:
        raise UsageError(f"ik: the task of {model.name} has no position rows (vx, vy, vz)")
    if args.line is not None:
        parts = args.line.split("->")
        if len(parts) != 2:
            raise UsageError(f'--line {args.line[:60]!r}: write it as "X0 -> X1"')
        points = [parse_vector(p, k, "--line") for p in parts]
    else:
        from ..io.files import read_bounded

        try:
            raw = read_bounded(args.path, MAX_PATH_BYTES)
        except OSError as e:
            raise UsageError(f"--path {args.path!r}: cannot read: {e.strerror}") from None
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            raise UsageError(f"--path {args.path!r}: not UTF-8 text") from None
        points = parse_waypoints(text, k, f"--path {args.path}")
    n = len(model.variables)
    bad = [j for j in args.restrict if not 1 <= j <= n]
    if bad:
        raise UsageError(f"--restrict {bad[0]}: {model.name} has joints 1..{n}")
    restricted = sorted({j - 1 for j in args.restrict})
    if n - len(restricted) < len(kin.rows):
        left = n - len(restricted)
        raise UsageError(f"--restrict leaves {left} joint{'s' * (left != 1)} for "
                         f"{len(kin.rows)} task rows")
    q0 = _start(kin, args, np.array(points[0]))
    sv = np.linalg.svd(np.delete(kin.jacobian(q0), restricted, axis=1), compute_uv=False)
    if sv[-1] <= REGULAR_MIN_RATIO * sv[0]:
        raise UsageError(f"the start configuration {np.round(q0, 6).tolist()} is singular "
                         f"(sigma_min/sigma_max = {sv[-1] / sv[0] if sv[0] else 0.0:.1e}); "
                         "start elsewhere")
    progress = progress_printer(args.quiet)

    def work(tell):
        distance = None
        labels = []
        if args.locus:
            cd, labels = _locus_distance(model, args, tell)
        if tell:
            tell(f"{model.name}: {args.steps} steps along the path, --norm {args.norm}")
        path = joint_rates_along(Kinematics(model), q0, points, norm=args.norm,
                                 duration=args.duration, steps=args.steps,
                                 restricted=restricted, gain=gain)
        if args.locus:
            near = [cd.nearest(q, warm=True) for q in path.q]
            D = np.array([r.distances for r in near], dtype=float)
            distance = (D.reshape(len(near), len(labels)),
                        np.array([r.component for r in near], dtype=int))
        return path, distance, labels

    got = limited(args, work, progress, "the path")
    if got is None:
        return EXIT_FAILED
    path, distance, labels = got
    text = _ik_table(model, path, distance, labels, args.format)
    if args.plot:
        from ..near.figures import path_figure

        axes = path_figure(path, None if distance is None else distance[0], labels)
        _save(axes[0].figure, args.plot)
    if args.output:
        write_atomic(args.output, text, "-o")
    else:
        sys.stdout.write(text)
    if path.stopped:
        print(f"rankloci: note: {model.name}: the path {path.stopped}", file=sys.stderr)
    if path.lp_fallbacks:
        print(f"rankloci: note: {path.lp_fallbacks} step(s) used the linear program where Ha and "
              f"Lee's algorithm did not certify an optimum", file=sys.stderr)
    return EXIT_OK


def _save(fig, path):
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format=Path(path).suffix.lower().lstrip("."), dpi=120)
    write_atomic(path, buf.getvalue(), "--plot")


def _ik_table(model, path, distance, labels, fmt) -> str:
    import numpy as np

    names = [v.name for v in model.variables]
    columns = (["t"] + names + [f"rate_{v}" for v in names]
               + ["index", "index_J", "index_all_faces", "mixing", "sigma_ratio",
                  "tracking_error"])
    data = [path.t[:, None], path.q, path.rates, path.index[:, None], path.minor_index[:, None],
            path.subspace_index[:, None], path.mixing[:, None], path.sigma_ratio[:, None],
            path.error[:, None]]
    if distance is not None:
        D, comp = distance
        columns += ["distance", "nearest_component"]
        finite = np.where(np.isfinite(D), D, np.inf)
        data += [finite.min(axis=1, initial=np.inf)[:, None], comp[:, None]]
    rows = np.hstack(data) if len(path.t) else np.zeros((0, len(columns)))
    if fmt == "json":
        doc = {"model": model.name, "norm": path.norm,
               "restricted": [j + 1 for j in path.restricted], "stopped": path.stopped or None,
               "lp_fallbacks": path.lp_fallbacks, "components": labels, "columns": columns,
               "rows": [[_num(x) for x in row] for row in rows]}
        return json.dumps(doc, indent=1) + "\n"
    lines = [",".join(columns)]
    for row in rows:
        lines.append(",".join(_fmt(c, x) for c, x in zip(columns, row)))
    return "\n".join(lines) + "\n"


def _num(x):
    import math

    x = float(x)
    return x if math.isfinite(x) else None


def _fmt(column, x) -> str:
    if column == "nearest_component":
        return str(int(x))
    return f"{float(x):.10g}"


def _measures(J) -> dict:
    """Ellipsoid and polytope numbers of J."""
    from ..near.manipulability import MAX_POLYTOPE_COLUMNS, ellipsoid, polytope

    E = ellipsoid(J)
    out = {"rows": int(J.shape[0]), "w": E.w, "semi_axes": E.radii.tolist(),
           "axes": E.axes.T.tolist(), "sigma_ratio": E.sigma_ratio,
           "ellipsoid_volume": E.volume}
    if J.shape[1] <= MAX_POLYTOPE_COLUMNS:
        P = polytope(J)
        out |= {"polytope_vertices": len(P.vertices), "polytope_facets": len(P.normals),
                "polytope_volume": P.volume, "w_p": P.w_p, "polytope_rank": P.rank,
                "polytope_flat": P.flat}
    return out


def cmd_manipulability(args) -> int:
    import numpy as np

    from ..near.path import Kinematics

    _check_out("--plot", args.plot, (".png", ".pdf", ".svg"))
    model = _robot(args)
    kin = Kinematics(model)
    q = np.array(parse_vector(args.q, len(model.variables), "--q"))
    J = kin.jacobian(q)
    pos = [kin.rows.index(r) for r in kin.position_rows]
    result = {"model": model.name, "q": q.tolist(),
              "task": _measures(J) | {"row_names": [_ROW_NAMES[r] for r in kin.rows]}}
    if pos and len(pos) < len(kin.rows):
        names = [_ROW_NAMES[kin.rows[i]] for i in pos]
        result["position"] = _measures(J[pos]) | {"row_names": names}
    if args.plot and len(pos) not in (2, 3):
        raise UsageError(f"--plot draws 2 or 3 position rows; the task of {model.name} has "
                         f"{len(pos)}")
    progress = progress_printer(args.quiet)
    if args.locus:
        def work(tell):
            cd, labels = _locus_distance(model, args, tell)
            return cd.nearest(q), labels

        got = limited(args, work, progress, "the locus computation")
        if got is None:
            return EXIT_FAILED
        near, labels = got
        if near.component > 0:
            s = np.linalg.svd(kin.jacobian(near.point), compute_uv=False)
            result["nearest_component"] = {
                "component": near.component, "equations": labels[near.component - 1],
                "distance": near.distance, "point": near.point.tolist(),
                "sigma_ratio_at_point": float(s[-1] / s[0]) if s[0] > 0 else 0.0,
                "distances": [_num(d) for d in near.distances]}
        else:
            result["nearest_component"] = None
    if args.plot:
        from ..near.figures import plot_manipulability

        _save(plot_manipulability(J[pos]).figure, args.plot)
    if args.format == "json":
        print(json.dumps(result, indent=1))
    else:
        print(_manipulability_text(result))
    return EXIT_OK


_ROW_NAMES = ("vx", "vy", "vz", "wx", "wy", "wz")


def _manipulability_text(r) -> str:
    q = ", ".join(f"{x:.4f}" for x in r["q"])
    lines = [f"{r['model']} at q = ({q})"]
    for key in ("task", "position"):
        if key not in r:
            continue
        m = r[key]
        lines.append(f"{key} rows ({', '.join(m['row_names'])}):")
        lines.append(f"  ellipsoid: w = sqrt(det J J') = {m['w']:.6g}, semi-axes "
                     f"{', '.join(f'{x:.6g}' for x in m['semi_axes'])}, "
                     f"sigma_min/sigma_max = {m['sigma_ratio']:.6g}")
        if "w_p" in m:
            flat = ", flat" if m["polytope_flat"] else ""
            lines.append(f"  polytope: {m['polytope_vertices']} vertices, "
                         f"{m['polytope_facets']} facets, volume {m['polytope_volume']:.6g}, "
                         f"cone-cell index w_p = {m['w_p']:.6g}, "
                         f"dimension {m['polytope_rank']}{flat}")
        else:
            lines.append("  polytope: too many columns to enumerate")
    near = r.get("nearest_component", "absent")
    if near is None:
        lines.append("nearest locus component: none reached")
    elif near != "absent":
        lines.append(f"nearest locus component: {near['component']}. {near['equations']}")
        lines.append(f"  distance {near['distance']:.6g} (joint space); sigma_min/sigma_max "
                     f"there {near['sigma_ratio_at_point']:.2e}")
    return "\n".join(lines)
