"""Typed results: the objects of the CLI's JSON (`ringlab diagnose --json`, `fit --json`,
`simulate --json`), field for field and under the same names, with `.to_dict()` giving back
that JSON object."""

from __future__ import annotations

import dataclasses
import typing
from typing import Any, Dict, List, Optional, Tuple, Type, TypeVar

# Fields the CLI leaves out of its JSON when they are None (serde's skip_serializing_if).
_OMIT_NONE = {"omit_none": True}

# A numpy array (numpy is imported where arrays are made, so `import ringlab` needs none).
NDArray = Any


def _beyond_json(doc: str) -> Any:
    """A field the CLI's JSON does not have (what the window draws: numpy arrays, the
    signature): given by the call beside the JSON, left out of `to_dict()` and `==`."""
    return dataclasses.field(default=None, repr=False, compare=False, metadata={"beyond_json": True, "doc": doc})


def _json_fields(cls: type) -> List[dataclasses.Field]:  # type: ignore[type-arg]
    return [f for f in dataclasses.fields(cls) if not f.metadata.get("beyond_json")]


def arrays(raw: List[Tuple[str, List[int], bytes]], ints: Tuple[str, ...] = ()) -> Dict[str, NDArray]:
    """The core's arrays, (name, shape, float64 bytes), as numpy arrays (`ints` as int64)."""
    import numpy as np

    out = {}
    for name, shape, data in raw:
        a = np.frombuffer(data, dtype=np.float64).reshape(shape).copy()
        out[name] = a.astype(np.int64) if name in ints else a
    return out


def _plain(value: Any) -> Any:
    if isinstance(value, _Result):
        return value.to_dict()
    if isinstance(value, list):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def _build(tp: Any, value: Any) -> Any:
    """`value` (parsed JSON) as the annotated type `tp`."""
    if value is None:
        return None
    origin = typing.get_origin(tp)
    args = typing.get_args(tp)
    if origin is typing.Union:  # Optional[X]
        inner = [a for a in args if a is not type(None)]
        return _build(inner[0], value)
    if origin in (list, List):
        return [_build(args[0], v) for v in value]
    if isinstance(tp, type) and issubclass(tp, _Result):
        return tp._from_json(value)
    return value


R = TypeVar("R", bound="_Result")


class _Result:
    """A result object: attributes as the JSON's keys; `to_dict()` is the JSON object."""

    @classmethod
    def _from_json(cls: Type[R], data: Dict[str, Any], **beyond: Any) -> R:
        """From the JSON object, with the fields beyond it (`_beyond_json`) as given."""
        hints = typing.get_type_hints(cls)
        names = [f.name for f in _json_fields(cls)]
        unknown = set(data) - set(names)
        if unknown:
            # The Rust side and these classes are one package: a key without a field is a bug.
            raise RuntimeError(f"{cls.__name__}: unexpected keys {sorted(unknown)}")
        return cls(**{n: _build(hints[n], data.get(n)) for n in names}, **beyond)

    def to_dict(self) -> Dict[str, Any]:
        """The object as the CLI prints it with `--json` (plain dicts, lists and numbers)."""
        out: Dict[str, Any] = {}
        for f in _json_fields(type(self)):
            value = getattr(self, f.name)
            if value is None and f.metadata.get("omit_none"):
                continue
            out[f.name] = _plain(value)
        return out


# --- diagnose -------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Partial(_Result):
    """For an `unexplained` finding: the candidate (one effect or a pair) that explains the
    largest share of the misfit beyond the noise."""

    names: List[str]
    explained_share: float
    rms_px: float
    excess_px: float


@dataclasses.dataclass(frozen=True)
class Glitch(_Result):
    """A tracked mark position left out as the tracker's glitch: the frame (as in the file), the
    mark (1 to 4) and what it was (`outlier` or `swapped`)."""

    frame: int
    mark: int
    kind: str


@dataclasses.dataclass(frozen=True)
class MismatchWindow(_Result):
    """A stretch where the baseline departs from the recording beyond its noise (s), its RMS
    misfit there (px) and its share of the misfit beyond the noise."""

    start_s: float
    end_s: float
    rms_px: float
    share: float


@dataclasses.dataclass(frozen=True)
class ModelFit(_Result):
    """A model fitted over the whole run (the diagnosis's `before` and `after`): its misfit (px),
    the part beyond the noise, its BIC score, its effect (`none`: the paper's model), its
    parameters by name (`C1`, `C1_sigma`, ..., `R_mm`, the effect's strength), and when its
    motion ends (s)."""

    rms_px: float
    excess_px: float
    score: float
    effect: str
    params: Dict[str, Optional[float]]
    end_s: Optional[float]
    slip_start: Optional[str] = dataclasses.field(default=None, metadata=_OMIT_NONE)


@dataclasses.dataclass(frozen=True)
class Candidate(_Result):
    """One candidate of the ranking (`none` is the baseline): its misfit (px), BIC and BIC
    against the baseline (negative: better), its fitted strength, or why it failed."""

    name: str
    rms_px: Optional[float]
    score: Optional[float]
    delta_score: Optional[float]
    strength: Optional[float]
    strength_sigma: Optional[float]
    error: Optional[str]
    stopped_at_segments: Optional[int] = dataclasses.field(default=None, metadata=_OMIT_NONE)


@dataclasses.dataclass(frozen=True)
class PairCandidate(_Result):
    """A pair of effects tried together after one was named (the forward selection)."""

    names: List[str]
    rms_px: Optional[float]
    delta_score: Optional[float]
    strengths: List[Optional[float]]
    error: Optional[str]


@dataclasses.dataclass(frozen=True)
class NamedShare(_Result):
    """A named effect's share of the named model's improvement on the paper's model: the part
    (0 to 1) of the cost removed that comes back without it, and the misfit without it (px)."""

    name: str
    share: Optional[float]
    rms_without_px: Optional[float]


@dataclasses.dataclass(frozen=True)
class NoiseCorrelation(_Result):
    """The tracker's noise correlated in time: the tracks' own reading (px), the correlation
    from one frame to the next, the lag where it has died out, the baseline's RMS (px)."""

    tracks_px: float
    lag1: float
    range_frames: int
    residual_px: float


@dataclasses.dataclass(frozen=True)
class Signature(_Result):
    """The measured features of the mismatch that tell the effects apart (the core's
    `Signature`; not in the CLI's JSON): where the baseline fitted to a growing stretch from the
    start stops following the recording (s, None if never) and that stretch's share of the run;
    the baseline's RMS in the first, middle and last third (px) and the share of its misfit
    beyond the noise in the last; when the motion ends in the recording, the baseline and the
    chosen model (s); the share of the baseline's misfit, and of the change to the chosen
    model, that points radially from the image centre; where the chosen model slides (s)."""

    departure_s: Optional[float]
    followed_share: Optional[float]
    thirds_rms_px: List[Optional[float]]
    late_share: Optional[float]
    end_data_s: Optional[float]
    end_before_s: Optional[float]
    end_after_s: Optional[float]
    radial_share: Optional[float]
    change_radial_share: Optional[float]
    slides_s: List[List[float]]


@dataclasses.dataclass(frozen=True)
class Diagnosis(_Result):
    """What `ringlab.diagnose` found: the object of `ringlab diagnose --json`.

    `left_out` is `none`, `unexplained` or the first effect named, `left_out_all` every effect
    named; `before` and `after` the paper's model and the chosen one on the same misfit;
    `candidates` every candidate with the baseline, best first; `explanation` in words.

    Beyond the JSON, what the window plots, as numpy arrays over the fitted frames:
    `fitted_frames` (indices into the recording's arrays) and `time_s`; the RMS residual per
    frame (px, over its tracked coordinates; NaN where none) of the baseline
    (`residual_before_px`), of the chosen model (`residual_after_px`) and of the baseline fitted
    only to the stretch it follows and run on (`residual_followed_px`); the test windows
    (`window_s`, (windows, 2), start and end in s) with their RMS (`window_before_px`,
    `window_after_px`, `window_followed_px`) and the RMS above which a window departs
    (`window_threshold_px`); point A in the image (`trace_data_px`, NaN where a mark is
    missing, `trace_before_px`, `trace_after_px`, each (frames, 2)) and the image's size
    (`image_px`); and the mismatch's `signature`.
    """

    left_out: str
    left_out_all: List[str]
    partial: Optional[Partial]
    glitches: int
    glitch_marks: List[Glitch]
    consistent_ratio: float
    mismatch: Optional[MismatchWindow]
    before: ModelFit
    after: ModelFit
    candidates: List[Candidate]
    pairs: List[PairCandidate]
    shares: List[NamedShare]
    explanation: str
    compute_seconds: float
    noise_px: float
    noise_correlation: Optional[NoiseCorrelation]
    windows: List[MismatchWindow]
    frames: int
    frames_fitted: int
    segments_rms_px: float
    fitted_frames: NDArray = _beyond_json("indices of the fitted frames (int64)")
    time_s: NDArray = _beyond_json("the fitted frames' times (s)")
    residual_before_px: NDArray = _beyond_json("the baseline's RMS residual per fitted frame (px)")
    residual_after_px: NDArray = _beyond_json("the chosen model's RMS residual per fitted frame (px)")
    residual_followed_px: NDArray = _beyond_json("the baseline fitted to the stretch it follows, run on (px)")
    window_s: NDArray = _beyond_json("the test windows, (windows, 2): start and end (s)")
    window_before_px: NDArray = _beyond_json("the baseline's RMS in each window (px)")
    window_after_px: NDArray = _beyond_json("the chosen model's RMS in each window (px)")
    window_followed_px: NDArray = _beyond_json("the followed stretch's fit's RMS in each window (px)")
    window_threshold_px: NDArray = _beyond_json("the RMS above which a window departs (px)")
    trace_data_px: NDArray = _beyond_json("point A in the image per fitted frame, (frames, 2) (px)")
    trace_before_px: NDArray = _beyond_json("point A of the baseline, (frames, 2) (px)")
    trace_after_px: NDArray = _beyond_json("point A of the chosen model, (frames, 2) (px)")
    image_px: NDArray = _beyond_json("the image's width and height (px)")
    signature: Optional[Signature] = _beyond_json("the measured features of the mismatch")

    def __repr__(self) -> str:
        return (
            f"Diagnosis(left_out={self.left_out!r}, left_out_all={self.left_out_all!r}, "
            f"before.rms_px={self.before.rms_px:.3f}, after.rms_px={self.after.rms_px:.3f}, "
            f"noise_px={self.noise_px:.3f}, frames={self.frames})"
        )


# --- fit ------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class FitEffect(_Result):
    """An effect fitted beside the drag: its name, strength and sigma."""

    name: str
    strength: float
    sigma: Optional[float]


@dataclasses.dataclass(frozen=True)
class FitResult(_Result):
    """What `ringlab.fit` found: the object of `ringlab fit --json`.

    `c` the drag coefficients C1..C3 with `c_sigma`; the start state at the first inner turning
    point in model units (`theta0`, `phidot0`, `psidot0`, `thetadot0`, `phi0`; a length unit of
    `length_unit_mm` and a time unit of `time_unit_s`); `rms_px` the multiple-shooting misfit.

    Beyond the JSON, what the window draws over the film, as numpy arrays over the recording's
    frames: `predicted_marks` (frames, 4, 2), the fitted model's marks in pixels (each segment
    from its fitted state), NaN outside the fitted segments; `mark_residual_px` (frames, 4),
    each mark's distance from its tracked position, and `residual_px` (frames), the RMS over
    each frame's coordinates: NaN where the model gives no mark, the mark was not tracked or
    was left out as a tracker's glitch, so that they cover the `residuals` coordinates that
    `rms_px` is taken over (`rms_px == sqrt(nansum(mark_residual_px**2) / residuals)`).
    """

    c: List[float]
    c_sigma: List[Optional[float]]
    theta0: float
    phidot0: float
    psidot0: float
    thetadot0: float
    phi0: float
    rms_px: float
    frames: int
    compute_seconds: float
    frames_fitted: int
    noise_px: Optional[float]
    start_frame: float
    start_time_s: float
    time_unit_s: float
    length_unit_mm: float
    segments: int
    segment_frames: int
    iterations: int
    residuals: int
    parameters: int
    coarse_c: Optional[List[float]]
    effect: Optional[FitEffect]
    predicted_marks: NDArray = _beyond_json("the model's marks, (frames, 4, 2) (px)")
    mark_residual_px: NDArray = _beyond_json("each mark's distance from the model's, (frames, 4) (px)")
    residual_px: NDArray = _beyond_json("the RMS residual per frame (px)")


# --- simulate -------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Phase(_Result):
    """A phase of the motion (`prograde`, `walk`, `retrograde`, ...) from `start` to `end`."""

    phase: str
    start: float
    end: float


@dataclasses.dataclass(frozen=True)
class RunEffect(_Result):
    """An effect the run had on: its name, strength and what the strength is."""

    name: str
    strength: float
    parameter: str


@dataclasses.dataclass(frozen=True)
class RunSummary(_Result):
    """A run's summary: the object of `ringlab simulate --json` (times in the case's units).

    `end_reason` is `flat`, `rest`, `t_end`, `other_rim`, `non_finite` or
    `step_size_too_small`; `lift_off` and `slip` the intervals `[start, end]` where the
    paper's pure-rolling assumptions break (F_N <= 0; friction beyond mu F_N).
    """

    case: str
    units: str
    t_end: float
    end_reason: str
    retrograde_turn: bool
    inflection_time: Optional[float]
    prograde_cycles: int
    cycles_before_retrograde: int
    retrograde_total_deg: float
    phases: List[Phase]
    lift_off: List[List[float]]
    slip: List[List[float]]
    mu: float
    effects: List[RunEffect]
    slip_mu: Optional[float]
    sliding: List[List[float]]
    sliding_total: float
    stick_residual: float
    friction_ratio_at_theta_max: List[float]
    f_f_at_theta_max: List[List[float]]
    theta_min: List[List[float]]
    theta_max: List[List[float]]
    energy_start: float
    energy_end: float
    rhs_evaluations: int
    steps: int
    rejected_steps: int
    compute_seconds: float
    error: Optional[str]


def field_names(cls: type) -> Tuple[str, ...]:
    """The JSON keys of a result class, in the CLI's order."""
    return tuple(f.name for f in _json_fields(cls))
