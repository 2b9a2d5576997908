"""ringlab.fit and ringlab.diagnose: the same answers as the CLI's (its JSON, field for field,
when the CLI is built; the figures it printed, recorded in data/expected.json, always), a
shared independent recording diagnosed as its truth says, progress, and the errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

import ringlab
from conftest import DATA, EXPECTED, cli_json, diagnosis_of, fit_of_sample, needs_cli

INDEPENDENT = ["glitches", "two-effects"]


def truth(name: str):
    return json.loads((DATA / "independent" / "truth.json").read_text())[name]


@pytest.mark.parametrize("name", INDEPENDENT)
def test_an_independent_recording_is_diagnosed_as_its_truth_says(name):
    d = diagnosis_of(name)
    said = sorted(d.left_out_all) if d.left_out_all else [d.left_out]
    assert said == sorted(truth(name)["left_out"]), d.explanation
    assert abs(d.noise_px / truth(name)["noise_px"] - 1) < 0.2
    assert d.after.rms_px <= d.before.rms_px
    assert d.candidates[0].name in {c.name for c in d.candidates}
    assert "left_out=" in repr(d)


@pytest.mark.parametrize("name", INDEPENDENT)
def test_the_diagnosis_gives_the_figures_the_cli_printed(name):
    want = EXPECTED[f"diagnose independent/{name}.csv"]
    d = diagnosis_of(name)
    got = {
        "left_out": d.left_out,
        "left_out_all": d.left_out_all,
        "before.rms_px": round(d.before.rms_px, 3),
        "after.rms_px": round(d.after.rms_px, 3),
        "noise_px": round(d.noise_px, 3),
        "glitches": d.glitches,
        "frames_fitted": d.frames_fitted,
    }
    assert got == want


@needs_cli
@pytest.mark.parametrize("name", INDEPENDENT)
def test_the_diagnosis_is_the_cli_s_json(name):
    cli = cli_json(["diagnose", str(DATA / "independent" / f"{name}.csv"), "--json"])
    mine = diagnosis_of(name).to_dict()
    cli.pop("compute_seconds"), mine.pop("compute_seconds")
    assert list(mine) == list(cli)  # the same names, in the same order
    assert mine == cli  # and the same numbers, to the last bit


def test_the_fit_gives_the_figures_the_cli_printed():
    want = EXPECTED["fit sample-ring.csv"]
    f = fit_of_sample()
    assert [round(c, 5) for c in f.c] == want["c"]
    assert round(f.rms_px, 4) == want["rms_px"]
    assert (f.frames_fitted, f.segments) == (want["frames_fitted"], want["segments"])


@needs_cli
def test_the_fit_is_the_cli_s_json():
    cli = cli_json(["fit", str(DATA / "sample-ring.csv"), "--json"])
    mine = fit_of_sample().to_dict()
    cli.pop("compute_seconds"), mine.pop("compute_seconds")
    assert list(mine) == list(cli)
    assert mine == cli


def test_result_objects_are_typed():
    d = diagnosis_of("two-effects")
    assert isinstance(d.before, ringlab.ModelFit) and isinstance(d.candidates[0], ringlab.Candidate)
    assert d.after.effect in d.left_out_all
    assert d.after.params["C1"] > 0
    assert isinstance(d.mismatch, ringlab.MismatchWindow)
    assert all(isinstance(p, ringlab.PairCandidate) for p in d.pairs)
    assert sorted(s.name for s in d.shares) == sorted(d.left_out_all)
    assert all(isinstance(s, ringlab.NamedShare) and 0 < s.share <= 1 for s in d.shares)
    g = diagnosis_of("glitches")
    assert len(g.glitch_marks) == g.glitches and isinstance(g.glitch_marks[0], ringlab.Glitch)
    assert g.glitch_marks[0].kind in ("outlier", "swapped")
    f = fit_of_sample()
    assert isinstance(f, ringlab.FitResult) and len(f.c) == 3 and f.effect is None


def test_progress_reaches_a_callback_on_the_calling_thread():
    import threading

    seen = []
    rec = ringlab.synth(t_end=20.0, seed=5)
    main = threading.get_ident()
    ringlab.fit(rec, progress=lambda f, m: seen.append((f, m, threading.get_ident())), coarse=False)
    assert seen, "no progress reported"
    assert all(0.0 <= f <= 1.0 and isinstance(m, str) for f, m, _ in seen)
    assert {t for _, _, t in seen} == {main}


def test_an_exception_in_the_callback_stops_the_work():
    rec = ringlab.synth(t_end=20.0, seed=5)

    def stop(fraction, message):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        ringlab.fit(rec, progress=stop)


def test_the_gil_is_released_while_it_runs():
    import threading
    import time

    rec = ringlab.Recording.read(DATA / "sample-ring.csv")
    done = threading.Event()
    results = []

    def work():
        try:
            results.append(ringlab.fit(rec, progress=False, coarse=False))
        finally:
            done.set()

    worker = threading.Thread(target=work)
    start = time.perf_counter()
    worker.start()
    counted = 0
    while not done.is_set():
        counted += 1  # pure Python on this thread, while the fit runs on the other
    worker.join()
    elapsed = time.perf_counter() - start
    assert results and elapsed > 0.2, elapsed
    # Held by the fit, the GIL would let this loop run only at the 50 ms polls.
    assert counted > 10_000 * elapsed, (counted, elapsed)


def test_a_path_is_read_first():
    d = ringlab.fit(DATA / "sample-ring.csv", progress=False, coarse=False, merges=0)
    assert d.frames == 1884


# --- errors -------------------------------------------------------------------------------------


def test_bad_parameters_are_value_errors():
    rec = ringlab.synth(t_end=10.0)
    for call, message in [
        (lambda: ringlab.fit(rec, effect="wind"), "effect 'wind' is not one of"),
        (lambda: ringlab.fit(rec, c_start=(0.1, 0.1)), "expected C1, C2, C3"),
        (lambda: ringlab.fit(rec, c_start=(0.1, -1, 0.1)), "every coefficient must be a positive number"),
        (lambda: ringlab.fit(rec, lens_k1=float("inf")), "lens_k1 = inf"),
        (lambda: ringlab.fit(rec, merges=-1), "merges = -1"),
        (lambda: ringlab.fit(rec, threads=0), "threads = 0"),
        (lambda: ringlab.fit(rec, progress="yes"), "progress = 'yes'"),
        (lambda: ringlab.diagnose(rec, candidates=["slip", "magic"]), "'magic' is not one of"),
        (lambda: ringlab.diagnose(rec, evidence=-1), "evidence = -1: must be a number >= 0"),
        (lambda: ringlab.synth(noise_px=-1), "noise_px = -1 must be a number >= 0"),
        (lambda: ringlab.synth(fps=0), "fps = 0 must be a positive number"),
        (lambda: ringlab.synth(effect="slip"), "effect slip needs effect_strength"),
        (lambda: ringlab.synth(effect_strength=0.2), "effect_strength needs effect"),
        (lambda: ringlab.synth(effect_extras=[1.0]), "effect_extras needs effect"),
        (lambda: ringlab.synth(effect="reynolds_drag", effect_strength=-2), "invalid effect"),
        (lambda: ringlab.synth(camera_distance_mm=10), "camera distance = 10 mm must exceed"),
        (lambda: ringlab.synth(drop_marks=1.5), "missing fraction = 1.5"),
        (lambda: ringlab.synth(slip_start="held"), "slip_start needs the effect slip"),
    ]:
        with pytest.raises(ValueError) as e:
            call()
        assert message in str(e.value), (message, str(e.value))
    with pytest.raises(TypeError, match="ringlab.Recording or a path"):
        ringlab.fit(42)  # type: ignore[arg-type]


def test_a_recording_that_cannot_be_fitted_is_a_fit_error():
    # Three seconds of a ring lying still: no motion to fit.
    marks = np.tile(ringlab.Recording.read(DATA / "sample-ring.csv").marks[-1], (900, 1, 1))
    rec = ringlab.Recording.from_arrays(marks, fps=300, px_per_mm=3.364764, body="paper-ring")
    with pytest.raises(ringlab.FitError) as e:
        ringlab.fit(rec, progress=False)
    assert str(e.value).startswith("fitting arrays: ")
    with pytest.raises(ringlab.FitError) as e:
        ringlab.diagnose(rec, progress=False)
    assert str(e.value).startswith("diagnosing arrays: ")


# --- what the window draws: the arrays beside the JSON ------------------------------------------


def check_fit_arrays(f: ringlab.FitResult, rec: ringlab.Recording, rms_px: float, residuals: int) -> None:
    """The fit's arrays against its rms_px and residual count (given as the CLI printed them)."""
    n = rec.frames
    assert f.predicted_marks.shape == (n, 4, 2) and f.mark_residual_px.shape == (n, 4) and f.residual_px.shape == (n,)
    finite = np.isfinite(f.mark_residual_px)
    assert 2 * int(finite.sum()) == residuals
    rms = np.sqrt(np.nansum(f.mark_residual_px**2) / (2 * finite.sum()))
    assert abs(rms / rms_px - 1) < 1e-12, (rms, rms_px)
    # Each residual is the mark's distance from the model's, where both are.
    apart = np.hypot(*np.moveaxis(f.predicted_marks - rec.marks, 2, 0))
    assert np.allclose(apart[finite], f.mark_residual_px[finite], rtol=1e-14, atol=0)
    assert np.isnan(f.mark_residual_px[np.isnan(rec.marks[:, :, 0])]).all()
    # Per frame: the RMS over the frame's coordinates with a residual.
    counts = finite.sum(axis=1)
    per_frame = np.sqrt(np.nansum(f.mark_residual_px**2, axis=1) / np.maximum(2 * counts, 1))
    assert np.array_equal(np.isnan(f.residual_px), counts == 0)
    assert np.allclose(f.residual_px[counts > 0], per_frame[counts > 0], rtol=1e-14, atol=0)
    # The model's marks cover one stretch of frames, the fitted ones.
    covered = np.flatnonzero(np.isfinite(f.predicted_marks).all(axis=(1, 2)))
    assert len(covered) == covered[-1] - covered[0] + 1
    assert np.isnan(f.predicted_marks[np.setdiff1d(np.arange(n), covered)]).all()


def test_the_fit_s_arrays_give_its_misfit():
    f = fit_of_sample()
    check_fit_arrays(f, ringlab.Recording.read(DATA / "sample-ring.csv"), f.rms_px, f.residuals)
    # The start (the first inner turning point) lies in the fitted stretch.
    covered = np.flatnonzero(np.isfinite(f.residual_px))
    assert covered[0] <= f.start_frame <= covered[-1]
    assert "predicted_marks" not in f.to_dict() and "predicted_marks" not in repr(f)


def test_a_glitch_has_no_residual():
    rec = ringlab.Recording.read(DATA / "independent" / "glitches.csv")
    f = ringlab.fit(rec, progress=False, coarse=False, merges=0)
    d = diagnosis_of("glitches")
    check_fit_arrays(f, rec, f.rms_px, f.residuals)
    marks = rec.marks
    inside = [g for g in d.glitch_marks if np.isfinite(f.predicted_marks[g.frame - rec.first_frame, g.mark - 1, 0])]
    assert len(inside) > 10, len(inside)
    for g in inside:
        i, k = g.frame - rec.first_frame, g.mark - 1
        assert np.isfinite(marks[i, k, 0]) and np.isnan(f.mark_residual_px[i, k]), g


@needs_cli
def test_the_fit_s_arrays_give_the_cli_s_misfit():
    cli = cli_json(["fit", str(DATA / "sample-ring.csv"), "--json"])
    check_fit_arrays(fit_of_sample(), ringlab.Recording.read(DATA / "sample-ring.csv"), cli["rms_px"], cli["residuals"])


def frame_counts(d: ringlab.Diagnosis, rec: ringlab.Recording) -> np.ndarray:
    """Coordinates per fitted frame: the marks tracked, less the glitches left out."""
    tracked = np.isfinite(rec.marks[:, :, 0])
    for g in d.glitch_marks:
        tracked[g.frame - rec.first_frame, g.mark - 1] = False
    return 2 * tracked[d.fitted_frames].sum(axis=1)


def series_rms(per_frame: np.ndarray, counts: np.ndarray) -> float:
    return float(np.sqrt(np.nansum(per_frame**2 * counts) / counts.sum()))


def check_diagnosis_arrays(d: ringlab.Diagnosis, rec: ringlab.Recording, before_px: float, after_px: float) -> None:
    n = d.frames_fitted
    assert d.fitted_frames.dtype == np.int64 and np.array_equal(d.fitted_frames, np.arange(n) + d.fitted_frames[0])
    assert np.array_equal(d.time_s, rec.time_s[d.fitted_frames])
    counts = frame_counts(d, rec)
    for series, rms in ((d.residual_before_px, before_px), (d.residual_after_px, after_px)):
        assert series.shape == (n,) and np.array_equal(np.isnan(series), counts == 0)
        assert abs(series_rms(series, counts) / rms - 1) < 1e-12, (series_rms(series, counts), rms)
    assert d.residual_followed_px.shape == (n,)
    # Each test window's RMS is its frames' together, for all three models.
    w = len(d.window_s)
    assert d.window_s.shape == (w, 2) and w >= n // 30
    frames = np.rint(d.window_s * rec.fps).astype(int) - rec.first_frame - d.fitted_frames[0]
    assert frames[0, 0] == 0 and frames[-1, 1] == n and np.array_equal(frames[1:, 0], frames[:-1, 1])
    for per_frame, windows in (
        (d.residual_before_px, d.window_before_px),
        (d.residual_after_px, d.window_after_px),
        (d.residual_followed_px, d.window_followed_px),
    ):
        got = [series_rms(per_frame[a:b], counts[a:b]) for a, b in frames]
        assert np.allclose(got, windows, rtol=1e-12, atol=0)
    assert (d.window_threshold_px > d.noise_px).all()
    # Point A: the marks' centroid, where all four were tracked (and none left out).
    all_four = counts == 8
    centroid = rec.marks[d.fitted_frames].mean(axis=1)
    assert np.allclose(d.trace_data_px[all_four], centroid[all_four], rtol=0, atol=1e-9)
    assert np.isnan(d.trace_data_px[~all_four]).all()
    for model in (d.trace_before_px, d.trace_after_px):
        assert model.shape == (n, 2) and np.isfinite(model).all()
    assert d.image_px.tolist() == list(rec.image_size or d.image_px.tolist())


@pytest.mark.parametrize("name", INDEPENDENT)
def test_the_diagnosis_s_series_give_its_misfits(name):
    d = diagnosis_of(name)
    rec = ringlab.Recording.read(DATA / "independent" / f"{name}.csv")
    check_diagnosis_arrays(d, rec, d.before.rms_px, d.after.rms_px)
    assert isinstance(d.signature, ringlab.Signature) and len(d.signature.thirds_rms_px) == 3
    assert "residual_before_px" not in d.to_dict() and "signature" not in d.to_dict()


def test_the_series_show_what_the_diagnosis_found():
    # two-effects: the baseline misses by 15 px against 0.5 px of noise, the chosen model not.
    d = diagnosis_of("two-effects")
    assert (d.window_before_px > d.window_threshold_px).mean() > 0.5
    assert (d.window_after_px > d.window_threshold_px).mean() < 0.1
    assert np.nanmedian(d.residual_after_px) < 2 * d.noise_px < np.nanmedian(d.residual_before_px)
    # glitches: nothing left out, so before and after are one model.
    g = diagnosis_of("glitches")
    assert np.array_equal(g.residual_before_px, g.residual_after_px, equal_nan=True)


@needs_cli
@pytest.mark.parametrize("name", INDEPENDENT)
def test_the_diagnosis_s_series_give_the_cli_s_misfits(name):
    cli = cli_json(["diagnose", str(DATA / "independent" / f"{name}.csv"), "--json"])
    rec = ringlab.Recording.read(DATA / "independent" / f"{name}.csv")
    check_diagnosis_arrays(diagnosis_of(name), rec, cli["before"]["rms_px"], cli["after"]["rms_px"])
    assert diagnosis_of(name).frames_fitted == cli["frames_fitted"]
