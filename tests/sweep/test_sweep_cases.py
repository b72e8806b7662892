"""The cases of a sweep: order, identity, hashes, URDF chains and directories."""

from __future__ import annotations

import dataclasses

from rankloci.sweep.cases import expand
from rankloci.sweep.spec import parse_spec

#: A Y-shaped robot: a 2-joint stem, then two branches of 1 and 2 joints.
Y_URDF = """<robot name="y">
  <link name="base"/><link name="a"/><link name="b"/><link name="c"/><link name="d"/>
  <link name="e"/>
  <joint name="j1" type="continuous"><parent link="base"/><child link="a"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="j2" type="continuous"><parent link="a"/><child link="b"/>
    <origin xyz="1 0 0"/><axis xyz="0 1 0"/></joint>
  <joint name="j3" type="continuous"><parent link="b"/><child link="c"/>
    <origin xyz="1 0 0"/><axis xyz="0 1 0"/></joint>
  <joint name="j4" type="continuous"><parent link="b"/><child link="d"/>
    <origin xyz="0 1 0"/><axis xyz="1 0 0"/></joint>
  <joint name="j5" type="continuous"><parent link="d"/><child link="e"/>
    <origin xyz="0 1 0"/><axis xyz="1 0 0"/></joint>
</robot>
"""


def test_order_is_the_specs_and_ids_are_unique():
    spec = parse_spec('models = ["planar2r", "planar3r"]\n[grid]\naugment = ["", "q1"]\n')
    cases, sources, skipped = expand(spec)
    assert [c.label for c in cases] == ["planar2r", "planar2r + q1", "planar3r",
                                        "planar3r + q1"]
    assert len({c.id for c in cases}) == 4 and not skipped
    assert all(c.source in sources for c in cases)


def test_the_id_is_what_the_case_is_and_the_hash_what_determines_its_result():
    a = expand(parse_spec('models = ["planar2r"]\n'))[0][0]
    b = expand(parse_spec('models = ["planar2r"]\nmethod = "subdeterminant"\n'))[0][0]
    c = expand(parse_spec('models = ["planar2r"]\ntimeout = 5\nmemory = 100\n'))[0][0]
    assert a.id == b.id and a.hash != b.hash          # same case, computed otherwise
    assert a.id == c.id and a.hash == c.hash          # limits are not part of the result
    d = expand(parse_spec('models = ["planar2r"]\n[grid.parameters]\nl1 = [2]\n'))[0][0]
    assert d.id != a.id and d.parameter_values["l1"] == 2


def test_every_chain_of_a_urdf_file_within_the_joint_bounds(tmp_path):
    (tmp_path / "y.urdf").write_text(Y_URDF)
    spec = parse_spec('[[model]]\npath = "y.urdf"\nchains = "all"\nmin_joints = 3\n',
                      base=tmp_path, file="s.toml")
    cases, _, _ = expand(spec)
    assert [(c.model, c.joints, c.base_link, c.tip) for c in cases] == [
        ("y.urdf:base->c", 3, "base", "c"), ("y.urdf:base->e", 4, "base", "e")]
    spec = parse_spec('[[model]]\npath = "y.urdf"\nchains = "all"\nmax_joints = 1\n',
                      base=tmp_path, file="s.toml")
    cases, _, skipped = expand(spec)
    assert cases == [] and skipped == ["y.urdf: no chain with 1 to 1 movable joints"]


def test_a_directory_gives_its_files_and_a_file_that_does_not_read_is_a_failed_case(tmp_path):
    models = tmp_path / "models"
    models.mkdir()
    (models / "y.urdf").write_text(Y_URDF.replace('<link name="e"/>', ""))  # j5's child missing
    (models / "two.toml").write_text('name = "two"\n[[joint]]\nkind = "revolute"\na = 1\n'
                                     '[[joint]]\nkind = "revolute"\na = 1\n')
    (models / "notes.txt").write_text("not a model")
    cases, _, _ = expand(parse_spec('models = ["models/"]\n', base=tmp_path))
    assert [c.model for c in cases] == ["two.toml", "y.urdf"]
    assert cases[0].problem == "" and cases[0].joints == 2
    assert "e" in cases[1].problem and cases[1].joints is None


def test_cases_are_frozen_and_picklable():
    import pickle

    case = expand(parse_spec('models = ["planar3r"]\n[grid.parameters]\nl2 = ["pi/4"]\n'))[0][0]
    assert pickle.loads(pickle.dumps(case)) == case
    assert dataclasses.is_dataclass(case)
