"""Refused inputs raise dentbend.DentError (a ValueError) with a message, and change nothing."""

import numpy as np
import pytest

import dentbend

DEPTH = 0.05


def test_dent_error_is_a_value_error():
    assert issubclass(dentbend.DentError, ValueError)


def dent_with(target, ball, impact, **changes):
    """Calls dent with one argument replaced, checking that no input array changed."""
    tp, tf = target
    bp, bf = ball
    arguments = dict(
        target_positions=tp, target_faces=tf, projectile_positions=bp, projectile_faces=bf, dent_distance=DEPTH
    )
    arguments.update(impact)
    arguments.update(changes)
    copies = {k: np.array(v, copy=True) for k, v in arguments.items() if isinstance(v, np.ndarray)}
    with pytest.raises(dentbend.DentError) as raised:
        dentbend.dent(**arguments)
    for name, copy in copies.items():
        assert np.array_equal(arguments[name], copy, equal_nan=copy.dtype.kind == "f"), name
    return str(raised.value)


def test_wrong_shapes_are_refused(target, ball, impact):
    tp, tf = target
    assert "shape" in dent_with(target, ball, impact, target_positions=tp[:, :2])
    assert "shape" in dent_with(target, ball, impact, target_faces=tf.reshape(-1))
    assert "shape" in dent_with(target, ball, impact, projectile_positions=np.zeros((4, 3, 1), np.float32))
    assert "3 numbers" in dent_with(target, ball, impact, point=(0.0, 0.0))
    assert "3 numbers" in dent_with(target, ball, impact, normal="up")


def test_wrong_dtypes_are_refused(target, ball, impact):
    tp, tf = target
    assert "dtype" in dent_with(target, ball, impact, target_positions=tp.astype(np.complex64))
    assert "dtype" in dent_with(target, ball, impact, target_positions=tp.astype(str))
    assert "dtype" in dent_with(target, ball, impact, target_faces=tf.astype(np.float32))
    assert "dtype" in dent_with(target, ball, impact, target_faces=tf.astype(bool))


def test_nan_and_infinity_are_refused(target, ball, impact):
    tp, _ = target
    bad = tp.copy()
    bad[5, 1] = np.nan
    dent_with(target, ball, impact, target_positions=bad)
    bad[5, 1] = np.inf
    dent_with(target, ball, impact, target_positions=bad)
    # Beyond float32's range: infinite once converted.
    huge = tp.astype(np.float64)
    huge[0, 0] = 1e300
    with np.errstate(over="ignore"):
        dent_with(target, ball, impact, target_positions=huge)
    dent_with(target, ball, impact, point=(np.nan, 0.0, 0.25))
    dent_with(target, ball, impact, normal=(0.0, 0.0, 0.0))
    dent_with(target, ball, impact, dent_distance=float("nan"))
    dent_with(target, ball, impact, dent_distance=-0.1)
    dent_with(target, ball, impact, sigma=float("inf"))


def test_indices_out_of_range_are_refused(target, ball, impact):
    tp, tf = target
    bad = tf.copy()
    bad[3, 2] = len(tp)
    assert str(len(tp)) in dent_with(target, ball, impact, target_faces=bad)
    negative = tf.astype(np.int64)
    negative[0, 0] = -1
    assert "-1" in dent_with(target, ball, impact, target_faces=negative)
    too_big = tf.astype(np.int64)
    too_big[0, 0] = 2**40
    assert str(2**40) in dent_with(target, ball, impact, target_faces=too_big)
    # Unsigned indices past int64's range are named as they are, not wrapped.
    huge = tf.astype(np.uint64)
    huge[0, 0] = 2**63 + 5
    assert str(2**63 + 5) in dent_with(target, ball, impact, target_faces=huge)


def test_empty_and_degenerate_meshes_are_refused(target, ball, impact):
    dent_with(target, ball, impact, target_positions=np.zeros((0, 3), np.float32), target_faces=np.zeros((0, 3), np.uint32))
    tp, tf = target
    # Every face collapsed to a point.
    dent_with(target, ball, impact, target_positions=np.zeros_like(tp))
    dent_with(target, ball, impact, target_faces=np.zeros((1, 3), np.uint32))


def test_bad_settings_are_refused(target, ball, impact):
    assert "refine" in dent_with(target, ball, impact, refine="sometimes")
    dent_with(target, ball, impact, refine=-1.0)


def test_a_projectile_moving_away_does_not_dent(target, ball, impact):
    moving_away = dict(impact, relative_velocity=(0.0, 0.0, 3.0))
    dent_with(target, ball, moving_away)
