"""Shared paths and slow results. Tests read only the repository's own files (tests/data, the
copies of the project's shared data) and files they write into pytest's tmp_path."""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
from pathlib import Path
from typing import Any, Dict, List, Optional

import pytest

import ringlab

REPO = Path(__file__).resolve().parents[2]
DATA = REPO / "tests" / "data"
HERE = Path(__file__).resolve().parent
# Figures recorded from the CLI (`expected.json`): checked when the CLI is not built.
EXPECTED = json.loads((HERE / "data" / "expected.json").read_text())


def cli_binary() -> Optional[Path]:
    """The CLI built from this tree (`cargo build --release`), if it is: $RINGLAB_CLI, or
    release/ringlab under $CARGO_TARGET_DIR or the repository's target."""
    given = os.environ.get("RINGLAB_CLI")
    if given:
        return Path(given)
    dirs = [Path(os.environ["CARGO_TARGET_DIR"])] if os.environ.get("CARGO_TARGET_DIR") else []
    dirs.append(REPO / "target")
    for d in dirs:
        p = d / "release" / "ringlab"
        if p.is_file() and os.access(p, os.X_OK):
            return p
    return None


def run_cli(args: List[str], cwd: Optional[Path] = None) -> str:
    exe = cli_binary()
    assert exe is not None
    out = subprocess.run([str(exe), *args], capture_output=True, text=True, cwd=cwd, timeout=600)
    assert out.returncode == 0, out.stderr
    return out.stdout


_cache: Dict[Any, Any] = {}


def cli_json(args: List[str]) -> Any:
    """The CLI's JSON for `args`, run once per session (a diagnosis takes ~10 s). A copy: the
    tests may pop keys."""
    key = ("cli",) + tuple(args)
    if key not in _cache:
        _cache[key] = run_cli(args)
    return json.loads(_cache[key])


def diagnosis_of(name: str) -> ringlab.Diagnosis:
    """`tests/data/independent/NAME.csv` diagnosed once per session (each takes ~10 s)."""
    key = ("diagnose", name)
    if key not in _cache:
        _cache[key] = ringlab.diagnose(ringlab.Recording.read(DATA / "independent" / f"{name}.csv"), progress=False)
    return _cache[key]


def fit_of_sample() -> ringlab.FitResult:
    key = ("fit", "sample-ring")
    if key not in _cache:
        _cache[key] = ringlab.fit(ringlab.Recording.read(DATA / "sample-ring.csv"), progress=False)
    return _cache[key]


needs_cli = pytest.mark.skipif(cli_binary() is None, reason="the CLI is not built (cargo build --release)")
needs_pandas = pytest.mark.skipif(importlib.util.find_spec("pandas") is None, reason="pandas is not installed")
needs_hdf5 = pytest.mark.skipif(
    importlib.util.find_spec("pandas") is None or importlib.util.find_spec("tables") is None,
    reason="pandas and PyTables (HDF5) are not installed",
)
