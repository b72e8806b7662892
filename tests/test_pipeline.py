"""The one pipeline: read -> J -> engine -> certify -> result, each stage a function of the last.

Run stage by stage, it gives the locus certified_locus gives; its values are frozen; the notes
of the model, of its matrix, of the computation and of the frame come in that order.
"""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp

from rankloci import pipeline
from rankloci.api.calls import certified_locus
from rankloci.io import load_model
from rankloci.parallel import Workers
from rankloci.verify import Verification


def _equations(locus):
    return [tuple(sp.sstr(e) for e in c.equations) for c in locus.components]


@pytest.fixture(scope="module")
def stages():
    model = load_model("planar3r")
    run = pipeline.Run()
    with Workers(1) as workers:
        run = dataclasses.replace(run, workers=workers)
        request = pipeline.read(model, task="position", seed=0)
        matrices = pipeline.matrices(request, run)
        engine = pipeline.engine(matrices, run)
        certified = pipeline.certify(engine, run)
    return model, request, matrices, engine, certified, pipeline.result(certified)


def test_the_stages_give_the_locus_every_command_shows(stages):
    model, request, matrices, engine, certified, result = stages
    shown, tm = certified_locus(model, task="position", seed=0, jobs=1)
    assert _equations(result) == _equations(shown)
    assert result.notes == shown.notes
    assert result.complete is shown.complete is True
    assert matrices.tm == tm and matrices.method == shown.method == "determinant"
    # the engine's own locus, before the certificate: the same components here
    assert _equations(engine.locus) == _equations(result)
    assert engine.grown is not None and engine.grown.method == "determinant"


def test_stage_values_are_frozen(stages):
    for value in stages[1:5]:
        with pytest.raises(dataclasses.FrozenInstanceError):
            value.seed = 1


def test_the_result_stage_assembles_the_notes_in_order(stages):
    _, request, matrices, _, certified, _ = stages
    model = dataclasses.replace(request.model, notes=("from the model file",))
    tm = dataclasses.replace(matrices.tm, notes=("from the matrix",), frame=2, point="tool")
    locus = dataclasses.replace(certified.locus, notes=("from the computation",))
    checks = Verification(False, notes=("from the checks",))
    stage = pipeline.Certified(pipeline.Matrices(dataclasses.replace(request, model=model), tm,
                                                 matrices.method), locus, checks)
    notes = pipeline.result(stage).notes
    assert notes[:4] == ("from the model file", "from the matrix", "from the computation",
                         "from the checks")
    assert len(notes) == 5 and notes[4].startswith("J was computed in link frame 2")
