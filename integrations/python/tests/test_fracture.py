"""dentbend.Damage's fracture and replication: a hard hit breaks a breakable body into pieces
with their mass, a Replica follows the server's dents and pieces bit for bit, bad settings and
bad messages change nothing."""

import numpy as np
import pytest

import dentbend
import meshes
from conftest import signed_volume

SLAB, BALL = 5, 2**33 + 1
WIRE_SLAB, BALL_SHAPE = 1, 4


def ball_hit(ball, speed, x=0.3, y=-0.2):
    """A 2 kg ball of radius 0.3 m falling at ``speed`` m/s on the slab's top at (x, y)."""
    bp, bf = ball
    surface = dentbend.Mesh(bp - np.float32([0, 0, 0.55]), bf)
    pose = np.eye(4)
    pose[:3, 3] = (x, y, 0.55)
    state = dentbend.BodyState(mass=2.0, center_of_mass=(x, y, 0.55), linear_velocity=(0, 0, -speed))
    return surface, dentbend.Hit(SLAB, BALL, (x, y, 0.25), (0, 0, -1), surface, projectile_to_world=pose,
                                 projectile_state=state)


def slab_world(target, **fracture):
    """The static 2 x 2 x 0.5 m slab (2 m^3): dents 1 cm per m/s above 1 m/s, breaks within
    0.5 m of a hit that removes 40 J."""
    damage = dentbend.Damage()
    tp, tf = target
    damage.add_body(SLAB, tp, tf, threshold_speed=1.0, depth_per_speed=0.01, max_depth=0.1)
    damage.add_projectile(BALL)
    damage.set_fracture(SLAB, **{"cells": 10, "radius": 0.5, "seed": 3, "toughness": 40.0, **fracture})
    return damage


def test_a_hard_hit_breaks_the_slab_into_pieces_with_their_mass(target, ball):
    damage = slab_world(target)
    # 0.5 x 2 kg x (4 m/s)^2 = 16 J: under the toughness, a dent and no break.
    damage.step([ball_hit(ball, 4.0)[1]])
    assert damage.fractures() == []
    # 0.5 x 2 kg x (8 m/s)^2 = 64 J: it breaks.
    dents = damage.step([ball_hit(ball, 8.0)[1]])
    assert len(dents) == 1
    (f,) = damage.fractures()
    assert (f.body, f.projectile, f.number, f.cause, f.whole) == (SLAB, BALL, 0, "energy", False)
    assert f.energy == pytest.approx(64.0, rel=0.01)
    assert np.array_equal(f.to_world, np.eye(4, dtype=np.float32))
    assert len(f.pieces) >= 2
    # Rest and pieces: closed solids of the slab's 2 m^3, less its two dents (3 and 7 cm deep
    # under a 0.3 m ball: under pi x 0.3^2 x 0.1 = 0.028 m^3), at 1000 kg/m^3, each piece's
    # mass its own volume's.
    rest_volume = signed_volume(damage.positions(SLAB), damage.faces(SLAB))
    assert f.rest_mass == pytest.approx(1000.0 * rest_volume, rel=1e-3)
    total = rest_volume
    for k, piece in enumerate(f.pieces):
        assert (piece.fracture, piece.index) == (0, k)
        volume = signed_volume(piece.positions, piece.faces)
        assert volume > 0 and piece.mass == pytest.approx(1000.0 * volume, rel=1e-3)
        centre = np.float32(piece.center_of_mass)
        assert np.allclose(piece.hull_points, centre + (piece.positions - centre) * 0.97, atol=1e-5)
        assert piece.inertia.shape == (3, 3) and np.allclose(piece.inertia, piece.inertia.T, atol=1e-4)
        total += volume
    assert 2.0 - 0.028 < total < 2.0 + 1e-4
    # The rest: every vertex new.
    assert np.array_equal(damage.moved(SLAB), np.arange(len(damage.positions(SLAB)), dtype=np.uint32))
    lin, _ = f.projectile_velocity
    assert 0.0 < np.linalg.norm(lin) < 8.0
    # The next step is quiet.
    damage.step([])
    assert damage.fractures() == []


def test_clear_fracture_makes_the_body_unbreakable(target, ball):
    damage = slab_world(target)
    damage.clear_fracture(SLAB)
    damage.step([ball_hit(ball, 8.0)[1]])
    assert damage.fractures() == []


def test_bad_fracture_settings_are_refused(target):
    damage = dentbend.Damage()
    tp, tf = target
    damage.add_body(SLAB, tp, tf)
    for bad, says in [
        (dict(cells=0, radius=0.5, toughness=1.0), "cells"),
        (dict(cells=4, radius=float("nan"), toughness=1.0), "radius"),
        (dict(cells=4, radius=0.5, toughness=float("nan")), "toughness"),
        (dict(cells=4, radius=0.5, toughness=-1.0), "toughness"),
        (dict(cells=4, radius=0.5), "toughness"),
        (dict(cells=4, radius=0.5, dent_limit=0.1, max_pieces=0), "max_pieces"),
        (dict(cells=4, radius=0.5, dent_limit=0.1, density=-1.0), "density"),
    ]:
        with pytest.raises(dentbend.DentError, match=says):
            damage.set_fracture(SLAB, **bad)
    with pytest.raises(dentbend.DentError, match="does not dent"):
        damage.set_fracture(77, cells=4, radius=0.5, toughness=1.0)
    # An open mesh bounds no solid.
    damage.add_body(6, tp, tf[:-2])
    with pytest.raises(dentbend.DentError, match="closed"):
        damage.set_fracture(6, cells=4, radius=0.5, toughness=1.0)


def test_a_replica_follows_the_servers_dents_and_pieces(target, ball):
    server = slab_world(target)
    surface, _ = ball_hit(ball, 8.0)
    tp, tf = target
    server.replicate(SLAB, WIRE_SLAB)
    server.add_wire_projectile(BALL_SHAPE, surface)
    client = dentbend.Replica()
    client.add_body(WIRE_SLAB, tp, tf, threshold_speed=1.0, depth_per_speed=0.01, max_depth=0.1)
    client.add_projectile(BALL_SHAPE, surface)
    client.join(server.snapshot())
    messages = []
    for speed, x in [(4.0, -0.5), (8.0, 0.4)]:
        server.step([ball_hit(ball, speed, x=x)[1]])
        messages.append(server.message())
        client.apply(messages[-1])
        assert np.array_equal(client.positions(WIRE_SLAB), server.positions(SLAB))
        assert np.array_equal(client.faces(WIRE_SLAB), server.faces(SLAB))
    (mine,) = client.fractures()
    (theirs,) = server.fractures()
    assert (mine.body, mine.whole, mine.number) == (WIRE_SLAB, False, theirs.number)
    assert len(mine.pieces) == len(theirs.pieces)
    for a, b in zip(mine.pieces, theirs.pieces):
        assert np.array_equal(a.positions, b.positions) and np.array_equal(a.faces, b.faces)
        assert a.mass == b.mass and a.linear_velocity == (0.0, 0.0, 0.0)
    # Every vertex of the rest is new, on both sides.
    assert np.array_equal(client.moved(WIRE_SLAB), server.moved(SLAB))
    client.forget_piece(mine.number, 0)
    server.forget_piece(theirs.number, 0)
    # A step that changes no carried body sends an empty message: no change.
    server.step([])
    assert server.message() == b""
    client.apply(server.message())
    assert client.fractures() == [] and len(client.moved(WIRE_SLAB)) == 0
    # A message repeated, truncated or garbage is refused, nothing changed.
    now = client.positions(WIRE_SLAB)
    for bad in [messages[-1], messages[-1][:5], b"\x00" * 40]:
        with pytest.raises(dentbend.DentError):
            client.apply(bad)
        assert np.array_equal(client.positions(WIRE_SLAB), now)
    with pytest.raises(dentbend.DentError, match="no body"):
        client.positions(99)


def test_a_game_asset_keeps_its_uvs_and_hard_edges_through_dents_and_breaks(ball):
    """A slab of 1 m cells (too coarse for the dent: it refines) with UVs and authored normals:
    a head-on dent from above keeps every top vertex's UV at twice its (x, y) within 1e-5 (new
    vertices included: it moves them straight down), the other sides' normals within 0.02 rad of
    their side's (a smoothed hard edge would turn them 45 degrees); its pieces carry UVs and unit
    normals."""
    positions, faces, normals, uvs = meshes.box_asset()
    damage = dentbend.Damage()
    damage.add_body(SLAB, positions, faces, threshold_speed=1.0, depth_per_speed=0.01, max_depth=0.1,
                    uvs=uvs, normals=normals)
    damage.add_projectile(BALL)
    damage.step([ball_hit(ball, 8.0)[1]])
    after, now_normals, now_uvs = damage.positions(SLAB), damage.normals(SLAB), damage.uvs(SLAB)
    assert len(after) > len(positions), "the dent refined the top"
    assert now_uvs.shape == (len(after), 2)
    top = np.concatenate([normals[:, 2] > 0.5, np.ones(len(after) - len(positions), dtype=bool)])
    assert np.abs(now_uvs[top] - 2.0 * after[top][:, :2]).max() < 1e-5
    off = ~top[: len(positions)]
    cos = np.einsum("ij,ij->i", now_normals[: len(positions)][off], normals[off])
    assert cos.min() > np.cos(0.02)
    damage.set_fracture(SLAB, cells=10, radius=0.6, seed=2, toughness=20.0)
    damage.step([ball_hit(ball, 8.0, x=-0.6, y=0.7)[1]])
    (f,) = damage.fractures()
    for piece in f.pieces:
        assert piece.uvs.shape == (len(piece.positions), 2) and np.isfinite(piece.uvs).all()
        assert np.allclose(np.linalg.norm(piece.normals, axis=1), 1.0, atol=1e-4)
    assert damage.uvs(SLAB).shape == (len(damage.positions(SLAB)), 2)
    # A body added without UVs has none.
    plain = dentbend.Damage()
    plain.add_body(1, positions, faces)
    assert plain.uvs(1) is None


def test_a_replica_keeps_the_assets_uvs(ball):
    """A replica given the same game asset follows a refining dent with the server's UVs (within
    1e-6) and normals (within 1e-5), positions bit for bit."""
    positions, faces, normals, uvs = meshes.box_asset()
    server = dentbend.Damage()
    server.add_body(SLAB, positions, faces, threshold_speed=1.0, depth_per_speed=0.01, max_depth=0.1, uvs=uvs,
                    normals=normals)
    server.add_projectile(BALL)
    surface, hit = ball_hit(ball, 8.0)
    server.replicate(SLAB, WIRE_SLAB)
    server.add_wire_projectile(BALL_SHAPE, surface)
    client = dentbend.Replica()
    client.add_body(WIRE_SLAB, positions, faces, threshold_speed=1.0, depth_per_speed=0.01, max_depth=0.1, uvs=uvs,
                    normals=normals)
    client.add_projectile(BALL_SHAPE, surface)
    client.join(server.snapshot())
    server.step([hit])
    client.apply(server.message())
    assert len(client.positions(WIRE_SLAB)) > len(positions)
    assert np.array_equal(client.positions(WIRE_SLAB), server.positions(SLAB))
    assert np.abs(client.uvs(WIRE_SLAB) - server.uvs(SLAB)).max() < 1e-6
    assert np.abs(client.normals(WIRE_SLAB) - server.normals(SLAB)).max() < 1e-5


def test_a_restored_asset_has_the_saved_uvs(ball):
    """Damage saved from a game asset (one dent, then two in one step: both refine) restores on
    a fresh one with the same mesh bit for bit and the same UVs (within 1e-6)."""
    positions, faces, normals, uvs = meshes.box_asset()

    def fresh():
        damage = dentbend.Damage()
        damage.add_body(SLAB, positions, faces, threshold_speed=1.0, depth_per_speed=0.01, max_depth=0.1, uvs=uvs,
                        normals=normals)
        damage.add_projectile(BALL)
        return damage

    damage = fresh()
    damage.record(SLAB, "slab")
    damage.step([ball_hit(ball, 8.0, x=-1.0, y=1.0)[1]])
    damage.step([ball_hit(ball, 6.0, x=1.2, y=0.8)[1], ball_hit(ball, 6.0, x=-1.2, y=-1.0)[1]])
    other = fresh()
    other.restore(SLAB, damage.save(), "slab")
    assert np.array_equal(other.positions(SLAB), damage.positions(SLAB))
    assert np.abs(other.uvs(SLAB) - damage.uvs(SLAB)).max() < 1e-6
