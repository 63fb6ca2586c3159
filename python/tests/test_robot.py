"""A robot's dynamics over many samples: the regressor times the parameters
is the inverse dynamics; arguments are checked."""

import numpy as np
import pytest

import momentlmi as m


@pytest.fixture(scope="module")
def leg():
    return m.Robot.builtin("cheetah3-leg")


def states(n, k=40, seed=3):
    rng = np.random.default_rng(seed)
    return [rng.uniform(-2, 2, (k, n)) for _ in range(3)]


def test_regressor_times_parameters_is_the_inverse_dynamics(leg):
    q, v, a = states(leg.dof)
    y = leg.regressor(q, v, a)
    p = len(leg.parameter_names)
    assert y.shape == (40, 3, p) and leg.joint_names == ["abad", "hip", "knee"]
    theta = np.zeros(p)
    theta[: 10 * len(leg.body_names)] = leg.params().ravel()
    tau = leg.rnea(q, v, a)
    assert np.abs(y @ theta - tau).max() < 1e-12 * np.abs(tau).max()
    # one sample as a vector, lists of numbers as arrays
    assert np.allclose(leg.rnea(q[0], v[0], a[0]), tau[:1], rtol=0, atol=1e-13)
    assert np.allclose(leg.rnea(q.tolist(), v, a), tau, rtol=0, atol=0)


def test_gravity_holds_the_leg_still(leg):
    """At rest the torques are gravity's: they change with the pose, not with time."""
    q = np.array([[0.0, -0.8, 1.6], [0.3, -0.5, 1.0]])
    zero = np.zeros_like(q)
    g = leg.rnea(q, zero, zero)
    assert np.abs(g).max() > 0.5  # the leg weighs several kg
    assert not np.allclose(g[0], g[1])


@pytest.mark.parametrize(
    "bad, message",
    [
        (dict(q=np.zeros((4, 2))), r"q: shape \(4, 2\), expected \(N, 3\) or \(3,\)"),
        (dict(v=np.zeros((5, 3))), r"v: 5 samples, q has 4"),
        (dict(a=np.full((4, 3), np.nan)), r"a: value NaN at \[0, 0\] is not finite"),
        (dict(q=np.zeros((2, 2, 3))), r"q: shape \(2, 2, 3\)"),
    ],
)
def test_bad_states_are_value_errors_naming_the_argument(leg, bad, message):
    args = dict(q=np.zeros((4, 3)), v=np.zeros((4, 3)), a=np.zeros((4, 3)))
    args.update(bad)
    for f in (leg.rnea, leg.regressor):
        with pytest.raises(ValueError, match=message):
            f(**args)


def test_unknown_robots_are_value_errors_and_missing_files_momentlmi_errors(tmp_path):
    # a name is an argument: a ValueError naming it and the built-in ones (issue 58)
    with pytest.raises(ValueError, match="name: no built-in robot 'arm' \\(built in: .*cheetah3-leg"):
        m.Robot.builtin("arm")
    with pytest.raises(m.ModelError, match="no-such.urdf"):
        m.Robot.from_urdf(tmp_path / "no-such.urdf")


def test_states_too_large_are_errors_not_infinities(leg):
    big = np.full((2, 3), 1e300)
    for f in (leg.rnea, leg.regressor):
        with pytest.raises(m.MomentlmiError, match="sample 0: a .* is not finite"):
            f(big, big, np.zeros((2, 3)))
    empty = np.zeros((0, 3))
    assert leg.rnea(empty, empty, empty).shape == (0, 3)
    r = m.Reducer(leg).update(empty, empty, empty, empty)
    assert r.samples == 0
    with pytest.raises(m.IdentifyError, match="no samples yet"):
        r.to_bytes()
