//! A frame's background registered against a reference frame's: the rigid motion of the image
//! (a shift and a turn about the image's centre) that carries the reference's table onto the
//! frame's, found coarse to fine on box-downsampled luma by Gauss-Newton on the brightness
//! (Lucas-Kanade, the reference's gradients standing for the frame's, as the inverse
//! compositional form does), with a gain and an offset for a light that changes (flicker),
//! Huber weights for what the masks miss (a shadow, the blur), and the ring's discs masked out
//! in both frames.

use super::frame::Frame;

/// The camera's pose in one frame: a point of the table at `p` in the reference frame is seen
/// at `R(turn) (p - c) + c + shift`, `c` the image's centre.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct CameraPose {
    pub shift_px: [f64; 2],
    pub turn_rad: f64,
}

impl CameraPose {
    /// Where a point of the table (reference frame) is seen in this frame.
    pub fn to_image(&self, p: [f64; 2], centre: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.turn_rad.sin_cos();
        let (dx, dy) = (p[0] - centre[0], p[1] - centre[1]);
        [
            c * dx - s * dy + centre[0] + self.shift_px[0],
            s * dx + c * dy + centre[1] + self.shift_px[1],
        ]
    }

    /// Where a point seen in this frame lies on the table (the reference frame).
    pub fn to_table(&self, p: [f64; 2], centre: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.turn_rad.sin_cos();
        let (dx, dy) = (p[0] - centre[0] - self.shift_px[0], p[1] - centre[1] - self.shift_px[1]);
        [c * dx + s * dy + centre[0], -s * dx + c * dy + centre[1]]
    }

    /// How far this pose moves a point `reach` px from the image's centre at most (px).
    pub fn displacement(&self, reach: f64) -> f64 {
        self.shift_px[0].hypot(self.shift_px[1]) + self.turn_rad.abs() * reach
    }
}

/// A disc of the image left out of the registration (the ring, its shadow), in luma pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disc {
    pub centre: [f64; 2],
    pub radius: f64,
}

/// The box factor of the finest level registered (luma pixels per sample).
const FINEST_FACTOR: usize = 4;
/// Levels, each half the one before: the coarsest carries a jump of a few of the finest's
/// samples between frames.
const LEVELS: usize = 3;
/// Gauss-Newton steps at most per level, and the step (in samples at the image's edge) below
/// which a level has converged.
const MAX_STEPS: usize = 8;
const CONVERGED: f64 = 0.005;
/// The share of each gradient's samples kept (the strongest): the rest carry little of the
/// motion for their cost.
const KEPT_SHARE: f64 = 0.3;
/// Huber's threshold in the residuals' robust spread.
const HUBER: f64 = 2.0;
/// A registration holds only where at least this share of the kept samples was used and the
/// table's brightness is seen at least this much of the reference's contrast.
const MIN_USED_SHARE: f64 = 0.3;
const MIN_GAIN: f64 = 0.3;

/// One level: box means of `factor x factor` luma pixels; sample `(u, v)` sits at luma
/// `(factor u + (factor - 1) / 2, ...)`.
#[derive(Clone, Debug, Default)]
pub struct Level {
    width: usize,
    height: usize,
    factor: f64,
    data: Vec<f32>,
}

impl Level {
    fn at(&self, u: usize, v: usize) -> f32 {
        self.data[v * self.width + u]
    }

    fn bilinear(&self, u: f64, v: f64) -> Option<f64> {
        let (u0, v0) = (u.floor(), v.floor());
        if !(u0 >= 0.0
            && v0 >= 0.0
            && u0 + 1.0 < self.width as f64
            && v0 + 1.0 < self.height as f64)
        {
            return None;
        }
        let (fu, fv) = ((u - u0) as f32, (v - v0) as f32);
        let i = v0 as usize * self.width + u0 as usize;
        let d = &self.data;
        let top = d[i] + fu * (d[i + 1] - d[i]);
        let bottom = d[i + self.width] + fu * (d[i + self.width + 1] - d[i + self.width]);
        Some((top + fv * (bottom - top)) as f64)
    }

    /// A luma point in this level's samples.
    fn sample_of_luma(&self, p: [f64; 2]) -> [f64; 2] {
        let o = (self.factor - 1.0) / 2.0;
        [(p[0] - o) / self.factor, (p[1] - o) / self.factor]
    }

    fn box_of_luma(frame: &Frame, factor: usize) -> Level {
        let (w, h) = (frame.width / factor, frame.height / factor);
        let mut data = vec![0f32; w * h];
        let mut row = vec![0u32; w];
        let scale = 1.0 / (factor * factor) as f32;
        for v in 0..h {
            row.iter_mut().for_each(|r| *r = 0);
            for y in v * factor..(v + 1) * factor {
                let line = &frame.luma[y * frame.width..y * frame.width + w * factor];
                for (u, r) in row.iter_mut().enumerate() {
                    *r += line[u * factor..(u + 1) * factor].iter().map(|&p| p as u32).sum::<u32>();
                }
            }
            for (u, r) in row.iter().enumerate() {
                data[v * w + u] = *r as f32 * scale;
            }
        }
        Level { width: w, height: h, factor: factor as f64, data }
    }

    fn halved(&self) -> Level {
        let (w, h) = (self.width / 2, self.height / 2);
        let mut data = vec![0f32; w * h];
        for v in 0..h {
            for u in 0..w {
                let s = self.at(2 * u, 2 * v)
                    + self.at(2 * u + 1, 2 * v)
                    + self.at(2 * u, 2 * v + 1)
                    + self.at(2 * u + 1, 2 * v + 1);
                data[v * w + u] = s / 4.0;
            }
        }
        Level { width: w, height: h, factor: 2.0 * self.factor, data }
    }
}

/// A frame's levels, finest first.
#[derive(Clone, Debug, Default)]
pub struct Pyramid {
    levels: Vec<Level>,
}

impl Pyramid {
    /// `None` where the frame is too small to register.
    pub fn of(frame: &Frame) -> Option<Pyramid> {
        let coarsest = FINEST_FACTOR << (LEVELS - 1);
        if frame.width < 16 * coarsest || frame.height < 16 * coarsest {
            return None;
        }
        let mut levels = vec![Level::box_of_luma(frame, FINEST_FACTOR)];
        for _ in 1..LEVELS {
            let next = levels[levels.len() - 1].halved();
            levels.push(next);
        }
        Some(Pyramid { levels })
    }
}

/// A reference sample kept: where it is, its brightness and gradient.
#[derive(Clone, Copy, Debug)]
struct Sample {
    u: f32,
    v: f32,
    value: f32,
    du: f32,
    dv: f32,
}

/// The reference's samples of strong gradient, per level.
#[derive(Clone, Debug)]
pub struct Reference {
    samples: Vec<Vec<Sample>>,
    /// The image's centre in luma pixels.
    centre: [f64; 2],
    /// The farthest a sample lies from the centre (luma px).
    reach: f64,
}

/// The camera's pose found in one frame, with its standard errors from the residuals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Registration {
    pub pose: CameraPose,
    /// The standard error of the displacement at the image's corners (luma px).
    pub sigma_px: f64,
}

impl Reference {
    /// The reference's strong-gradient samples outside `ring` (luma pixels).
    pub fn new(p: &Pyramid, ring: Option<Disc>, width: usize, height: usize) -> Reference {
        let centre = [(width as f64 - 1.0) / 2.0, (height as f64 - 1.0) / 2.0];
        let samples = p.levels.iter().map(|l| strong_samples(l, ring)).collect();
        Reference { samples, centre, reach: centre[0].hypot(centre[1]) }
    }

    pub fn centre(&self) -> [f64; 2] {
        self.centre
    }
    pub fn reach(&self) -> f64 {
        self.reach
    }

    /// The frame's pose, from `start` (the last frame's), coarse to fine; `None` where the
    /// table is not seen well enough to tell.
    pub fn register(
        &self,
        frame: &Pyramid,
        ring: Option<Disc>,
        start: CameraPose,
    ) -> Option<Registration> {
        let mut state = Solve { pose: start, gain: 1.0, offset: 0.0, spread: f64::INFINITY };
        let mut last = None;
        for (level, samples) in frame.levels.iter().zip(&self.samples).rev() {
            state.spread = f64::INFINITY;
            for _ in 0..MAX_STEPS {
                let step = state.step(level, samples, self.centre, ring)?;
                let moved = step.moved_samples(self.reach / level.factor);
                last = Some(step);
                if moved < CONVERGED {
                    break;
                }
            }
        }
        let fit = last?;
        (fit.used as f64 >= MIN_USED_SHARE * self.samples[0].len() as f64
            && state.gain >= MIN_GAIN
            && fit.sigma_px.is_finite())
        .then_some(Registration { pose: state.pose, sigma_px: fit.sigma_px })
    }
}

/// The samples of a level whose gradient along either axis is among the strongest, outside
/// the ring's disc and a sample from the edge.
fn strong_samples(l: &Level, ring: Option<Disc>) -> Vec<Sample> {
    let mut all = Vec::with_capacity(l.width * l.height);
    let disc = ring.map(|d| (l.sample_of_luma(d.centre), d.radius / l.factor));
    for v in 1..l.height.saturating_sub(1) {
        for u in 1..l.width.saturating_sub(1) {
            if let Some((c, r)) = disc
                && (u as f64 - c[0]).hypot(v as f64 - c[1]) <= r
            {
                continue;
            }
            let du = (l.at(u + 1, v) - l.at(u - 1, v)) / 2.0;
            let dv = (l.at(u, v + 1) - l.at(u, v - 1)) / 2.0;
            all.push(Sample { u: u as f32, v: v as f32, value: l.at(u, v), du, dv });
        }
    }
    let threshold = |g: fn(&Sample) -> f32| {
        let mut m: Vec<f32> = all.iter().map(|s| g(s).abs()).collect();
        if m.is_empty() {
            return 0.0;
        }
        let k = (((1.0 - KEPT_SHARE) * m.len() as f64) as usize).min(m.len() - 1);
        *m.select_nth_unstable_by(k, f32::total_cmp).1
    };
    let (tu, tv) = (threshold(|s| s.du), threshold(|s| s.dv));
    all.retain(|s| (s.du.abs() >= tu || s.dv.abs() >= tv) && (s.du != 0.0 || s.dv != 0.0));
    all
}

/// The Gauss-Newton state: the pose, the light's gain and offset, the residuals' spread.
struct Solve {
    pose: CameraPose,
    gain: f64,
    offset: f64,
    spread: f64,
}

/// One step's outcome.
struct Step {
    delta: [f64; 5],
    used: usize,
    sigma_px: f64,
}

impl Step {
    /// The step's largest movement of a sample `reach` samples from the centre.
    fn moved_samples(&self, reach: f64) -> f64 {
        self.delta[0].hypot(self.delta[1]) + self.delta[2].abs() * reach
    }
}

/// The normal equations of one step: `H delta = -g` for (shift u, shift v, turn, gain,
/// offset).
#[derive(Default)]
struct Normal {
    h: [[f64; 5]; 5],
    g: [f64; 5],
    weighted_sq: f64,
    abs_sum: f64,
    used: usize,
}

impl Solve {
    /// One Gauss-Newton step at `level`; `None` where the equations are singular.
    fn step(
        &mut self,
        level: &Level,
        samples: &[Sample],
        centre: [f64; 2],
        ring: Option<Disc>,
    ) -> Option<Step> {
        let n = self.normal(level, samples, centre, ring);
        if n.used < 16 {
            return None;
        }
        let delta = solve5(n.h, n.g.map(|g| -g))?;
        // The new warp: the step applied on the reference's side, then the old warp.
        let f = level.factor;
        let (s, co) = self.pose.turn_rad.sin_cos();
        let t = [delta[0] * f, delta[1] * f];
        self.pose.shift_px[0] += co * t[0] - s * t[1];
        self.pose.shift_px[1] += s * t[0] + co * t[1];
        self.pose.turn_rad += delta[2];
        self.gain += delta[3];
        self.offset += delta[4];
        self.spread = 1.25 * n.abs_sum / n.used as f64;
        let variance = n.weighted_sq / (n.used as f64 - 5.0);
        let cov = invert5(n.h)?;
        let reach = centre[0].hypot(centre[1]) / f;
        let sigma_samples =
            (variance * (cov[0][0] + cov[1][1])).sqrt() + (variance * cov[2][2]).sqrt() * reach;
        Some(Step { delta, used: n.used, sigma_px: sigma_samples * f })
    }

    /// The weighted normal equations over the samples seen in the frame outside its ring.
    fn normal(
        &self,
        level: &Level,
        samples: &[Sample],
        centre: [f64; 2],
        ring: Option<Disc>,
    ) -> Normal {
        let c = level.sample_of_luma(centre);
        let (s, co) = self.pose.turn_rad.sin_cos();
        let t = [self.pose.shift_px[0] / level.factor, self.pose.shift_px[1] / level.factor];
        let disc =
            ring.map(|d| (level.sample_of_luma(d.centre), (d.radius / level.factor).powi(2)));
        let huber = HUBER * self.spread;
        let mut n = Normal::default();
        for sm in samples {
            let (x, y) = (sm.u as f64 - c[0], sm.v as f64 - c[1]);
            let (wu, wv) = (co * x - s * y + c[0] + t[0], s * x + co * y + c[1] + t[1]);
            if let Some((dc, r2)) = disc
                && (wu - dc[0]).powi(2) + (wv - dc[1]).powi(2) <= r2
            {
                continue;
            }
            let Some(seen) = level.bilinear(wu, wv) else { continue };
            let value = sm.value as f64;
            let r = seen - self.gain * value - self.offset;
            let w = if r.abs() <= huber { 1.0 } else { huber / r.abs() };
            let (gu, gv) = (self.gain * sm.du as f64, self.gain * sm.dv as f64);
            let j = [gu, gv, -gu * y + gv * x, -value, -1.0];
            for a in 0..5 {
                let wa = w * j[a];
                n.g[a] += wa * r;
                for b in a..5 {
                    n.h[a][b] += wa * j[b];
                }
            }
            n.weighted_sq += w * r * r;
            n.abs_sum += r.abs();
            n.used += 1;
        }
        for a in 0..5 {
            for b in 0..a {
                n.h[a][b] = n.h[b][a];
            }
        }
        n
    }
}

/// `H x = b` by Gaussian elimination with partial pivoting; `None` where `H` is singular.
fn solve5(mut h: [[f64; 5]; 5], mut b: [f64; 5]) -> Option<[f64; 5]> {
    let scale = (0..5).map(|i| h[i][i].abs()).fold(0.0, f64::max);
    for col in 0..5 {
        let pivot = (col..5).max_by(|&i, &j| h[i][col].abs().total_cmp(&h[j][col].abs()))?;
        if !(h[pivot][col].abs() > 1e-12 * scale) {
            return None;
        }
        h.swap(col, pivot);
        b.swap(col, pivot);
        for row in col + 1..5 {
            let f = h[row][col] / h[col][col];
            for k in col..5 {
                h[row][k] -= f * h[col][k];
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; 5];
    for row in (0..5).rev() {
        let s: f64 = (row + 1..5).map(|k| h[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / h[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// `H`'s inverse, column by column; `None` where singular.
fn invert5(h: [[f64; 5]; 5]) -> Option<[[f64; 5]; 5]> {
    let mut inv = [[0.0; 5]; 5];
    for col in 0..5 {
        let mut e = [0.0; 5];
        e[col] = 1.0;
        let x = solve5(h, e)?;
        for row in 0..5 {
            inv[row][col] = x[row];
        }
    }
    Some(inv)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A textured table (a sum of waves, as wood's grain in two directions) seen through `pose`.
    fn table(w: usize, h: usize, pose: CameraPose, gain: f64) -> Frame {
        let centre = [(w as f64 - 1.0) / 2.0, (h as f64 - 1.0) / 2.0];
        let mut luma = vec![0u8; w * h];
        for y in 0..h {
            for x in 0..w {
                let [u, v] = pose.to_table([x as f64, y as f64], centre);
                let t = 110.0
                    + 30.0 * (u / 23.0 + 0.3 * (v / 41.0).sin()).sin()
                    + 25.0 * (v / 17.0 + 0.5 * (u / 57.0).cos()).sin()
                    + 15.0 * ((u + v) / 31.0).cos();
                luma[y * w + x] = (t * gain).round().clamp(0.0, 255.0) as u8;
            }
        }
        Frame { width: w, height: h, luma, cb: vec![], cr: vec![] }
    }

    #[test]
    fn a_shifted_turned_table_is_registered() {
        let (w, h) = (640, 512);
        let truth = CameraPose { shift_px: [6.3, -4.1], turn_rad: 1.2f64.to_radians() };
        let reference = Pyramid::of(&table(w, h, CameraPose::default(), 1.0)).unwrap();
        let frame = Pyramid::of(&table(w, h, truth, 0.9)).unwrap();
        let r = Reference::new(&reference, None, w, h);
        let found = r.register(&frame, None, CameraPose::default()).unwrap();
        let centre = r.centre();
        for p in [[0.0, 0.0], [639.0, 511.0], [320.0, 100.0]] {
            let (a, b) = (found.pose.to_image(p, centre), truth.to_image(p, centre));
            assert!((a[0] - b[0]).hypot(a[1] - b[1]) < 0.1, "{a:?} vs {b:?}: {found:?}");
        }
        assert!(found.sigma_px < 0.1, "{found:?}");
    }

    #[test]
    fn a_frame_without_texture_is_not_registered() {
        let (w, h) = (640, 512);
        let reference = Pyramid::of(&table(w, h, CameraPose::default(), 1.0)).unwrap();
        let flat = Frame { width: w, height: h, luma: vec![128; w * h], cb: vec![], cr: vec![] };
        let r = Reference::new(&reference, None, w, h);
        assert_eq!(r.register(&Pyramid::of(&flat).unwrap(), None, CameraPose::default()), None);
    }

    #[test]
    fn pose_round_trips() {
        let p = CameraPose { shift_px: [3.0, -2.0], turn_rad: 0.03 };
        let c = [100.0, 80.0];
        let q = p.to_table(p.to_image([12.0, 170.0], c), c);
        assert!((q[0] - 12.0).abs() < 1e-9 && (q[1] - 170.0).abs() < 1e-9);
    }
}
