"""ringlab.simulate: the paper's ring against the shared reference solution, the columns of
`simulate --out`, the summary of `simulate --json`."""

from __future__ import annotations

import csv
import io
import math

import numpy as np
import pytest

import ringlab
from conftest import DATA, needs_cli, needs_pandas, run_cli


def reference():
    lines = [l for l in (DATA / "paper-ring-reference.csv").read_text().splitlines() if not l.startswith("#")]
    rows = list(csv.reader(lines))
    head, body = rows[0], np.array(rows[1:], dtype=float)
    return {name: body[:, i] for i, name in enumerate(head)}


def reference_end() -> float:
    line = next(l for l in (DATA / "paper-ring-reference.csv").read_text().splitlines() if "run ends" in l)
    return float(line.rsplit("t=", 1)[1])


def test_paper_ring_theta_matches_the_reference():
    # As crates/ringlab-core/tests/paper_reference.rs: theta to 1e-6 up to t = 50, the end
    # (theta at pi/2 - 0.02) to 0.1%.
    ref = reference()
    run = ringlab.simulate("paper-ring")
    keep = ref["t"] <= 50.0
    k = np.rint(ref["t"][keep] / 0.05).astype(int)
    assert keep.sum() >= 1000
    assert np.max(np.abs(run.t[k] - ref["t"][keep])) < 1e-9
    worst = np.max(np.abs(run.theta[k] - ref["theta"][keep]))
    assert worst < 1e-6, worst
    for name in ("x_a", "y_a", "w3"):
        assert np.max(np.abs(getattr(run, name)[k] - ref[name][keep])) < 1e-6, name
    assert run.end_reason == "flat"
    assert abs(run.t_end / reference_end() - 1) < 1e-3
    assert abs(run.theta[-1] - (math.pi / 2 - 0.02)) < 0.02


def test_summary_is_the_run_s():
    run = ringlab.simulate()
    assert run.retrograde_turn and run.summary.retrograde_turn
    assert [p.phase for p in run.phases][:2] == ["prograde", "walk"]
    assert run.inflection_time == pytest.approx(27.9, abs=0.1)
    assert isinstance(run.lift_off, list) and isinstance(run.slip, list)
    d = run.to_dict()
    assert d["case"] == "paper-ring" and d["end_reason"] == "flat"
    assert d["phases"][0] == {"phase": "prograde", "start": 0.0, "end": run.phases[0].end}
    # `sliding` is the column; the summary's intervals are in run.summary.
    assert run.sliding.shape == run.t.shape and run.summary.sliding == []
    assert len(run) == run.samples.shape[0] == run.t.shape[0]


def test_overrides_and_effects():
    base = ringlab.simulate(t_end=10.0)
    assert base.t[-1] == pytest.approx(10.0) and base.end_reason == "t_end"
    faster = ringlab.simulate(t_end=10.0, phidot0=5.0)
    assert faster.phi[-1] != base.phi[-1]
    dragged = ringlab.simulate(t_end=10.0, effects={"rolling_friction": 0.003})
    assert dragged.summary.effects[0].name == "rolling_friction"
    assert dragged.energy[-1] < base.energy[-1]
    slipping = ringlab.simulate(t_end=5.0, effects={"slip": 0.2}, slip_start="held")
    assert slipping.summary.slip_mu == 0.2


@needs_cli
def test_columns_and_summary_equal_the_cli_s(tmp_path):
    out = tmp_path / "run.csv"
    printed = run_cli(["simulate", "--preset", "paper-ring", "--t-end", "30", "--out", str(out), "--json"])
    import json

    cli = json.loads(printed)
    run = ringlab.simulate("paper-ring", t_end=30.0)
    mine = run.to_dict()
    cli.pop("compute_seconds"), mine.pop("compute_seconds")
    assert mine == cli
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    header = out.read_text().splitlines()[0].split(",")
    assert tuple(header) == run.columns
    assert table.shape == run.samples.shape
    assert np.array_equal(table, run.samples)


@needs_pandas
def test_to_pandas():
    df = ringlab.simulate(t_end=5.0).to_pandas()
    assert list(df.columns)[:3] == ["t", "phi", "theta"]
    assert df["t"].iloc[-1] == pytest.approx(5.0)


def test_presets_and_effects_are_listed():
    assert "paper-ring" in ringlab.presets()
    effects = ringlab.effects()
    assert "reynolds_drag" in effects and "camera_perspective" in effects


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"preset": "no-such-ring"}, "no-such-ring"),
        ({"c1": float("nan")}, "c1 = NaN: must be a finite number"),
        ({"dt": -1.0}, "case 'paper-ring' with the given overrides"),
        ({"c1": "drag"}, "c1 = 'drag' is not a number"),
        ({"effects": {"wind": 1.0}}, "effect 'wind' is not one of"),
        ({"effects": {"camera_distortion": 0.1}}, "changes the camera, not the motion"),
        ({"effects": {"rolling_friction": -1.0}}, "rolling_friction"),
        ({"effects": {"slip": 50.0}}, "for this body mu must stay below"),
        ({"slip_start": "held"}, "slip_start needs the effect slip"),
        ({"effects": {"slip": 0.3}, "slip_start": "later"}, "not 'cone' or 'held'"),
        ({"preset": "coin", "config": "x.toml"}, "either preset or config"),
    ],
)
def test_bad_parameters_are_value_errors(kwargs, message):
    with pytest.raises(ValueError, match=None) as e:
        ringlab.simulate(**kwargs)
    assert message in str(e.value)


def test_unknown_override_is_a_type_error():
    with pytest.raises(TypeError, match="c4"):
        ringlab.simulate(c4=0.1)


def test_a_case_file(tmp_path):
    from conftest import REPO

    text = (REPO / "crates" / "ringlab-core" / "assets" / "presets" / "paper-ring.toml").read_text()
    path = tmp_path / "case.toml"
    path.write_text(text.replace("t_end = 1000.0", "t_end = 2.0"))
    run = ringlab.simulate(config=path)
    assert run.t[-1] == pytest.approx(2.0)
    bad = tmp_path / "bad.toml"
    bad.write_text("name = 'x'\n")
    with pytest.raises(ValueError, match="bad.toml"):
        ringlab.simulate(config=bad)
    with pytest.raises(ValueError, match="missing.toml"):
        ringlab.simulate(config=tmp_path / "missing.toml")
