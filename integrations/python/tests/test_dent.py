"""dentbend.dent: what a dent makes, on numpy arrays."""

import sys
import threading
import time

import numpy as np
import pytest

import dentbend
from conftest import signed_volume

DEPTH = 0.05


def test_a_ball_dents_the_top_of_a_box_as_deep_as_asked(target, ball, impact):
    tp, tf = target
    bp, bf = ball
    result = dentbend.dent(tp, tf, bp, bf, dent_distance=DEPTH, **impact)
    assert result.positions.dtype == np.float32 and result.positions.shape[1] == 3
    assert result.faces.dtype == np.uint32 and result.faces.shape[1] == 3
    assert result.moved.dtype == np.uint32 and len(result.moved) > 0
    # The peak displacement is the dent distance (the library's own rounding: float32, 1e-5 m).
    assert result.max_displacement == pytest.approx(DEPTH, abs=1e-5)
    # The vertex under the contact went down by the dent distance, along -z.
    top_centre = int(np.argmin(np.linalg.norm(tp - np.float32([0, 0, 0.25]), axis=1)))
    assert result.positions[top_centre, 2] == pytest.approx(0.25 - DEPTH, abs=1e-4)
    # Vertices far from the ball (beyond 3 ball radii) did not move at all.
    far = np.linalg.norm(tp[:, :2], axis=1) > 0.9
    assert np.array_equal(result.positions[: len(tp)][far], tp[far])
    # Every vertex that changed is in moved (which also lists the refinement's new vertices,
    # and may list a vertex whose displacement rounded to nothing in float32).
    changed = np.flatnonzero(np.any(result.positions[: len(tp)] != tp, axis=1))
    assert set(changed) <= set(result.moved.tolist())
    assert set(range(len(tp), len(result.positions))) <= set(result.moved.tolist())


def test_the_inputs_are_not_modified_and_the_outputs_are_owned(target, ball, impact):
    tp, tf = target
    bp, bf = ball
    copies = [a.copy() for a in (tp, tf, bp, bf)]
    result = dentbend.dent(tp, tf, bp, bf, dent_distance=DEPTH, **impact)
    for before, after in zip(copies, (tp, tf, bp, bf)):
        assert np.array_equal(before, after)
    for array in (result.positions, result.faces, result.moved):
        assert array.flags.owndata or array.base is not None
        assert array.flags.c_contiguous and array.flags.writeable
    assert not np.shares_memory(result.positions, tp)


def test_other_dtypes_are_converted_to_the_same_dent(target, ball, impact):
    tp, tf = target
    bp, bf = ball
    exact = dentbend.dent(tp, tf, bp, bf, dent_distance=DEPTH, **impact)
    converted = dentbend.dent(
        tp.astype(np.float64), tf.astype(np.int64), bp.tolist(), bf.astype(np.int32), dent_distance=DEPTH, **impact
    )
    assert np.array_equal(exact.positions, converted.positions)
    assert np.array_equal(exact.faces, converted.faces)
    # A Fortran-ordered (non-contiguous rows) array is read correctly too.
    fortran = dentbend.dent(np.asfortranarray(tp), tf, bp, bf, dent_distance=DEPTH, **impact)
    assert np.array_equal(exact.positions, fortran.positions)


def test_refinement_is_described_for_carrying_attributes(target, ball, impact):
    tp, tf = target
    bp, bf = ball
    result = dentbend.dent(tp, tf, bp, bf, dent_distance=DEPTH, refine="auto", **impact)
    added = len(result.positions) - len(tp)
    # The box's 25 cm grid is coarse for a 30 cm ball: the dent refines it.
    assert added > 0
    assert result.parents.shape == (added, 2) and result.fractions.shape == (added,)
    assert np.all((result.fractions > 0) & (result.fractions < 1))
    # A new vertex's parents come before it.
    own = np.arange(len(tp), len(result.positions))
    assert np.all(result.parents.max(axis=1) < own)
    assert result.face_parents.shape == (len(result.faces),)
    assert result.face_parents.max() < len(tf)
    # Interpolating the input positions by parents and fractions puts every new vertex on its
    # input face's plane; the dent then moved it at most the dent distance from there.
    rest = np.concatenate([tp.astype(np.float64), np.zeros((added, 3))])
    for k, ((a, b), t) in enumerate(zip(result.parents, result.fractions)):
        rest[len(tp) + k] = (1 - t) * rest[a] + t * rest[b]
    offset = np.linalg.norm(result.positions.astype(np.float64) - rest, axis=1)
    assert offset.max() <= DEPTH + 1e-4


def test_refine_off_keeps_the_faces(target, ball, impact):
    tp, tf = target
    bp, bf = ball
    for setting in ("off", False):
        result = dentbend.dent(tp, tf, bp, bf, dent_distance=DEPTH, refine=setting, **impact)
        assert np.array_equal(result.faces, tf)
        assert len(result.positions) == len(tp)
        assert result.parents.shape == (0, 2)
        assert np.array_equal(result.face_parents, np.arange(len(tf)))


def test_preserve_volume_puts_the_dents_volume_back(target, ball, impact):
    tp, tf = target
    bp, bf = ball
    before = signed_volume(tp, tf)
    free = dentbend.dent(tp, tf, bp, bf, dent_distance=DEPTH, **impact)
    kept = dentbend.dent(tp, tf, bp, bf, dent_distance=DEPTH, preserve_volume=True, **impact)
    lost_free = before - signed_volume(free.positions, free.faces)
    lost_kept = abs(before - signed_volume(kept.positions, kept.faces))
    assert lost_free > 1e-4
    # The rim puts back all but a few percent of what the dent took (the library's volume
    # tolerance is 1 % of the cavity; 5 % leaves room for float32 positions).
    assert lost_kept < 0.05 * lost_free


def test_the_interpreter_lock_is_released_while_it_dents(target, ball, impact):
    tp, tf = target
    bp, bf = ball
    counter = 0
    stop = False

    def spin():
        nonlocal counter
        while not stop:
            counter += 1
            time.sleep(0)

    # Without a forced switch, the spinning thread runs during the call only if the call
    # itself lets the lock go.
    interval = sys.getswitchinterval()
    sys.setswitchinterval(100.0)
    thread = threading.Thread(target=spin)
    try:
        thread.start()
        time.sleep(0.01)
        before = counter
        dentbend.dent(tp, tf, bp, bf, dent_distance=DEPTH, refine=0.01, **impact)
        during = counter - before
    finally:
        stop = True
        thread.join()
        sys.setswitchinterval(interval)
    assert during > 0
