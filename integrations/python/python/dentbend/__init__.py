"""dentbend: real-time denting and bending of rigid bodies without finite elements (SCA 2014).

Arrays in and out are numpy arrays: positions ``(N, 3)`` float32 in metres, faces ``(M, 3)``
uint32 vertex indices, counter-clockwise seen from outside. Arrays already of that dtype and
C-contiguous are read in place; others are converted once. The interpreter lock is released
while the library works.

Every refused input raises :class:`DentError` (a :class:`ValueError`) with the library's
message, and nothing passed in is modified.

>>> import dentbend
>>> result = dentbend.dent(target_positions, target_faces, ball_positions, ball_faces,
...                        point=(0, 0, 1), normal=(0, 0, -1), relative_velocity=(0, 0, -3),
...                        dent_distance=0.05)
>>> result.positions, result.faces, result.moved, result.max_displacement
"""

from ._dentbend import (
    AppliedDent,
    BodyState,
    Damage,
    DentError,
    DentResult,
    Fracture,
    Hit,
    Mesh,
    Piece,
    Replica,
    ReplicaFracture,
    __version__,
    dent,
)

__all__ = [
    "AppliedDent",
    "BodyState",
    "Damage",
    "DentError",
    "DentResult",
    "Fracture",
    "Hit",
    "Mesh",
    "Piece",
    "Replica",
    "ReplicaFracture",
    "__version__",
    "dent",
]
