"""Type stubs of invfem (the extension module invfem._invfem, re-exported by the package).

tests/python/test_stubs.py checks them against the built module: the same public names, the same
argument names and kinds, a docstring on each.
"""

import os
from collections.abc import Callable
from typing import Any, TypedDict

import numpy as np
import numpy.typing as npt

__version__: str

# Scene values: what the scene's JSON holds (NumPy integer and floating scalars are accepted too).
_Json = Any

class _Surface(TypedDict, total=False):
    vertices: npt.NDArray[np.float64]
    triangles: npt.NDArray[np.int32]
    uv: npt.NDArray[np.float64]
    uv_triangles: npt.NDArray[np.int32]
    nodes: npt.NDArray[np.int32]

class _Certificate(TypedDict):
    total: int
    self: list[int]
    cross: dict[tuple[int, int], int]
    candidates: int
    examples: list[tuple[int, int, int, int]]

class Simulation:
    """A scene built and stepped in this process (invfem run's world, checks and writers)."""

    def __init__(
        self,
        scene: str | os.PathLike[str] | dict[str, _Json],
        *,
        set: dict[str, _Json] = ...,
        quick: bool = False,
        out: str | os.PathLike[str] | None = None,
        formats: str = "obj",
        overwrite: bool = False,
        threads: int = 0,
        base_dir: str | os.PathLike[str] | None = None,
        memory_limit: str = "",
        strict: bool = False,
    ) -> None:
        """Builds a scene from a file or a dict; a bad field raises ValueError naming its JSON path."""
    @property
    def time(self) -> float:
        """The simulated time [s]."""
    @property
    def frame(self) -> int:
        """The last whole frame reached (frame k is at t = k / fps)."""
    @property
    def fps(self) -> float:
        """The scene's frames per second."""
    @property
    def frames(self) -> int:
        """The scene's frames after frame 0."""
    @property
    def objects(self) -> list[str]:
        """The simulated objects' names (solids and cloths)."""
    @property
    def bodies(self) -> list[str]:
        """The kinematic bodies' names (colliders)."""
    def step_frame(self) -> dict[str, Any]:
        """Advances one frame (written to `out` when given); returns the frame's report."""
    def advance_to(self, t: float) -> dict[str, Any]:
        """Advances to time t [s] (>= time), writing nothing; returns the report of the steps taken."""
    def positions(self, name: str) -> npt.NDArray[np.float64]:
        """An object's node positions, or a body's surface vertices: (n, 3) float64 [m]."""
    def velocities(self, name: str) -> npt.NDArray[np.float64]:
        """As positions: (n, 3) float64 [m/s]."""
    def surface(self, name: str) -> _Surface:
        """The written surface: vertices, triangles (int32), uv, uv_triangles, and nodes for an object."""
    def tets(self, name: str) -> npt.NDArray[np.int32]:
        """A solid's tets, (T, 4) int32 node indices; (0, 4) for a cloth."""
    def element_fields(self, name: str) -> dict[str, npt.NDArray[np.float64]]:
        """Per-element quantities as the VTU frames hold them, e.g. det_F and inverted: {name: (T,)}."""
    def drive_body(self, name: str, source: Callable[[int], npt.ArrayLike] | None) -> None:
        """Frames of a sequence collider from Python: source(k) returns frame k, (V, 3); None: the files."""
    def set_body_frame(self, name: str, k: int, x: npt.ArrayLike) -> None:
        """Gives frame k of a sequence collider, (V, 3); a step to frame k needs frames up to k + 1."""
    def save_checkpoint(self, dir: str) -> str:
        """Writes DIR/checkpoints/NNNN.ckpt at a whole frame; returns its path."""
    def load_checkpoint(self, path: str) -> None:
        """Restores a checkpoint of this scene; stepping on is bit-identical to the run that wrote it."""

def check(
    surfaces: list[tuple[npt.ArrayLike, npt.ArrayLike]],
    welds: list[npt.ArrayLike | None] | None = None,
    count_self: list[bool] | None = None,
    max_examples: int = 10,
) -> _Certificate:
    """The intersection certificate (invfem check) on arrays of (vertices (n, 3), triangles (m, 3))."""
