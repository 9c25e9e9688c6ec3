//! Deterministic synthetic scenes with per-frame ground truth.
//!
//! A person-like target (an ellipse, red "shirt" above its centre row, blue "trousers"
//! from it down, darker towards the left and right edges) walks over a textured
//! background: blotchy, moderately saturated colour noise with finer luminance texture, so
//! a colour tracker has a fair but not trivial task. Every frame gets Gaussian camera noise.
//!
//! Ground plane: the camera looks down on a floor whose horizon is at row
//! [`Scene::horizon_y`]; the target's half-height is `hy = scale_per_row * (cy - horizon_y)`
//! (px), so it grows [`Scene::scale_per_row`] px per px it moves down the image (the RBPF's
//! `alpha / beta`), and its half-width is `hx = aspect * hy`. Coordinates are 0-based pixels,
//! pixel centres at integer coordinates; a pixel `(x, y)` belongs to the target when
//! `((x - cx) / hx)^2 + ((y - cy) / hy)^2 <= 1`.
//!
//! Everything is drawn from the seed with a local SplitMix64 and plain IEEE arithmetic
//! (no transcendental functions), so the same configuration gives the same bytes on any
//! host. Frames render on demand, in any order.
//!
//! # Example
//! ```
//! use rbtrack_host::scene::{Scene, SceneConfig, Variant};
//! let scene = Scene::new(SceneConfig::new(Variant::Perspective, 1)).unwrap();
//! let rgb = scene.render(0).unwrap();
//! assert_eq!(rgb.len(), 320 * 240 * 3);
//! let t = scene.truth(0).unwrap();
//! assert!(t.visible && t.hy > 0.0);
//! ```

use crate::metrics::BBox;
use crate::pixels::Frame;
use rbtrack::fixed::Q16;
use rbtrack::tracker::Config;
use std::fmt;

/// Colour of the target's upper half (shirt), RGB888.
pub const TOP_COLOUR: [u8; 3] = [200, 45, 40];
/// Colour of the target's lower half (trousers), RGB888.
pub const BOTTOM_COLOUR: [u8; 3] = [45, 65, 185];
/// Share of its pixels that must be seen for a target to count as `visible`.
pub const VISIBLE_MIN_FRACTION: f64 = 0.25;

/// Ground-plane slope `d hy / d cy` (px of half-height per px down the image).
const SCALE_PER_ROW: f64 = 0.264;
/// Horizon row as a share of the frame height.
const HORIZON: f64 = 0.047;
/// Half-width over half-height of the target.
const ASPECT: f64 = 0.42;
/// Smallest half-axis drawn, px.
const MIN_HALF_AXIS: f64 = 1.5;
/// Frames the `Occlusion` variant hides the target for (fewer in short scenes).
const OCCLUDED_FRAMES: usize = 15;

/// What happens in a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// Walks diagonally from the top (far) to the bottom (near): height grows about 2.5x.
    Perspective,
    /// A second, identical target walks the other way and crosses in front of the target
    /// (lower in the image, so nearer and drawn over it) mid-sequence.
    Distractor,
    /// A full-height pillar of background-like texture hides the target completely for
    /// 15 frames as it walks across.
    Occlusion,
    /// Global brightness ramps 100% -> 60% (mid-sequence) -> 110% (end).
    BrightnessRamp,
    /// Moves 8-15 px/frame (at 320 px width, scaled with width), changing direction every
    /// 6-12 frames, bouncing off the frame's inner region.
    FastMotion,
    /// Walks out of the right edge, stays fully out for about 20% of the frames (20 of
    /// 100), then walks back in.
    LeaveAndReturn,
}

impl Variant {
    /// All variants.
    pub const ALL: [Variant; 6] = [
        Variant::Perspective,
        Variant::Distractor,
        Variant::Occlusion,
        Variant::BrightnessRamp,
        Variant::FastMotion,
        Variant::LeaveAndReturn,
    ];

    /// Short lowercase name (`perspective`, `distractor`, `occlusion`, `brightness`,
    /// `fast`, `leave`).
    pub fn name(self) -> &'static str {
        match self {
            Variant::Perspective => "perspective",
            Variant::Distractor => "distractor",
            Variant::Occlusion => "occlusion",
            Variant::BrightnessRamp => "brightness",
            Variant::FastMotion => "fast",
            Variant::LeaveAndReturn => "leave",
        }
    }

    /// The variant called `name` (as [`Variant::name`], case-insensitive).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|v| v.name().eq_ignore_ascii_case(name.trim()))
    }

    fn salt(self) -> u64 {
        match self {
            Variant::Perspective => 1,
            Variant::Distractor => 2,
            Variant::Occlusion => 3,
            Variant::BrightnessRamp => 4,
            Variant::FastMotion => 5,
            Variant::LeaveAndReturn => 6,
        }
    }
}

impl fmt::Display for Variant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Scene parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneConfig {
    /// What happens.
    pub variant: Variant,
    /// Seed of the background, the motion and the noise.
    pub seed: u64,
    /// Frame width, px (32..=4096).
    pub width: u32,
    /// Frame height, px (32..=4096).
    pub height: u32,
    /// Number of frames (>= 10).
    pub frames: usize,
    /// Standard deviation of the per-pixel, per-channel camera noise, levels of 255.
    pub noise_sigma: f64,
}

impl SceneConfig {
    /// QVGA (320x240), 100 frames, noise sigma 6 levels.
    pub fn new(variant: Variant, seed: u64) -> Self {
        Self {
            variant,
            seed,
            width: 320,
            height: 240,
            frames: 100,
            noise_sigma: 6.0,
        }
    }
}

/// Invalid scene configuration or frame index.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneError {
    /// Width or height outside 32..=4096 px.
    Size {
        /// Requested width, px.
        width: u32,
        /// Requested height, px.
        height: u32,
    },
    /// Fewer than 10 frames requested.
    TooFewFrames(usize),
    /// Noise sigma negative or not finite.
    Noise(f64),
    /// Frame index past the end.
    FrameIndex {
        /// Requested 0-based index.
        index: usize,
        /// Number of frames.
        len: usize,
    },
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Size { width, height } => {
                write!(f, "scene size {width}x{height} px outside 32..=4096")
            }
            Self::TooFewFrames(n) => write!(f, "scene needs at least 10 frames, got {n}"),
            Self::Noise(s) => write!(f, "noise sigma {s} must be finite and >= 0"),
            Self::FrameIndex { index, len } => {
                write!(
                    f,
                    "frame index {index} out of range (scene has {len} frames)"
                )
            }
        }
    }
}

impl std::error::Error for SceneError {}

/// Ground truth of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Truth {
    /// Ellipse centre column, px (may lie outside the frame).
    pub cx: f64,
    /// Ellipse centre row, px.
    pub cy: f64,
    /// Half-width, px.
    pub hx: f64,
    /// Half-height, px.
    pub hy: f64,
    /// Box of the ellipse ([`BBox::from_ellipse`]), not clipped to the frame.
    pub bbox: BBox,
    /// Share of the target's pixels that are drawn: inside the frame and not hidden by a
    /// nearer object; in `[0, 1]`.
    pub visible_fraction: f64,
    /// `visible_fraction >= VISIBLE_MIN_FRACTION`.
    pub visible: bool,
    /// Global brightness gain applied to the frame (1 = unchanged).
    pub brightness: f64,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Ell {
    cx: f64,
    cy: f64,
    hx: f64,
    hy: f64,
}

impl Ell {
    fn contains(&self, x: i64, y: i64) -> bool {
        let dx = (x as f64 - self.cx) / self.hx;
        let dy = (y as f64 - self.cy) / self.hy;
        dx * dx + dy * dy <= 1.0
    }

    /// Integer pixel ranges that may hold ellipse pixels (unclipped).
    fn span(&self) -> (i64, i64, i64, i64) {
        (
            (self.cx - self.hx).floor() as i64,
            (self.cx + self.hx).ceil() as i64,
            (self.cy - self.hy).floor() as i64,
            (self.cy + self.hy).ceil() as i64,
        )
    }
}

/// Column range `x0..=x1` of a full-height occluding pillar, px.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Pillar {
    x0: i64,
    x1: i64,
}

/// A generated scene: configuration, textures and per-frame ground truth.
#[derive(Clone, Debug)]
pub struct Scene {
    config: SceneConfig,
    horizon_y: f64,
    truth: Vec<Truth>,
    distractor: Vec<Option<Ell>>,
    pillar: Option<Pillar>,
    background: Vec<f32>,
    occluder_texture: Vec<f32>,
}

impl Scene {
    /// Builds the scene: textures and the whole trajectory (cheap; frames render later).
    pub fn new(config: SceneConfig) -> Result<Self, SceneError> {
        let (w, h) = (config.width, config.height);
        if !(32..=4096).contains(&w) || !(32..=4096).contains(&h) {
            return Err(SceneError::Size {
                width: w,
                height: h,
            });
        }
        if config.frames < 10 {
            return Err(SceneError::TooFewFrames(config.frames));
        }
        if !config.noise_sigma.is_finite() || config.noise_sigma < 0.0 {
            return Err(SceneError::Noise(config.noise_sigma));
        }
        let horizon_y = HORIZON * h as f64;
        let mut rng = SplitMix64::new(mix(config.seed, config.variant.salt()));
        let background = texture(w, h, &mut rng);
        let occluder_texture = if config.variant == Variant::Occlusion {
            texture(w, h, &mut rng)
        } else {
            Vec::new()
        };
        let path = trajectory(&config, horizon_y, &mut rng);
        let distractor: Vec<Option<Ell>> = match config.variant {
            Variant::Distractor => distractor_path(&config, horizon_y),
            _ => vec![None; config.frames],
        };
        let pillar = (config.variant == Variant::Occlusion).then(|| place_pillar(&path));
        let truth = path
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let fraction = visible_fraction(e, distractor[i].as_ref(), pillar, w, h);
                Truth {
                    cx: e.cx,
                    cy: e.cy,
                    hx: e.hx,
                    hy: e.hy,
                    bbox: BBox::from_ellipse(e.cx, e.cy, e.hx, e.hy),
                    visible_fraction: fraction,
                    visible: fraction >= VISIBLE_MIN_FRACTION,
                    brightness: brightness(&config, i),
                }
            })
            .collect();
        Ok(Self {
            config,
            horizon_y,
            truth,
            distractor,
            pillar,
            background,
            occluder_texture,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &SceneConfig {
        &self.config
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.truth.len()
    }

    /// Always false: a scene has at least 10 frames.
    pub fn is_empty(&self) -> bool {
        self.truth.is_empty()
    }

    /// Frame width, px.
    pub fn width(&self) -> u32 {
        self.config.width
    }

    /// Frame height, px.
    pub fn height(&self) -> u32 {
        self.config.height
    }

    /// Ground-plane slope: px of half-height gained per px the centre moves down
    /// (`d hy / d cy`, the RBPF's `alpha / beta`).
    pub fn scale_per_row(&self) -> f64 {
        SCALE_PER_ROW
    }

    /// Sets what an engineer who knows this scene would tell the tracker: the ground-plane
    /// slope (`scale_per_row`) and, since the walkers move smoothly at a steady speed,
    /// constant velocity (noise 1 px/frame, 0.95 kept) with motion-adaptive noise
    /// (`noise_gain` 2, `noise_floor` 0.15), which keeps the particles on the target's
    /// path when a look-alike crosses it. The rest of `config` is left as it is.
    pub fn configure(&self, config: &mut Config) {
        config.scale_per_row = Q16::from_f64(self.scale_per_row());
        config.velocity_noise = Q16::ONE;
        config.velocity_keep = Q16::from_f64(0.95);
        config.noise_gain = Q16::from_int(2);
        config.noise_floor = Q16::from_f64(0.15);
    }

    /// Row of the horizon, px: the half-height is `scale_per_row * (cy - horizon_y)`.
    pub fn horizon_y(&self) -> f64 {
        self.horizon_y
    }

    /// Half-width over half-height of the target.
    pub fn aspect(&self) -> f64 {
        ASPECT
    }

    /// Half-height (px) of a target centred on row `cy` (px), at least 1.5 px.
    pub fn half_height_at(&self, cy: f64) -> f64 {
        (SCALE_PER_ROW * (cy - self.horizon_y)).max(MIN_HALF_AXIS)
    }

    /// Ground truth of frame `index`.
    pub fn truth(&self, index: usize) -> Option<&Truth> {
        self.truth.get(index)
    }

    /// Ground truth of every frame.
    pub fn truths(&self) -> &[Truth] {
        &self.truth
    }

    /// Ground-truth boxes of every frame.
    pub fn boxes(&self) -> Vec<BBox> {
        self.truth.iter().map(|t| t.bbox).collect()
    }

    /// Centre and half-axes `(cx, cy, hx, hy)` of the distractor in frame `index`, px, for
    /// the `Distractor` variant.
    pub fn distractor(&self, index: usize) -> Option<(f64, f64, f64, f64)> {
        self.distractor
            .get(index)
            .copied()
            .flatten()
            .map(|e| (e.cx, e.cy, e.hx, e.hy))
    }

    /// Column range `(x0, x1)` (inclusive, px) of the occluding pillar, for `Occlusion`.
    pub fn occluder_columns(&self) -> Option<(i64, i64)> {
        self.pillar.map(|p| (p.x0, p.x1))
    }

    /// Renders frame `index` as RGB888 (`width * height * 3` bytes, stride `width * 3`).
    pub fn render(&self, index: usize) -> Result<Vec<u8>, SceneError> {
        let truth = self.truth.get(index).ok_or(SceneError::FrameIndex {
            index,
            len: self.len(),
        })?;
        let (w, h) = (self.config.width as i64, self.config.height as i64);
        let mut canvas = self.background.clone();
        let target = Ell {
            cx: truth.cx,
            cy: truth.cy,
            hx: truth.hx,
            hy: truth.hy,
        };
        let mut people = vec![target];
        if let Some(d) = self.distractor[index] {
            people.push(d);
        }
        // Painter's order: farther (higher in the image) first.
        people.sort_by(|a, b| a.cy.total_cmp(&b.cy));
        for e in &people {
            paint_person(&mut canvas, w, h, e);
        }
        if let Some(p) = self.pillar {
            for y in 0..h {
                for x in p.x0.max(0)..=p.x1.min(w - 1) {
                    let i = ((y * w + x) * 3) as usize;
                    canvas[i..i + 3].copy_from_slice(&self.occluder_texture[i..i + 3]);
                }
            }
        }
        let mut rng = SplitMix64::new(mix(
            mix(self.config.seed, self.config.variant.salt()),
            0x6e6f_6973_6500_0000 ^ index as u64,
        ));
        let gain = truth.brightness;
        let sigma = self.config.noise_sigma;
        Ok(canvas
            .iter()
            .map(|&v| {
                let v = v as f64 * gain + sigma * rng.gaussian();
                (v + 0.5).floor().clamp(0.0, 255.0) as u8
            })
            .collect())
    }

    /// Iterator over the rendered frames (RGB888), in order.
    pub fn frames(&self) -> impl Iterator<Item = Frame> + '_ {
        (0..self.len()).filter_map(|i| {
            let rgb = self.render(i).ok()?;
            Frame::rgb888(self.width(), self.height(), rgb).ok()
        })
    }
}

fn paint_person(canvas: &mut [f32], w: i64, h: i64, e: &Ell) {
    let (x0, x1, y0, y1) = e.span();
    for y in y0.max(0)..=y1.min(h - 1) {
        for x in x0.max(0)..=x1.min(w - 1) {
            if !e.contains(x, y) {
                continue;
            }
            let dx = (x as f64 - e.cx) / e.hx;
            let shade = (1.0 - 0.3 * dx * dx) as f32;
            let colour = if (y as f64) < e.cy {
                TOP_COLOUR
            } else {
                BOTTOM_COLOUR
            };
            let i = ((y * w + x) * 3) as usize;
            for c in 0..3 {
                canvas[i + c] = colour[c] as f32 * shade;
            }
        }
    }
}

fn visible_fraction(
    e: &Ell,
    nearer_candidate: Option<&Ell>,
    pillar: Option<Pillar>,
    w: u32,
    h: u32,
) -> f64 {
    let nearer = nearer_candidate.filter(|d| d.cy > e.cy);
    let (x0, x1, y0, y1) = e.span();
    let (mut total, mut seen) = (0u64, 0u64);
    for y in y0..=y1 {
        for x in x0..=x1 {
            if !e.contains(x, y) {
                continue;
            }
            total += 1;
            let inside = x >= 0 && y >= 0 && x < w as i64 && y < h as i64;
            let hidden = nearer.is_some_and(|d| d.contains(x, y))
                || pillar.is_some_and(|p| x >= p.x0 && x <= p.x1);
            if inside && !hidden {
                seen += 1;
            }
        }
    }
    if total == 0 {
        0.0
    } else {
        seen as f64 / total as f64
    }
}

fn brightness(config: &SceneConfig, i: usize) -> f64 {
    if config.variant != Variant::BrightnessRamp {
        return 1.0;
    }
    let u = i as f64 / (config.frames - 1) as f64;
    if u <= 0.5 {
        lerp(1.0, 0.6, u / 0.5)
    } else {
        lerp(0.6, 1.1, (u - 0.5) / 0.5)
    }
}

fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a + (b - a) * t
}

/// Triangle wave of period 1 in `[-1, 1]`.
fn triangle(t: f64) -> f64 {
    let f = t - t.floor();
    if f < 0.5 {
        4.0 * f - 1.0
    } else {
        3.0 - 4.0 * f
    }
}

fn person_at(cx: f64, cy: f64, horizon_y: f64) -> Ell {
    let hy = (SCALE_PER_ROW * (cy - horizon_y)).max(MIN_HALF_AXIS);
    Ell {
        cx,
        cy,
        hx: (ASPECT * hy).max(MIN_HALF_AXIS),
        hy,
    }
}

fn trajectory(config: &SceneConfig, horizon_y: f64, rng: &mut SplitMix64) -> Vec<Ell> {
    let n = config.frames;
    let (w, h) = (config.width as f64, config.height as f64);
    let u = |i: usize| i as f64 / (n - 1) as f64;
    let at = |cx, cy| person_at(cx, cy, horizon_y);
    match config.variant {
        Variant::Perspective => (0..n)
            .map(|i| {
                let sway = 0.01 * w * triangle(i as f64 / 24.0);
                at(
                    lerp(0.25 * w, 0.70 * w, u(i)) + sway,
                    lerp(0.30 * h, 0.68 * h, u(i)),
                )
            })
            .collect(),
        Variant::Distractor => (0..n)
            .map(|i| at(lerp(0.15 * w, 0.85 * w, u(i)), 0.52 * h))
            .collect(),
        Variant::Occlusion => (0..n)
            .map(|i| {
                at(
                    lerp(0.12 * w, 0.88 * w, u(i)),
                    lerp(0.50 * h, 0.56 * h, u(i)),
                )
            })
            .collect(),
        Variant::BrightnessRamp => (0..n)
            .map(|i| {
                let sway = 0.01 * w * triangle(i as f64 / 20.0);
                at(
                    lerp(0.20 * w, 0.80 * w, u(i)),
                    lerp(0.40 * h, 0.60 * h, u(i)) + sway,
                )
            })
            .collect(),
        Variant::FastMotion => fast_path(config, horizon_y, rng),
        Variant::LeaveAndReturn => {
            let out = ((0.2 * n as f64).round() as usize).max(1);
            let exit = ((0.35 * n as f64).round() as usize).max(1);
            let back_start = exit + out - 1;
            let back_len = (n - 1 - back_start).max(1) as f64;
            (0..n)
                .map(|i| {
                    let cy = lerp(0.50 * h, 0.58 * h, u(i));
                    let e = at(0.0, cy);
                    // Fully outside once the leftmost pixel column exceeds w - 1.
                    let x_out = w - 1.0 + e.hx + 0.5;
                    let cx = if i <= exit {
                        lerp(0.45 * w, x_out, i as f64 / exit as f64)
                    } else if i <= back_start {
                        x_out
                    } else {
                        lerp(x_out, 0.55 * w, (i - back_start) as f64 / back_len)
                    };
                    at(cx, cy)
                })
                .collect()
        }
    }
}

fn fast_path(config: &SceneConfig, horizon_y: f64, rng: &mut SplitMix64) -> Vec<Ell> {
    let (w, h) = (config.width as f64, config.height as f64);
    let (xmin, xmax, ymin, ymax) = (0.12 * w, 0.88 * w, 0.32 * h, 0.70 * h);
    let speed_scale = w / 320.0;
    let (mut x, mut y) = (0.5 * w, 0.5 * h);
    let (mut vx, mut vy) = (0.0, 0.0);
    let mut until_turn = 0;
    let mut path = Vec::with_capacity(config.frames);
    for _ in 0..config.frames {
        path.push(person_at(x, y, horizon_y));
        if until_turn == 0 {
            let speed = (8.0 + 7.0 * rng.uniform()) * speed_scale;
            let (dx, dy) = loop {
                let (a, b) = (2.0 * rng.uniform() - 1.0, 2.0 * rng.uniform() - 1.0);
                let r2 = a * a + b * b;
                if r2 > 0.04 && r2 <= 1.0 {
                    let r = r2.sqrt();
                    break (a / r, b / r);
                }
            };
            (vx, vy) = (speed * dx, speed * dy);
            until_turn = 6 + (rng.next_u64() % 7) as usize;
        }
        until_turn -= 1;
        (x, vx) = reflect(x + vx, vx, xmin, xmax);
        (y, vy) = reflect(y + vy, vy, ymin, ymax);
    }
    path
}

/// Mirrors a position that left `[lo, hi]` back inside, flipping the velocity.
fn reflect(p: f64, v: f64, lo: f64, hi: f64) -> (f64, f64) {
    if p < lo {
        ((2.0 * lo - p).min(hi), -v)
    } else if p > hi {
        ((2.0 * hi - p).max(lo), -v)
    } else {
        (p, v)
    }
}

fn distractor_path(config: &SceneConfig, horizon_y: f64) -> Vec<Option<Ell>> {
    let n = config.frames;
    let (w, h) = (config.width as f64, config.height as f64);
    (0..n)
        .map(|i| {
            let u = i as f64 / (n - 1) as f64;
            Some(person_at(lerp(0.85 * w, 0.15 * w, u), 0.58 * h, horizon_y))
        })
        .collect()
}

/// The narrowest full-height pillar that hides every pixel of the target in the middle
/// `OCCLUDED_FRAMES` frames (fewer for short scenes).
fn place_pillar(path: &[Ell]) -> Pillar {
    let hidden = OCCLUDED_FRAMES.min(path.len() / 3).max(1);
    let first = (path.len() - hidden) / 2;
    let mut p = Pillar {
        x0: i64::MAX,
        x1: i64::MIN,
    };
    for e in &path[first..first + hidden] {
        let (x0, x1, y0, y1) = e.span();
        for y in y0..=y1 {
            for x in x0..=x1 {
                if e.contains(x, y) {
                    p.x0 = p.x0.min(x);
                    p.x1 = p.x1.max(x);
                }
            }
        }
    }
    p
}

/// Blotchy colour texture, RGB as f32 levels: a coarse lattice of moderately saturated
/// colours, plus two finer octaves of luminance, smoothly interpolated.
fn texture(w: u32, h: u32, rng: &mut SplitMix64) -> Vec<f32> {
    let coarse_cell = (w as f64 / 6.0).max(8.0);
    let mid_cell = (w as f64 / 26.0).max(3.0);
    let fine_cell = 4.0;
    let colour = Lattice::new(w, h, coarse_cell, 3, rng, |r| {
        let grey = 70.0 + 110.0 * r.uniform();
        (0..3).map(|_| grey + 90.0 * (r.uniform() - 0.5)).collect()
    });
    let mid = Lattice::new(w, h, mid_cell, 1, rng, |r| vec![50.0 * (r.uniform() - 0.5)]);
    let fine = Lattice::new(w, h, fine_cell, 1, rng, |r| {
        vec![20.0 * (r.uniform() - 0.5)]
    });
    let mut out = Vec::with_capacity(w as usize * h as usize * 3);
    for y in 0..h {
        for x in 0..w {
            let lum = mid.sample(x, y, 0) + fine.sample(x, y, 0);
            for c in 0..3 {
                out.push((colour.sample(x, y, c) + lum).clamp(0.0, 255.0) as f32);
            }
        }
    }
    out
}

/// Value noise: random values on a square lattice of `cell` px, smoothstep-interpolated.
struct Lattice {
    cell: f64,
    cols: usize,
    channels: usize,
    values: Vec<f64>,
}

impl Lattice {
    fn new(
        w: u32,
        h: u32,
        cell: f64,
        channels: usize,
        rng: &mut SplitMix64,
        mut draw: impl FnMut(&mut SplitMix64) -> Vec<f64>,
    ) -> Self {
        let cols = (w as f64 / cell).ceil() as usize + 2;
        let rows = (h as f64 / cell).ceil() as usize + 2;
        let values = (0..cols * rows).flat_map(|_| draw(rng)).collect();
        Self {
            cell,
            cols,
            channels,
            values,
        }
    }

    fn sample(&self, x: u32, y: u32, c: usize) -> f64 {
        let (fx, fy) = (x as f64 / self.cell, y as f64 / self.cell);
        let (ix, iy) = (fx.floor() as usize, fy.floor() as usize);
        let smooth = |t: f64| t * t * (3.0 - 2.0 * t);
        let (tx, ty) = (smooth(fx - ix as f64), smooth(fy - iy as f64));
        let v = |i: usize, j: usize| self.values[((j * self.cols) + i) * self.channels + c];
        let top = lerp(v(ix, iy), v(ix + 1, iy), tx);
        let bottom = lerp(v(ix, iy + 1), v(ix + 1, iy + 1), tx);
        lerp(top, bottom, ty)
    }
}

/// Mixes two words into a seed (SplitMix64 finaliser of their combination).
fn mix(a: u64, b: u64) -> u64 {
    SplitMix64::new(a ^ b.rotate_left(32) ^ 0x9e37_79b9_7f4a_7c15).next_u64()
}

/// SplitMix64: tiny, fast, good enough for textures and noise.
#[derive(Clone, Debug)]
struct SplitMix64(u64);

impl SplitMix64 {
    fn new(seed: u64) -> Self {
        Self(seed)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` with 53 bits.
    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Approximately standard normal: the sum of four 16-bit uniforms, centred and scaled
    /// to unit variance (Irwin-Hall; tails cut at 3.46 sigma).
    fn gaussian(&mut self) -> f64 {
        let r = self.next_u64();
        let sum: u64 = (0..4).map(|k| (r >> (16 * k)) & 0xFFFF).sum();
        // Each uniform is (v + 0.5) / 65536; mean of the sum 2, variance 4/12.
        let s = (sum as f64 + 2.0) / 65536.0;
        (s - 2.0) * 1.732_050_807_568_877_2
    }
}
