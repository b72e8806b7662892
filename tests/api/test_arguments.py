"""Bad arguments raise one error type, in the Python API's own words, before any work starts."""

from __future__ import annotations

import pytest
import sympy as sp

import rankloci
from rankloci.errors import ArgumentError, ModelError, RanklociError

x, y, k = sp.symbols("x y k")
M = sp.Matrix([[sp.cos(x), k * y], [sp.sin(x), 1]])

#: (call, the argument the error names)
BAD = [
    (lambda: rankloci.locus("planar2r", seed="a"), "seed"),
    (lambda: rankloci.locus("planar2r", seed=-1), "seed"),
    (lambda: rankloci.locus("planar2r", seed=1.5), "seed"),
    (lambda: rankloci.locus("planar2r", timeout="5"), "timeout"),
    (lambda: rankloci.locus(M, variables="xy", parameters={k: 2}), "variables"),
    (lambda: rankloci.locus(M, variables=[1], parameters={k: 2}), "variables"),
    (lambda: rankloci.locus(M, variables=[x, x, y], parameters={k: 2}), "variables"),
    (lambda: rankloci.locus(M, parameters=[2]), "parameters"),
    (lambda: rankloci.locus(M, variables=[x, y, k], parameters={k: 2}), "parameters"),
    (lambda: rankloci.locus("planar2r", task="nope"), "task"),
    (lambda: rankloci.locus("planar2r", task=3), "task"),
    (lambda: rankloci.locus("planar2r", task=[7]), "task"),
    (lambda: rankloci.locus(M, parameters={k: 2}, task="position"), "task"),
    (lambda: rankloci.locus("planar2r", augment="q1 + q2"), "augment"),
    (lambda: rankloci.locus("planar2r", augment=[3]), "augment"),
    (lambda: rankloci.locus("planar2r", method="qr"), "method"),
    (lambda: rankloci.locus("planar2r", numeric="yes"), "numeric"),
    (lambda: rankloci.locus("planar2r", verify="no"), "verify"),
    (lambda: rankloci.locus("puma560", frame="world"), "frame"),
    (lambda: rankloci.locus("puma560", frame=9), "frame"),
    (lambda: rankloci.locus("puma560", tip=3), "tip"),
    (lambda: rankloci.jacobian("planar2r", point="elbow"), "point"),
    (lambda: rankloci.check("planar2r", samples="3"), "samples"),
    (lambda: rankloci.check("planar2r", seed="a"), "seed"),
    (lambda: rankloci.load_model("planar2r", base_link=4), "base_link"),
]


@pytest.mark.parametrize("call, argument", BAD)
def test_bad_argument_raises_an_argument_error_naming_it(call, argument):
    with pytest.raises(ArgumentError) as info:
        call()
    assert isinstance(info.value, RanklociError)
    assert info.value.argument == argument
    message = str(info.value)
    assert message.startswith(f"{argument}=")
    assert "--" not in message and "field '" not in message      # no command-line words
    assert "concatenate" not in message


def test_argument_error_is_still_a_value_and_a_type_error():
    """Code written against the builtin errors of earlier versions keeps catching them."""
    with pytest.raises(ValueError):
        rankloci.locus("planar2r", method="qr")
    with pytest.raises(TypeError):
        rankloci.locus("planar2r", seed="a")


def test_augment_that_does_not_parse_speaks_of_augment_not_the_flag():
    with pytest.raises(ModelError) as info:
        rankloci.locus("puma560", augment=["q1 +"])
    assert str(info.value).startswith("augment: cannot parse 'q1 +'")
    with pytest.raises(ModelError, match=r"^augment 'lock\(q9\)': q9 is not a joint variable"):
        rankloci.jacobian("planar2r", augment=["lock(q9)"])


def test_the_command_line_keeps_its_flag_in_the_message(capsys):
    from rankloci.cli import main

    assert main(["locus", "planar2r", "--augment", "q1 +", "--quiet"]) == 2
    assert "--augment: cannot parse" in capsys.readouterr().err


def test_good_arguments_pass_and_nothing_is_computed_for_bad_ones(caplog):
    import logging

    with caplog.at_level(logging.INFO, logger="rankloci"):
        with pytest.raises(ArgumentError):
            rankloci.locus("puma560", seed="a")
    assert [r for r in caplog.records if r.name == "rankloci"] == []   # no work started
    L = rankloci.locus("planar2r", seed=3, timeout=0, task=[0, 1], augment=(), numeric=True,
                       frame="auto")
    assert len(L.components) == 1
