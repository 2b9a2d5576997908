//! The steps of a diagnosis (see the module doc of `analysis::diagnose`).

use super::again::{Again, Singles};
use super::candidates::{fit_baseline, fit_candidates};
use super::departure::{self, Departure};
use super::explain::explain;
use super::noise_correlation::{self, NoiseCorrelation};
use super::options::{DiagnoseError, DiagnoseOptions, DiagnoseProgress};
use super::plan;
use super::progress::Reporter;
use super::ranking::Fits;
use super::ranking::rank;
use super::residual::{
    MIN_WINDOW_FRAMES, NoiseLevel, WINDOW_S, Window, departures, frame_rms, frame_sums, windows,
};
use super::result::{
    Candidate, Diagnosis, Finding, MismatchWindow, ModelFit, NamedShare, PairCandidate,
    ResidualSeries, Signature, Trace, named_extras,
};
use super::rules::bic;
use super::seen_camera::seen_camera;
use super::select::{Selection, forward_selection};
use super::signature::{measure, run_end};
use super::whole::{Level, WholeFit};
use crate::analysis::fit::lm::LmError;
use crate::analysis::fit::shooting::{PredictedMarks, Shooting};
use crate::analysis::fit::{FitError, FitOptions, FitProgress, FitResult, fit};
use crate::physics::Initial;
use crate::physics::effects::EffectKind;
use crate::recording::glitches::{Glitch, find_glitches_against};
use crate::recording::tracks::{CheckedTracks, check_tracks, with_more_glitches};
use crate::recording::{Camera, FrameMarks, MARKS, Recording};
use std::ops::Range;
use std::sync::atomic::AtomicBool;
use web_time::Instant;

fn lm_error(e: LmError) -> DiagnoseError {
    match e {
        LmError::Cancelled => DiagnoseError::Cancelled,
        LmError::BadStart => DiagnoseError::Baseline,
    }
}

/// Diagnoses a recording: which physics (or measurement effect) the paper's model left out,
/// if any. Runs for seconds: call it off the UI thread. `progress` is called from worker
/// threads; `cancel` stops it with [`DiagnoseError::Cancelled`]. The stages, in order:
pub fn diagnose(
    rec: &Recording,
    opts: &DiagnoseOptions,
    progress: &(dyn Fn(&DiagnoseProgress) + Sync),
    cancel: &AtomicBool,
) -> Result<Diagnosis, DiagnoseError> {
    let mut laps = Laps::new();
    let progress = &Reporter::new(progress);
    let opts = &suspects(rec, opts)?;
    let run = Run { opts, progress, cancel };
    let fit_opts = FitOptions { leave_out_glitches: false, ..opts.fit.clone() };
    let (tracks, base) = baseline_without_glitches(&run, rec, &fit_opts)?;
    let rec = &tracks.recording;
    laps.lap("multiple-shooting fit");
    // Every fit from here on is made on this problem or one made from it, and stops by its
    // flag.
    let ms = base.shooting(&rec.frames, cancel);
    let noise = Noise::of(&base, rec);
    progress.seeing_camera();
    let seen = seen_camera(&base, &ms, &opts.candidates, opts.evidence)?;
    laps.lap("the camera the segments see");
    let (baseline, levels) = baseline_path(&ms, &base, progress)?;
    // A tracker's noise correlated in time, read from the baseline's residual.
    let noise = noise.with_correlation(&baseline, &ms, tracks.noise.as_ref());
    laps.lap("baseline over the whole run");
    let again = Again::new(rec, &fit_opts, seen.as_ref());
    let (departure, baseline, fits) =
        candidates_and_departure(&run, &again, &ms, &base, baseline, &levels, &noise)?;
    laps.lap("candidates and departure");
    let select = |ranked: &mut [(Candidate, Option<&WholeFit>)], noise: &Noise| {
        let sel = Selection {
            again: &again,
            ms: &ms,
            levels: &levels,
            baseline: &baseline,
            noise_px: noise.px,
            dependence: noise.dependence(),
            evidence: opts.evidence,
            progress,
        };
        forward_selection(&sel, ranked, |w| plan::run(w))
    };
    let mut ranked = rank(&baseline, &fits, noise.dependence());
    let (mut finding, mut chosen, mut shares, mut pairs) = select(&mut ranked, &noise)?;
    // A missing effect hides a tracker's correlation from the baseline's residual; the
    // residual of the model named (else of the best single candidate) may show it, and the
    // decision is made again against the noise corrected for it.
    let best = noise.best_model(&finding, chosen.as_ref(), &ranked);
    let noise = match best.and_then(|w| noise.again_from(w, &ms, tracks.noise.as_ref())) {
        Some(corrected) => {
            ranked = rank(&baseline, &fits, corrected.dependence());
            (finding, chosen, shares, pairs) = select(&mut ranked, &corrected)?;
            corrected
        }
        None => noise,
    };
    laps.lap("pairs and the decision");
    progress.explaining();
    let candidates = ranked.into_iter().map(|(c, _)| c).collect();
    let fit = chosen.as_ref().unwrap_or(&baseline);
    let chosen = Chosen { finding, fit, candidates, shares, pairs };
    let decided = Decided {
        baseline: &baseline,
        chosen,
        departure: &departure,
        noise: &noise,
        evidence: opts.evidence,
    };
    let mut d = describe(&tracks, &base, &ms, decided, laps.take())?;
    d.explanation = explain(&d);
    laps.lap("residuals, signature, words");
    d.stage_seconds.extend(laps.take());
    d.compute_seconds = laps.total();
    Ok(d)
}

/// The seconds of each stage, and of the whole.
struct Laps {
    start: Instant,
    lap: Instant,
    done: Vec<(&'static str, f64)>,
}

impl Laps {
    fn new() -> Laps {
        let now = Instant::now();
        Laps { start: now, lap: now, done: Vec::new() }
    }
    fn lap(&mut self, name: &'static str) {
        self.done.push((name, self.lap.elapsed().as_secs_f64()));
        self.lap = Instant::now();
    }
    fn take(&mut self) -> Vec<(&'static str, f64)> {
        std::mem::take(&mut self.done)
    }
    fn total(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

/// The pixel noise the diagnosis judges by, and the width of its residual windows.
struct Noise {
    px: f64,
    /// Whether it came from the marks' tracks (else the baseline's misfit stands in).
    from_marks: bool,
    window_frames: usize,
    /// The tracker's correlation in time, where the baseline's residual shows one.
    correlation: Option<NoiseCorrelation>,
}

impl Noise {
    fn of(base: &FitResult, rec: &Recording) -> Noise {
        let from_marks = base.noise_px.is_some_and(|v| v.is_finite() && v > 0.0);
        let px = base.noise_px.filter(|_| from_marks).unwrap_or(base.rms_px);
        let window_frames = ((WINDOW_S * rec.header.fps).round() as usize).max(MIN_WINDOW_FRAMES);
        Noise { px, from_marks, window_frames, correlation: None }
    }

    /// The level corrected for a tracker's correlation in time, where the residual of the
    /// whole-run `baseline` shows one and nothing else (`noise_correlation`).
    fn with_correlation(
        self,
        baseline: &WholeFit,
        ms: &Shooting,
        tracks: Option<&crate::recording::noise::NoiseEstimate>,
    ) -> Noise {
        let (Some(tracks), Some(pred)) = (tracks.filter(|_| self.from_marks), baseline.marks(ms))
        else {
            return self;
        };
        match noise_correlation::measure(ms.observed, baseline.span.start, &pred, tracks) {
            Some(c) => Noise { px: c.px, correlation: Some(c), ..self },
            None => self,
        }
    }

    /// The model whose residual may show the tracker's correlation where the baseline's did
    /// not: the one named, else (`unexplained`) the single candidate that fits best.
    fn best_model<'a>(
        &self,
        finding: &Finding,
        chosen: Option<&'a WholeFit>,
        ranked: &[(Candidate, Option<&'a WholeFit>)],
    ) -> Option<&'a WholeFit> {
        if self.correlation.is_some() {
            return None;
        }
        match finding {
            Finding::Nothing => None,
            Finding::Named(_) => chosen,
            Finding::Unexplained { .. } => ranked
                .iter()
                .filter(|(c, w)| !c.effect.is_baseline() && w.is_some() && c.rms_px.is_finite())
                .min_by(|a, b| a.0.rms_px.total_cmp(&b.0.rms_px))
                .and_then(|(_, w)| *w),
        }
    }

    /// The level corrected as [`Noise::with_correlation`] does, from the residual of `fit`.
    fn again_from(
        &self,
        fit: &WholeFit,
        ms: &Shooting,
        tracks: Option<&crate::recording::noise::NoiseEstimate>,
    ) -> Option<Noise> {
        let noise = Noise { correlation: None, ..*self }.with_correlation(fit, ms, tracks);
        noise.correlation.is_some().then_some(noise)
    }

    fn level(&self) -> NoiseLevel {
        NoiseLevel { px: self.px, spread: self.correlation.as_ref().map_or(1.0, |c| c.spread()) }
    }

    /// Residuals per independent one, for BIC ([`bic`]).
    fn dependence(&self) -> f64 {
        self.correlation.as_ref().map_or(1.0, |c| c.dependence())
    }
}

/// What was decided: the finding, the model that stands for it, every candidate and pair.
struct Chosen<'a> {
    finding: Finding,
    fit: &'a WholeFit,
    candidates: Vec<Candidate>,
    shares: Vec<NamedShare>,
    pairs: Vec<PairCandidate>,
}

/// Stage 0: the options checked, and the suspects: where the header gives the camera every
/// model uses it, and the effect that stands in for it is no suspect.
fn suspects(rec: &Recording, opts: &DiagnoseOptions) -> Result<DiagnoseOptions, DiagnoseError> {
    if !(opts.evidence.is_finite() && opts.evidence >= 0.0) {
        return Err(DiagnoseError::Options(format!(
            "evidence {} must be a number >= 0",
            opts.evidence
        )));
    }
    // A camera a tracker fitted from the ring (its scale `scale_free`) is a start, not known:
    // the motion places it better, so the effect that fits it stays a suspect.
    let camera_known = rec.header.camera_distance_mm.is_some()
        && !Camera::for_recording(&rec.header, &rec.frames).scale_free;
    Ok(DiagnoseOptions {
        candidates: opts
            .candidates
            .iter()
            .copied()
            .filter(|&k| !(camera_known && k.in_plan().header_camera))
            .collect(),
        ..opts.clone()
    })
}

/// Stage 1: the paper's model fitted by multiple shooting (`analysis::fit`).
fn baseline_fit(
    run: &Run,
    rec: &Recording,
    fit_opts: &FitOptions,
) -> Result<FitResult, DiagnoseError> {
    let progress = run.progress;
    fit(rec, fit_opts, &|p: &FitProgress| progress.baseline_fit(p), run.cancel).map_err(|e| {
        if e == FitError::Cancelled { DiagnoseError::Cancelled } else { DiagnoseError::Fit(e) }
    })
}

/// Stage 1 without the tracker's glitches: those the tracks show left out of every fit (the
/// noise is measured from the tracks alone), then those the tracks alone let through, found
/// against that fit, and the fit made again without them.
fn baseline_without_glitches(
    run: &Run,
    rec: &Recording,
    fit_opts: &FitOptions,
) -> Result<(CheckedTracks, FitResult), DiagnoseError> {
    let tracks = check_tracks(rec);
    let base = baseline_fit(run, &tracks.recording, fit_opts)?;
    let more = glitches_against(&base, &tracks);
    if more.is_empty() {
        return Ok((tracks, base));
    }
    let tracks = with_more_glitches(&tracks, &more);
    let base = baseline_fit(run, &tracks.recording, fit_opts)?;
    Ok((tracks, base))
}

/// Positions that the multiple-shooting fit `base` predicts far beyond the noise and beyond
/// their neighbours' misfit: a tracker's glitches that the tracks alone did not show
/// ([`find_glitches_against`]).
fn glitches_against(base: &FitResult, tracks: &CheckedTracks) -> Vec<Glitch> {
    let Some(noise) = tracks.noise else { return Vec::new() };
    let frames = &tracks.recording.frames;
    let ms = base.shooting(frames, &crate::analysis::fit::shooting::NEVER_CANCELLED);
    let mut predicted: Vec<Option<[[f64; 2]; MARKS]>> = vec![None; frames.len()];
    for (s, (span, y0)) in ms.segments.iter().zip(&base.segment_states).enumerate() {
        let Some(marks) = ms.predict(&base.model, &base.camera, s, y0) else { continue };
        for (slot, m) in predicted[span.clone()].iter_mut().zip(marks) {
            *slot = Some(m);
        }
    }
    find_glitches_against(frames, &predicted, noise.px, &tracks.glitches)
}

/// Stage 2: the baseline over the whole run (`whole`), from the segments' states.
fn baseline_path(
    ms: &Shooting,
    base: &FitResult,
    progress: &Reporter,
) -> Result<(WholeFit, Vec<Level>), DiagnoseError> {
    let residuals = base.residual_count.max(1) as f64;
    let mut on_baseline = |segments: usize, cost: f64| {
        progress.baseline_path(base.segments.len(), segments, (cost / residuals).sqrt())
    };
    fit_baseline(ms, &base.segment_states, &mut on_baseline).map_err(lm_error)
}

/// One diagnosis's options (its suspects), progress bar and cancel flag (which its fits'
/// problems carry on from the baseline's fit, [`Shooting::cancel`]).
#[derive(Clone, Copy)]
struct Run<'a> {
    opts: &'a DiagnoseOptions,
    progress: &'a Reporter<'a>,
    cancel: &'a AtomicBool,
}

/// What the decision leaves to be described: the baseline, the model chosen, where the
/// baseline departs, the noise and the evidence asked.
struct Decided<'a> {
    baseline: &'a WholeFit,
    chosen: Chosen<'a>,
    departure: &'a Departure,
    noise: &'a Noise,
    evidence: f64,
}

/// Stage 3: where the baseline departs, if it does not follow the whole run, beside every
/// candidate fitted on the baseline's path; then the plan's singles phase (`plan.rs`: each
/// pass only where no fit before it has settled the recording).
fn candidates_and_departure(
    run: &Run,
    again: &Again,
    ms: &Shooting,
    base: &FitResult,
    baseline: WholeFit,
    levels: &[Level],
    noise: &Noise,
) -> Result<(Departure, WholeFit, Fits), DiagnoseError> {
    let Run { opts, progress, .. } = *run;
    let (noise_px, width) = (noise.px, noise.window_frames);
    let follows_whole =
        departure::follows(ms, &baseline, baseline.span.clone(), noise.level(), width);
    let (departure, candidates) = rayon::join(
        || {
            if follows_whole {
                Ok(Departure::none(&baseline))
            } else {
                departure::find(ms, &base.segment_states, noise.level(), width)
            }
        },
        || candidates_stage(ms, baseline.clone(), levels, opts, progress),
    );
    let departure = departure.map_err(lm_error)?;
    let (baseline, fits) = candidates?;
    let mut singles = Singles {
        again,
        ms,
        levels,
        baseline: &baseline,
        fits,
        through_seen: Vec::new(),
        noise_px,
        dependence: noise.dependence(),
        progress,
    };
    plan::run(&mut singles)?;
    let fits = singles.fits;
    Ok((departure, baseline, fits))
}

/// Stage 6: the residuals before and after, the mismatch windows, the signature, the trace:
/// everything the words, the report and the window show.
fn describe(
    tracks: &CheckedTracks,
    base: &FitResult,
    ms: &Shooting,
    decided: Decided,
    stage_seconds: Vec<(&'static str, f64)>,
) -> Result<Diagnosis, DiagnoseError> {
    let rec = &tracks.recording;
    let Decided { baseline, chosen, departure, noise, evidence } = decided;
    let Chosen { finding, fit: chosen, candidates, shares, pairs } = chosen;
    let clock = Clock { first_frame: rec.first_frame, fps: rec.header.fps, dt: base.dt };
    let misfits = Misfits::of(rec, ms, baseline, chosen, departure, noise)?;
    let span = baseline.span.clone();
    let (mismatch, found) = mismatch_windows(
        departure,
        &span,
        (&misfits.sums_followed, &misfits.win_followed),
        (&misfits.sums_before, &misfits.win_before),
        noise.px,
        &|frame| clock.time_s(frame),
    );
    let signature = signature(rec, ms, (baseline, chosen), departure, &misfits, noise.px, &clock);
    let residuals = misfits.series(&span, &clock);
    let trace = Trace {
        t_s: residuals.t_s.clone(),
        data_px: rec.frames[span.clone()].iter().map(centroid).collect(),
        before_px: misfits.pred_before.iter().map(predicted_centroid).collect(),
        after_px: misfits.pred_after.iter().map(predicted_centroid).collect(),
        image_px: image_size(base, rec),
    };
    let n = baseline.residual_count;
    let score = |w: &WholeFit| bic(w.cost, n, w.parameter_count, noise.dependence());
    Ok(Diagnosis {
        finding,
        mismatch,
        windows: found,
        noise_px: noise.px,
        noise_from_marks: noise.from_marks,
        noise_correlation: noise.correlation.clone(),
        glitches: tracks.glitches.clone(),
        before: model_fit(baseline, score(baseline), base, &clock, signature.end_before_s),
        after: model_fit(chosen, score(chosen), base, &clock, signature.end_after_s),
        candidates,
        pairs,
        shares,
        evidence,
        header_body_mm: [rec.header.outer_radius_mm, rec.header.width_mm],
        residuals,
        trace,
        signature,
        explanation: String::new(),
        segments_rms_px: base.rms_px,
        segments: base.segments.len(),
        frames: rec.frames.len(),
        first_frame: rec.first_frame,
        frames_fitted: span.len(),
        fps: rec.header.fps,
        stage_seconds,
        compute_seconds: 0.0,
    })
}

/// The recording's clock: a frame (or model time) in seconds from the film's start.
struct Clock {
    first_frame: u64,
    fps: f64,
    dt: f64,
}

impl Clock {
    fn time_s(&self, frame: f64) -> f64 {
        (self.first_frame as f64 + frame) / self.fps
    }

    fn model_s(&self, t_model: f64) -> f64 {
        self.time_s(t_model / self.dt)
    }
}

/// The misfit of the baseline (before), of the model chosen (after) and of the stretch's fit
/// run on over the whole span (followed): each frame's sums and the residual windows.
struct Misfits {
    pred_before: PredictedMarks,
    pred_after: PredictedMarks,
    sums_before: Vec<(f64, usize)>,
    sums_after: Vec<(f64, usize)>,
    sums_followed: Vec<(f64, usize)>,
    win_before: Vec<Window>,
    win_after: Vec<Window>,
    win_followed: Vec<Window>,
}

impl Misfits {
    fn of(
        rec: &Recording,
        ms: &Shooting,
        baseline: &WholeFit,
        chosen: &WholeFit,
        departure: &Departure,
        noise: &Noise,
    ) -> Result<Misfits, DiagnoseError> {
        let pred_before = baseline.marks(ms).ok_or(DiagnoseError::Baseline)?;
        let pred_after = chosen.marks(ms).ok_or(DiagnoseError::Baseline)?;
        // The stretch's fit run on over the whole span (its own span is the stretch alone).
        let followed_on = WholeFit { span: baseline.span.clone(), ..departure.fit.clone() };
        let pred_followed = followed_on.marks(ms).ok_or(DiagnoseError::Baseline)?;
        let span = baseline.span.clone();
        let sums = |pred: &PredictedMarks| frame_sums(&rec.frames, span.clone(), pred);
        let (sums_before, sums_after) = (sums(&pred_before), sums(&pred_after));
        let sums_followed = sums(&pred_followed);
        let wins = |sums: &[(f64, usize)]| windows(sums, noise.level(), noise.window_frames);
        Ok(Misfits {
            win_before: wins(&sums_before),
            win_after: wins(&sums_after),
            win_followed: wins(&sums_followed),
            pred_before,
            pred_after,
            sums_before,
            sums_after,
            sums_followed,
        })
    }

    /// The residuals as the report and the window plot them, frame by frame and by window.
    fn series(&self, span: &Range<usize>, clock: &Clock) -> ResidualSeries {
        let at = |frame: usize| clock.time_s((span.start + frame) as f64);
        ResidualSeries {
            t_s: span.clone().map(|i| clock.time_s(i as f64)).collect(),
            before_px: frame_rms(&self.sums_before),
            after_px: frame_rms(&self.sums_after),
            window_s: self
                .win_before
                .iter()
                .map(|w| (at(w.frames.start), at(w.frames.end)))
                .collect(),
            window_before_px: self.win_before.iter().map(|w| w.rms_px).collect(),
            window_after_px: self.win_after.iter().map(|w| w.rms_px).collect(),
            window_threshold_px: self.win_before.iter().map(|w| w.threshold_px).collect(),
            followed_px: frame_rms(&self.sums_followed),
            window_followed_px: self.win_followed.iter().map(|w| w.rms_px).collect(),
        }
    }
}

/// The residual's signature ([`measure`]) with the times of the runs' ends, slides and the
/// departure.
fn signature(
    rec: &Recording,
    ms: &Shooting,
    (baseline, chosen): (&WholeFit, &WholeFit),
    departure: &Departure,
    misfits: &Misfits,
    noise_px: f64,
    clock: &Clock,
) -> Signature {
    let span = baseline.span.clone();
    let t_stop = 2.0 * rec.frames.len() as f64 * clock.dt;
    let (end_before, _) = run_end(baseline, ms, t_stop);
    let (end_after, slides) = run_end(chosen, ms, t_stop);
    let mut signature = Signature::from_measured(measure(
        &rec.frames[span.clone()],
        &misfits.sums_before,
        &misfits.pred_before,
        &misfits.pred_after,
        baseline.camera.centre_px,
        noise_px,
    ));
    signature.end_data_s = (span.end < rec.frames.len()).then(|| clock.time_s(span.end as f64));
    signature.end_before_s = end_before.map(|t| clock.model_s(t));
    signature.end_after_s = end_after.map(|t| clock.model_s(t));
    signature.slides_s =
        slides.into_iter().map(|(a, b)| (clock.model_s(a), clock.model_s(b))).collect();
    signature.departure_s = departure.departs.then(|| clock.time_s(departure.followed.end as f64));
    signature.followed_share = departure.followed.len() as f64 / span.len().max(1) as f64;
    signature
}

/// A fitted model as the diagnosis reports it (`score`: its BIC; `end_s`: where its run ends).
fn model_fit(
    w: &WholeFit,
    score: f64,
    base: &FitResult,
    clock: &Clock,
    end_s: Option<f64>,
) -> ModelFit {
    ModelFit {
        effect: w.kind,
        rms_px: w.rms_px(),
        cost: w.cost,
        residual_count: w.residual_count,
        parameter_count: w.parameter_count,
        score,
        c: w.c,
        c_sigma: w.c_sigma,
        strength: w.strength,
        extras: w.extras.clone(),
        tilt_deg: named_extras(&w.extras).tilt_deg,
        rim_share: named_extras(&w.extras).rim_share,
        also: w.also.clone(),
        body_mm: w.body.map(|(v, s)| (v * base.units.length_mm, s * base.units.length_mm)),
        start: Initial::from_state(&w.start),
        start_s: clock.time_s(w.span.start as f64),
        model: w.model.clone(),
        camera: w.camera,
        units: base.units,
        end_s,
    }
}

/// The mismatch (from the departure to the last departing window of the baseline fitted up to
/// it: `sums`, `wins`) and the departing windows after the departure, in seconds; each with
/// the whole-run baseline's RMS inside it (`before`).
fn mismatch_windows(
    departure: &Departure,
    span: &Range<usize>,
    (sums, wins): (&[(f64, usize)], &[Window]),
    (before, wins_before): (&[(f64, usize)], &[Window]),
    noise_px: f64,
    time_s: &dyn Fn(f64) -> f64,
) -> (Option<MismatchWindow>, Vec<MismatchWindow>) {
    if !departure.departs {
        return (None, Vec::new());
    }
    let from = departure.followed.end - span.start;
    let var = noise_px * noise_px;
    let excess_in = |r: &Range<usize>| {
        sums[r.clone()].iter().map(|x| x.0 - var * x.1 as f64).sum::<f64>().max(0.0)
    };
    let total = excess_in(&(from..sums.len()));
    let stats = |r: &Range<usize>| {
        let (s, c) = before[r.clone()].iter().fold((0.0, 0usize), |a, x| (a.0 + x.0, a.1 + x.1));
        (
            if c > 0 { (s / c as f64).sqrt() } else { f64::NAN },
            if total > 0.0 { (excess_in(r) / total).min(1.0) } else { 0.0 },
        )
    };
    let window = |r: Range<usize>| {
        let (rms_px, share) = stats(&r);
        MismatchWindow {
            start_s: time_s((span.start + r.start) as f64),
            end_s: time_s((span.start + r.end) as f64),
            rms_px,
            share,
        }
    };
    let found: Vec<Range<usize>> = departures(wins)
        .into_iter()
        .map(|(r, _)| r.start.max(from)..r.end)
        .filter(|r| r.end > r.start)
        .collect();
    // The mismatch runs on to the last window where the stretch's fit or the whole-run baseline
    // departs: where the departure is at the very start, the stretch's fit knows only the first
    // frames and can stop departing where a fit to so little happens to pass by the data.
    let last_before = departures(wins_before).last().map(|(r, _)| r.end);
    let end = found
        .last()
        .map(|r| r.end)
        .into_iter()
        .chain(last_before)
        .max()
        .unwrap_or(before.len())
        .max(from + 1)
        .min(sums.len().min(before.len()));
    (Some(window(from..end)), found.into_iter().map(window).collect())
}

/// The candidates along the baseline's path, with progress.
fn candidates_stage(
    ms: &Shooting,
    baseline: WholeFit,
    levels: &[super::whole::Level],
    opts: &DiagnoseOptions,
    progress: &Reporter,
) -> Result<(WholeFit, Vec<(EffectKind, Result<WholeFit, LmError>)>), DiagnoseError> {
    let kinds: Vec<EffectKind> =
        opts.candidates.iter().copied().filter(|&k| !k.is_baseline()).collect();
    let residuals = baseline.residual_count.max(1) as f64;
    let on_level = |k: EffectKind, segments: usize, cost: f64| {
        progress.candidate_level(k, segments, (cost / residuals).sqrt(), kinds.len())
    };
    let on_done = |k: EffectKind| progress.candidate_done(k, kinds.len());
    fit_candidates(ms, baseline, levels, &kinds, &on_level, &on_done).map_err(lm_error)
}

/// Point A of a frame: the centroid of its marks when all four are tracked.
fn centroid(f: &FrameMarks) -> Option<[f64; 2]> {
    let mut s = [0.0; 2];
    for m in f {
        let m = (*m)?;
        s[0] += m[0] / 4.0;
        s[1] += m[1] / 4.0;
    }
    Some(s)
}

fn predicted_centroid(p: &[[f64; 2]; 4]) -> [f64; 2] {
    [p.iter().map(|m| m[0]).sum::<f64>() / 4.0, p.iter().map(|m| m[1]).sum::<f64>() / 4.0]
}

fn image_size(base: &FitResult, rec: &Recording) -> [f64; 2] {
    match (rec.header.image_width_px, rec.header.image_height_px) {
        (Some(w), Some(h)) => [w, h],
        _ => [2.0 * base.camera.centre_px[0], 2.0 * base.camera.centre_px[1]],
    }
}
