"""The functions: `simulate`, `synth`, `fit`, `diagnose`, `presets`, `effects`."""

from __future__ import annotations

import json
import os
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _core
from ._progress import ProgressArg, callback
from ._recording import PathLike, Recording
from ._results import Diagnosis, FitResult, RunSummary, Signature, arrays

# numpy is imported where arrays are made: a diagnosis of a file needs none, and
# `import ringlab` stays a few milliseconds.
if TYPE_CHECKING:
    import numpy as np

# simulate's and synth's overrides of the case (the CLI's --c1 .. --atol).
_OVERRIDES = (
    "c1", "c2", "c3", "theta0", "thetadot0", "phidot0", "psidot0", "phi0",
    "mu", "t_end", "dt", "rtol", "atol",
)  # fmt: skip


def _overrides(given: Mapping[str, Any]) -> List[Tuple[str, float]]:
    out = []
    for name, value in given.items():
        if name not in _OVERRIDES:
            raise TypeError(f"unexpected keyword argument '{name}' (the case's overrides are {', '.join(_OVERRIDES)})")
        try:
            out.append((name, float(value)))
        except (TypeError, ValueError):
            raise ValueError(f"{name} = {value!r} is not a number") from None
    return out


def _recording(rec: Union[Recording, PathLike]) -> Recording:
    if isinstance(rec, Recording):
        return rec
    if isinstance(rec, (str, os.PathLike)):
        return Recording.read(rec)
    raise TypeError(f"expected a ringlab.Recording or a path, got {type(rec).__name__}")


class Run:
    """One run of the model (`ringlab.simulate`): the samples as numpy arrays named as the
    columns of `ringlab simulate --out` (`run.t`, `run.theta`, `run.x_p`, ...; `run.columns`
    lists them) and the summary (`run.summary`, the object of `simulate --json`), whose fields
    are also attributes of the run (`run.phases`, `run.inflection_time`, `run.lift_off`,
    `run.slip`, `run.end_reason`, ...). `sliding` is the column (1 where the contact slides);
    the summary's intervals of sliding are `run.summary.sliding`.
    """

    def __init__(self, summary: RunSummary, samples: np.ndarray, columns: Sequence[str]) -> None:
        self.summary = summary
        # Every column: an array (rows, columns).
        self.samples = samples
        self.columns: Tuple[str, ...] = tuple(columns)

    def __getattr__(self, name: str) -> Any:
        # Columns first, then the summary's fields.
        columns = self.__dict__.get("columns", ())
        if name in columns:
            return self.__dict__["samples"][:, columns.index(name)]
        summary = self.__dict__.get("summary")
        if summary is not None and hasattr(summary, name):
            return getattr(summary, name)
        raise AttributeError(f"'Run' has no attribute '{name}'")

    def __dir__(self) -> List[str]:
        return sorted(set(super().__dir__()) | set(self.columns) | set(RunSummary.__dataclass_fields__))

    def __len__(self) -> int:
        return int(self.samples.shape[0])

    def to_dict(self) -> Dict[str, Any]:
        """The summary as `ringlab simulate --json` prints it."""
        return self.summary.to_dict()

    def to_pandas(self) -> Any:
        """The samples as a pandas DataFrame (the columns of `simulate --out`); needs pandas."""
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError("Run.to_pandas needs pandas: pip install pandas") from e
        return pd.DataFrame(self.samples, columns=list(self.columns))

    def __repr__(self) -> str:
        s = self.summary
        return (
            f"Run(case={s.case!r}, {len(self)} samples, t_end={s.t_end:.4g}, end_reason={s.end_reason!r}, "
            f"retrograde_turn={s.retrograde_turn}, inflection_time={s.inflection_time})"
        )


def simulate(
    preset: Optional[str] = "paper-ring",
    *,
    config: Optional[PathLike] = None,
    effects: Optional[Mapping[str, float]] = None,
    slip_start: Optional[str] = None,
    **overrides: float,
) -> Run:
    """One run of the model, as `ringlab simulate`.

    `preset`: a preset's name (`ringlab.presets()`), or `config` a case file in the presets'
    TOML shape. Overrides, in the case's units: `c1`, `c2`, `c3` (drag), `theta0`,
    `thetadot0`, `phidot0`, `psidot0`, `phi0` (start), `mu`, `t_end`, `dt` (the samples'
    spacing), `rtol`, `atol`. `effects`: physics beyond the paper's model by name and
    dimensionless strength, e.g. `{"reynolds_drag": 0.25}` (`ringlab.effects()` lists them);
    `slip_start` (`cone` or `held`) with `slip`.

    Returns a `Run`: the samples as arrays named as `simulate --out`'s columns and the summary.
    A bad name or value raises `ValueError` with the CLI's message.
    """
    if config is not None and preset == "paper-ring":
        preset = None  # the default preset gives way to a case file
    summary_json, samples, columns = _core.simulate(
        preset=preset,
        config=None if config is None else os.fspath(config),
        overrides=_overrides(overrides),
        effects=[(str(k), float(v)) for k, v in (effects or {}).items()],
        slip_start=slip_start,
    )
    summary = RunSummary._from_json(json.loads(summary_json))
    import numpy as np

    array = np.frombuffer(samples, dtype=np.float64).reshape(-1, len(columns)).copy()
    return Run(summary, array, columns)


def synth(
    preset: Optional[str] = "paper-ring",
    *,
    config: Optional[PathLike] = None,
    effect: Optional[str] = None,
    effect_strength: Optional[float] = None,
    effect_extras: Sequence[float] = (),
    slip_start: Optional[str] = None,
    noise_px: float = 0.5,
    fps: float = 300.0,
    px_per_mm: Optional[float] = None,
    lens_k1: float = 0.0,
    seed: int = 1,
    rest_frames: int = 60,
    image_size: Tuple[float, float] = (1280.0, 1024.0),
    drop_marks: float = 0.0,
    reverse_marks: bool = False,
    camera_distance_mm: Optional[float] = None,
    camera_tilt_deg: float = 0.0,
    camera_in_header: bool = False,
    **overrides: float,
) -> Recording:
    """A recording made from the model, as `ringlab synth`: the four marks filmed with
    Gaussian pixel noise `noise_px`, at `fps`, `px_per_mm` (default the paper's 135.6 px per
    40.3 mm), through a lens (`lens_k1`) or a pinhole camera (`camera_distance_mm`,
    `camera_tilt_deg`, named in the header only with `camera_in_header`), with marks dropped at
    random (`drop_marks`, a probability) and an `effect` of `effect_strength` concealed in it
    (any of `ringlab.effects()`, the camera's included), with its extra numbers beyond the
    strength in `effect_extras` (as `--effect-extra`). The case as `simulate`'s (`preset` or
    `config`, and the same overrides). `seed` seeds the noise. Bad values raise `ValueError`.
    """
    if config is not None and preset == "paper-ring":
        preset = None
    w, h = image_size
    rec = _core.synth(
        preset=preset,
        config=None if config is None else os.fspath(config),
        overrides=_overrides(overrides),
        noise_px=float(noise_px),
        fps=float(fps),
        px_per_mm=None if px_per_mm is None else float(px_per_mm),
        lens_k1=float(lens_k1),
        effect=effect,
        effect_strength=None if effect_strength is None else float(effect_strength),
        effect_extras=[float(x) for x in effect_extras],
        slip_start=slip_start,
        seed=int(seed),
        rest_frames=int(rest_frames),
        image_size=(float(w), float(h)),
        drop_marks=float(drop_marks),
        reverse_marks=bool(reverse_marks),
        camera_distance_mm=None if camera_distance_mm is None else float(camera_distance_mm),
        camera_tilt_deg=float(camera_tilt_deg),
        camera_in_header=bool(camera_in_header),
    )
    return Recording(rec)


def _threads(threads: Optional[int]) -> Optional[int]:
    if threads is None:
        return None
    if int(threads) < 1:
        raise ValueError(f"threads = {threads}: must be at least 1 (or None: all cores)")
    return int(threads)


def fit(
    rec: Union[Recording, PathLike],
    *,
    effect: Optional[str] = None,
    effect_start: float = 0.0,
    segment_frames: int = 60,
    merges: int = 2,
    coarse: bool = True,
    c_start: Optional[Sequence[float]] = None,
    lens_k1: float = 0.0,
    progress: ProgressArg = True,
    threads: Optional[int] = None,
) -> FitResult:
    """The model fitted to a recording, as `ringlab fit`: the drag C1..C3 and the start state
    at the first inner turning point (multiple shooting on the marks' pixels).

    `effect`: an effect's strength fitted too (from `effect_start`); `segment_frames`,
    `merges`, `coarse` (the coarse drag grid), `c_start` and `lens_k1` as the CLI's flags.
    `progress`: True for a bar on stderr, False for none, or a callable `(fraction, message)`
    (called on this thread). `threads`: default all cores.

    Runs with the GIL released; Ctrl-C stops it and raises `KeyboardInterrupt`. Returns a
    `FitResult` (the object of `ringlab fit --json`, with the model's marks and residuals frame
    by frame as numpy arrays: `predicted_marks`, `mark_residual_px`, `residual_px`); a
    recording that cannot be fitted raises `ringlab.FitError`, a bad value `ValueError`.
    """
    r = _recording(rec)
    cb, bar = callback(progress)
    c = None if c_start is None else [float(x) for x in c_start]
    if c is not None and len(c) != 3:
        raise ValueError(f"c_start = {c_start!r}: expected C1, C2, C3")
    for name, v in (("segment_frames", segment_frames), ("merges", merges)):
        if int(v) < 0:
            raise ValueError(f"{name} = {v}: must be >= 0")
    try:
        out = _core.fit(
            r._rec,
            segment_frames=int(segment_frames),
            merges=int(merges),
            coarse=bool(coarse),
            c_start=c,
            effect=effect,
            effect_start=float(effect_start),
            lens_k1=float(lens_k1),
            progress=cb,
            threads=_threads(threads),
        )
    finally:
        if bar is not None:
            bar.finish()
    text, raw = out
    return FitResult._from_json(json.loads(text), **arrays(raw))


def diagnose(
    rec: Union[Recording, PathLike],
    candidates: Optional[Sequence[str]] = None,
    progress: ProgressArg = True,
    *,
    evidence: Optional[float] = None,
    threads: Optional[int] = None,
) -> Diagnosis:
    """Which physics (or what of the camera) the paper's model left out of a recording, as
    `ringlab diagnose`.

    `candidates`: the effects to try (default every effect of `ringlab.effects()`);
    `evidence`: the BIC drop an effect needs to be named (default 10). `progress`: True for a
    bar on stderr, False for none, or a callable `(fraction, message)` (called on this
    thread). `threads`: default all cores.

    Runs with the GIL released (seconds to a minute); Ctrl-C stops it and raises
    `KeyboardInterrupt`. Returns a `Diagnosis` (the object of `ringlab diagnose --json`:
    `left_out`, `left_out_all`, `before.rms_px`, `after.rms_px`, `candidates`, ...; with the
    series the window plots as numpy arrays: `fitted_frames`, `residual_before_px`,
    `residual_after_px`, `window_s`, `trace_data_px`, ..., and the `signature`); a recording
    that cannot be diagnosed raises `ringlab.FitError`, a bad value `ValueError`.
    """
    r = _recording(rec)
    cb, bar = callback(progress)
    if isinstance(candidates, str):
        candidates = candidates.split(",")
    try:
        out = _core.diagnose(
            r._rec,
            candidates=None if candidates is None else [str(c) for c in candidates],
            evidence=None if evidence is None else float(evidence),
            progress=cb,
            threads=_threads(threads),
        )
    finally:
        if bar is not None:
            bar.finish()
    text, signature, raw = out
    return Diagnosis._from_json(
        json.loads(text),
        signature=Signature._from_json(json.loads(signature)),
        **arrays(raw, ints=("fitted_frames",)),
    )


def presets() -> List[str]:
    """The presets' names (`simulate(preset=...)`, `body=...`)."""
    return list(_core.presets())


def effects() -> Dict[str, str]:
    """The effects beyond the paper's model: name -> what its strength is."""
    return {name: parameter for name, parameter, _camera in _core.effects()}
