"""The memo of determinants and factorisations: equal keys hit, size bounded."""

import sympy as sp

from rankloci.algebra import PolyMemo, PolyRing, laplace_det


def _ring():
    x, y = sp.symbols("x y")
    return PolyRing((), (x, y), ())


def test_equal_keys_are_found_and_distinct_keys_are_not():
    ring = _ring()
    x, y = ring.gens
    memo = PolyMemo(10_000)
    calls = []

    def product(key):
        calls.append(key)
        return key[0] * key[1]

    assert memo.get((x + 1, y), product) == (x + 1) * y
    assert memo.get((x + 1, y), product) == (x + 1) * y
    assert len(calls) == 1
    # same term counts, different polynomials: a different entry
    assert memo.get((x + 2, y), product) == (x + 2) * y
    assert len(calls) == 2


def test_oldest_entries_are_dropped_beyond_the_term_budget():
    ring = _ring()
    x, y = ring.gens
    memo = PolyMemo(12)
    calls = []

    def square(key):
        calls.append(key)
        return key[0] ** 2

    memo.get((x + 1,), square)          # 2 + 3 terms
    memo.get((y + 1,), square)          # 2 + 3 terms: 10 in all
    memo.get((x + y,), square)          # 2 + 3 more: the first is dropped
    assert memo._terms <= 12
    memo.get((x + y,), square)
    assert len(calls) == 3
    memo.get((x + 1,), square)          # recomputed
    assert len(calls) == 4


def test_a_value_larger_than_the_budget_is_returned_but_not_kept():
    ring = _ring()
    x, y = ring.gens
    memo = PolyMemo(3)
    p = memo.get((x + y + 1,), lambda key: key[0] ** 3)
    assert p == (x + y + 1) ** 3
    assert memo._terms == 0


def test_memoised_determinants_are_the_determinants():
    ring = _ring()
    x, y = ring.gens
    memo = PolyMemo(10_000)
    blocks = [[[x, y, 1], [y, x + 1, 2], [1, x * y, y]],
              [[x, y, 1], [y, x + 1, 2], [1, x * y, y]],
              [[y, x, 1], [x, y + 1, 2], [1, x * y, x]]]
    for block in blocks:
        flat = tuple(ring.ctx.constant(e) if isinstance(e, int) else e for row in block for e in row)
        got = memo.get(flat, lambda key: laplace_det([list(key[3 * i:3 * i + 3]) for i in range(3)]))
        expect = laplace_det([[ring.ctx.constant(e) if isinstance(e, int) else e for e in row]
                              for row in block])
        assert got == expect


def test_a_determinant_polls_its_caller_and_stops_when_asked():
    """laplace_det calls ``poll`` before each product; an exception there ends it, and a
    memo fed by it keeps nothing (so that a stopped computation leaves no partial entry)."""
    import pytest

    ring = _ring()
    x, y = ring.gens
    block = [[x + k * y + i for k in range(4)] for i in range(4)]
    calls = []
    laplace_det(block, poll=lambda: calls.append(1))
    assert len(calls) > 4

    class Stop(Exception):
        pass

    def stop_after_two():
        calls.append(1)
        if len(calls) > 2:
            raise Stop

    memo = PolyMemo(10_000)
    flat = tuple(e for row in block for e in row)
    calls.clear()
    with pytest.raises(Stop):
        memo.get(flat, lambda key: laplace_det(block, poll=stop_after_two))
    assert len(calls) == 3
    assert memo.get(flat, lambda key: laplace_det(block)) == laplace_det(block)
