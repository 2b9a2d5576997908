"""`ringlab.Recording`: a recording of a ring's four marks, from a file or from numpy arrays."""

from __future__ import annotations

import errno
import json
import os
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _core, _dlc_h5

# numpy is imported where arrays are made: a diagnosis of a file needs none, and
# `import ringlab` stays a few milliseconds.
if TYPE_CHECKING:
    import numpy as np

PathLike = Union[str, "os.PathLike[str]"]
# A preset's name (its body), or the body's dimensions in mm.
Body = Union[str, Mapping[str, Any]]

_BODY_KEYS = ("shape", "outer_radius_mm", "width_mm", "thickness_mm")


def _body_args(body: Optional[Body]) -> Dict[str, Any]:
    """`body` as the core's keyword arguments."""
    if body is None:
        return {}
    if isinstance(body, str):
        return {"body_preset": body}
    if isinstance(body, Mapping):
        unknown = set(body) - set(_BODY_KEYS)
        if unknown:
            raise ValueError(f"body: unknown keys {sorted(unknown)}; the keys are {', '.join(_BODY_KEYS)}")
        out: Dict[str, Any] = {}
        for key in _BODY_KEYS:
            if body.get(key) is not None:
                out[key] = str(body[key]) if key == "shape" else _number(body[key], f"body['{key}']")
        return out
    raise ValueError(f"body = {body!r}: a preset's name or a dict with {', '.join(_BODY_KEYS)}")


def _number(x: Any, name: str) -> float:
    try:
        return float(x)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {x!r} is not a number") from None


def _existing(path: PathLike) -> str:
    """The path as a string; a missing file is Python's FileNotFoundError, as open() gives."""
    p = os.fspath(path)
    if not isinstance(p, str):
        p = os.fsdecode(p)
    if not os.path.exists(p):
        raise FileNotFoundError(errno.ENOENT, os.strerror(errno.ENOENT), p)
    return p


class Recording:
    """A recording: the four marks' pixel positions frame by frame, the frame rate, the scale
    at the table and the body (format v1, `RECORDING_FORMAT.md`).

    Made by `Recording.read` (format v1, or a tracker's file as `ringlab import` reads it),
    `Recording.from_arrays` (a numpy array of the marks) or `ringlab.synth`.
    """

    __slots__ = ("_rec", "_header")

    def __init__(self, _rec: Any) -> None:
        if not isinstance(_rec, _core.Recording):
            raise TypeError("use Recording.read, Recording.from_arrays or ringlab.synth")
        self._rec = _rec
        self._header: Dict[str, Any] = json.loads(_rec.header_json())

    @classmethod
    def read(
        cls,
        path: Union[PathLike, Sequence[PathLike]],
        *,
        format: Optional[str] = None,
        fps: Optional[float] = None,
        px_per_mm: Optional[float] = None,
        marks: Optional[Sequence[str]] = None,
        min_likelihood: Optional[float] = None,
        body: Optional[Body] = None,
        columns: Optional[Sequence[str]] = None,
        unit: Optional[str] = None,
        y_up: bool = False,
    ) -> "Recording":
        """Reads a recording: format v1, a DeepLabCut CSV or HDF5 file (`.h5`, read with pandas
        and PyTables), a Tracker data table (one file per point mass: give a list) or `.trk`
        project, a TrackMate spots CSV, or a plain CSV.

        The keywords are `ringlab import`'s flags, for what a tracker's file does not say:
        `format` (`dlc`, `tracker`, `trackmate`, `csv`; default: told from the file), `fps`,
        `px_per_mm`, `marks` (the four names in cyclic order round the rim), `min_likelihood`
        (DeepLabCut, default 0.6), `body` (a preset's name, or a dict with `shape`,
        `outer_radius_mm`, `width_mm`, `thickness_mm`), `columns` and `unit` (plain CSV), `y_up`.
        A v1 file says everything itself and ignores them (`notes` says so).

        Raises `ringlab.RecordingError` (a `ValueError`) for a file that cannot be read as a
        recording, with the file and line (an HDF5 file: its table's row); `FileNotFoundError`
        for a missing file; `ValueError` for a bad keyword; `ImportError` for an HDF5 file
        where pandas or PyTables (`tables`) is not installed.
        """
        paths = [path] if isinstance(path, (str, bytes, os.PathLike)) else list(path)
        if not paths:
            raise ValueError("path: no file given")
        files = [_existing(p) for p in paths]
        table: Tuple[Optional[bytes], int] = (None, 0)
        if len(files) == 1 and _dlc_h5.is_hdf5(files[0]):
            if format is not None and format.lower() in ("tracker", "trackmate", "csv"):
                raise ValueError(f"format '{format}': {files[0]} is an HDF5 file, read as DeepLabCut's table (format='dlc')")
            table = _dlc_h5.as_csv(files[0])
        rec = _core.Recording.read(
            files,
            format=format,
            fps=None if fps is None else _number(fps, "fps"),
            px_per_mm=None if px_per_mm is None else _number(px_per_mm, "px_per_mm"),
            marks=None if marks is None else [str(m) for m in marks],
            min_likelihood=None if min_likelihood is None else _number(min_likelihood, "min_likelihood"),
            columns=None if columns is None else [str(c) for c in columns],
            unit=unit,
            y_up=bool(y_up),
            table=table[0],
            table_header_rows=table[1],
            **_body_args(body),
        )
        return cls(rec)

    @classmethod
    def from_arrays(
        cls,
        marks: Any,
        *,
        fps: float,
        px_per_mm: float,
        body: Body,
        first_frame: int = 0,
        image_size: Optional[Tuple[float, float]] = None,
        camera_distance_mm: Optional[float] = None,
        camera_tilt_deg: Optional[float] = None,
    ) -> "Recording":
        """A recording from the marks' pixel positions (y down, as images are).

        `marks`: an array of shape (frames, 4, 2), the four marks in cyclic order round the rim,
        x and y in pixels, NaN for a mark not found; frame `i` is frame number
        `first_frame + i` (at `(first_frame + i) / fps` s). `body`: a preset's name (its body)
        or a dict with `shape` ('ring' or 'disk'), `outer_radius_mm`, `width_mm` and, for a
        ring, `thickness_mm`. `image_size` (width, height in px) and the camera's distance and
        tilt, where known, go into the header as a file's would.

        The marks go through the same assembly as a tracker's file in `ringlab import` (their
        cyclic order checked, frames without any mark at either end left out). Raises
        `ringlab.RecordingError` for marks that do not make a recording (half a mark, inf, out
        of order, fewer than two usable frames), `ValueError` for a bad keyword.
        """
        import numpy as np

        a = np.asarray(marks, dtype=np.float64)
        if a.ndim != 3 or a.shape[1:] != (4, 2):
            raise ValueError(f"marks: shape {a.shape}, expected (frames, 4, 2)")
        a = np.ascontiguousarray(a)
        size = None
        if image_size is not None:
            w, h = image_size
            size = (_number(w, "image_size[0]"), _number(h, "image_size[1]"))
        rec = _core.Recording.from_arrays(
            a.tobytes(),
            a.shape[0],
            _number(fps, "fps"),
            _number(px_per_mm, "px_per_mm"),
            first_frame=int(first_frame),
            image_size=size,
            camera_distance_mm=None if camera_distance_mm is None else _number(camera_distance_mm, "camera_distance_mm"),
            camera_tilt_deg=None if camera_tilt_deg is None else _number(camera_tilt_deg, "camera_tilt_deg"),
            **_body_args(body),
        )
        return cls(rec)

    # --- what it holds ---

    @property
    def marks(self) -> np.ndarray:
        """The marks, shape (frames, 4, 2), pixels (y down), NaN where a mark was not tracked."""
        import numpy as np

        a = np.frombuffer(self._rec.marks_bytes(), dtype=np.float64).reshape(-1, 4, 2)
        return a.copy()

    @property
    def frames(self) -> int:
        """Number of frames."""
        return int(self._header["frames"])

    def __len__(self) -> int:
        return self.frames

    @property
    def first_frame(self) -> int:
        """Number of the first frame (frame n is at n / fps s)."""
        return int(self._header["first_frame"])

    @property
    def frame_numbers(self) -> np.ndarray:
        """The frames' numbers."""
        import numpy as np

        return np.arange(self.first_frame, self.first_frame + self.frames, dtype=np.int64)

    @property
    def time_s(self) -> np.ndarray:
        """Each frame's time (s)."""
        return self.frame_numbers / self.fps

    @property
    def fps(self) -> float:
        return float(self._header["fps"])

    @property
    def px_per_mm(self) -> float:
        """The scale at the table."""
        return float(self._header["px_per_mm"])

    @property
    def body(self) -> Dict[str, Any]:
        """The body: shape, outer_radius_mm, width_mm, thickness_mm (the form `body=` takes)."""
        return {k: self._header[k] for k in _BODY_KEYS}

    @property
    def image_size(self) -> Optional[Tuple[float, float]]:
        """(width, height) in px, where the header gives it."""
        w, h = self._header["image_width_px"], self._header["image_height_px"]
        return None if w is None or h is None else (float(w), float(h))

    @property
    def camera_distance_mm(self) -> Optional[float]:
        """The camera's distance from the table (mm), where the header gives it."""
        d = self._header["camera_distance_mm"]
        return None if d is None else float(d)

    @property
    def camera_tilt_deg(self) -> Optional[float]:
        """The camera's tilt from the table's normal (degrees), where the header gives it."""
        t = self._header["camera_tilt_deg"]
        return None if t is None else float(t)

    @property
    def marks_tracked(self) -> int:
        """Number of mark positions tracked, all frames together."""
        return int(self._header["marks_tracked"])

    @property
    def source(self) -> str:
        """What it was read as (`ringlab v1`, `DeepLabCut CSV`, ..., `numpy arrays`)."""
        return str(self._header["source"])

    @property
    def name(self) -> str:
        """The file it was read from (`arrays` for from_arrays), as messages name it."""
        return str(self._header["name"])

    @property
    def mark_names(self) -> List[str]:
        """The names taken as marks 1 to 4 (a tracker's bodyparts or tracks)."""
        return list(self._header["mark_names"])

    @property
    def notes(self) -> List[str]:
        """What the import said beyond the recording (points left out, defaults taken)."""
        return list(self._header["notes"])

    @property
    def header_extra(self) -> List[Tuple[str, str]]:
        """The header's keys beyond the format's, in file order."""
        return [(k, v) for k, v in self._header["extra"]]

    def write(self, path: PathLike, *, exact: bool = False) -> None:
        """Writes it as format v1 (pixels to 0.01 px; `exact`: digits that read back bit for bit),
        for the CLI and the window."""
        self._rec.write(os.fspath(path), bool(exact))

    def __eq__(self, other: object) -> bool:
        """The same header numbers, frames and marks (not where it came from)."""
        if not isinstance(other, Recording):
            return NotImplemented
        return bool(self._rec.same_as(other._rec))

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return (
            f"Recording({self.name!r}: {self.frames} frames from {self.first_frame} at "
            f"{self.fps:g} fps, {self.px_per_mm:g} px/mm, {self._header['shape']} "
            f"R={self._header['outer_radius_mm']:g} mm, {self.marks_tracked} marks tracked)"
        )
