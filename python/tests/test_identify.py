"""`identify` from arrays gives the command line's report on the same data:
prepared samples, raw samples (filtered and differentiated), held-out data."""

import json

import numpy as np
import pytest

import momentlmi as m
from conftest import NOT_COMPARED, ROOT, json_differences, read_csv


@pytest.fixture(scope="module")
def leg():
    return m.Robot.builtin("cheetah3-leg")


@pytest.fixture(scope="module")
def files(tmp_path_factory, cli):
    d = tmp_path_factory.mktemp("id")
    out = {}
    for name, seconds, seed in (("train", 2, 1), ("val", 1, 2)):
        out[name] = d / f"{name}.csv"
        cli("simulate", "--robot", "cheetah3-leg", "--seconds", seconds, "--seed", seed, "--out", out[name])
    # the training file without q̈ (and q̇): a raw log, filtered and differentiated
    text = out["train"].read_text().splitlines()
    keep = [k for k, c in enumerate(text[0].split(",")) if not c.startswith(("qd_", "qdd_"))]
    out["raw"] = d / "raw.csv"
    out["raw"].write_text("\n".join(",".join(np.array(l.split(","))[keep]) for l in text) + "\n")
    return out


def arrays(path, joints, raw=False):
    t, q, qd, qdd, tau = read_csv(path, joints)
    return dict(t=t, q=q, tau=tau) if raw else dict(t=t, q=q, qd=qd, qdd=qdd, tau=tau)


def same(mine, theirs):
    assert [b["name"] for b in mine["bodies"]] == [b["name"] for b in theirs["bodies"]]
    pa = np.array([b["params"] for b in mine["bodies"]])
    pb = np.array([b["params"] for b in theirs["bodies"]])
    # the solves agree to the interior-point method's tolerance (docs/python.md)
    assert np.abs(pa - pb).max() <= 1e-6 * np.abs(pb).max()
    for k in ("training_rms", "validation_rms"):
        assert (mine[k] is None) == (theirs[k] is None), k
        if mine[k] is not None:
            assert np.allclose(mine[k], theirs[k], rtol=1e-7), k
    assert mine["training_samples"] == theirs["training_samples"]


def test_prepared_arrays_with_held_out_data(leg, files, cli):
    mine = m.identify(leg, arrays(files["train"], leg.joint_names), validate=arrays(files["val"], leg.joint_names))
    theirs = json.loads(cli("identify", "--robot", "cheetah3-leg", "--data", files["train"], "--validate",
                            files["val"], "--constraints", "ellipsoid", "--json").stdout)
    same(mine, theirs)
    assert mine["validation_samples"] == 1000


def test_raw_arrays_are_prepared_as_a_raw_log_is(leg, files, cli):
    mine = m.identify(leg, [arrays(files["raw"], leg.joint_names, raw=True)], constraints="consistent")
    theirs = json.loads(cli("identify", "--robot", "cheetah3-leg", "--data", files["raw"],
                            "--constraints", "consistent", "--json").stdout)
    same(mine, theirs)
    prep = mine["data_preparation"]["training"][0]
    assert not prep["taken_as_prepared"] and prep["cutoff_hz"] == theirs["data_preparation"]["training"][0]["cutoff_hz"]


def test_a_dataframe_is_read_by_its_column_names(leg, files):
    pd = pytest.importorskip("pandas", reason="pandas is not installed: DataFrames are not tried")
    df = pd.read_csv(files["train"])
    a = m.identify(leg, df)
    b = m.identify(leg, arrays(files["train"], leg.joint_names))
    assert [x["params"] for x in a["bodies"]] == [x["params"] for x in b["bodies"]]


def test_bad_data_are_value_errors_naming_the_segment(leg, files):
    d = arrays(files["train"], leg.joint_names)
    with pytest.raises(ValueError, match=r"data: qd has 10 samples, t has 2000"):
        m.identify(leg, dict(d, qd=d["qd"][:10]))
    with pytest.raises(ValueError, match=r"data\[1\]: tau: value inf"):
        m.identify(leg, [d, dict(d, tau=np.full_like(d["tau"], np.inf))])
    with pytest.raises(ValueError, match="data: no t"):
        m.identify(leg, dict(q=d["q"]))
    with pytest.raises(ValueError, match="unknown keys"):
        m.identify(leg, dict(d, torque=d["tau"]))
    with pytest.raises(ValueError, match="weight: 'best'"):
        m.identify(leg, d, weight="best")
    back = dict(d, t=d["t"][::-1].copy())
    with pytest.raises(m.DataError, match="not after"):
        m.identify(leg, back)


def test_the_real_kuka_runs_as_the_command_line_identifies_them(cli):
    """python/examples/kuka_lwr4.py's identification: the KUKA LWR4+'s archives read
    with numpy.load (raw: filtered and differentiated), held out on run 3."""
    from conftest import ROOT

    kuka = ROOT / "robots" / "kuka-lwr4"
    robot = m.Robot.from_urdf(kuka / "kuka_lwr4.urdf", sidecar=kuka / "kuka_lwr4.toml")

    def run(k):
        z = np.load(kuka / "data" / f"measurements_{k}.npz")
        return dict(t=z["times"], q=z["positions"], tau=z["torques"])

    opts = dict(constraints="ellipsoid", friction="viscous,coulomb,offset,load,stribeck",
                regularizer="entropic", weight=1e-2)
    mine = m.identify(robot, [run(1), run(2)], validate=run(3), **opts)
    runs = [kuka / "data" / f"measurements_{k}.npz" for k in (1, 2, 3)]
    theirs = json.loads(cli("identify", "--robot", kuka / "kuka_lwr4.urdf", "--data", runs[0], "--data", runs[1],
                            "--validate", runs[2], "--friction", opts["friction"], "--constraints", "ellipsoid",
                            "--regularizer", "entropic", "--weight", "1e-2", "--json").stdout)
    assert np.allclose(mine["validation_rms"], theirs["validation_rms"], rtol=1e-6)
    assert mine["all_bodies_consistent"] and 0.30 < np.mean(mine["validation_rms"]) < 0.36


def test_predict_with_the_identified_parameters_gives_the_held_out_rms(leg):
    train, held_out = m.simulate(leg, 3.0, seed=1), m.simulate(leg, 1.0, seed=2)
    r = m.identify(leg, train, validate=held_out, friction="viscous,coulomb,offset")
    tau = leg.predict(r, held_out["q"], held_out["qd"], held_out["qdd"])
    rms = np.sqrt(np.mean((held_out["tau"] - tau) ** 2, axis=0))
    assert np.allclose(rms, r["validation_rms"], rtol=1e-9)
    with pytest.raises(m.MomentlmiError, match="params: not a parameter file"):
        leg._r.predict("{}", held_out["q"], held_out["qd"], held_out["qdd"])


def test_the_result_is_the_command_lines_file(leg, files, cli, tmp_path):
    r = m.identify(leg, arrays(files["train"], leg.joint_names))
    assert isinstance(r, dict) and r.params.shape == (6, 10) and r.body_names == leg.body_names
    model = tmp_path / "model.json"
    model.write_text(r.to_json())
    # the command line takes it as a parameter file, and predicts what Python predicts
    out = tmp_path / "pred.csv"
    cli("predict", "--robot", "cheetah3-leg", "--params", model, "--data", files["val"], "--out", out)
    t, q, qd, qdd, _ = read_csv(files["val"], leg.joint_names)
    theirs = np.genfromtxt(out, delimiter=",", names=True)
    mine = leg.predict(model, q, qd, qdd)
    for j, name in enumerate(leg.joint_names):
        assert np.allclose(theirs[f"tau_{name}"], mine[:, j], rtol=0, atol=1e-9), name


def test_a_segments_joints_put_its_columns_in_the_robots_order(leg, files):
    d = arrays(files["train"], leg.joint_names)
    turned = {k: (v[:, ::-1] if k != "t" else v) for k, v in d.items()}
    turned["joints"] = leg.joint_names[::-1]
    assert np.array_equal(m.identify(leg, turned).params, m.identify(leg, d).params)
    with pytest.raises(ValueError, match="are not the robot's"):
        m.identify(leg, dict(d, joints=["a", "b", "c"]))


def test_friction_auto_chooses_as_the_command_line_does(leg, files, cli):
    mine = m.identify(leg, arrays(files["train"], leg.joint_names), friction="auto", weight="auto")
    theirs = json.loads(cli("identify", "--robot", "cheetah3-leg", "--data", files["train"], "--constraints",
                            "ellipsoid", "--friction", "auto", "--weight", "auto", "--json").stdout)
    sel, ref = mine["model_selection"], theirs["model_selection"]
    assert sel["chosen"] == ref["chosen"] and len(sel["laws"]) == len(ref["laws"]) > 20
    assert mine["weight"] == sel["laws"][sel["chosen"]]["weight"] == theirs["weight"]
    same(mine, theirs)


def test_the_default_chooses_the_law_as_the_command_line_does(leg, files, cli):
    """No friction and no weight: the law and the weight chosen, as `identify` without
    --friction and --weight; too short to choose: viscous + Coulomb kept, with a warning."""
    d = arrays(files["train"], leg.joint_names)
    mine = m.identify(leg, d)
    theirs = json.loads(cli("identify", "--robot", "cheetah3-leg", "--data", files["train"], "--constraints",
                            "ellipsoid", "--json").stdout)
    sel, ref = mine["model_selection"], theirs["model_selection"]
    assert sel["chosen"] == ref["chosen"] and len(sel["laws"]) == len(ref["laws"]) > 20
    assert mine["weight"] == theirs["weight"] == sel["laws"][sel["chosen"]]["weight"]
    same(mine, theirs)
    short = {k: v[:100] for k, v in d.items()}
    kept = m.identify(leg, short)
    assert kept.get("model_selection") is None and kept["weight"] == 1e-6
    assert [w["kind"] for w in kept["warnings"]].count("law_not_chosen") == 1, kept["warnings"]
    with pytest.raises(Exception, match="cross-validation: fold"):
        m.identify(leg, short, friction="auto")


PANDA = ROOT / "robots" / "panda"
ROBOTS = {"leg": (["--robot", "cheetah3-leg"], lambda: m.Robot.builtin("cheetah3-leg")),
          "panda": (["--robot", PANDA / "panda.urdf", "--sidecar", PANDA / "panda.toml"],
                    lambda: m.Robot.from_urdf(PANDA / "panda.urdf", sidecar=PANDA / "panda.toml"))}


@pytest.fixture(scope="module")
def logs(tmp_path_factory, cli):
    """Three seconds of the leg and of the Panda (prepared CSV)."""
    d = tmp_path_factory.mktemp("field")
    out = {}
    for name, (args, _) in ROBOTS.items():
        out[name] = d / f"{name}.csv"
        cli("simulate", *args, "--seconds", 3, "--seed", 5, "--out", out[name])
    return out


def both(name, logs, cli, *flags, **options):
    """The command line's `identify --json` and Python's on the same log and options."""
    args, robot = ROBOTS[name]
    theirs = json.loads(cli("identify", *args, "--data", logs[name], "--constraints", "ellipsoid", *flags,
                            "--json", ok=(0, 1)).stdout)
    r = robot()
    with pytest.warns(m.MomentlmiWarning) if theirs["degenerate_bodies"] else _no_check():
        mine = m.identify(r, arrays(logs[name], r.joint_names), **options)
    return mine, theirs


class _no_check:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


@pytest.mark.parametrize("name", ROBOTS)
def test_the_json_equals_the_command_lines_field_by_field(name, logs, cli):
    """The defaults (the friction law and the weight chosen): the same reduction of the
    same samples, the same report to 1e-6 relative or 1e-9 absolute in every field but
    the times and the file's name: bodies, friction, base parameters (same order),
    directions, model selection …"""
    mine, theirs = both(name, logs, cli)
    assert json_differences(dict(mine), theirs, skip=NOT_COMPARED) == []
    assert mine["model_selection"] is not None and len(mine["identifiability"]["base_parameters"]) > 30


@pytest.mark.parametrize("name", ROBOTS)
def test_the_streamed_reduction_reports_the_same_base_parameters(name, logs, cli):
    """A given law and weight: the command line reduces the file while it reads it, in
    blocks; Python reduces the arrays whole. The sums differ in their last bits; the
    base parameters (canonical: issue 58) and every field outside the bodies agree to
    1e-6 / 1e-9 all the same. The bodies' numbers agree to the interior-point
    tolerance: the parameters to 1e-6 of the largest (the directions the data do not
    excite are held by the prior's small weight alone; a near-degenerate body's derived
    numbers differ by up to about 1e-4 relative)."""
    mine, theirs = both(name, logs, cli, "--friction", "viscous,coulomb", "--weight", "1e-6",
                        friction="viscous,coulomb", weight=1e-6)
    assert theirs["timings"]["streamed"] and not mine["timings"]["streamed"]
    named = lambda r: [b["combination"] for b in r["identifiability"]["base_parameters"]]
    assert named(mine) == named(theirs)
    assert json_differences(dict(mine), theirs, skip=NOT_COMPARED + (r"/bodies",)) == []
    same(mine, theirs)
