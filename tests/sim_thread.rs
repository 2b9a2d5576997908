//! The integrator thread as the UI sees it: states in order and complete, a bounded channel
//! that holds the worker back, restarts and continuations, failures reported not panicked.
//! These tests wait for the thread (with a generous deadline against hangs) but assert only
//! what arrived, never how fast.

use ringlab::config::{Case, load_preset};
use ringlab::physics::EndReason;
use ringlab::sim::{CHANNEL_CAPACITY, SimHandle, Track};
use std::time::{Duration, Instant};

fn case(name: &str) -> Case {
    let f = load_preset(name).expect("preset loads");
    f.build().expect("preset builds")
}

/// Pumps until `done` holds, failing after a minute (a hang, not slowness).
fn pump_until(h: &mut SimHandle, until: f64, done: impl Fn(&SimHandle) -> bool) {
    let deadline = Instant::now() + Duration::from_secs(60);
    while !done(h) {
        h.pump(until);
        assert!(Instant::now() < deadline, "the integrator thread stopped delivering");
        std::thread::yield_now();
    }
}

fn assert_on_grid(track: &Track, dt: f64) {
    let s = track.samples();
    for (k, w) in s.windows(2).enumerate() {
        assert!(w[1].t > w[0].t, "state {k} out of order");
    }
    // Every output time k dt, none missing (the last state is the end point).
    for (k, x) in s[..s.len() - 1].iter().enumerate() {
        assert!((x.t - k as f64 * dt).abs() < 1e-9, "state {k} at t = {} (a gap)", x.t);
    }
}

#[test]
fn states_arrive_in_order_without_gaps_and_match_a_run_in_one_go() {
    let c = case("paper-ring");
    let dt = c.dt;
    let mut h = SimHandle::spawn(c.clone()).expect("thread starts");
    pump_until(&mut h, f64::INFINITY, |h| h.track.is_finished());
    let end = h.track.end().expect("ended").clone();
    assert_eq!(end.reason, EndReason::Flat);
    assert_on_grid(&h.track, dt);

    let reference = Track::compute(c);
    assert_eq!(
        h.track.samples(),
        reference.samples(),
        "the thread computes what a run in one go computes"
    );
    assert_eq!(h.track.turning_points().len(), reference.turning_points().len());
    assert_eq!(h.track.analysis(), reference.analysis());
    assert!(h.track.inflection_time().is_some());
}

#[test]
fn the_channel_is_bounded_and_the_worker_waits_for_the_display() {
    let c = case("paper-ring");
    let total_states = Track::compute(c.clone()).samples().len();
    assert!(total_states > 2 * CHANNEL_CAPACITY, "the run is longer than the channel");
    let mut h = SimHandle::spawn(c).expect("thread starts");
    // Take nothing; let the worker fill the channel until it stops sending.
    let deadline = Instant::now() + Duration::from_secs(60);
    let mut last = u64::MAX;
    loop {
        std::thread::sleep(Duration::from_millis(50));
        let now = h.in_flight();
        if now == last && now > 0 {
            break;
        }
        last = now;
        assert!(Instant::now() < deadline, "the worker never settled");
    }
    assert!(h.in_flight() <= CHANNEL_CAPACITY as u64, "{} events in flight", h.in_flight());
    // Only the initial state, which the handle knows without the worker.
    assert_eq!(h.track.samples().len(), 1);

    // The display asks for the first 5 time units only: the track stops there (plus the one
    // state beyond), the rest waits in the channel.
    pump_until(&mut h, 5.0, |h| h.track.last_time().is_some_and(|t| t >= 5.0));
    assert!(h.track.last_time().is_some_and(|t| t < 5.0 + 0.051));
    assert!(!h.track.is_finished());
    assert!(h.in_flight() <= CHANNEL_CAPACITY as u64);

    pump_until(&mut h, f64::INFINITY, |h| h.track.is_finished());
    assert_eq!(h.track.samples().len(), total_states);
}

#[test]
fn restart_replaces_the_run_and_drops_its_stale_states() {
    let ring = case("paper-ring");
    let disk = case("paper-disk-drag");
    let mut h = SimHandle::spawn(ring).expect("thread starts");
    pump_until(&mut h, 10.0, |h| h.track.last_time().is_some_and(|t| t >= 10.0));
    let first_run = h.run();
    h.restart(disk.clone());
    assert_eq!(h.run(), first_run + 1);
    assert_eq!(h.track.samples().len(), 1, "the new run starts from its initial state alone");
    assert_eq!(h.track.samples()[0].t, 0.0);
    pump_until(&mut h, f64::INFINITY, |h| h.track.is_finished());
    assert_eq!(h.track.run(), first_run + 1);
    let reference = Track::compute(disk);
    assert_eq!(h.track.samples(), reference.samples(), "nothing of the old run is left");
    assert!(h.track.inflection_time().is_none(), "the disk-like drag makes no retrograde turn");
}

#[test]
fn continuing_keeps_the_past_and_changes_the_drag_from_then_on() {
    let ring = case("paper-ring");
    let dt = ring.dt;
    let mut disk_drag = ring.clone();
    disk_drag.model = case("paper-disk-drag").model;
    let mut h = SimHandle::spawn(ring.clone()).expect("thread starts");
    pump_until(&mut h, 30.0, |h| h.track.last_time().is_some_and(|t| t >= 30.0));
    h.continue_from(disk_drag, 30.0);
    pump_until(&mut h, f64::INFINITY, |h| h.track.is_finished());

    let ring_only = Track::compute(ring);
    let before = h.track.samples_until(29.0);
    assert_eq!(before, ring_only.samples_until(29.0), "the past is kept as it was");
    assert_on_grid(&h.track, dt);
    let after = h.track.state_at(40.0).expect("state").sample;
    let ring_after = ring_only.state_at(40.0).expect("state").sample;
    assert!(
        (after.y[3] - ring_after.y[3]).abs() + (after.y[5] - ring_after.y[5]).abs() > 1e-6,
        "the new drag acts"
    );
    // Turning points of the past are kept; the analysis continues from the original start.
    assert!(h.track.turning_points().iter().filter(|p| p.sample.t <= 30.0).count() >= 10);
    assert_eq!(h.track.start().map(|s| s.t), Some(0.0));
}

#[test]
fn a_run_that_cannot_start_reports_why_and_the_thread_lives_on() {
    let mut bad = case("paper-ring");
    bad.initial.theta = f64::NAN;
    let mut h = SimHandle::spawn(bad).expect("thread starts");
    pump_until(&mut h, f64::INFINITY, |h| h.track.is_finished());
    assert!(h.track.failed().is_some_and(|m| m.contains("theta")), "{:?}", h.track.failed());
    assert!(h.is_alive());
    h.restart(case("paper-ring"));
    pump_until(&mut h, 1.0, |h| h.track.last_time().is_some_and(|t| t >= 1.0));
    assert!(h.track.failed().is_none());
}

#[test]
fn a_run_in_place_goes_only_as_far_as_asked_and_matches_the_thread() {
    // A web page has no thread: the same run integrated in slices on the caller's thread.
    let c = case("paper-ring");
    let mut h = SimHandle::in_place(c.clone());
    assert!(h.is_in_place() && h.is_alive());
    pump_until(&mut h, 20.0, |h| h.track.last_time().is_some_and(|t| t >= 20.0));
    let reached = h.track.last_time().expect("states");
    assert!(reached < 40.0, "asked for t = 20, integrated to {reached}");
    assert_eq!(h.in_flight(), 0);
    pump_until(&mut h, f64::INFINITY, |h| h.track.is_finished());
    assert_eq!(h.track.end().expect("ended").reason, EndReason::Flat);
    assert_on_grid(&h.track, c.dt);
    let reference = Track::compute(c);
    assert_eq!(h.track.samples(), reference.samples());
    assert_eq!(h.track.turning_points().len(), reference.turning_points().len());
}
