"""The certificate a locus carries: what the witness-point check proved, as data.

:func:`rankloci.exact.witness.certify_components` computes it; a locus holds
it and writes it to its JSON, from which :meth:`Certificate.from_dict` reads
it back.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

__all__ = ["Certificate", "CERTIFICATE_KIND", "VERDICTS"]

CERTIFICATE_KIND = "witness points modulo a prime"

#: The verdicts of a certificate.
VERDICTS = ("passed", "failed", "undecided")


@dataclass(frozen=True)
class Certificate:
    """The outcome of :func:`rankloci.exact.witness.certify_components`.

    Attributes
    ----------
    verdict : {"passed", "failed", "undecided"}
        ``"passed"``: the reported components are the whole locus (complete and sound), with
        the stated error bound.  ``"failed"``: a witness point disproves it (``findings``).
        ``"undecided"``: the certificate could not be computed (``findings`` says why).
    kind : str
        :data:`CERTIFICATE_KIND`.
    prime : int or None
        The prime P of the finite field.
    seed : int
        Seed of the random choices (chart, subspaces, compressions): the same seed and
        inputs give the same certificate.
    codimensions : tuple of int
        The codimensions that can occur (1 .. m - n + 1) and were checked.
    witness_points : dict
        Codimension -> number of witness points of the locus (over the algebraic closure).
    findings : tuple of str
        What disproves the locus, or why no verdict was reached.
    error_bound : float
        Upper bound of the probability that a ``"passed"`` verdict is wrong.
    seconds : float
    redundant : tuple of int
        Components (1-based) whose dimension is below the determinantal bound of their rank
        drop: they lie inside larger ones, or are not singular; the locus without them is what
        a passing certificate is about.
    complex_components : tuple of tuple of sympy.Expr
        The equations of components of the complex locus that have no real point (proved:
        they fix a variable at values none of which is real, or are a sum of squares without
        a common real zero); they are no part of a robot's locus, and the certificate counts
        their witness points as covered.
    real_parts : tuple of dict
        Components of the complex locus whose real points are fewer or of lower dimension
        (reported components with ``real_points_of``): per complex component its equation,
        the polynomials whose squares it is a weighted sum of, and its real points, which the
        certificate proved lie on the reported components (see
        :mod:`rankloci.exact.real_points`).
    """

    verdict: str
    kind: str = CERTIFICATE_KIND
    prime: int | None = None
    seed: int = 0
    codimensions: tuple = ()
    witness_points: dict = field(default_factory=dict)
    findings: tuple = ()
    error_bound: float = 0.0
    seconds: float = 0.0
    redundant: tuple = ()
    discovered: tuple = field(default=(), compare=False, repr=False)
    discovered_complex: tuple = field(default=(), compare=False, repr=False)
    slices: tuple = field(default=(), compare=False, repr=False)
    discovered_merged: tuple = field(default=(), compare=False, repr=False)
    uncovered: int = field(default=0, compare=False)
    complex_components: tuple = ()
    real_parts: tuple = ()

    @property
    def passed(self) -> bool:
        return self.verdict == "passed"

    @classmethod
    def from_dict(cls, data, names=None) -> "Certificate":
        """The certificate as :meth:`to_dict` wrote it (ValueError naming a bad field);
        ``names`` maps the variables' names to their symbols (see
        :func:`~rankloci.expr.parse_expression`)."""
        if not isinstance(data, dict):
            raise ValueError("must be an object")
        verdict = data.get("verdict")
        if verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {VERDICTS}")
        prime = data.get("prime")
        if prime is not None and (not isinstance(prime, int) or isinstance(prime, bool)
                                  or not 0 < prime < 2 ** 64):
            raise ValueError("prime must be a positive integer below 2**64 or null")
        ints = [data.get("seed", 0)] + list(data.get("codimensions", []))
        counts = data.get("witness_points", {})
        if not isinstance(counts, dict) or not all(
                isinstance(k, str) and k.isdigit() and len(k) < 6 for k in counts):
            raise ValueError("witness_points must map codimensions to counts")
        ints += list(counts.values())
        if not all(isinstance(v, int) and not isinstance(v, bool) and 0 <= v < 2 ** 63
                   for v in ints):
            raise ValueError("seed, codimensions and witness point counts must be "
                             "non-negative integers")
        redundant = data.get("redundant", [])
        if not isinstance(redundant, list) or not all(
                isinstance(v, int) and not isinstance(v, bool) and 0 < v < 10 ** 6
                for v in redundant):
            raise ValueError("redundant must be a list of component numbers")
        findings = data.get("findings", [])
        if not isinstance(findings, list) or not all(isinstance(f, str) for f in findings):
            raise ValueError("findings must be a list of strings")
        numbers = [data.get("error_bound", 0.0), data.get("seconds", 0.0)]
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and 0 <= v < 1e12
                   for v in numbers):
            raise ValueError("error_bound and seconds must be non-negative numbers")
        complex_components = data.get("complex_components", [])
        if not isinstance(complex_components, list) or not all(
                isinstance(eqs, list) and all(isinstance(e, str) for e in eqs)
                for eqs in complex_components):
            raise ValueError("complex_components must be a list of lists of equations")
        from ..errors import ExpressionError
        from ..expr import parse_expression

        try:
            complex_components = tuple(tuple(parse_expression(e, names) for e in eqs)
                                       for eqs in complex_components[:50])
        except ExpressionError as exc:
            raise ValueError(f"complex_components: {exc}") from None
        real_parts = data.get("real_parts", [])
        if not isinstance(real_parts, list) or not all(
                isinstance(r, dict) and all(isinstance(k, str) for k in r) for r in real_parts):
            raise ValueError("real_parts must be a list of objects")
        return cls(verdict, kind=str(data.get("kind", CERTIFICATE_KIND))[:80], prime=prime,
                   seed=data.get("seed", 0), codimensions=tuple(data.get("codimensions", [])),
                   witness_points={int(k): v for k, v in counts.items()},
                   findings=tuple(f[:2000] for f in findings[:200]),
                   error_bound=float(numbers[0]), seconds=float(numbers[1]),
                   redundant=tuple(redundant), complex_components=complex_components,
                   real_parts=tuple(real_parts[:50]))

    def to_dict(self) -> dict:
        return {"kind": self.kind, "verdict": self.verdict, "prime": self.prime,
                "seed": self.seed, "codimensions": list(self.codimensions),
                "witness_points": {str(k): v for k, v in self.witness_points.items()},
                "error_bound": self.error_bound, "findings": list(self.findings),
                "redundant": list(self.redundant),
                "complex_components": [[sp.sstr(e) for e in eqs]
                                       for eqs in self.complex_components],
                **({"real_parts": list(self.real_parts)} if self.real_parts else {}),
                "seconds": round(self.seconds, 4)}
