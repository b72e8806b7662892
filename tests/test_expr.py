"""The safe expression parser: what it accepts, what it refuses, and that it never runs code."""

from __future__ import annotations

import ast
import json
import warnings

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rankloci import expr as expr_module
from rankloci.errors import ExpressionError, ModelError, RanklociError
from rankloci.expr import (
    MAX_DEPTH,
    MAX_DIGITS,
    MAX_EXPONENT,
    MAX_LENGTH,
    AngleSnapWarning,
    exact_number,
    parse_expression,
    snap_angle,
)
from rankloci.io.toml_model import parse_model
from rankloci.tolerances import ANGLE_SNAP_ATOL

q1, q2 = sp.symbols("q1 q2", real=True)
l1 = sp.Symbol("l1", real=True)
NAMES = {"q1": q1, "q2": q2, "l1": l1}

HYPOTHESIS = settings(max_examples=500, deadline=None, derandomize=True, database=None,
                      suppress_health_check=[HealthCheck.too_slow])


# --- accepted forms ----------------------------------------------------------------------

@pytest.mark.parametrize("text, expected", [
    ("q1", q1),
    ("cos(q1) - pi/2", sp.cos(q1) - sp.pi / 2),
    ("-q1 + +q2", -q1 + q2),
    ("l1*sin(q1 + q2)**2", l1 * sp.sin(q1 + q2) ** 2),
    ("q1**-2", q1 ** -2),
    ("2**(1/2)", sp.sqrt(2)),
    ("sqrt(l1) / 3", sp.sqrt(l1) / 3),
    ("atan2(q2, q1)", sp.atan2(q2, q1)),
    ("tan(q1) + asin(q1) + acos(q1) + atan(q1) + exp(q1) + abs(q1)",
     sp.tan(q1) + sp.asin(q1) + sp.acos(q1) + sp.atan(q1) + sp.exp(q1) + sp.Abs(q1)),
    ("E", sp.E),
    ("  q1  ", q1),
    ("1_000", sp.Integer(1000)),
    ("((((q1))))", q1),
    ("sin(cos(atan2(sin(q1), cos(q2 + l1))))", sp.sin(sp.cos(sp.atan2(sp.sin(q1), sp.cos(q2 + l1))))),
])
def test_accepted_forms(text, expected, work):
    assert parse_expression(text, NAMES) == expected
    assert work["built"] <= _syntax_nodes(text)  # no node built twice (see test_refused_...)


@pytest.mark.parametrize("text, expected", [
    ("0.4318", sp.Rational(2159, 5000)),
    ("0.1", sp.Rational(1, 10)),
    ("1e-3", sp.Rational(1, 1000)),
    ("2.5e2", sp.Integer(250)),
    ("-0.0203", sp.Rational(-203, 10000)),
])
def test_floats_become_exact_rationals(text, expected):
    out = parse_expression(text)
    assert out == expected
    assert out.is_Rational and not out.atoms(sp.Float)


def test_numbers_pass_through_exactly():
    assert parse_expression(0.4318) == sp.Rational(2159, 5000)
    assert parse_expression(7) == sp.Integer(7)
    assert exact_number("0.15005") == sp.Rational(3001, 20000)
    assert exact_number(-2) == -2
    for bad in (True, float("nan"), float("inf"), "abc", None, [1]):
        with pytest.raises(ExpressionError):
            exact_number(bad)


def test_pi_over_two_stays_exact():
    out = parse_expression("pi/2")
    assert out == sp.pi / 2
    assert not out.atoms(sp.Float)
    assert sp.cos(out) == 0 and sp.sin(out) == 1


def test_float_text_is_not_snapped():
    """A float written as *text* is an exact decimal, never silently turned into pi/2."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = parse_expression("1.5707963267948966")
    assert out != sp.pi / 2 and out.is_Rational


# --- angle snapping ----------------------------------------------------------------------

@pytest.mark.parametrize("k", range(-24, 25))
def test_snap_angle_hits_every_multiple_of_pi_over_12(k):
    import math

    value = k * math.pi / 12
    if k == 0:
        assert snap_angle(value) == 0
    else:
        assert snap_angle(value) == sp.pi * sp.Rational(k, 12)
    assert snap_angle(value + 100 * ANGLE_SNAP_ATOL) is None


def test_float_alpha_in_model_file_snaps_with_warning_naming_the_joint():
    text = ('name = "snap"\n[[joint]]\nalpha = 0\n'
            '[[joint]]\nalpha = 1.5707963267948966\ntheta = -3.141592653589793\n')
    with pytest.warns(AngleSnapWarning) as record:
        model = parse_model(text)
    assert model.joints[1].dh.alpha == sp.pi / 2
    assert model.joints[1].dh.theta == -sp.pi
    messages = [str(w.message) for w in record]
    assert any("joint 2" in m and "'alpha'" in m and "pi/2" in m for m in messages), messages
    assert any("joint 2" in m and "'theta'" in m for m in messages), messages


def test_float_angle_far_from_a_multiple_stays_an_exact_decimal():
    with warnings.catch_warnings():
        warnings.simplefilter("error", AngleSnapWarning)
        model = parse_model('name = "nosnap"\n[[joint]]\nalpha = 0.3\n')
    assert model.joints[0].dh.alpha == sp.Rational(3, 10)


# --- refusals ------------------------------------------------------------------------------

REFUSED = {
    "import": "__import__('os').system('x')",
    "attribute": "q1.__class__",
    "attribute-call": "q1.subs(q1, 2)",
    "lambda": "lambda: 1",
    "lambda-call": "(lambda x: x)(1)",
    "list-comprehension": "[x for x in (1, 2)]",
    "generator": "sum(x for x in (1,))",
    "subscript": "q1[0]",
    "subscript-of-tuple": "(1, 2)[0]",
    "string": "'abc'",
    "bytes": "b'abc'",
    "string-in-call": "sin('q1')",
    "keyword-argument": "sin(q1, evaluate=False)",
    "unknown-name": "q3",
    "unknown-function": "eval('1')",
    "builtin-open": "open('/etc/passwd')",
    "huge-exponent": "9**9**9",
    "huge-exponent-negative": "2**-100",
    "symbolic-exponent": "2**q1",
    "irrational-exponent": "2**pi",
    "nested-huge-power": "((((9**64)**64)**64)**64)**64",
    "nested-power-of-product": "(((10**40*10**40)**64)**64)",
    "deep-unary": "-" * (MAX_DEPTH + 10) + "1",
    "deep-sum": "(q1 + " * (MAX_DEPTH + 10) + "q1" + ")" * (MAX_DEPTH + 10),
    "deep-calls": "sin(" * (MAX_DEPTH + 10) + "q1" + ")" * (MAX_DEPTH + 10),
    "deep-parentheses": "(" * 300 + "1" + ")" * 300,
    "too-long": "+".join(["1"] * (MAX_LENGTH // 2 + 1)),
    "floor-division": "pi//2",
    "modulo": "q1 % 2",
    "bit-xor": "q1 ^ 2",
    "shift": "1 << 2",
    "comparison": "q1 < 2",
    "boolean": "True",
    "boolean-op": "q1 and q2",
    "not": "not q1",
    "conditional": "1 if q1 else 2",
    "walrus": "(x := 1)",
    "tuple": "1, 2",
    "list": "[1]",
    "dict": "{1: 2}",
    "set": "{1}",
    "fstring": "f'{q1}'",
    "complex-literal": "1j",
    "infinite-float": "1e999",
    "long-integer": "1" + "0" * 60,
    "ellipsis": "...",
    "none": "None",
    "starred": "atan2(*q1)",
    "wrong-arity": "sin(q1, q2)",
    "atan2-arity": "atan2(q1)",
    "bare-function": "sin",
    "division-by-zero": "1/0",
    "division-by-zero-exact": "q1/(sin(pi))",
    "zero-to-negative-power": "0**-1",
    "empty": "",
    "blank": "   ",
    "syntax": "q1 +",
    "statement": "import os",
    "assignment": "x = 1",
    "null-byte": "1\x00",
    "await": "await q1",
    "matmul": "q1 @ q2",
}


#: Bits of the largest exact number parsing may compute.  A power is refused before it is formed
#: when exponent * bits(base) > 4 * MAX_DIGITS * MAX_EXPONENT, and every other result is a sum,
#: product or quotient of checked values (at most MAX_NUMBER_DIGITS digits each, far fewer bits).
WORK_BITS = 4 * MAX_DIGITS * MAX_EXPONENT


@pytest.fixture
def work(monkeypatch):
    """The work parsing does: syntax nodes built, and the bits of the largest number computed.

    Every node goes through ``_build`` and every computed value through ``_checked`` (before it
    can be refused), so counting there measures the work without a clock.
    """
    record = {"built": 0, "bits": 0}
    build, checked = expr_module._build, expr_module._checked

    def counted_build(*args):
        record["built"] += 1
        return build(*args)

    def measured_checked(value, text):
        bits = [max(abs(r.p), r.q).bit_length() for r in value.atoms(sp.Rational)]
        record["bits"] = max([record["bits"], *bits])
        return checked(value, text)

    monkeypatch.setattr(expr_module, "_build", counted_build)
    monkeypatch.setattr(expr_module, "_checked", measured_checked)
    return record


def _syntax_nodes(text):
    """Expression nodes of ``text`` that name a value (a called function's name does not);
    0 if the text does not parse."""
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError, RecursionError):
        return 0
    nodes = list(ast.walk(tree))
    return sum(isinstance(n, ast.expr) for n in nodes) - sum(isinstance(n, ast.Call) for n in nodes)


@pytest.mark.parametrize("text", REFUSED.values(), ids=REFUSED.keys())
def test_refused_with_expression_error(text, work):
    with pytest.raises(ExpressionError) as info:
        parse_expression(text, NAMES)
    # a refusal is immediate: each syntax node is built at most once, and no huge number is
    # computed on the way (``9**9**9``, nested powers are refused before they are formed)
    assert work["built"] <= _syntax_nodes(text)
    assert work["bits"] <= WORK_BITS
    message = str(info.value)
    assert message.startswith("cannot parse ")
    assert len(message) < 3 * MAX_LENGTH  # the message quotes at most the (bounded) text


@pytest.mark.parametrize("text, reason", [
    ("__import__('os')", "call of '__import__' is not allowed"),
    ("__import__", "unknown name '__import__'"),
    ("pi//2", "operator FloorDiv is not allowed"),
    ("q3", "unknown name 'q3'"),
    ("9**9**9", f"exponent larger than {MAX_EXPONENT}"),
    ("sin(q1, evaluate=False)", "keyword arguments are not allowed"),
    ("q1.__class__", "Attribute is not allowed"),
])
def test_refusal_names_the_reason(text, reason):
    with pytest.raises(ExpressionError) as info:
        parse_expression(text, NAMES)
    assert info.value.reason.startswith(reason)
    assert str(info.value) == f"cannot parse {text!r}: {info.value.reason}"


def test_names_map_is_the_only_source_of_symbols():
    """A name is allowed only if given; ``names`` may rename it to any expression."""
    with pytest.raises(ExpressionError, match="unknown name 'l1'"):
        parse_expression("l1")
    assert parse_expression("l1", {"l1": sp.Rational(1, 2)}) == sp.Rational(1, 2)
    # caller's names shadow the constants
    assert parse_expression("E", {"E": q1}) == q1


def test_largest_accepted_numbers_are_still_bounded():
    """The limits are not off by one: a 40-digit literal and exponent 64 are fine."""
    assert parse_expression("9" * 40) == sp.Integer(int("9" * 40))
    assert parse_expression(f"q1**{MAX_EXPONENT}", NAMES) == q1 ** MAX_EXPONENT
    with pytest.raises(ExpressionError):
        parse_expression(f"q1**{MAX_EXPONENT + 1}", NAMES)


# --- fuzzing: only RanklociError, never anything else ---------------------------------------

TOKENS = ["q1", "q2", "l1", "pi", "E", "sin", "cos", "atan2", "sqrt", "abs", "exp", "tan",
          "(", ")", "(", ")", "**", "*", "/", "//", "+", "-", "%", ",", ".", " ", "0", "1", "2",
          "9", "64", "0.5", "1e308", "1e-308", "1.5707963267948966", "__class__", "__import__",
          "[", "]", "lambda", ":", "'", "\"", "x", "=", "j", "_", "e", "not", "if", "else", "@"]

token_text = st.lists(st.sampled_from(TOKENS), max_size=30).map("".join)
any_text = st.one_of(st.text(max_size=200), token_text)


def _parse_model_or_model_error(text):
    """parse_model succeeds or raises ModelError (a RanklociError); anything else fails the test."""
    try:
        model = parse_model(text, file="fuzz.toml")
    except ModelError as e:
        assert isinstance(e, RanklociError)
        assert str(e).startswith("fuzz.toml: ")
        return
    assert model.name == "fuzz"


@HYPOTHESIS
@given(any_text)
def test_parse_expression_fuzz_raises_only_expression_error(text):
    try:
        out = parse_expression(text, NAMES)
    except ExpressionError:
        return
    assert isinstance(out, sp.Basic)
    assert out.free_symbols <= {q1, q2, l1}


def _model_text(field: str, value: str) -> str:
    """A small valid model with one field replaced by a TOML basic string holding ``value``."""
    string = json.dumps(value, ensure_ascii=False)  # a JSON string literal is a TOML basic string
    fields = {"a": '"l1"', "alpha": '"pi/2"', "d": "0", "theta": "0", "expr": '"q1 + q2"', "xyz": '0'}
    fields[field] = string
    return (f'name = "fuzz"\n[parameters]\nl1 = 0.5\n'
            f'[base]\nxyz = [{fields["xyz"]}, 0, 0]\n'
            f'[[joint]]\na = {fields["a"]}\nalpha = {fields["alpha"]}\nd = {fields["d"]}\ntheta = {fields["theta"]}\n'
            f'[[joint]]\na = 1\n'
            f'[[augment]]\nexpr = {fields["expr"]}\n')


def test_model_template_is_valid():
    """The fuzz template parses when the field is harmless, so the fuzz reaches the parser."""
    for field in ("a", "alpha", "d", "theta", "expr", "xyz"):
        model = parse_model(_model_text(field, "1"))
        assert model.dof == 2


@HYPOTHESIS
@given(st.sampled_from(["a", "alpha", "d", "theta", "expr", "xyz"]), any_text)
def test_parse_model_fuzz_in_expression_fields(field, text):
    _parse_model_or_model_error(_model_text(field, text))


TOML_PIECES = ['name = "fuzz"\n', "[[joint]]\n", "[parameters]\n", "[[augment]]\n", "[base]\n", "[tool]\n",
               "matrix = [[1, 2], [3]]\n", 'variables = ["x"]\n', 'a = "l1"\n', "l1 = 0.5\n",
               "alpha = 1.5707963267948966\n",
               'kind = "prismatic"\n', 'kind = 3\n', 'task = "planar"\n', "rows = [0, 9]\n", 'frame = "tool"\n',
               'expr = "q1"\n', 'xyz = [0, 0, "pi"]\n', "rpy = [1, 2]\n", "limits = [1, 0]\n", 'convention = "mdh"\n',
               "q1 = 2\n", 'name = 5\n', "joint = []\n", "theta = nan\n", "d = inf\n", 'x = {a = 1}\n', "= \n",
               "alpha = -inf\n", "rpy = [nan, 0, 0]\n", "limits = [-inf, inf]\n", "l1 = 1e400\n", 'a = "1e400"\n',
               'theta = "((9**64)**64)**64"\n', 'alpha = 1e-320\n', 'expr = "q1**64**2"\n']


@settings(HYPOTHESIS, max_examples=1500)
@given(st.one_of(st.text(max_size=300), st.lists(st.sampled_from(TOML_PIECES), max_size=15).map("".join)))
def test_parse_model_fuzz_whole_file(text):
    _parse_model_or_model_error(text)
