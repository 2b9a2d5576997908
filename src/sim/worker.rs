//! The integrator thread and its two channels: commands in (unbounded, rare), events out
//! (bounded: the back-pressure that keeps the worker a fixed number of states ahead of the
//! display). Where no thread can be had (a web page: wasm32 has one thread) the same runs are
//! integrated in slices on the caller's thread instead, as far as each frame needs and within a
//! time budget, so the frame stays on time (`Inline`).

pub use super::event::{Event, RunEnd};
use super::track::Track;
use crate::config::Case;
use crate::physics::{Sample, Simulation, StateVec};
use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{
    self, Receiver, RecvTimeoutError, Sender, SyncSender, TryRecvError, TrySendError,
};
use std::thread::JoinHandle;
use std::time::Duration;
use thiserror::Error;

/// Events the channel holds before the worker waits: about 50 model time units of the paper
/// ring at its output spacing, i.e. 2.4 s of motion, 0.12 s of display at 20x.
pub const CHANNEL_CAPACITY: usize = 1024;
/// How long the worker waits for a command while the channel is full before trying again.
const FULL_WAIT: Duration = Duration::from_millis(1);
/// Output samples integrated per slice between looks at the command channel.
const SLICE_SAMPLES: f64 = 16.0;
/// The longest one `pump` integrates in place (no thread): a frame at 60 Hz has 16.7 ms, and
/// the window pumps twice a frame.
const INLINE_BUDGET: Duration = Duration::from_millis(5);

/// Where a run starts.
#[derive(Clone, Debug, PartialEq)]
pub enum Start {
    /// The case's initial state at t = 0.
    Initial,
    /// A state reached earlier (to continue with changed drag).
    From { t: f64, y: StateVec },
}

enum Command {
    Run { run: u64, case: Box<Case>, start: Start },
}

#[derive(Debug, Error)]
pub enum SimError {
    #[error("cannot start the integrator thread: {0}")]
    Spawn(#[from] std::io::Error),
}

/// The runs integrated on the caller's thread where there is no integrator thread.
#[derive(Default)]
struct Inline {
    current: Option<Running>,
    pending: VecDeque<Event>,
}

/// The UI's end of one integrator thread (or of the runs integrated in place), with the track
/// of what it has received.
pub struct SimHandle {
    inline: Option<Inline>,
    commands: Option<Sender<Command>>,
    events: Option<Receiver<Event>>,
    thread: Option<JoinHandle<()>>,
    run: u64,
    /// Events the worker has put into the channel, and those taken out here.
    sent: Arc<AtomicU64>,
    taken: u64,
    pub track: Track,
    /// The track of the run before a restart, shown until the new run's first state arrives
    /// (so that the view does not go blank for a frame).
    previous: Option<Track>,
}

impl SimHandle {
    /// Starts the thread and a run of `case` from its initial state.
    pub fn spawn(case: Case) -> Result<SimHandle, SimError> {
        let (cmd_tx, cmd_rx) = mpsc::channel();
        let (ev_tx, ev_rx) = mpsc::sync_channel(CHANNEL_CAPACITY);
        let sent = Arc::new(AtomicU64::new(0));
        let counter = sent.clone();
        let thread = std::thread::Builder::new()
            .name("ringlab-integrator".into())
            .spawn(move || worker(cmd_rx, ev_tx, &counter))?;
        let mut handle = SimHandle {
            inline: None,
            commands: Some(cmd_tx),
            events: Some(ev_rx),
            thread: Some(thread),
            run: 0,
            sent,
            taken: 0,
            track: Track::new(0, case.clone()),
            previous: None,
        };
        handle.start(case, Start::Initial);
        Ok(handle)
    }

    /// A run of `case` integrated on this thread, in slices as [`SimHandle::pump`] needs them
    /// (where no thread can be had: a web page).
    pub fn in_place(case: Case) -> SimHandle {
        let mut handle = SimHandle {
            inline: Some(Inline::default()),
            commands: None,
            events: None,
            thread: None,
            run: 0,
            sent: Arc::new(AtomicU64::new(0)),
            taken: 0,
            track: Track::new(0, case.clone()),
            previous: None,
        };
        handle.start(case, Start::Initial);
        handle
    }

    /// The integrator thread, or where none can be had, the run in place.
    pub fn spawn_or_in_place(case: Case) -> SimHandle {
        if cfg!(target_arch = "wasm32") {
            return SimHandle::in_place(case);
        }
        SimHandle::spawn(case.clone()).unwrap_or_else(|_| SimHandle::in_place(case))
    }

    /// Whether the runs are integrated on the caller's thread.
    pub fn is_in_place(&self) -> bool {
        self.inline.is_some()
    }

    /// The number of the newest run asked for.
    pub fn run(&self) -> u64 {
        self.run
    }

    /// Replaces the current run by a new one of `case` from its initial state.
    pub fn restart(&mut self, case: Case) {
        self.start(case, Start::Initial);
    }

    /// Continues from the last received state at or before `t` with `case` (its drag and
    /// friction; the state carries on). Falls back to a restart when nothing was received yet.
    pub fn continue_from(&mut self, case: Case, t: f64) {
        match self.track.sample_at_or_before(t).copied() {
            Some(s) if self.track.case().model.body == case.model.body => {
                self.track.continue_with(self.run + 1, case.clone(), s.t);
                self.send(case, Start::From { t: s.t, y: s.y });
            }
            _ => self.restart(case),
        }
    }

    fn start(&mut self, case: Case, start: Start) {
        let run = self.run + 1;
        let old = std::mem::replace(&mut self.track, Track::new(run, case.clone()));
        if !old.samples().is_empty() {
            self.previous = Some(old);
        }
        // The first state of a fresh run is the initial state itself: shown at once, in the
        // frame of the change, without waiting for the worker (its copy is then skipped).
        if start == Start::Initial && case.initial.validate().is_ok() {
            let first = Sample::new(&case.model, 0.0, &case.initial.to_state());
            self.track.apply(Event::Started { run, start: first });
            self.track.apply(Event::State { run, sample: first });
        }
        self.send(case, start);
    }

    /// The track to show: the current run's, or until it has a state, the one before it.
    pub fn shown(&self) -> &Track {
        match &self.previous {
            Some(p) if self.track.samples().is_empty() => p,
            _ => &self.track,
        }
    }

    fn send(&mut self, case: Case, start: Start) {
        self.run += 1;
        if let Some(inline) = &mut self.inline {
            let cmd = Command::Run { run: self.run, case: Box::new(case), start };
            start_run(cmd, &mut inline.current, &mut inline.pending);
            return;
        }
        if let Some(tx) = &self.commands {
            // A send fails only when the worker has gone (it panicked); the track then stays
            // empty and the UI shows that nothing arrives.
            let _ = tx.send(Command::Run { run: self.run, case: Box::new(case), start });
        }
    }

    /// Takes events from the channel without waiting: all that are there, but states only
    /// while the track holds none at or beyond `until` (so the worker stays a channel's
    /// length ahead instead of running to the end at once). Returns how many were taken.
    pub fn pump(&mut self, until: f64) -> usize {
        if !self.track.samples().is_empty() {
            self.previous = None;
        }
        if self.inline.is_some() {
            return self.pump_in_place(until);
        }
        let Some(rx) = &self.events else { return 0 };
        let mut taken = 0;
        while self.track.last_time().is_none_or(|t| t < until) && !self.track.is_finished() {
            match rx.try_recv() {
                Ok(ev) => {
                    taken += 1;
                    self.taken += 1;
                    if ev.run() == self.run {
                        self.track.apply(ev);
                    }
                }
                Err(TryRecvError::Empty | TryRecvError::Disconnected) => break,
            }
        }
        taken
    }

    /// [`SimHandle::pump`] without a thread: integrates slices here until the track reaches
    /// `until`, the run ends, or the frame's budget is spent.
    fn pump_in_place(&mut self, until: f64) -> usize {
        let Some(inline) = &mut self.inline else { return 0 };
        let clock = web_time::Instant::now();
        let mut taken = 0;
        while self.track.last_time().is_none_or(|t| t < until) && !self.track.is_finished() {
            let Some(ev) = inline.pending.pop_front() else {
                if clock.elapsed() > INLINE_BUDGET
                    || !produce_or_end(&mut inline.current, &mut inline.pending)
                {
                    break;
                }
                continue;
            };
            taken += 1;
            self.taken += 1;
            if ev.run() == self.run {
                self.track.apply(ev);
            }
        }
        taken
    }

    /// Events the worker has sent and the UI has not taken yet: never more than the channel
    /// holds ([`CHANNEL_CAPACITY`]).
    pub fn in_flight(&self) -> u64 {
        self.sent.load(Ordering::Acquire).saturating_sub(self.taken)
    }

    /// Events taken from the channel so far.
    pub fn taken(&self) -> u64 {
        self.taken
    }

    /// Whether the worker thread is still alive (a run in place always is).
    pub fn is_alive(&self) -> bool {
        self.inline.is_some() || self.thread.as_ref().is_some_and(|t| !t.is_finished())
    }
}

impl Drop for SimHandle {
    fn drop(&mut self) {
        // Closing both channels ends the worker within one wait.
        self.commands = None;
        self.events = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// A run in progress on the worker.
struct Running {
    run: u64,
    sim: Simulation,
    dt: f64,
    turns_sent: usize,
}

impl Running {
    fn new(run: u64, case: Case, start: Start) -> Result<(Running, Sample), String> {
        let opts = case.opts.clone();
        let dt = opts.sample_dt.unwrap_or(case.dt);
        let sim = match start {
            Start::Initial => Simulation::new(case.model, &case.initial, opts),
            Start::From { t, y } => {
                // A slide in progress belongs to the run's start, not to a state it reached.
                let mut model = case.model;
                model.effects.slip_start_velocity = [0.0, 0.0];
                Simulation::from_state(model, t, y, opts)
            }
        }
        .map_err(|e| e.to_string())?;
        let first = *sim.final_sample();
        // A start at a turning point is recorded as one; it was sent with the earlier run
        // when continuing, so only a fresh start reports it.
        Ok((Running { run, turns_sent: 0, dt, sim }, first))
    }

    /// Integrates one slice and queues its events in time order. Returns true once ended.
    fn produce(&mut self, out: &mut VecDeque<Event>) -> bool {
        let t_stop = self.sim.t() + SLICE_SAMPLES * self.dt;
        let mut states = Vec::new();
        let ended = self.sim.advance(t_stop, &mut |s: &Sample| states.push(*s));
        let turns = &self.sim.turning_points()[self.turns_sent..];
        let mut k = 0;
        for s in states {
            while k < turns.len() && turns[k].sample.t <= s.t {
                out.push_back(Event::Turn { run: self.run, point: turns[k] });
                k += 1;
            }
            out.push_back(Event::State { run: self.run, sample: s });
        }
        for p in &turns[k..] {
            out.push_back(Event::Turn { run: self.run, point: *p });
        }
        self.turns_sent = self.sim.turning_points().len();
        ended.is_some()
    }
}

fn worker(commands: Receiver<Command>, events: SyncSender<Event>, sent: &AtomicU64) {
    let mut current: Option<Running> = None;
    let mut pending: VecDeque<Event> = VecDeque::new();
    loop {
        let idle = current.is_none() && pending.is_empty();
        let cmd = if idle {
            match commands.recv() {
                Ok(c) => Some(c),
                Err(_) => return,
            }
        } else {
            match commands.try_recv() {
                Ok(c) => Some(c),
                Err(TryRecvError::Empty) => None,
                Err(TryRecvError::Disconnected) => return,
            }
        };
        if let Some(cmd) = cmd {
            start_run(cmd, &mut current, &mut pending);
            continue;
        }

        // Hand over what is queued; a full channel means the display is far enough behind.
        while let Some(ev) = pending.pop_front() {
            match events.try_send(ev) {
                Ok(()) => {
                    sent.fetch_add(1, Ordering::Release);
                }
                Err(TrySendError::Full(ev)) => {
                    pending.push_front(ev);
                    break;
                }
                Err(TrySendError::Disconnected(_)) => return,
            }
        }
        if !pending.is_empty() {
            match commands.recv_timeout(FULL_WAIT) {
                Ok(cmd) => start_run(cmd, &mut current, &mut pending),
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => return,
            }
            continue;
        }

        produce_or_end(&mut current, &mut pending);
    }
}

/// Integrates one slice of the current run into `pending`, and once it ends, its summary.
/// False where there was no run to integrate.
fn produce_or_end(current: &mut Option<Running>, pending: &mut VecDeque<Event>) -> bool {
    let Some(r) = current else { return false };
    if r.produce(pending)
        && let Some(r) = current.take()
    {
        let run = r.run;
        let summary = r.sim.finish();
        let end = RunEnd {
            reason: summary.end_reason,
            t_end: summary.t_end,
            lift_off: summary.lift_off,
            slip: summary.slip,
        };
        pending.push_back(Event::Ended { run, end });
    }
    true
}

fn start_run(cmd: Command, current: &mut Option<Running>, pending: &mut VecDeque<Event>) {
    let Command::Run { run, case, start } = cmd;
    // Whatever the old run still had queued is of no use now.
    pending.clear();
    let fresh = start == Start::Initial;
    match Running::new(run, *case, start) {
        Ok((mut r, first)) => {
            pending.push_back(Event::Started { run, start: first });
            if fresh {
                for p in r.sim.turning_points() {
                    pending.push_back(Event::Turn { run, point: *p });
                }
            }
            r.turns_sent = r.sim.turning_points().len();
            *current = Some(r);
        }
        Err(message) => {
            pending.push_back(Event::Failed { run, message });
            *current = None;
        }
    }
}
