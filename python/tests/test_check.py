"""A URDF checked from Python gives the command line's verdicts and margins."""

import json

import pytest

import momentlmi as m

URDF = """<?xml version="1.0"?>
<robot name="two">
  <link name="base"/>
  <link name="upper">
    <inertial><origin xyz="0 0 0.1"/><mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.002"/></inertial>
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.06 0.06 0.3"/></geometry></collision>
  </link>
  <link name="lower">
    <inertial><origin xyz="0 0 0.1"/><mass value="1"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.005"/></inertial>
    <collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.03" length="0.2"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="5"/></joint>
  <joint name="j2" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="5"/></joint>
</robot>
"""


@pytest.fixture()
def urdf(tmp_path):
    p = tmp_path / "two.urdf"
    p.write_text(URDF)
    return p


def test_check_urdf_equals_check_json(urdf, cli):
    mine = m.check_urdf(urdf)
    theirs = json.loads(cli("check", urdf, "--json", ok=(0, 1)).stdout)["links"]
    assert [l["name"] for l in mine] == ["upper", "lower"]
    assert mine == theirs
    # lower's Izz > Ixx + Iyy: not consistent; upper fits its box
    verdict = {l["name"]: l["status"] for l in mine}
    assert verdict == {"upper": "ok", "lower": "triangle_violation"}


def test_repair_urdf_writes_a_consistent_copy(urdf, tmp_path):
    out = tmp_path / "fixed.urdf"
    text, repaired = m.repair_urdf(urdf, out)
    assert repaired == ["lower"] and out.read_text() == text
    assert [l["status"] for l in m.check_urdf(out)] == ["ok", "ok"]


def test_a_missing_urdf_is_a_urdf_error(tmp_path):
    with pytest.raises(m.UrdfError, match="missing.urdf"):
        m.check_urdf(tmp_path / "missing.urdf")
    with pytest.raises(ValueError, match="target: 'all'"):
        m.repair_urdf(tmp_path / "missing.urdf", target="all")
