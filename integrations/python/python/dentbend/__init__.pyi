"""Type stubs of dentbend (the extension module's public names)."""

from typing import Literal, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
Float32x3 = npt.NDArray[np.float32]
UInt32 = npt.NDArray[np.uint32]

class DentError(ValueError):
    """An input dentbend refuses, with the library's message; nothing was changed."""

class DentResult:
    """What :func:`dent` made."""

    @property
    def positions(self) -> Float32x3:
        """The dented target's positions, ``(N, 3)`` float32, m (input vertices first)."""
    @property
    def faces(self) -> UInt32:
        """Its triangles, ``(M, 3)`` uint32 (split input faces keep their row)."""
    @property
    def moved(self) -> UInt32:
        """Vertices the dent moved or added, ascending."""
    @property
    def max_displacement(self) -> float:
        """Largest displacement of a vertex, m."""
    @property
    def kept(self) -> float:
        """Fraction of the dent kept by the crossing guard (1.0: all of it)."""
    @property
    def parents(self) -> UInt32:
        """``(K, 2)``: for each added vertex, the ends of the edge it split."""
    @property
    def fractions(self) -> npt.NDArray[np.float32]:
        """``(K,)``: where along that edge (attribute = (1 - t) * a + t * b)."""
    @property
    def face_parents(self) -> UInt32:
        """``(M,)``: for each output face, the input face it is part of."""
    @property
    def warnings(self) -> list[str]:
        """The library's warnings."""

def dent(
    target_positions: ArrayLike,
    target_faces: ArrayLike,
    projectile_positions: ArrayLike,
    projectile_faces: ArrayLike,
    point: ArrayLike,
    normal: ArrayLike,
    relative_velocity: ArrayLike,
    dent_distance: float,
    *,
    preserve_volume: bool = False,
    refine: Union[Literal["auto", "off"], bool, float, None] = "auto",
    sigma: Optional[float] = None,
    guard_crossings: bool = True,
) -> DentResult:
    """Dents the target where the projectile hits it (both in world coordinates at contact).

    ``point`` is the contact (m), ``normal`` points from the contact into the target,
    ``relative_velocity`` is the projectile's velocity relative to the target (m/s; all zero:
    head-on along ``normal``), ``dent_distance`` the deepest displacement (m). ``sigma`` is the
    smoothing width (m; ``None``: half the dent distance); ``preserve_volume`` raises a rim that
    puts the dent's volume back; ``refine`` adds vertices where the target is too coarse for the
    dent ("auto"), never ("off"), or down to a longest edge (m). ``guard_crossings`` scales a
    dent back so that no faces cross. The inputs are not modified.
    """

class Mesh:
    """A triangle mesh made once and shared by hits as a projectile's surface."""

    def __init__(self, positions: ArrayLike, faces: ArrayLike) -> None: ...
    @property
    def positions(self) -> Float32x3: ...
    @property
    def faces(self) -> UInt32: ...

class BodyState:
    """A body's motion before the step, world coordinates."""

    def __init__(
        self,
        mass: float = 0.0,
        center_of_mass: Optional[ArrayLike] = None,
        linear_velocity: Optional[ArrayLike] = None,
        angular_velocity: Optional[ArrayLike] = None,
        inverse_inertia: Optional[ArrayLike] = None,
    ) -> None:
        """``mass`` kg (0: cannot move), m, m/s, rad/s, world inverse inertia 3x3 (1/(kg m^2);
        ``None``: that of a solid ball of radius 0.5 m and this mass)."""

class Hit:
    """One contact of a step, as the engine reported it before resolving it."""

    def __init__(
        self,
        target: int,
        projectile: int,
        point: ArrayLike,
        normal: ArrayLike,
        projectile_surface: Mesh,
        *,
        projectile_to_world: Optional[ArrayLike] = None,  # 4x4 rotation and translation
        target_state: Optional[BodyState] = None,
        projectile_state: Optional[BodyState] = None,
    ) -> None: ...

class AppliedDent:
    """One dent a step made."""

    @property
    def target(self) -> int: ...
    @property
    def projectile(self) -> int: ...
    @property
    def point(self) -> tuple[float, float, float]: ...
    @property
    def dent_distance(self) -> float: ...
    @property
    def depth_made(self) -> float: ...
    @property
    def moved_vertices(self) -> int: ...

class Piece:
    """One piece that broke loose: a closed mesh in the broken body's own coordinates (place it
    with its fracture's ``to_world``) and its mass properties."""

    @property
    def fracture(self) -> int: ...
    @property
    def index(self) -> int: ...
    @property
    def positions(self) -> Float32x3: ...
    @property
    def faces(self) -> UInt32: ...
    @property
    def normals(self) -> Float32x3: ...
    @property
    def uvs(self) -> Optional[npt.NDArray[np.float32]]:
        """(N, 2) when the body had UVs; a cut's projected at its texel density."""
    @property
    def hull_points(self) -> Float32x3:
        """The vertices shrunk 3 % toward the centre of mass: a convex collider's points."""
    @property
    def mass(self) -> float: ...
    @property
    def center_of_mass(self) -> tuple[float, float, float]: ...
    @property
    def inertia(self) -> npt.NDArray[np.float32]:
        """(3, 3), about the centre of mass, mesh axes, kg m^2."""
    @property
    def linear_velocity(self) -> tuple[float, float, float]:
        """World, m/s (zero on a replica)."""
    @property
    def angular_velocity(self) -> tuple[float, float, float]:
        """World, rad/s (zero on a replica)."""

class Fracture:
    """A body a step broke; it keeps its id with its rest unless ``whole``."""

    @property
    def body(self) -> int: ...
    @property
    def projectile(self) -> int: ...
    @property
    def number(self) -> int: ...
    @property
    def cause(self) -> Literal["energy", "dent"]: ...
    @property
    def whole(self) -> bool: ...
    @property
    def energy(self) -> float: ...
    @property
    def accumulated_dent(self) -> float: ...
    @property
    def to_world(self) -> npt.NDArray[np.float32]:
        """(4, 4): the body's mesh -> world transform when it broke."""
    @property
    def rest_mass(self) -> Optional[float]: ...
    @property
    def rest_center_of_mass(self) -> Optional[tuple[float, float, float]]: ...
    @property
    def rest_inertia(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def pieces(self) -> list[Piece]: ...
    @property
    def projectile_velocity(
        self,
    ) -> Optional[tuple[tuple[float, float, float], tuple[float, float, float]]]: ...

class ReplicaFracture:
    """A fracture a replica's message replayed: the server's pieces, bit for bit."""

    @property
    def body(self) -> int: ...
    @property
    def whole(self) -> bool: ...
    @property
    def number(self) -> int: ...
    @property
    def pieces(self) -> list[Piece]: ...

class Damage:
    """Bodies keyed by 64-bit ids; each :meth:`step` applies one step's dents and fractures (all
    or none)."""

    def __init__(self) -> None: ...
    def add_body(
        self,
        id: int,
        positions: ArrayLike,
        faces: ArrayLike,
        *,
        to_world: Optional[ArrayLike] = None,
        threshold_speed: float = 1.0,
        depth_per_speed: float = 0.01,
        max_depth: float = 0.1,
        sigma: Optional[float] = None,
        preserve_volume: bool = False,
        progressive: bool = False,
        uvs: Optional[ArrayLike] = None,  # (N, 2), a game asset's texture coordinates
        normals: Optional[ArrayLike] = None,  # (N, 3), authored (split at hard edges)
    ) -> None: ...
    def add_projectile(self, id: int) -> None: ...
    def set_pose(self, id: int, to_world: ArrayLike) -> None: ...
    def step(self, hits: Sequence[Hit]) -> list[AppliedDent]: ...
    def positions(self, id: int) -> Float32x3: ...
    def normals(self, id: int) -> Float32x3: ...
    def uvs(self, id: int) -> Optional[npt.NDArray[np.float32]]:
        """(N, 2); ``None`` for a body added without UVs."""
    def faces(self, id: int) -> UInt32: ...
    def moved(self, id: int) -> UInt32: ...
    def set_fracture(
        self,
        id: int,
        *,
        cells: int,
        radius: float,
        seed: int = 0,
        toughness: Optional[float] = None,
        dent_limit: Optional[float] = None,
        density: float = 1000.0,
        max_pieces: int = 1024,
    ) -> None:
        """Breaks along a pattern of ``cells`` cells within ``radius`` m of the hit when an
        impact removes ``toughness`` J or the dents add up to ``dent_limit`` m."""
    def clear_fracture(self, id: int) -> None: ...
    def fractures(self) -> list[Fracture]:
        """The bodies the last step broke."""
    def forget_piece(self, fracture: int, index: int) -> None: ...
    def replicate(self, id: int, wire_id: int) -> None: ...
    def add_wire_projectile(self, shape_id: int, mesh: Mesh) -> None: ...
    def message(self) -> bytes:
        """The last step's message for the replicas (empty when the step changed no carried body; a Replica takes it as no change)."""
    def snapshot(self) -> bytes:
        """A late joiner's start."""
    def record(self, id: int, name: str) -> None: ...
    def save(self) -> bytes: ...
    def restore(self, id: int, data: bytes, name: str) -> None: ...

class Replica:
    """A client's copy of the bodies a server's :class:`Damage` carries: add the same base
    meshes and surfaces, :meth:`join` its snapshot, :meth:`apply` its messages in order."""

    def __init__(self) -> None: ...
    def add_body(
        self,
        wire_id: int,
        positions: ArrayLike,
        faces: ArrayLike,
        *,
        threshold_speed: float = 1.0,
        depth_per_speed: float = 0.01,
        max_depth: float = 0.1,
        sigma: Optional[float] = None,
        preserve_volume: bool = False,
        progressive: bool = False,
        uvs: Optional[ArrayLike] = None,
        normals: Optional[ArrayLike] = None,
    ) -> None: ...
    def add_projectile(self, shape_id: int, mesh: Mesh) -> None: ...
    def join(self, snapshot: bytes) -> None: ...
    def apply(self, message: bytes) -> None: ...
    def fractures(self) -> list[ReplicaFracture]:
        """The bodies the last message broke."""
    def positions(self, wire_id: int) -> Float32x3: ...
    def normals(self, wire_id: int) -> Float32x3: ...
    def uvs(self, wire_id: int) -> Optional[npt.NDArray[np.float32]]: ...
    def faces(self, wire_id: int) -> UInt32: ...
    def moved(self, wire_id: int) -> UInt32: ...
    def forget_piece(self, fracture: int, index: int) -> None: ...
