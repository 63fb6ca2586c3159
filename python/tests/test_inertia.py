"""One body's parameters: the pseudo-inertia, consistency, realizability,
four point masses, the nearest consistent π and Pinocchio's order."""

import numpy as np
import pytest

import momentlmi as m


def box(mass, sides, com=(0.0, 0.0, 0.0)):
    """π of a solid box (sides in m) with its centre at `com`."""
    a, b, c = sides
    ic = mass / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    x = np.asarray(com)
    i = ic + mass * (x @ x * np.eye(3) - np.outer(x, x))
    return np.array([mass, *(mass * x), i[0, 0], i[0, 1], i[0, 2], i[1, 1], i[1, 2], i[2, 2]])


def test_pseudo_inertia_of_a_point_mass():
    x = np.array([0.1, -0.2, 0.3])
    pi = np.array([2.0, *(2 * x), 0, 0, 0, 0, 0, 0])
    i = 2.0 * (x @ x * np.eye(3) - np.outer(x, x))
    pi[4:] = [i[0, 0], i[0, 1], i[0, 2], i[1, 1], i[1, 2], i[2, 2]]
    v = np.append(x, 1.0)
    assert np.allclose(m.pseudo_inertia(pi), 2.0 * np.outer(v, v), atol=1e-15)


def test_consistency_and_the_triangle_inequality():
    pi = box(3.0, (0.2, 0.1, 0.05), com=(0.05, 0, 0))
    assert m.is_consistent(pi)
    bad = pi.copy()
    bad[9] = bad[4] + bad[7] + 1.0  # Izz > Ixx + Iyy: no body has it
    report = m.check_consistency(bad)
    assert not report["consistent"] and not m.is_consistent(bad)
    near, dist = m.nearest_consistent(bad)
    assert m.is_consistent(near) and dist > 0 and near[0] == pytest.approx(3.0)


def test_four_point_masses_have_the_same_parameters():
    pi = box(1.5, (0.3, 0.2, 0.1), com=(0.02, -0.01, 0.03))
    masses, xyz = m.four_point_masses(pi)
    j = sum(mk * np.outer(np.append(x, 1), np.append(x, 1)) for mk, x in zip(masses, xyz))
    assert masses.shape == (4,) and xyz.shape == (4, 3) and (masses >= 0).all()
    assert np.allclose(j, m.pseudo_inertia(pi), atol=1e-12)


def test_realizable_in_its_box_not_in_a_smaller_ellipsoid():
    sides = np.array([0.3, 0.2, 0.1])
    pi = box(2.0, sides)
    # the box's circumscribed ellipsoid: semi-axes √3/2 × sides
    assert m.realizable_in(pi, [0, 0, 0], np.sqrt(3) / 2 * sides)
    assert not m.realizable_in(pi, [0, 0, 0], 0.2 * sides)
    # the same ellipsoid given with its axes turned a quarter about z (axes as columns)
    a = np.sqrt(3) / 2 * sides
    rot = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
    same = m.realizability(pi, [0, 0, 0], a[[1, 0, 2]], rot)["trace_jq"]
    other = m.realizability(pi, [0, 0, 0], a[[1, 0, 2]])["trace_jq"]
    assert same == pytest.approx(m.realizability(pi, [0, 0, 0], a)["trace_jq"], rel=1e-12)
    assert other != pytest.approx(same, rel=1e-3)


def test_pinocchio_order_swaps_iyy_and_ixz():
    pi = np.arange(1.0, 11.0)
    p = m.to_pinocchio(pi)
    assert list(p) == [1, 2, 3, 4, 5, 6, 8, 7, 9, 10]
    assert np.array_equal(m.from_pinocchio(p), pi)


def test_pinocchio_round_trip():
    pin = pytest.importorskip("pinocchio", reason="Pinocchio is not installed: its round trip is not checked")
    pi = box(1.2, (0.3, 0.2, 0.1), com=(0.05, -0.02, 0.01))
    inertia = pin.Inertia.FromDynamicParameters(m.to_pinocchio(pi))
    assert np.allclose(m.from_pinocchio(inertia.toDynamicParameters()), pi, atol=1e-14)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: m.pseudo_inertia(np.zeros(9)), "pi: shape (9,), expected (10,)"),
        (lambda: m.is_consistent(np.full(10, np.inf)), "pi: value inf at [0, 0] is not finite"),
        (lambda: m.realizable_in(np.ones(10), [0, 0], [1, 1, 1]), "center: shape (2,)"),
        (lambda: m.pseudo_inertia("abc"), "pi: not an array of numbers"),
    ],
)
def test_bad_arrays_are_value_errors_naming_them(call, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")):
        call()


def test_library_errors_are_momentlmi_errors():
    with pytest.raises(m.InertiaError, match="semi-axes must be positive"):
        m.realizable_in(np.ones(10), [0, 0, 0], [1, -1, 1])
    assert issubclass(m.InertiaError, m.MomentlmiError)


def test_a_tolerance_must_be_a_finite_number():
    for tol in (np.nan, np.inf, -1.0):
        with pytest.raises(ValueError, match="tol: "):
            m.is_consistent(box(1.0, (0.1, 0.1, 0.1)), tol=tol)
