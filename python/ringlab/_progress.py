"""The progress of a fit or a diagnosis: a bar on stderr (`progress=True`), or the caller's
own callback `progress(fraction, message)`."""

from __future__ import annotations

import sys
import time
from typing import Callable, Optional, Union

ProgressArg = Union[bool, None, Callable[[float, str], object]]


class Bar:
    """A one-line bar on stderr, as the CLI's: shown only once the work has run for 0.3 s, only
    where someone watches (a terminal or a notebook), never moving backwards."""

    WIDTH = 30

    def __init__(self) -> None:
        self.started = time.monotonic()
        self.fraction = 0.0
        self.shown = False
        stream = sys.stderr
        isatty = getattr(stream, "isatty", None)
        self.watched = bool(isatty and isatty()) or "ipykernel" in sys.modules

    def __call__(self, fraction: float, message: str) -> None:
        self.fraction = max(self.fraction, min(max(fraction, 0.0), 1.0))
        elapsed = time.monotonic() - self.started
        if not self.watched or elapsed < 0.3:
            return
        self.shown = True
        done = int(round(self.fraction * self.WIDTH))
        bar = "=" * done + (">" if done < self.WIDTH else "") + " " * (self.WIDTH - done - 1)
        minutes, seconds = divmod(int(elapsed), 60)
        line = f"[{bar[: self.WIDTH]}] {100 * self.fraction:3.0f}% {minutes}:{seconds:02d} {message}"
        sys.stderr.write("\r" + line[:119].ljust(119))
        sys.stderr.flush()

    def finish(self) -> None:
        if self.shown:
            sys.stderr.write("\r" + " " * 119 + "\r")
            sys.stderr.flush()


def callback(progress: ProgressArg) -> tuple[Optional[Callable[[float, str], object]], Optional[Bar]]:
    """The callable to hand to the core, and the bar to finish afterwards (if one)."""
    if progress is True:
        bar = Bar()
        return bar, bar
    if progress is None or progress is False:
        return None, None
    if callable(progress):
        return progress, None
    raise ValueError(f"progress = {progress!r}: True, False or a callable(fraction, message)")
