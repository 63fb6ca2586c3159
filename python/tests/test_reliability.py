"""Issue 58, item 6: the package as a NumPy/pandas user meets it. Each test is one
defect of the hostile sweep (each failed on the code before the fix): labelled
columns found by name, the same argument kinds everywhere, the report's warnings as
Python warnings, bad arguments as ValueError/TypeError naming them, pickling, a short
repr and __version__."""

import importlib.metadata
import json
import pickle
import shutil
import warnings

import numpy as np
import pytest

import momentlmi as m


@pytest.fixture(scope="module")
def leg():
    return m.Robot.builtin("cheetah3-leg")


@pytest.fixture(scope="module")
def sim(leg):
    return m.simulate(leg, 1.0, seed=4)


@pytest.fixture(scope="module")
def result(leg, sim):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", m.MomentlmiWarning)
        return m.identify(leg, sim, friction="viscous,coulomb", weight=1e-6)


def recorded(call):
    """`call()`'s value and the MomentlmiWarnings it issued."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        value = call()
    return value, [w.message for w in rec if issubclass(w.category, m.MomentlmiWarning)]


# -- labelled columns by name ------------------------------------------------


def test_dataframes_are_matched_by_column_name_not_position(leg, sim, result):
    pd = pytest.importorskip("pandas", reason="pandas is not installed: DataFrames are not tried")
    joints = leg.joint_names
    shuffled = joints[::-1]  # the columns in another order than the robot's

    def frame(x, prefix=""):
        df = pd.DataFrame(x, columns=[f"{prefix}{j}" for j in joints])
        return df[[f"{prefix}{j}" for j in shuffled]]

    q, qd, qdd, tau = (sim[k][:50] for k in ("q", "qd", "qdd", "tau"))
    want = leg.rnea(q, qd, qdd)
    assert np.array_equal(leg.rnea(frame(q), frame(qd), frame(qdd)), want)
    # the CSV's names (q_<joint> …), and one frame holding them all for each argument
    whole = pd.concat([frame(q, "q_"), frame(qd, "qd_"), frame(qdd, "qdd_"), frame(tau, "tau_")], axis=1)
    assert np.array_equal(leg.rnea(whole, whole, whole), want)
    assert np.array_equal(leg.regressor(frame(q), frame(qd), frame(qdd)), leg.regressor(q, qd, qdd))
    assert np.array_equal(leg.predict(result, frame(q), frame(qd), frame(qdd)), leg.predict(result, q, qd, qdd))
    # one sample as a Series, by its index's names
    assert np.array_equal(leg.rnea(frame(q).iloc[3], qd[3], qdd[3]), want[3:4])
    a = m.Reducer(leg).update(frame(q), frame(qd), frame(qdd), frame(tau))
    b = m.Reducer(leg).update(q, qd, qdd, tau)
    assert np.array_equal(a.gram(), b.gram())
    # a dict's DataFrame member, by name too
    seg = dict(t=sim["t"], q=frame(sim["q"]), qd=sim["qd"], qdd=sim["qdd"], tau=frame(sim["tau"], "tau_"))
    again, _ = recorded(lambda: m.identify(leg, seg, friction="viscous,coulomb", weight=1e-6))
    assert np.array_equal(again.params, result.params)
    # missing or ambiguous names, and labels that cannot name π's values
    with pytest.raises(ValueError, match="v: labelled columns are matched by name .* missing qd_knee"):
        leg.rnea(q, frame(qd, "qd_").drop(columns="qd_knee"), qdd)
    with pytest.raises(ValueError, match="a: both qdd_<joint> and <joint>"):
        leg.rnea(q, qd, pd.concat([frame(qdd), frame(qdd, "qdd_")], axis=1))
    with pytest.raises(TypeError, match="pi: a pandas Series"):
        m.is_consistent(pd.Series(leg.params()[0]))


# -- the same argument kinds across functions --------------------------------


def test_parameters_are_a_result_a_dict_json_text_or_a_path(leg, sim, result, tmp_path):
    q, qd, qdd = sim["q"][:20], sim["qd"][:20], sim["qdd"][:20]
    want = leg.predict(result, q, qd, qdd)
    path = tmp_path / "model.json"
    path.write_text(result.to_json())
    for params in (result.to_json(), dict(result), str(path), path):
        assert np.array_equal(leg.predict(params, q, qd, qdd), want), type(params)
    with pytest.raises(m.ModelError, match="params: .*missing.json"):
        leg.predict(tmp_path / "missing.json", q, qd, qdd)
    with pytest.raises(TypeError, match="params: an identify result"):
        leg.predict(3, q, qd, qdd)
    # a prior and a nominal as JSON text, as a dict and as a path: the same
    priors = [recorded(lambda p=p: m.identify(leg, sim, prior=p, friction="viscous,coulomb", weight=1e-3))[0]
              for p in (result.to_json(), result, path)]
    assert all(np.array_equal(p.params, priors[0].params) for p in priors)
    nominal = [recorded(lambda p=p: m.diagnose(leg, sim, nominal=p))[0]["heldout_rms_nominal"] for p in (result.to_json(), path)]
    assert nominal[0] == nominal[1]


def test_lists_are_lists_or_comma_separated_strings(leg):
    a = m.simulate(leg, 0.3, effects="backlash,payload", seed=2)
    b = m.simulate(leg, 0.3, effects=["backlash", "payload"], seed=2)
    assert np.array_equal(a["tau"], b["tau"])
    assert not np.array_equal(a["tau"], m.simulate(leg, 0.3, effects="backlash", seed=2)["tau"])
    d = m.simulate(leg, 1.0, seed=3)
    x, _ = recorded(lambda: m.identify(leg, d, friction=["viscous", "coulomb"], weight=1e-6))
    y, _ = recorded(lambda: m.identify(leg, d, friction="viscous, coulomb", weight=1e-6))
    assert np.array_equal(x.params, y.params)
    with pytest.raises(TypeError, match="effects: 3 is not a string"):
        m.simulate(leg, 0.3, effects=[3])


# -- the report's warnings ---------------------------------------------------


def test_every_warning_of_the_report_is_a_python_warning(leg):
    d = m.simulate(leg, 2.0, seed=1)
    # unconstrained: bodies that are not physically consistent
    r, ws = recorded(lambda: m.identify(leg, d, constraints="none", friction="viscous,coulomb", weight=1e-6))
    assert not r["all_bodies_consistent"]
    assert [w.kind for w in ws] == ["inconsistent_bodies"], ws
    assert ", ".join(r["inconsistent_bodies"]) in str(ws[0])
    # the first joint held still: fewer directions identified than the structure allows
    q, qd, qdd = d["q"].copy(), d["qd"].copy(), d["qdd"].copy()
    q[:, 0], qd[:, 0], qdd[:, 0] = 0.1, 0.0, 0.0
    tau = leg.rnea(q, qd, qdd) + np.random.default_rng(1).normal(0, 0.05, q.shape)
    held = dict(t=d["t"], q=q, qd=qd, qdd=qdd, tau=tau)
    r, ws = recorded(lambda: m.identify(leg, held, constraints="consistent", friction="viscous,coulomb", weight=1e-6))
    ident = r["identifiability"]
    assert ident["rank"] < ident["structural_rank"]
    assert [w.kind for w in ws] == ["identifiability"], ws
    assert str(ws[0]).startswith(f"{ident['rank']} of 66 parameter directions")
    # the report's own warnings (by kind), and bodies identified as rods or plates
    short = {k: v[:100] for k, v in d.items() if k != "joints"}
    r, ws = recorded(lambda: m.identify(leg, short))
    kinds = [w["kind"] for w in r["warnings"]]
    assert "law_not_chosen" in kinds and [w.kind for w in ws][: len(kinds)] == kinds, ws
    r, ws = recorded(lambda: m.Reducer(leg).update(d["q"], d["qd"], d["qdd"], d["tau"]).solve("ellipsoid", 1e-6))
    assert sorted(w.kind for w in ws) == ["degenerate_body"] * len(r["degenerate_bodies"]) and ws


def test_an_inaccurate_solve_is_a_python_warning(leg):
    """Torques in µN·m (×1e6) and a weight of 1e-12: Clarabel stops at its reduced
    tolerances; the report says so and so does Python."""
    d = m.simulate(leg, 1.0, seed=1)
    r, ws = recorded(lambda: m.Reducer(leg).update(d["q"], d["qd"], d["qdd"], d["tau"] * 1e6).solve("semi", 1e-12))
    assert r["status"] == "solved_inaccurately"
    assert "inaccurate" in [w.kind for w in ws]
    assert any("reduced tolerances" in str(w) for w in ws)


# -- bad arguments -------------------------------------------------------------


@pytest.mark.parametrize(
    "call, error, message",
    [
        (lambda leg, d: m.Robot.builtin("cheetah4"), ValueError, "name: no built-in robot 'cheetah4'"),
        (lambda leg, d: m.identify("cheetah4", d), ValueError, "robot: no built-in robot 'cheetah4'"),
        (lambda leg, d: m.identify(42, d), TypeError, "robot: a Robot, a built-in robot's name"),
        (lambda leg, d: m.simulate(leg, 1, seed=-1), ValueError, r"seed: -1 is not an integer in \[0, 2\*\*64 - 1\]"),
        (lambda leg, d: m.simulate(leg, 1, seed=1.5), TypeError, "seed: 1.5 is not an integer"),
        (lambda leg, d: m.excite(leg, seeds=-2), ValueError, "seeds: -2"),
        (lambda leg, d: m.simulate(leg, "1"), TypeError, "seconds: '1' is not a number"),
        (lambda leg, d: m.identify(leg, d, cutoff_hz=-5), ValueError, "cutoff_hz: -5.0 is not > 0"),
        (lambda leg, d: m.identify(leg, d, cutoff_hz=float("nan")), ValueError, "cutoff_hz: nan is not finite"),
        (lambda leg, d: m.identify(leg, d, weight=True), TypeError, "weight: True is not a number"),
        (lambda leg, d: m.identify(leg, d, constraints=3), TypeError, "constraints: 3 is not a string"),
        (lambda leg, d: m.identify(leg, 5), TypeError, "data: a dict of arrays or a DataFrame"),
        (lambda leg, d: m.Reducer(leg).update(d["q"], d["qd"], d["qdd"], d["tau"]).solve(weight="auto"),
         ValueError, "weight: 'auto': Reducer.solve takes a number >= 0"),
        (lambda leg, d: m.Reducer(leg).solve(weight=-1.0), ValueError, "weight: -1.0 is not >= 0"),
        (lambda leg, d: m.Reducer.from_bytes(leg, "abc"), TypeError, "data: bytes"),
        (lambda leg, d: m.nearest_consistent(np.ones(10), eps="x"), TypeError, "eps: 'x' is not a number"),
    ],
)
def test_bad_arguments_are_value_or_type_errors_naming_them(leg, sim, call, error, message):
    with pytest.raises(error, match=message):
        call(leg, sim)


def test_a_robot_may_be_named_where_one_is_expected(leg, sim, result):
    by_name, _ = recorded(lambda: m.identify("cheetah3-leg", sim, friction="viscous,coulomb", weight=1e-6))
    assert np.array_equal(by_name.params, result.params)
    assert np.array_equal(m.simulate("cheetah3-leg", 0.2)["tau"], m.simulate(leg, 0.2)["tau"])
    assert m.Reducer("cheetah3-leg").robot.joint_names == leg.joint_names


# -- pickling ------------------------------------------------------------------


def test_robots_reducers_and_results_pickle(leg, sim, result, tmp_path):
    q, qd, qdd, tau = (sim[k] for k in ("q", "qd", "qdd", "tau"))
    leg2 = pickle.loads(pickle.dumps(leg))
    assert repr(leg2) == repr(leg) and np.array_equal(leg2.rnea(q, qd, qdd), leg.rnea(q, qd, qdd))
    red = m.Reducer(leg).update(q, qd, qdd, tau)
    red2 = pickle.loads(pickle.dumps(red))
    assert red2.samples == red.samples and np.array_equal(red2.gram(), red.gram())
    red2.update(q[:10], qd[:10], qdd[:10], tau[:10])  # it goes on adding
    assert red2.samples == red.samples + 10
    assert pickle.loads(pickle.dumps(m.Reducer(leg))).samples == 0
    res2 = pickle.loads(pickle.dumps(result))
    assert isinstance(res2, m.IdentifyResult) and res2 == result and res2.to_json() == result.to_json()
    assert np.array_equal(leg.predict(res2, q, qd, qdd), leg.predict(result, q, qd, qdd))
    # a URDF robot with its sidecar, loaded again from its files (checked unchanged)
    from conftest import ROOT

    kuka = ROOT / "robots" / "kuka-lwr4"
    urdf = tmp_path / "kuka.urdf"
    shutil.copy(kuka / "kuka_lwr4.urdf", urdf)
    arm = m.Robot.from_urdf(urdf, sidecar=kuka / "kuka_lwr4.toml")
    blob = pickle.dumps(arm)
    assert np.array_equal(pickle.loads(blob).params(), arm.params())
    head, last = urdf.read_text().rsplit('<mass value="', 1)  # the last link's mass, ×10 or so
    urdf.write_text(head + '<mass value="1' + last)
    with pytest.raises(m.MomentlmiError, match="not the robot that was pickled"):
        pickle.loads(blob)


def test_a_robot_and_a_reducer_cross_process_boundaries(leg, sim):
    import concurrent.futures
    import multiprocessing

    q, qd, qdd, tau = (sim[k] for k in ("q", "qd", "qdd", "tau"))
    ctx = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(2, mp_context=ctx) as pool:
        parts = list(pool.map(_reduce_part, [leg, leg], [q[:500], q[500:]], [qd[:500], qd[500:]],
                              [qdd[:500], qdd[500:]], [tau[:500], tau[500:]]))
    whole = m.Reducer(leg).update(q, qd, qdd, tau)
    merged = parts[0].merge(parts[1])
    assert merged.samples == whole.samples
    assert np.abs(merged.gram() - whole.gram()).max() <= 1e-10 * np.abs(whole.gram()).max()


def _reduce_part(robot, q, qd, qdd, tau):
    return m.Reducer(robot).update(q, qd, qdd, tau)


# -- repr and version ------------------------------------------------------------


def test_a_result_has_a_short_repr_and_the_package_a_version(result):
    text = repr(result)
    assert "\n" not in text and len(text) < 300, text
    for part in ("robot='cheetah3-leg'", "status='solved'", "training_rms=[", "base_parameters="):
        assert part in text, text
    assert str(result) == text and json.loads(result.to_json()) == dict(result)
    assert m.__version__ == importlib.metadata.version("momentlmi")
