//! The playback clock. It counts seconds of the real motion (a case in model units converts
//! with its time unit), so that two runs side by side share one clock whatever their units.

/// Slowest and fastest playback, times real time.
pub const SPEED_MIN: f64 = 0.05;
pub const SPEED_MAX: f64 = 20.0;

#[derive(Clone, Debug, PartialEq)]
pub struct Player {
    /// Seconds since the start of the motion.
    seconds: f64,
    playing: bool,
    speed: f64,
}

impl Default for Player {
    fn default() -> Self {
        Player { seconds: 0.0, playing: true, speed: 1.0 }
    }
}

impl Player {
    pub fn seconds(&self) -> f64 {
        self.seconds
    }
    pub fn is_playing(&self) -> bool {
        self.playing
    }
    pub fn speed(&self) -> f64 {
        self.speed
    }

    pub fn play(&mut self) {
        self.playing = true;
    }
    pub fn pause(&mut self) {
        self.playing = false;
    }
    pub fn toggle(&mut self) {
        self.playing = !self.playing;
    }

    /// Sets the speed, kept within [`SPEED_MIN`, `SPEED_MAX`] (a non-number leaves it).
    pub fn set_speed(&mut self, speed: f64) {
        if !speed.is_nan() {
            self.speed = speed.clamp(SPEED_MIN, SPEED_MAX);
        }
    }

    /// Moves to `seconds` (not before the start).
    pub fn seek(&mut self, seconds: f64) {
        if seconds.is_finite() {
            self.seconds = seconds.max(0.0);
        }
    }

    /// Back to the start, playing.
    pub fn reset(&mut self) {
        self.seconds = 0.0;
        self.playing = true;
    }

    /// Pauses and moves on by one step (one output interval of the run, in seconds).
    pub fn step(&mut self, step_seconds: f64, end: Option<f64>) {
        self.playing = false;
        let t = self.seconds + step_seconds.max(0.0);
        self.seconds = end.map_or(t, |e| t.min(e));
    }

    /// Advances by `wall_seconds` of wall-clock time at the set speed while playing, but not
    /// past `available` (the newest state received: the clock waits for the integrator there)
    /// and not past `end` (where the run is over: playback pauses).
    pub fn advance(&mut self, wall_seconds: f64, available: f64, end: Option<f64>) {
        if !self.playing || !(wall_seconds > 0.0) {
            return;
        }
        let target = self.seconds + wall_seconds * self.speed;
        if let Some(e) = end
            && target >= e
        {
            self.seconds = self.seconds.max(e);
            self.playing = false;
            return;
        }
        self.seconds = self.seconds.max(target.min(available));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_moves_at_the_set_speed_and_waits_for_states() {
        let mut p = Player::default();
        p.set_speed(2.0);
        p.advance(0.5, 10.0, None);
        assert_eq!(p.seconds(), 1.0);
        // Only 1.2 s computed so far: the clock waits there.
        p.advance(0.5, 1.2, None);
        assert_eq!(p.seconds(), 1.2);
        p.pause();
        p.advance(1.0, 10.0, None);
        assert_eq!(p.seconds(), 1.2);
    }

    #[test]
    fn speed_is_clamped_and_the_end_pauses() {
        let mut p = Player::default();
        p.set_speed(100.0);
        assert_eq!(p.speed(), SPEED_MAX);
        p.set_speed(0.0);
        assert_eq!(p.speed(), SPEED_MIN);
        p.set_speed(20.0);
        p.advance(1.0, 100.0, Some(5.0));
        assert_eq!(p.seconds(), 5.0);
        assert!(!p.is_playing());
    }

    #[test]
    fn step_pauses_and_seek_stays_at_or_after_the_start() {
        let mut p = Player::default();
        p.step(0.25, None);
        assert!(!p.is_playing());
        assert_eq!(p.seconds(), 0.25);
        p.step(1.0, Some(1.0));
        assert_eq!(p.seconds(), 1.0);
        p.seek(-3.0);
        assert_eq!(p.seconds(), 0.0);
        p.seek(f64::NAN);
        assert_eq!(p.seconds(), 0.0);
    }
}
