"""One locus computation: its ring, its matrix, its branch tree, its leaves and notes.

A method (:mod:`rankloci.methods`) grows the tree through a
:class:`Context`: it opens branches, adds nodes, and records the leaves that
are components.  The algebra of branches lives in :mod:`.branch` and
:mod:`.cover`, their points in :mod:`.sampler`, the numeric tests in
:mod:`.probe`, and the pruning of branches inside components already found
in :mod:`.prune`.
"""

from __future__ import annotations

import types

import networkx as nx
import numpy as np
import sympy as sp

from ..algebra import PolyMemo, PolyRing, circle_free_det, irreducible_factors
from ..algebra.ring import square_root_primes
from ..errors import LocusError, LocusTimeout
from ..loci import Outcome, dimension_bound
from . import cover, prune, reducible
from .branch import Branch, SubstitutedMatrices
from .modular import ModularProbe
from .precise import PreciseProbe
from .probe import Probe
from .sampler import BranchSampler

__all__ = ["Context"]

#: Terms of polynomials (keys and values) kept by each of a computation's memos of
#: determinants and factorisations: ~30 bytes a term, so about 150 MB each at most.
MEMO_MAX_TERMS = 5_000_000


class Context:
    """State of one locus computation.

    Parameters
    ----------
    tm : TaskMatrix
        The matrix (after constant pivot columns were taken out).
    method : str
        The method's name, for messages.
    rng : numpy.random.Generator
        The random source of every numeric probe.
    progress : callable, optional
        Called with one-line progress messages.
    should_stop : callable, optional
        Polled at every node; when it returns True the computation raises
        :class:`~rankloci.errors.LocusTimeout`.
    """

    def __init__(self, tm, *, method: str, rng: np.random.Generator, progress=None,
                 should_stop=None):
        self.tm = tm
        self.method = method
        angles = tuple(tm.angles)
        others = tuple(v for v in tm.variables if v not in angles)
        used = set().union(*(e.free_symbols for e in tm.matrix)) if len(tm.matrix) else set()
        params = tuple(sorted((p for p in tm.parameters if p in used), key=lambda s: s.name))
        unknown = used - set(tm.variables) - set(params)
        if unknown:
            raise LocusError(f"the matrix uses symbols that are neither variables nor parameters: "
                             f"{', '.join(sorted(map(str, unknown)))}")
        self.ring = PolyRing(angles, others, params, square_root_primes(tm.matrix))
        self.M = self.ring.from_sympy_rows(sp.Matrix(tm.matrix))
        self.shape = tm.matrix.shape
        self.rng = rng
        #: the model's own parameter values (of the parameters the matrix uses)
        self.model_values = {p: float(tm.parameters[p]) for p in params}
        # Zero tests in the tree use generic parameter values, so that a
        # polynomial is "zero" only when it is zero for all parameters; the
        # model's own values are used for the samples reported to the user.
        generic = {p: _generic_value(v, self.rng) for p, v in self.model_values.items()}
        self.model_sampler = BranchSampler(self.ring, self.model_values, self.rng) if params else None
        self.sampler = BranchSampler(self.ring, generic, self.rng, fallback=self.model_sampler)
        if self.model_sampler is None:
            self.model_sampler = self.sampler
        self.probe = Probe(self.ring)
        # its own random stream, so that the numeric samples do not depend on it
        self.modular = ModularProbe(self.ring, rng.spawn(1)[0])
        self.precise = PreciseProbe(self.ring, self.M)
        self._closure_caches: dict = {}
        self.substituted = SubstitutedMatrices(self.ring)
        # sibling branches often substitute into a block without changing it
        self._dets = PolyMemo(MEMO_MAX_TERMS)
        self._factors = PolyMemo(MEMO_MAX_TERMS)
        # node labels: a tree repeats a condition on many nodes (on centauro's arm, 27
        # distinct labels on 97 nodes, up to 32000 characters, 0.77 s to print them all)
        self._labels = PolyMemo(MEMO_MAX_TERMS)
        self.tree = nx.DiGraph()
        self.leaves: list[tuple[Branch, int]] = []
        # The state below changes only through the methods of this class (note,
        # set_exclusions, add_exclusions, count_repaired, symbolic_direction, resume); the
        # other modules read it.
        #: branch key -> polynomials a component of that leaf is reported without (see
        #: .reducible: its equations also hold, with J regular, where a substitution degenerates)
        self._exclusions: dict = {}
        self._notes: list[str] = []
        #: leaves changed by hints (see .reducible.repair_leaves), over every round of them
        self._repaired = 0
        #: (leaf key, rank drop) -> the symbolic lost directions of its component (finalize)
        self._directions: dict = {}
        self._listen(progress, should_stop)

    def _listen(self, progress, should_stop):
        self.progress = progress or (lambda msg: None)
        #: whether messages are read: a message that prints a leaf's conditions costs as much
        #: as the rest of the leaf's bookkeeping where they have thousands of terms
        self.reporting = progress is not None
        self.should_stop = should_stop or (lambda: False)

    # --- the state other modules change through these methods ----------------------------

    @property
    def notes(self) -> tuple:
        """What the computation has to say about its result, in order."""
        return tuple(self._notes)

    def note(self, text: str) -> None:
        """Add a note."""
        self._notes.append(text)

    @property
    def exceptional_exclusions(self) -> types.MappingProxyType:
        """Branch key -> the polynomials a component of that leaf is reported without."""
        return types.MappingProxyType(self._exclusions)

    def set_exclusions(self, branch: Branch, polys) -> None:
        """The exclusions of ``branch``'s component are ``polys`` (those kept before go)."""
        self._exclusions[branch.key] = list(polys)

    def add_exclusions(self, branch: Branch, polys) -> list:
        """Add to the exclusions of ``branch``'s component those of ``polys`` not among them;
        returns those added."""
        kept = self._exclusions.setdefault(branch.key, [])
        new = [f for f in polys if not any(f == k for k in kept)]
        kept.extend(new)
        return new

    @property
    def repaired(self) -> int:
        """Leaves changed by hints, over every round of them."""
        return self._repaired

    def count_repaired(self, n: int) -> int:
        """Count ``n`` more leaves changed by hints; returns the total."""
        self._repaired += n
        return self._repaired

    def symbolic_direction(self, key, make):
        """The lost directions kept under ``key`` (leaf key, rank drop), made by ``make()`` the
        first time: a computation resumed with hints finalises the same leaves again."""
        if key not in self._directions:
            self._directions[key] = make()
        return self._directions[key]

    def replace_leaf(self, branch: Branch, node: int, split) -> bool:
        """Take the leaf ``(branch, node)`` out and call ``split()``, which records its pieces;
        when that returns False the leaf goes back in its place.  Returns what it returned."""
        at = next(i for i, (b, n) in enumerate(self.leaves) if b is branch and n == node)
        del self.leaves[at]
        if split():
            return True
        self.leaves.insert(at, (branch, node))
        return False

    def resume(self, *, progress=None, should_stop=None, notes_kept: int) -> None:
        """Take the computation up again with new listeners, keeping its first ``notes_kept``
        notes (those of a later finalisation are written again)."""
        del self._notes[notes_kept:]
        self._listen(progress, should_stop)

    def copy(self) -> "Context":
        """An independent copy to take the computation up again in: the tree, the leaves,
        the exclusions, the notes, the random streams and every cache whose entries depend on
        them are copied, so that nothing done with the copy changes this context.  The ring,
        the matrix and the memos of exact results (determinants, factors, labels, numeric
        evaluators), which depend on nothing random, are shared."""
        import copy

        new = copy.copy(self)
        new.rng = copy.deepcopy(self.rng)
        new.tree = self.tree.copy()
        new.leaves = list(self.leaves)
        new._exclusions = {k: list(v) for k, v in self._exclusions.items()}
        new._notes = list(self._notes)
        new._directions = dict(self._directions)
        new._closure_caches = dict(self._closure_caches)
        fallback = None
        if self.model_sampler is not None and self.model_sampler is not self.sampler:
            fallback = self.model_sampler.copy(new.rng)
        new.sampler = self.sampler.copy(new.rng, fallback=fallback)
        new.model_sampler = fallback if fallback is not None else new.sampler
        new.modular = self.modular.copy()
        return new

    @property
    def full_rank(self) -> int:
        """min(rows, cols) of the matrix."""
        return min(len(self.M), len(self.M[0]))

    # --- the tree -------------------------------------------------------------------------

    def tick(self):
        """Raise :class:`LocusTimeout` if the caller asked to stop."""
        if self.should_stop():
            raise LocusTimeout(
                f"the {self.method} computation did not finish within its time budget "
                f"({self.tree.number_of_nodes()} branches explored)")

    def add_node(self, parent, branch: Branch, **attrs) -> int:
        """A new node of the tree for ``branch`` below ``parent`` (None: a root)."""
        node = self.tree.number_of_nodes()
        cond = branch.conditions[-1] if branch.conditions else None
        label = (self._labels.get((cond,), lambda key: sp.sstr(self.ring.to_sympy(key[0])))
                 if cond is not None else "(all configurations)")
        self.tree.add_node(node, condition=label, depth=len(branch.conditions), **attrs)
        if parent is not None:
            self.tree.add_edge(parent, node)
        return node

    def annotate(self, node: int, **attrs):
        """Set attributes (``outcome``, ``columns``, ``k`` ...) of a node."""
        self.tree.nodes[node].update(attrs)

    def open_branch(self, branch: Branch, node: int):
        """Sample points of ``branch``, or None after marking ``node`` empty or known."""
        self.tick()
        if prune.known_symbolically(self, branch):
            self.annotate(node, outcome=Outcome.KNOWN)
            return None
        pts = self.sampler.points(branch)
        if not pts:
            self.annotate(node, outcome=Outcome.EMPTY)
            return None
        if prune.below_bound(self, branch, pts):
            self.annotate(node, outcome=Outcome.BELOW_BOUND)
            return None
        if prune.known(self, branch):
            self.annotate(node, outcome=Outcome.KNOWN)
            return None
        return pts

    def leaf(self, branch: Branch, node: int, outcome: Outcome):
        """Record a terminal branch, if the whole matrix really loses rank on it.

        A branch of J-dagger where the chosen null vectors vanish is no
        component: J has full rank at its generic points, and those points
        are covered by the sub-branch on which the null vectors degenerate.
        """
        pts = self.sampler.points(branch)
        if prune.known(self, branch):
            self.annotate(node, outcome=Outcome.KNOWN)
            return
        if pts and self.regular_throughout(branch, pts):
            self.annotate(node, outcome=Outcome.COVERED)
            return
        # the points modulo a prime can lie on a piece without real points, and nearly
        # degenerate geometry brings regular real points below the numeric tolerance:
        # the real points decide, in extended precision (see .precise)
        if pts and self.precise.affordable(branch):
            # the first point not shown regular ends the test; a point singular to rounding
            # in double precision (LEAF_PRECISE_FLOOR) ends it without the extended precision
            if all(self.real_verdict(branch, g) is False for g in pts):
                self.annotate(node, outcome=Outcome.COVERED,
                              note="regular at its real points (extended precision)")
                return
        # more points than the first few, all singular: the equations may also hold on a
        # regular piece (see .reducible); such a branch is split on a minor
        regular, _, exceptional = reducible.ranked_points(self, branch)
        if exceptional:
            self.annotate(node, outcome=Outcome.EXCEPTIONAL)
            return
        if regular and reducible.split_on_minor(self, branch, node, regular, outcome):
            return
        self.annotate(node, outcome=outcome)
        self.leaves.append((branch, node))
        if self.reporting:
            self.progress(f"component found at branch {node} ({outcome}): "
                          f"{', '.join(sp.sstr(self.ring.to_sympy(c)) for c in branch.conditions)}")

    def regular_throughout(self, branch: Branch, points) -> bool:
        """Is the whole matrix of full rank at the generic points of every piece of ``branch``?

        Yes when it is at every real sample point.  When it is at none, the exact rank
        modulo a prime decides (it corrects ranks that near-degenerate geometry pushes
        below the numeric tolerance, see :meth:`rank`).  When it is at some points and not
        at others, the branch may be reducible with a singular piece that a rank taken over
        all the points would hide (PR2's finger chains): no, and the caller looks closer,
        unless the branch is below the determinantal dimension bound
        (:func:`rankloci.verify.dimension_bound`, rank drop 1) at each singular point.
        Every component of the set where the matrix loses rank has at least that
        dimension, so a singular piece of a smaller branch lies inside a larger component,
        reached by a branch of its own.
        """
        regular = [self.probe.rank_at(self.M, g) == self.full_rank for g in points]
        if all(regular):
            return True
        if not any(regular):
            return self.rank(self.M, branch, points) == self.full_rank
        singular = [g for g, r in zip(points, regular) if not r]
        return max(self.local_dimension(branch, g) for g in singular) < self.dimension_bound

    @property
    def dimension_bound(self) -> int:
        """The smallest dimension of a component of the locus, in the joint variables.

        :func:`rankloci.verify.dimension_bound` for rank drop 1, which bounds every
        component whatever its rank drop.
        """

        joints = self.ring.n_angles + len(self.ring.others)
        return dimension_bound((len(self.M), len(self.M[0])), joints, 1)

    def local_dimension(self, branch: Branch, g) -> int:
        """Dimension of ``branch`` at its point ``g``, numerically.

        The joint variables minus the rank of the conditions' gradient at ``g``
        (see :func:`rankloci.numeric.equations.dimension_from_gradient`).
        """
        from ..numeric.equations import dimension_from_gradient

        joints = self.ring.n_angles + len(self.ring.others)
        if not branch.conditions:
            return joints
        grads = [d for c in branch.conditions for d in self.ring.gradient(c)]
        G = np.asarray(self.ring.compile(grads)(np.asarray([g], dtype=float)), dtype=float)
        return dimension_from_gradient(G.reshape(len(branch.conditions), joints))

    def closure_cache(self, leaf: Branch) -> dict:
        """The evaluators and conversions of ``leaf``'s polynomials that the closure proofs
        of :func:`.prune.in_closure` keep between points (kept by the leaf's identity)."""
        got = self._closure_caches.get(id(leaf))
        if got is None or got[0] is not leaf:
            got = (leaf, {})
            self._closure_caches[id(leaf)] = got
        return got[1]

    def real_verdict(self, branch: Branch, g, ratio: float | None = None) -> bool | None:
        """Is the whole matrix singular at the real point of ``branch`` next to ``g``?

        Singular where its sigma_min/sigma_max (rows scaled; ``ratio`` when the caller has
        it) is at most LEAF_PRECISE_FLOOR in double precision, decided in extended precision
        (:mod:`.precise`) otherwise; None where that is undecided.
        """
        from ..tolerances import LEAF_PRECISE_FLOOR
        from .probe import scaled_ratio

        if ratio is None:
            ratio = scaled_ratio(*self.probe.evaluated(self.M, g))
        if ratio <= LEAF_PRECISE_FLOOR:
            return True
        return self.precise.singular(branch, g)

    def leaves_below(self, parent: int, children, outcome: Outcome, **attrs):
        """One node per child branch below ``parent``: a leaf, or empty without real points."""
        for child in children:
            self.tick()
            node = self.add_node(parent, child, **attrs)
            if self.sampler.points(child):
                self.leaf(child, node, outcome)
            else:
                self.annotate(node, outcome=Outcome.EMPTY)

    def split(self, branch: Branch, parent: int, p, where: str, then, *,
              keep_parameter_only: bool = False):
        """A refined node for each branch of ``branch`` on a factor of ``p``, passed to ``then``.

        Factors in the parameters alone are noted (see
        :meth:`special_parameters`) and not followed, unless
        ``keep_parameter_only``.  ``then(child, node)`` carries on below.
        """
        seen: set = set()       # the factors' branches can coincide: each is followed once
        for f in self.factors(p):
            if self.parameter_only(f) and not keep_parameter_only:
                self.special_parameters(f, where)
                continue
            for child in cover.distinct(cover.children(self, branch, f), seen):
                then(child, self.add_node(parent, child, outcome=Outcome.REFINED))

    # --- decisions on a branch ---------------------------------------------------------------

    def rank(self, M, branch: Branch, points) -> int:
        """Rank of ``M`` (substituted for ``branch``) on ``branch``.

        The larger of the exact rank at points modulo a prime (see
        :mod:`.modular`), where the branch has such points, and the numeric
        rank at its real sample points.  The exact rank corrects a numeric
        rank that near-degenerate geometry pushes below the tolerance; the
        real points reach pieces of a reducible branch that the points
        modulo the prime, each solved for one chosen generator, can miss.
        """
        numeric = self.probe.generic_rank(M, points)
        exact = self.modular.rank(M, branch)
        return numeric if exact is None else max(exact, numeric)

    def vanishes(self, p, branch: Branch, points) -> bool:
        """Does ``p`` vanish on ``branch``?  Both at the real points and, where possible, exactly."""
        if not self.probe.vanishes(p, points):
            return False
        exact = self.modular.vanishes(p, branch)
        return True if exact is None else exact

    # --- algebra with notes -----------------------------------------------------------------

    def substitute(self, M, branch: Branch, max_terms: int | None = None):
        """``M`` with the substitutions of ``branch`` applied (memoised).

        With ``max_terms``, :class:`~rankloci.algebra.TermLimit` is raised where a
        substituted matrix would hold more terms than that.
        """
        return self.substituted.of(M, branch, max_terms)

    def factors(self, p):
        """The irreducible factors of ``p`` that can vanish on the circle."""
        return list(self._factors.get((p,), lambda key: irreducible_factors(key[0], self.ring)))

    def det(self, block, max_terms: int | None = None):
        """The determinant of a square block (a list of rows), without powers of C**2 + S**2.

        See :func:`~rankloci.algebra.circle_free_det`: the factors that can vanish on the
        circles are those of the determinant, and cofactors are brought to a common scale
        by :func:`~rankloci.methods.null_vectors.left_null_vectors`.  With ``max_terms``,
        :class:`~rankloci.algebra.TermLimit` is raised where the expansion goes over it.
        """
        n = len(block)
        flat = tuple(x for row in block for x in row)
        return self._dets.get(flat, lambda key: circle_free_det(
            [list(key[i * n:(i + 1) * n]) for i in range(n)], self.ring, poll=self.tick,
            max_terms=max_terms))

    def parameter_only(self, f) -> bool:
        """Does ``f`` involve parameters only (no joint variable)?"""
        joint = 2 * self.ring.n_angles + len(self.ring.others)
        return all(i >= joint for i in self.ring.variable_indices(f))

    def model_point(self) -> np.ndarray:
        """A generator vector with the model's parameter values (joint generators zero)."""
        vals = np.zeros(len(self.ring.names))
        base = 2 * self.ring.n_angles + len(self.ring.others)
        for j, p in enumerate(self.ring.params):
            vals[base + j] = self.model_values[p]
        vals[self.ring.surd_start:] = self.ring.surd_values
        return vals

    def point_at(self, values) -> np.ndarray | None:
        """The generator vector of a configuration (a dict from variable names to values),
        with the model's parameter values; None when a variable is missing.

        An angle within HINT_ANGLE_SNAP_ATOL of a multiple k pi is taken as k pi: its
        half-angle generators are exactly 0 and +-1, so that conditions like q = pi
        vanish there exactly.
        """
        from ..tolerances import HINT_ANGLE_SNAP_ATOL

        g = self.model_point()
        na = self.ring.n_angles
        try:
            for i, a in enumerate(self.ring.angles):
                v = float(values[a.name])
                k = round(v / np.pi)
                if abs(v - k * np.pi) <= HINT_ANGLE_SNAP_ATOL:
                    g[2 * i], g[2 * i + 1] = ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[k % 4]
                else:
                    g[2 * i], g[2 * i + 1] = np.cos(v / 2), np.sin(v / 2)
            for j, x in enumerate(self.ring.others):
                g[2 * na + j] = float(values[x.name])
        except KeyError:
            return None
        return g

    def special_parameters(self, f, where: str):
        """Note a parameter-only factor that is not analysed further."""
        text = sp.sstr(self.ring.to_sympy(f))
        vals = self.model_point()
        if any(n.startswith((f"the model's parameter values satisfy {text} = 0",
                             f"for parameters with {text} = 0")) for n in self._notes):
            return
        if self.probe.vanishes(f, [vals]):
            note = (f"the model's parameter values satisfy {text} = 0, a special case of the "
                    f"symbolic analysis ({where}); rerun with --numeric")
        else:
            note = f"for parameters with {text} = 0 the analysis differs ({where}); not pursued"
        if note not in self._notes:
            self._notes.append(note)


def _generic_value(value: float, rng) -> float:
    """A random value near ``value`` that satisfies no special relation."""
    scale = abs(value) if value else 1.0
    return float(np.sign(value or 1.0) * scale * rng.uniform(0.6, 1.4))
