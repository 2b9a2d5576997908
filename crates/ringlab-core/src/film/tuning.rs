//! The film tracker's numbers in one place, each with what it is and its unit, as a physics
//! engine's integration parameters or a particle tracker's locate arguments are: the
//! follower ([`FollowTuning`]) and each stage after it ([`super::stages`]) take them by
//! reference. [`TrackTuning::default`] holds the values the tracker is made and tested with;
//! why each is what it is, is said at its field.

/// Everything the tracker weighs against a number.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackTuning {
    /// Frames looked through for the four marks before giving up (frames).
    pub acquire_frames: u64,
    /// Where the scale is given, the marks' semi-major axis is looked for between these
    /// multiples of the marks' circle's radius at that scale (a tilted or near camera shrinks
    /// or grows it).
    pub semi_major_given: (f64, f64),
    /// Where no scale is given, the least semi-major axis looked for (px).
    pub least_semi_major_px: f64,
    /// The ring's scale may differ from a `--px-per-mm` given by this share before a note
    /// says so (relative).
    pub scale_check: f64,
    /// The table scale's largest relative uncertainty at which a near camera's fitted
    /// pinhole checks the centres' error (`pose_error`) (relative).
    pub pose_scale_sigma: f64,
    pub follow: FollowTuning,
    pub join: JoinTuning,
    pub spread: SpreadTuning,
    pub stray_hue: StrayHueTuning,
    pub few: FewTuning,
    pub brief: BriefTuning,
}

impl Default for TrackTuning {
    fn default() -> TrackTuning {
        TrackTuning {
            acquire_frames: super::ACQUIRE_FRAMES,
            semi_major_given: (0.6, 1.6),
            least_semi_major_px: 3.0,
            scale_check: 0.03,
            pose_scale_sigma: 0.02,
            follow: FollowTuning::default(),
            join: JoinTuning::default(),
            spread: SpreadTuning::default(),
            stray_hue: StrayHueTuning::default(),
            few: FewTuning::default(),
            brief: BriefTuning::default(),
        }
    }
}

/// The follower's numbers (`follow`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowTuning {
    /// Positions kept per mark, and centres of the four, for the predictions (frames).
    pub history: usize,
    /// A mark's prediction holds this many frames after it was last seen (frames).
    pub predict_gap: u64,
    /// The prediction's gate: this much (px) plus `gate_per_step` of the mark's last step
    /// per frame predicted, at most `gate_most_px` (px).
    pub gate_px: f64,
    pub gate_per_step: f64,
    pub gate_most_px: f64,
    /// A mark seen once: the step taken as its last (px per frame).
    pub first_step_px: f64,
    /// A mark seen once or not in consecutive frames is looked for at least this far (px)
    /// from where it was.
    pub still_gate_px: f64,
    /// A mark found is kept only at this share of the mark's typical strength or more.
    pub least_strength: f64,
    /// The weight of a frame's strength (and, for colours, width) in the mark's running
    /// typical value.
    pub learn_rate: f64,
    /// Colours: a followed mark is kept only with a hue this close to its own (radians).
    pub hue_reach: f64,
    /// Colours: the hues a mark showed when found anew, kept for its own (their medoid): one
    /// from a blur (the ring acquired on edge) or a look-alike does not carry it.
    pub hues: usize,
    /// Colours: a mark looked for round the whole ring meets more look-alikes than one
    /// followed, and is taken only with a hue this close to its own (radians),
    pub wide_hue: f64,
    /// not this near (px) a mark found (each chroma sample is weighed against a ring of
    /// samples 4 away, 8 px: beside a mark, that ring takes in its colour and the difference
    /// shows its complement),
    pub fringe_px: f64,
    /// and not where the marks found would spread wider than this many times the ring's size.
    pub wider: f64,
    /// Colours: the brightness centre may lie this far (px) from the chroma's.
    pub brightness_reach_px: f64,
    /// Colours: a mark's blob may be fitted up to this many times its typical width.
    pub widest: f64,
    /// Dots: the discs tried, the dot's radius as first measured plus these (px). The
    /// parallelogram's gap cannot see an error common to the four marks (the light's side
    /// darkens each dot alike), and a disc inside the dot's blurred edge has one: none is
    /// tried inside it.
    pub disc_margins: [f64; DISCS],
    /// Dots: frames of the discs' running gap sums' memory (frames).
    pub disc_memory: f64,
    /// Dots: frames of four before the disc with the least gap is taken (frames).
    pub disc_frames: usize,
    /// The ring is looked for anew near marks seen within this many frames (frames).
    pub lost_frames: u64,
    /// Four found anew must have their centre within this many times the ring's size (and
    /// `refound_reach_px` more) of the marks last seen: all four seen, or fewer.
    pub refound_reach: (f64, f64),
    pub refound_reach_px: f64,
    /// A mark placed by the other three (the parallelogram) is looked for within this share
    /// of the opposite pair's distance and `placed_gate_px` more, at most
    /// `placed_gate_most_px` (px).
    pub placed_gate: f64,
    pub placed_gate_px: f64,
    pub placed_gate_most_px: f64,
    /// The marks' ellipse of a frame this recent (frames) tells one mark left on a
    /// look-alike, with a tolerance of `figure_tolerance_px` plus `figure_tolerance` of the
    /// ring's size (px).
    pub figure_frames: u64,
    pub figure_tolerance_px: f64,
    pub figure_tolerance: f64,
    /// Four marks whose parallelogram gap exceeds this share of their size plus
    /// `parallelogram_px` (px) hold one taken from something else.
    pub parallelogram: f64,
    pub parallelogram_px: f64,
}

/// Discs tried for the dots' centroid (`FollowTuning::disc_margins`).
pub const DISCS: usize = 5;

impl Default for FollowTuning {
    fn default() -> FollowTuning {
        FollowTuning {
            history: 4,
            predict_gap: 3,
            gate_px: 4.0,
            gate_per_step: 0.6,
            gate_most_px: 20.0,
            first_step_px: 6.0,
            still_gate_px: 8.0,
            least_strength: 0.4,
            learn_rate: 0.1,
            hue_reach: 0.6,
            hues: 9,
            wide_hue: 0.35,
            fringe_px: 10.0,
            wider: 1.15,
            brightness_reach_px: 3.0,
            widest: 1.6,
            disc_margins: [0.25, 0.75, 1.25, 1.75, 2.5],
            disc_memory: 100.0,
            disc_frames: 10,
            lost_frames: 8,
            refound_reach: (0.5, 1.2),
            refound_reach_px: 10.0,
            placed_gate: 0.08,
            placed_gate_px: 3.0,
            placed_gate_most_px: 10.0,
            figure_frames: 6,
            figure_tolerance_px: 2.0,
            figure_tolerance: 0.05,
            parallelogram: 0.06,
            parallelogram_px: 1.5,
        }
    }
}

/// Numbering identical dots across a loss from the ring's turning (`stages::join`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JoinTuning {
    /// Phases used on each side of a loss (frames).
    pub window: usize,
    /// Fewest phases on a side for a fit (frames).
    pub fewest: usize,
    /// Samples farther apart than this (frames) end a side's window: a phase unwrapped across
    /// a longer hole may have lost whole turns.
    pub most_apart: usize,
    /// At most this many phases next to the loss may be dropped from a side (frames).
    pub most_dropped: usize,
    /// The phase's noise is taken as at least this (rad): a side that a parabola fits exactly
    /// must not make every shift but one look impossible.
    pub least_noise: f64,
    /// The shift that fits best is taken where every other adds at least this many times its
    /// extra misfit: a quarter turn five times the curve's own departure over the loss.
    pub clear: f64,
    /// ...and at least this much over the noise (a chi-square with three degrees of freedom
    /// passes 16.3 once in a thousand).
    pub doubt: f64,
}

impl Default for JoinTuning {
    fn default() -> JoinTuning {
        JoinTuning {
            window: 16,
            fewest: 6,
            most_apart: 2,
            most_dropped: 4,
            least_noise: 0.004,
            clear: 25.0,
            doubt: 100.0,
        }
    }
}

/// Frames whose marks do not spread as the ring does (`stages::spread`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpreadTuning {
    /// Frames each side whose four marks give the ring's size (frames).
    pub window: usize,
    /// Frames with four marks needed in the window (frames).
    pub least_fours: usize,
    /// The size's tolerance, this share of the size plus `tolerance_px` (px): the centres'
    /// noise and a near camera's departure from an affine figure, with room for a camera
    /// twice as near or tilted by 20 degrees.
    pub tolerance: f64,
    pub tolerance_px: f64,
}

impl Default for SpreadTuning {
    fn default() -> SpreadTuning {
        SpreadTuning { window: 150, least_fours: 10, tolerance: 0.08, tolerance_px: 1.5 }
    }
}

/// Coloured marks whose hue strays from the mark's (`stages::stray_hue`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrayHueTuning {
    /// Frames each side whose hues give the mark's (frames).
    pub window: usize,
    /// Hues needed near a frame for its mark's hue to be known.
    pub least_hues: usize,
    /// The farthest a mark's hue may lie from the mark's (radians): a quarter of the way to
    /// the next mark's (four distinct hues lie about a quarter turn apart).
    pub stray: f64,
}

impl Default for StrayHueTuning {
    fn default() -> StrayHueTuning {
        StrayHueTuning { window: 300, least_hues: 20, stray: 0.4 }
    }
}

/// Frames of one or two marks where the ring is mostly lost (`stages::few`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FewTuning {
    /// The fewest marks in a frame that check one another.
    pub least_marks: usize,
    /// Frames each side that may vouch for a frame of fewer (frames).
    pub window: usize,
    /// The share of those with `least_marks` or more that does.
    pub least_share: f64,
}

impl Default for FewTuning {
    fn default() -> FewTuning {
        FewTuning { least_marks: 3, window: 10, least_share: 0.3 }
    }
}

/// Glimpses between frames where the ring was lost (`stages::brief`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BriefTuning {
    /// The fewest frames in a row that stand (frames).
    pub least_run: usize,
}

impl Default for BriefTuning {
    fn default() -> BriefTuning {
        BriefTuning { least_run: 3 }
    }
}
