"""dentbend.Damage: bodies keyed by ids, steps applied all or nothing, save and restore."""

import numpy as np
import pytest

import dentbend

CAR, BALL = 2**40 + 7, 9


def hit(ball, speed=6.0, target=CAR):
    bp, bf = ball
    surface = dentbend.Mesh(bp - np.float32([0, 0, 0.55]), bf)
    pose = np.eye(4)
    pose[2, 3] = 0.55
    state = dentbend.BodyState(mass=4.0, center_of_mass=(0, 0, 0.55), linear_velocity=(0, 0, -speed))
    return dentbend.Hit(target, BALL, (0, 0, 0.25), (0, 0, -1), surface, projectile_to_world=pose, projectile_state=state)


def world(target, **settings):
    damage = dentbend.Damage()
    tp, tf = target
    damage.add_body(CAR, tp, tf, threshold_speed=1.0, depth_per_speed=0.01, max_depth=0.1, **settings)
    damage.add_projectile(BALL)
    return damage


def test_a_step_dents_the_body_it_hits(target, ball):
    damage = world(target)
    tp, _ = target
    dents = damage.step([hit(ball)])
    assert len(dents) == 1
    dent = dents[0]
    assert (dent.target, dent.projectile) == (CAR, BALL)
    # 6 m/s against a 1 m/s threshold at 1 cm per m/s: 5 cm.
    assert dent.dent_distance == pytest.approx(0.05, abs=1e-5)
    assert dent.depth_made == pytest.approx(0.05, abs=1e-4)
    positions = damage.positions(CAR)
    assert positions.min(axis=0)[2] == pytest.approx(-0.25, abs=1e-4)
    assert np.any(positions[: len(tp)] != tp)
    moved = damage.moved(CAR)
    # The moved list is what the dent moved plus what its refinement added.
    assert len(moved) >= dent.moved_vertices
    assert isinstance(dent.point, tuple) and dent.point == pytest.approx((0.0, 0.0, 0.25), abs=1e-6)
    assert damage.normals(CAR).shape == positions.shape
    assert damage.faces(CAR).max() < len(positions)


def test_a_slow_hit_does_not_dent(target, ball):
    damage = world(target)
    assert damage.step([hit(ball, speed=0.5)]) == []
    tp, _ = target
    assert np.array_equal(damage.positions(CAR), tp)


def test_a_failed_step_changes_nothing(target, ball):
    damage = world(target)
    damage.step([hit(ball)])
    before = damage.positions(CAR)
    with pytest.raises(dentbend.DentError, match="123"):
        damage.step([hit(ball), hit(ball, target=123)])
    assert np.array_equal(damage.positions(CAR), before)


def test_saved_damage_restores_the_same_mesh(target, ball):
    damage = world(target)
    damage.record(CAR, "car")
    damage.step([hit(ball)])
    damage.step([hit(ball, speed=3.0)])
    saved = damage.save()
    assert isinstance(saved, bytes) and saved.startswith(b"{")
    other = world(target)
    other.restore(CAR, saved, "car")
    assert np.array_equal(other.positions(CAR), damage.positions(CAR))
    assert np.array_equal(other.faces(CAR), damage.faces(CAR))
    with pytest.raises(dentbend.DentError, match="no body"):
        other.restore(CAR, saved, "truck")
    with pytest.raises(dentbend.DentError):
        other.restore(CAR, b"{not json", "car")


def test_bad_bodies_and_poses_are_refused(target):
    damage = dentbend.Damage()
    tp, tf = target
    with pytest.raises(dentbend.DentError):
        damage.add_body(1, tp, tf, max_depth=float("nan"))
    with pytest.raises(dentbend.DentError):
        damage.add_body(1, tp[:, :2], tf)
    with pytest.raises(dentbend.DentError, match="does not dent"):
        damage.positions(1)
    with pytest.raises(dentbend.DentError, match="does not dent"):
        damage.set_pose(1, np.eye(4))
    damage.add_body(1, tp, tf)
    skewed = np.eye(4)
    skewed[3, 0] = 1.0
    with pytest.raises(dentbend.DentError, match="last row"):
        damage.set_pose(1, skewed)
    scaled = np.diag([2.0, 2.0, 2.0, 1.0])
    with pytest.raises(dentbend.DentError, match="rotation and translation"):
        damage.set_pose(1, scaled)
    with pytest.raises(dentbend.DentError, match="rotation and translation"):
        damage.set_pose(1, np.diag([-1.0, 1.0, 1.0, 1.0]))
    with pytest.raises(dentbend.DentError):
        damage.add_body(2, tp, tf, sigma=0.0)
    with pytest.raises(dentbend.DentError):
        dentbend.BodyState(mass=-1.0)
    with pytest.raises(dentbend.DentError):
        dentbend.BodyState(mass=float("nan"))
