"""ringlab.Recording: read from every format `ringlab import` reads, made from arrays (equal
to the same file read), written back, and every error."""

from __future__ import annotations

import re

import numpy as np
import pytest

import ringlab
from conftest import DATA, needs_hdf5, needs_pandas

SAMPLE = DATA / "sample-ring.csv"
RING = {"shape": "ring", "outer_radius_mm": 20.66, "width_mm": 18.0, "thickness_mm": 1.0}


def test_read_a_v1_file():
    rec = ringlab.Recording.read(SAMPLE)
    assert rec.source == "ringlab v1"
    assert (rec.frames, rec.first_frame, rec.fps, rec.px_per_mm) == (1884, 0, 300.0, 3.364764)
    assert rec.body == RING
    assert rec.image_size == (1280.0, 1024.0)
    assert rec.marks.shape == (1884, 4, 2)
    assert rec.marks[0, 0].tolist() == [675.59, 449.11]
    assert rec.time_s[300] == 1.0
    assert rec.marks_tracked == 1884 * 4
    assert "1884 frames" in repr(rec)


def test_from_arrays_equals_the_same_file_read():
    read = ringlab.Recording.read(SAMPLE)
    made = ringlab.Recording.from_arrays(
        read.marks,
        fps=read.fps,
        px_per_mm=read.px_per_mm,
        body=read.body,
        first_frame=read.first_frame,
        image_size=read.image_size,
    )
    assert made == read
    assert np.array_equal(made.marks, read.marks)
    assert made.source == "numpy arrays" and made.name == "arrays"
    # The same recording, the same answer.
    opts = dict(progress=False, coarse=False, merges=0)
    assert ringlab.fit(made, **opts).to_dict() | {"compute_seconds": 0} == ringlab.fit(read, **opts).to_dict() | {"compute_seconds": 0}


def test_missing_marks_and_a_preset_body():
    read = ringlab.Recording.read(SAMPLE)
    marks = read.marks
    marks[10, 2] = np.nan
    marks[:5] = np.nan  # frames without any mark at the start are left out
    rec = ringlab.Recording.from_arrays(marks, fps=300, px_per_mm=3.364764, body="paper-ring", first_frame=100)
    assert rec.first_frame == 105 and rec.frames == 1879
    assert np.isnan(rec.marks[5, 2]).all() and rec.marks_tracked == 1879 * 4 - 1
    assert rec.body["shape"] == "ring"
    assert rec.image_size is None


def test_write_and_read_back(tmp_path):
    rec = ringlab.synth(t_end=5.0, seed=3)
    path = tmp_path / "synth.csv"
    rec.write(path, exact=True)
    back = ringlab.Recording.read(path)
    assert back == rec
    rec.write(tmp_path / "rounded.csv")
    rounded = ringlab.Recording.read(tmp_path / "rounded.csv")
    assert np.allclose(rounded.marks, rec.marks, atol=0.005)


def dlc_frame(rec):
    """The recording as DeepLabCut's DataFrame: (scorer, bodyparts, coords) columns, a
    likelihood per point (low where the mark was not found)."""
    import pandas as pd

    marks = rec.marks
    n = len(marks)
    rng = np.random.default_rng(1)
    columns, data = [], []
    for k, part in enumerate(["m1", "m2", "m3", "m4"]):
        found = ~np.isnan(marks[:, k, 0])
        lik = np.where(found, rng.uniform(0.7, 1.0, n), rng.uniform(0.0, 0.5, n))
        x = np.where(found, marks[:, k, 0], rng.uniform(0, 1280, n))
        y = np.where(found, marks[:, k, 1], rng.uniform(0, 1024, n))
        for coord, v in (("x", x), ("y", y), ("likelihood", lik)):
            columns.append(("DLC_resnet50_ringsJan1shuffle1_100000", part, coord))
            data.append(v)
    index = pd.MultiIndex.from_tuples(columns, names=["scorer", "bodyparts", "coords"])
    return pd.DataFrame(np.array(data).T, columns=index)


def docs_recipe(df):
    """docs/python.md's lines from a DeepLabCut DataFrame in hand to a recording."""
    df = df.droplevel("scorer", axis=1)[["m1", "m2", "m3", "m4"]]  # the marks, in cyclic order round the rim
    xy = df.drop(columns="likelihood", level="coords").to_numpy().reshape(len(df), 4, 2)
    xy[df.xs("likelihood", axis=1, level="coords").to_numpy() < 0.6] = np.nan  # as `ringlab import --from dlc`
    return ringlab.Recording.from_arrays(xy, fps=300, px_per_mm=3.364764, body="paper-ring", first_frame=int(df.index[0]))


@needs_pandas
def test_a_deeplabcut_csv_and_its_dataframe_give_one_recording(tmp_path):
    read = ringlab.Recording.read(SAMPLE)
    marks = read.marks
    marks[np.random.default_rng(2).random((len(marks), 4)) < 0.05] = np.nan
    truth = ringlab.Recording.from_arrays(marks, fps=300, px_per_mm=3.364764, body="paper-ring")
    df = dlc_frame(truth)
    df.to_csv(tmp_path / "ringDLC.csv")
    from_csv = ringlab.Recording.read(tmp_path / "ringDLC.csv", fps=300, px_per_mm=3.364764, body="paper-ring")
    assert from_csv.source == "DeepLabCut CSV"
    assert from_csv.mark_names == ["m1", "m2", "m3", "m4"]
    assert any("likelihood" in n for n in from_csv.notes)
    assert docs_recipe(df) == from_csv == truth


@needs_hdf5
def test_the_docs_example_from_a_deeplabcut_hdf5_file(tmp_path):
    import pandas as pd

    read = ringlab.Recording.read(SAMPLE)
    path = tmp_path / "ringDLC_resnet50_ringsJan1shuffle1_100000.h5"
    dlc_frame(read).to_hdf(path, key="df_with_missing", format="table")
    rec = docs_recipe(pd.read_hdf(path))
    assert rec == ringlab.Recording.from_arrays(read.marks, fps=300, px_per_mm=3.364764, body="paper-ring")


def test_other_formats_need_what_they_do_not_say(tmp_path):
    plain = tmp_path / "plain.csv"
    rows = ["frame,x1,y1,x2,y2,x3,y3,x4,y4"]
    for i, f in enumerate(ringlab.Recording.read(SAMPLE).marks[:200]):
        rows.append(",".join([str(i)] + [f"{v:.2f}" for v in f.ravel()]))
    plain.write_text("\n".join(rows) + "\n")
    with pytest.raises(ringlab.RecordingError, match="name its format with format="):
        ringlab.Recording.read(plain)
    with pytest.raises(ringlab.RecordingError, match="give fps="):
        ringlab.Recording.read(plain, format="csv")
    with pytest.raises(ringlab.RecordingError, match="body="):
        ringlab.Recording.read(plain, format="csv", fps=300, px_per_mm=3.36)
    rec = ringlab.Recording.read(plain, format="csv", fps=300, px_per_mm=3.36, body=RING)
    assert rec.frames == 200 and rec.source == "plain CSV"


# --- errors -------------------------------------------------------------------------------------


def test_a_missing_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        ringlab.Recording.read(tmp_path / "nothing.csv")


@pytest.mark.parametrize(
    "text, message",
    [
        ("", "the file is empty"),
        ("# ringlab-recording v2\n", "format version 'v2' is not supported"),
        ("# ringlab-recording v1\n# fps = 300\nframe,x1,y1,x2,y2,x3,y3,x4,y4\n", "missing required header key"),
        (
            "# ringlab-recording v1\n# fps = abc\n# px_per_mm = 3\n# shape = ring\n# outer_radius_mm = 20\n"
            "# width_mm = 18\n# thickness_mm = 1\nframe,x1,y1,x2,y2,x3,y3,x4,y4\n",
            ":2: fps = 'abc' is not a number",
        ),
        (
            "# ringlab-recording v1\n# fps = 300\n# px_per_mm = 3\n# shape = ring\n# outer_radius_mm = 20\n"
            "# width_mm = 18\n# thickness_mm = 1\nframe,x1,y1,x2,y2,x3,y3,x4,y4\n0,1,2,3,4,5,6,7,8\n",
            "fewer than two usable frames",
        ),
    ],
)
def test_a_bad_file_is_a_recording_error(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ringlab.RecordingError) as e:
        ringlab.Recording.read(path)
    assert message in str(e.value) and "bad.csv" in str(e.value)
    assert isinstance(e.value, ValueError)


def test_bad_read_keywords_are_value_errors():
    for kwargs, message in [
        ({"format": "excel"}, "format 'excel': not one of"),
        ({"fps": -3}, "fps = -3: must be a positive number"),
        ({"fps": "fast"}, "fps = 'fast' is not a number"),
        ({"unit": "inch"}, "unit 'inch'"),
        ({"min_likelihood": 2}, "min_likelihood = 2: must lie in [0, 1]"),
        ({"body": "no-such-ring"}, "no-such-ring"),
        ({"body": {"shape": "cube"}}, "shape 'cube'"),
        ({"body": {"shape": "ring", "outer_radius_mm": 20, "width_mm": 18}}, "thickness_mm"),
        ({"body": {"radius": 3}}, "unknown keys"),
        ({"body": 3}, "a preset's name or a dict"),
    ]:
        with pytest.raises(ValueError) as e:
            ringlab.Recording.read(SAMPLE, **kwargs)
        assert message in str(e.value), (kwargs, str(e.value))
    with pytest.raises(ValueError, match="no file"):
        ringlab.Recording.read([])


def test_bad_arrays():
    good = ringlab.Recording.read(SAMPLE).marks[:100]
    kw = dict(fps=300, px_per_mm=3.36, body=RING)
    cases = [
        (good[:, :3], {}, ValueError, "expected (frames, 4, 2)"),
        (good, {"fps": 0}, ValueError, "fps = 0: must be a positive number"),
        (good, {"px_per_mm": float("nan")}, ValueError, "px_per_mm = NaN"),
        (good, {"body": {"shape": "ring"}}, ValueError, "outer_radius_mm"),
        (good, {"body": {"shape": "ring", "outer_radius_mm": 5, "width_mm": 18, "thickness_mm": 9}}, ValueError, "impossible"),
        (good, {"first_frame": -1}, ValueError, "first_frame = -1: must lie in"),
        (good, {"image_size": (0, 10)}, ValueError, "image width = 0"),
        (good, {"camera_tilt_deg": 85}, ValueError, "camera_tilt_deg = 85"),
        (good, {"camera_distance_mm": -5}, ValueError, "camera_distance_mm = -5"),
        (np.full((10, 4, 2), np.nan), {}, ringlab.RecordingError, "fewer than two usable frames"),
        (good[:, [0, 2, 1, 3]], {}, ringlab.RecordingError, "marks[:, [0, 2, 1, 3]]"),
    ]
    half = good.copy()
    half[7, 1, 0] = np.nan
    cases.append((half, {}, ringlab.RecordingError, "marks[7, 1]"))
    inf = good.copy()
    inf[3, 0, 1] = np.inf
    cases.append((inf, {}, ringlab.RecordingError, "is not finite"))
    cases.append(([["a"]], {}, ValueError, "could not convert"))
    for marks, extra, error, message in cases:
        with pytest.raises(error) as e:
            ringlab.Recording.from_arrays(marks, **{**kw, **extra})
        assert message in str(e.value), (message, str(e.value))


def test_recordings_are_made_by_the_constructors_only():
    with pytest.raises(TypeError, match="Recording.read"):
        ringlab.Recording("file.csv")


@needs_hdf5
def test_the_docs_example_runs_as_written(tmp_path, monkeypatch, capsys):
    """docs/python.md's example, executed as it stands, on a DeepLabCut file of the sample's
    first 600 frames (written where the example looks for it)."""
    from conftest import REPO

    text = (REPO / "docs" / "python.md").read_text()
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    name = re.search(r'"([^"]+\.h5)"', code).group(1)
    short = ringlab.Recording.read(SAMPLE).marks[:600]
    rec = ringlab.Recording.from_arrays(short, fps=300, px_per_mm=3.364764, body="paper-ring")
    dlc_frame(rec).to_hdf(tmp_path / name, key="df_with_missing", format="table")
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "docs/python.md", "exec"), {})
    printed = capsys.readouterr().out.splitlines()
    assert printed[0].split()[0] in ["none", "unexplained", *ringlab.effects()], printed
    assert len(printed) >= 3, printed  # the explanation, and the frame the fit misses most


# --- DeepLabCut's HDF5 files ---------------------------------------------------------------------


def dlc_csv_and_h5(tmp_path, df):
    """A DeepLabCut CSV of `df`, and an HDF5 file of that CSV's data as pandas reads it (every
    number as the CSV writes it), under DeepLabCut's key."""
    import pandas as pd

    csv = tmp_path / "ringDLC.csv"
    df.to_csv(csv)
    table = pd.read_csv(csv, header=[0, 1, 2], index_col=0)
    # pandas reads back the numbers it wrote (repr's digits), to the bit.
    assert table.to_numpy().tobytes() == df.to_numpy().tobytes()
    h5 = tmp_path / "ringDLC.h5"
    table.to_hdf(h5, key="df_with_missing", format="table")
    return csv, h5


@needs_hdf5
def test_a_deeplabcut_hdf5_file_reads_as_its_csv_bit_for_bit(tmp_path):
    marks = ringlab.Recording.read(SAMPLE).marks
    marks[np.random.default_rng(3).random((len(marks), 4)) < 0.05] = np.nan
    truth = ringlab.Recording.from_arrays(marks, fps=300, px_per_mm=3.364764, body="paper-ring")
    csv, h5 = dlc_csv_and_h5(tmp_path, dlc_frame(truth))
    kw = dict(fps=300, px_per_mm=3.364764, body="paper-ring")
    from_csv, from_h5 = ringlab.Recording.read(csv, **kw), ringlab.Recording.read(h5, **kw)
    assert from_h5 == from_csv == truth
    assert from_h5.marks.tobytes() == from_csv.marks.tobytes()
    assert (from_h5.source, from_h5.name) == ("DeepLabCut HDF5", str(h5))
    assert from_h5.mark_names == from_csv.mark_names and from_h5.notes == from_csv.notes
    assert any("likelihood" in n for n in from_h5.notes)
    # The same likelihood cut, the same keywords: a higher one drops more marks.
    strict = dict(kw, min_likelihood=0.9)
    assert ringlab.Recording.read(h5, **strict) == ringlab.Recording.read(csv, **strict)
    assert ringlab.Recording.read(h5, **strict).marks_tracked < from_h5.marks_tracked
    # DeepLabCut's own file (fixed format, written from the DataFrame it made) reads the same.
    dlc_frame(truth).to_hdf(tmp_path / "fixed.h5", key="df_with_missing")
    assert ringlab.Recording.read(tmp_path / "fixed.h5", **kw) == truth


@needs_hdf5
def test_a_multi_animal_hdf5_file_names_its_marks_by_individual(tmp_path):
    import pandas as pd

    truth = ringlab.Recording.read(SAMPLE)
    one = dlc_frame(truth)
    other = one + 40.0  # a second ring beside the first
    both = pd.concat([one, other], axis=1, keys=["ring1", "ring2"], names=["individuals"])
    both = both.reorder_levels(["scorer", "individuals", "bodyparts", "coords"], axis=1)
    both.to_hdf(tmp_path / "two.h5", key="df_with_missing")
    kw = dict(fps=300, px_per_mm=3.364764, body="paper-ring")
    rec = ringlab.Recording.read(tmp_path / "two.h5", marks=[f"ring1/m{k}" for k in range(1, 5)], **kw)
    assert rec == ringlab.Recording.from_arrays(truth.marks, **kw)
    assert rec.mark_names == ["ring1/m1", "ring1/m2", "ring1/m3", "ring1/m4"]
    with pytest.raises(ValueError, match="'m1' is not in the file"):
        ringlab.Recording.read(tmp_path / "two.h5", marks=["m1", "m2", "m3", "m4"], **kw)


def bad_h5(tmp_path, make):
    path = tmp_path / "bad.h5"
    make(path)
    with pytest.raises(ringlab.RecordingError) as e:
        ringlab.Recording.read(path, fps=300, px_per_mm=3.36, body="paper-ring")
    assert str(path) in str(e.value)
    return str(e.value)


@needs_hdf5
def test_a_bad_hdf5_file_is_a_recording_error_naming_it(tmp_path):
    import pandas as pd

    good = dlc_frame(ringlab.Recording.read(SAMPLE)).iloc[:300]

    def renamed(path):
        cols = [(s, b, "p" if (b, c) == ("m2", "likelihood") else c) for s, b, c in good.columns]
        df = good.copy()
        df.columns = pd.MultiIndex.from_tuples(cols, names=good.columns.names)
        df.to_hdf(path, key="df_with_missing")

    def indexed(path, index):
        df = good.copy()
        df.index = index
        df.to_hdf(path, key="df_with_missing")

    def with_value(path, value):
        df = good.copy()
        df.iloc[3, 0] = value
        df.to_hdf(path, key="df_with_missing")

    def two_tables(path):
        good.to_hdf(path, key="a")
        good.to_hdf(path, key="b")

    cases = [
        (lambda p: p.write_text("scorer,bodyparts\n"), "cannot read it as a pandas HDF5 file"),
        (lambda p: pd.DataFrame({"x": [1.0, 2.0]}).to_hdf(p, key="df_with_missing"), "its columns' levels are None, expected scorer, bodyparts, coords"),
        (renamed, "columns 3 to 5 are (DLC_resnet50_ringsJan1shuffle1_100000, m2, x; "),
        (lambda p: good.droplevel("scorer", axis=1).to_hdf(p, key="df_with_missing"), "levels are bodyparts, coords"),
        (lambda p: good.iloc[:, :4].to_hdf(p, key="df_with_missing"), "4 columns, expected x, y and likelihood per point"),
        (lambda p: pd.Series([1.0]).to_hdf(p, key="df_with_missing"), "is a Series, not a DataFrame"),
        (two_tables, "2 tables (/a, /b) and none under '/df_with_missing'"),
        (lambda p: indexed(p, [5 if i == 6 else i for i in range(300)]), "frame 5 is in its table twice (rows 5 and 6)"),
        (lambda p: indexed(p, [f"img{i:03}.png" for i in range(300)]), "(row 0 of its table): frame 'img000.png' is not a whole number"),
        (lambda p: with_value(p, np.inf), "(row 3 of its table): m1 x = inf is not a finite number"),
        (lambda p: good.iloc[:, :9].to_hdf(p, key="df_with_missing"), "3 point(s) found (m1, m2, m3); four marks are needed"),
    ]
    for make, message in cases:
        got = bad_h5(tmp_path, make)
        assert message in got, (message, got)
        (tmp_path / "bad.h5").unlink()


@needs_hdf5
def test_an_hdf5_file_is_not_read_as_another_format(tmp_path):
    path = tmp_path / "ring.h5"
    dlc_frame(ringlab.Recording.read(SAMPLE)).to_hdf(path, key="df_with_missing")
    with pytest.raises(ValueError, match="an HDF5 file, read as DeepLabCut's table"):
        ringlab.Recording.read(path, format="csv", fps=300, px_per_mm=3.36, body="paper-ring")


@pytest.mark.parametrize("missing", ["pandas", "tables"])
def test_an_hdf5_file_without_pandas_or_pytables_is_an_import_error(tmp_path, monkeypatch, missing):
    import sys

    path = tmp_path / "ring.h5"
    path.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(100))
    monkeypatch.setitem(sys.modules, missing, None)  # `import` of it now raises ImportError
    with pytest.raises(ImportError) as e:
        ringlab.Recording.read(path, fps=300, px_per_mm=3.36, body="paper-ring")
    assert "pandas" in str(e.value) and "tables" in str(e.value)
