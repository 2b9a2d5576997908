# Stub of the extension module ringlab._core (python/src, Rust): what the package's Python side
# calls. Users call the functions of `ringlab` (typed in its own modules), not these.
from os import PathLike
from typing import Callable, List, Optional, Sequence, Tuple

__version__: str
DEFAULT_EVIDENCE: float

class RecordingError(ValueError):
    """A recording that cannot be read or made: which file (and line), and what is wrong."""

class FitError(RuntimeError):
    """A fit or diagnosis that cannot be made from this recording."""

Progress = Optional[Callable[[float, str], object]]
# Named float64 arrays: (name, shape, the bytes of a C-ordered array).
Arrays = List[Tuple[str, List[int], bytes]]

class Recording:
    @staticmethod
    def read(
        paths: Sequence[str],
        format: Optional[str] = None,
        fps: Optional[float] = None,
        px_per_mm: Optional[float] = None,
        marks: Optional[Sequence[str]] = None,
        min_likelihood: Optional[float] = None,
        body_preset: Optional[str] = None,
        shape: Optional[str] = None,
        outer_radius_mm: Optional[float] = None,
        width_mm: Optional[float] = None,
        thickness_mm: Optional[float] = None,
        columns: Optional[Sequence[str]] = None,
        unit: Optional[str] = None,
        y_up: bool = False,
        table: Optional[bytes] = None,
        table_header_rows: int = 0,
    ) -> Recording: ...
    @staticmethod
    def from_arrays(
        marks: bytes,
        frames: int,
        fps: float,
        px_per_mm: float,
        body_preset: Optional[str] = None,
        shape: Optional[str] = None,
        outer_radius_mm: Optional[float] = None,
        width_mm: Optional[float] = None,
        thickness_mm: Optional[float] = None,
        first_frame: int = 0,
        image_size: Optional[Tuple[float, float]] = None,
        camera_distance_mm: Optional[float] = None,
        camera_tilt_deg: Optional[float] = None,
    ) -> Recording: ...
    def header_json(self) -> str: ...
    def marks_bytes(self) -> bytes: ...
    def write(self, path: str | PathLike[str], exact: bool) -> None: ...
    def same_as(self, other: Recording) -> bool: ...

def simulate(
    preset: Optional[str] = None,
    config: Optional[str] = None,
    overrides: Sequence[Tuple[str, float]] = ...,
    effects: Sequence[Tuple[str, float]] = ...,
    slip_start: Optional[str] = None,
) -> Tuple[str, bytes, List[str]]: ...
def synth(
    preset: Optional[str] = None,
    config: Optional[str] = None,
    overrides: Sequence[Tuple[str, float]] = ...,
    noise_px: float = 0.5,
    fps: float = 300.0,
    px_per_mm: Optional[float] = None,
    lens_k1: float = 0.0,
    effect: Optional[str] = None,
    effect_strength: Optional[float] = None,
    effect_extras: Sequence[float] = ...,
    slip_start: Optional[str] = None,
    seed: int = 1,
    rest_frames: int = 60,
    image_size: Tuple[float, float] = (1280.0, 1024.0),
    drop_marks: float = 0.0,
    reverse_marks: bool = False,
    camera_distance_mm: Optional[float] = None,
    camera_tilt_deg: float = 0.0,
    camera_in_header: bool = False,
) -> Recording: ...
def fit(
    rec: Recording,
    segment_frames: int = 60,
    merges: int = 2,
    coarse: bool = True,
    c_start: Optional[Sequence[float]] = None,
    effect: Optional[str] = None,
    effect_start: float = 0.0,
    lens_k1: float = 0.0,
    progress: Progress = None,
    threads: Optional[int] = None,
) -> Tuple[str, Arrays]: ...
def diagnose(
    rec: Recording,
    candidates: Optional[Sequence[str]] = None,
    evidence: Optional[float] = None,
    progress: Progress = None,
    threads: Optional[int] = None,
) -> Tuple[str, str, Arrays]: ...
def presets() -> List[str]: ...
def effects() -> List[Tuple[str, str, bool]]: ...
