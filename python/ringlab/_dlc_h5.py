"""DeepLabCut's HDF5 files (`*.h5`): the pandas table DeepLabCut writes, read with pandas and
PyTables (imported here, where they are needed) and handed to the core's DeepLabCut reader as
the CSV DeepLabCut writes beside it (every number in Python's round-trip form), so that the
two files give one recording, bit for bit, with the same likelihood cut and notes."""

from __future__ import annotations

import csv
import io
import os
from typing import Any, List, Tuple

from ._core import RecordingError

# The first bytes of an HDF5 file (its superblock's signature).
HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
_EXTENSIONS = (".h5", ".hdf5", ".hdf")
# The key DeepLabCut stores its table under.
_DLC_KEY = "/df_with_missing"
# The names of the column levels: one animal, or several (multi-animal projects).
_LEVELS = (("scorer", "bodyparts", "coords"), ("scorer", "individuals", "bodyparts", "coords"))
_COORDS = ["x", "y", "likelihood"]


def is_hdf5(path: str) -> bool:
    """An HDF5 file by its name or its first bytes."""
    if path.lower().endswith(_EXTENSIONS):
        return True
    if not os.path.isfile(path):
        return False  # the core says what it cannot read
    with open(path, "rb") as f:
        return f.read(len(HDF5_SIGNATURE)) == HDF5_SIGNATURE


def _pandas() -> Any:
    try:
        import pandas
        import tables  # noqa: F401  (pandas reads HDF5 through PyTables)
    except ImportError as e:
        raise ImportError(
            "reading DeepLabCut's .h5 files needs pandas and tables (PyTables): pip install pandas tables"
        ) from e
    return pandas


def _table(pd: Any, path: str) -> Any:
    """The file's DeepLabCut table: under DeepLabCut's key, or the file's only table."""
    try:
        with pd.HDFStore(path, mode="r") as store:
            keys: List[str] = list(store.keys())
            key = _DLC_KEY if _DLC_KEY in keys else keys[0] if len(keys) == 1 else None
            if key is None:
                what = "no pandas table" if not keys else f"{len(keys)} tables ({', '.join(keys)}) and none under '{_DLC_KEY}'"
                raise RecordingError(f"{path}: not a DeepLabCut file: it holds {what}")
            df = store[key]
    except RecordingError:
        raise
    except Exception as e:  # PyTables' and pandas' own: not HDF5, not a table pandas wrote
        raise RecordingError(f"{path}: cannot read it as a pandas HDF5 file ({type(e).__name__}: {e})") from e
    if not isinstance(df, pd.DataFrame):
        raise RecordingError(f"{path}: not a DeepLabCut file: its table '{key}' is a {type(df).__name__}, not a DataFrame")
    return df


def _check_columns(pd: Any, path: str, df: Any) -> None:
    """DeepLabCut's columns: the levels by name, and (x, y, likelihood) per point, numbers."""
    bad = lambda what: RecordingError(f"{path}: not a DeepLabCut table: {what}")  # noqa: E731
    cols = df.columns
    names = tuple(cols.names) if isinstance(cols, pd.MultiIndex) else (cols.name,)
    if names not in _LEVELS:
        levels = " or ".join(", ".join(n) for n in _LEVELS)
        raise bad(f"its columns' levels are {', '.join(map(str, names))}, expected {levels}")
    if len(cols) == 0 or len(cols) % 3:
        raise bad(f"{len(cols)} columns, expected x, y and likelihood per point")
    for i in range(0, len(cols), 3):
        three = [cols[i + k] for k in range(3)]
        if [c[-1] for c in three] != _COORDS or len({c[:-1] for c in three}) != 1:
            listed = "; ".join(", ".join(map(str, c)) for c in three)
            raise bad(f"columns {i} to {i + 2} are ({listed}), expected one point's x, y, likelihood")
    for c in cols:
        if not pd.api.types.is_numeric_dtype(df[c]) or pd.api.types.is_bool_dtype(df[c]):
            raise bad(f"column ({', '.join(map(str, c))}) holds {df[c].dtype}, not numbers")
    repeated = df.index[df.index.duplicated()]
    if len(repeated):
        rows = [i for i, f in enumerate(df.index) if f == repeated[0]]
        raise RecordingError(f"{path}: frame {repeated[0]} is in its table twice (rows {rows[0]} and {rows[1]})")


def as_csv(path: str) -> Tuple[bytes, int]:
    """The file's DeepLabCut table as DeepLabCut's CSV, and the number of its header rows."""
    pd = _pandas()
    df = _table(pd, path)
    _check_columns(pd, path, df)
    import numpy as np

    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    names = list(df.columns.names)
    for level, name in enumerate(names):
        w.writerow([name] + [str(c[level]) for c in df.columns])
    values = df.to_numpy(dtype=np.float64)
    # repr: the shortest digits that read back as the same float; blank: nothing found.
    for frame, row in zip(df.index, values.tolist()):
        w.writerow([str(frame)] + ["" if v != v else repr(v) for v in row])
    return out.getvalue().encode("utf-8"), len(names)
