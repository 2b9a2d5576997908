"""ringlab: rolling rings and disks, after Jalali, Sarebangholi & Alam, *Terminal retrograde
turn of rolling rings*, from Python.

    import ringlab
    run = ringlab.simulate("paper-ring")                  # the model: run.t, run.theta, ...
    rec = ringlab.Recording.read("ring.csv")              # any file `ringlab import` reads
    rec = ringlab.Recording.from_arrays(marks, fps=300, px_per_mm=3.36, body="steel-ring")
    f = ringlab.fit(rec)                                  # drag and start state
    d = ringlab.diagnose(rec)                             # what the model left out
    print(d.left_out, d.before.rms_px, d.after.rms_px)

The results carry the names and numbers of the CLI's JSON (`ringlab diagnose --json`,
`fit --json`, `simulate --json`); `.to_dict()` gives that object. docs/python.md in the
repository has the whole API.
"""

from ._core import DEFAULT_EVIDENCE, FitError, RecordingError, __version__
from ._api import Run, diagnose, effects, fit, presets, simulate, synth
from ._recording import Recording
from ._results import (
    Candidate,
    Diagnosis,
    FitEffect,
    FitResult,
    Glitch,
    MismatchWindow,
    ModelFit,
    NamedShare,
    NoiseCorrelation,
    PairCandidate,
    Partial,
    Phase,
    RunEffect,
    RunSummary,
    Signature,
)

__all__ = [
    "DEFAULT_EVIDENCE",
    "Candidate",
    "Diagnosis",
    "FitEffect",
    "FitError",
    "FitResult",
    "Glitch",
    "MismatchWindow",
    "ModelFit",
    "NamedShare",
    "NoiseCorrelation",
    "PairCandidate",
    "Partial",
    "Phase",
    "Recording",
    "RecordingError",
    "Run",
    "RunEffect",
    "RunSummary",
    "Signature",
    "__version__",
    "diagnose",
    "effects",
    "fit",
    "presets",
    "simulate",
    "synth",
]
