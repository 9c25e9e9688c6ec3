//! Tracking accuracy by the OTB conventions: centre error, IoU, success curve and AUC,
//! precision at 20 px.
//!
//! Coordinates are 0-based pixels. A [`BBox`] `{x, y, w, h}` with integer fields covers
//! the pixels `x..=x+w-1` and `y..=y+h-1`, so its centre is `(x + (w-1)/2, y + (h-1)/2)`
//! (as OTB computes it) and its area is `w * h`. An ellipse with centre `(cx, cy)` on a
//! pixel centre and half-axes `(hx, hy)` in px maps to the box of size `2hx x 2hy` with the
//! same centre, and back, exactly ([`BBox::from_ellipse`], [`BBox::to_ellipse_f64`]).
//!
//! Nothing here returns NaN: empty or non-finite boxes have area 0 and IoU 0; a centre
//! error involving a non-finite coordinate is `f64::INFINITY`; statistics over zero frames
//! are 0.

/// Number of IoU thresholds of the success curve: `0, 0.05, ..., 1`.
pub const SUCCESS_STEPS: usize = 21;

/// Largest centre-error threshold of the precision curve, px (thresholds `0..=50`).
pub const PRECISION_MAX_PX: usize = 50;

/// Centre-error threshold of the headline precision figure, px.
pub const PRECISION_PX: f64 = 20.0;

/// Axis-aligned box in 0-based pixel coordinates: top-left `(x, y)`, size `w x h`, px.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BBox {
    /// Left edge, px (0-based).
    pub x: f64,
    /// Top edge, px (0-based).
    pub y: f64,
    /// Width, px.
    pub w: f64,
    /// Height, px.
    pub h: f64,
}

impl BBox {
    /// A box from its top-left corner and size, px.
    pub const fn new(x: f64, y: f64, w: f64, h: f64) -> Self {
        Self { x, y, w, h }
    }

    /// The box of an ellipse: centre `(cx, cy)` (pixel centres at integer coordinates),
    /// half-axes `(hx, hy)` px; size `2hx x 2hy`, top-left `(cx - hx + 0.5, cy - hy + 0.5)`.
    pub fn from_ellipse(cx: f64, cy: f64, hx: f64, hy: f64) -> Self {
        let (w, h) = (2.0 * hx, 2.0 * hy);
        Self::new(cx - (w - 1.0) / 2.0, cy - (h - 1.0) / 2.0, w, h)
    }

    /// The ellipse of this box `(cx, cy, hx, hy)`, px: inverse of [`BBox::from_ellipse`].
    pub fn to_ellipse_f64(&self) -> (f64, f64, f64, f64) {
        let (cx, cy) = self.centre();
        (cx, cy, self.w / 2.0, self.h / 2.0)
    }

    /// Centre `(x + (w-1)/2, y + (h-1)/2)`, px (OTB convention).
    pub fn centre(&self) -> (f64, f64) {
        (self.x + (self.w - 1.0) / 2.0, self.y + (self.h - 1.0) / 2.0)
    }

    /// True when all fields are finite and the box has positive width and height.
    /// OTB skips frames whose ground truth is not valid.
    pub fn is_valid(&self) -> bool {
        self.is_finite() && self.w > 0.0 && self.h > 0.0
    }

    fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.w.is_finite() && self.h.is_finite()
    }

    /// Area `w * h`, px²; 0 for an empty or non-finite box.
    pub fn area(&self) -> f64 {
        if self.is_valid() {
            self.w * self.h
        } else {
            0.0
        }
    }

    /// Area of the overlap with `other`, px²; 0 when either box is empty or non-finite.
    pub fn intersection_area(&self, other: &BBox) -> f64 {
        if !self.is_valid() || !other.is_valid() {
            return 0.0;
        }
        let w = (self.x + self.w).min(other.x + other.w) - self.x.max(other.x);
        let h = (self.y + self.h).min(other.y + other.h) - self.y.max(other.y);
        if w > 0.0 && h > 0.0 {
            w * h
        } else {
            0.0
        }
    }

    /// Intersection over union in `[0, 1]`; 0 when either box is empty or non-finite.
    pub fn iou(&self, other: &BBox) -> f64 {
        let inter = self.intersection_area(other);
        let union = self.area() + other.area() - inter;
        if inter > 0.0 && union > 0.0 {
            (inter / union).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// Euclidean distance between the centres, px; `f64::INFINITY` if any coordinate is
    /// not finite.
    pub fn centre_error(&self, other: &BBox) -> f64 {
        if !self.is_finite() || !other.is_finite() {
            return f64::INFINITY;
        }
        let (ax, ay) = self.centre();
        let (bx, by) = other.centre();
        let d = (ax - bx).hypot(ay - by);
        if d.is_finite() {
            d
        } else {
            f64::INFINITY
        }
    }

    /// This box read as 1-based (OTB files) converted to 0-based: `x - 1, y - 1`.
    pub fn from_one_based(self) -> Self {
        Self::new(self.x - 1.0, self.y - 1.0, self.w, self.h)
    }

    /// This 0-based box converted to 1-based: `x + 1, y + 1`.
    pub fn to_one_based(self) -> Self {
        Self::new(self.x + 1.0, self.y + 1.0, self.w, self.h)
    }

    /// The part of the box inside a `width x height` frame (may be empty: `w` or `h` 0).
    pub fn clip(&self, width: f64, height: f64) -> Self {
        let x0 = self.x.clamp(0.0, width.max(0.0));
        let y0 = self.y.clamp(0.0, height.max(0.0));
        let x1 = (self.x + self.w.max(0.0)).clamp(0.0, width.max(0.0));
        let y1 = (self.y + self.h.max(0.0)).clamp(0.0, height.max(0.0));
        Self::new(x0, y0, (x1 - x0).max(0.0), (y1 - y0).max(0.0))
    }
}

/// The IoU thresholds of the success curve: `0, 0.05, ..., 1`.
pub fn success_thresholds() -> [f64; SUCCESS_STEPS] {
    core::array::from_fn(|i| i as f64 / (SUCCESS_STEPS - 1) as f64)
}

/// Success curve: for each threshold `t` of [`success_thresholds`], the share of frames
/// with IoU `> t` (OTB uses the strict inequality). All zeros for no frames.
pub fn success_curve(ious: &[f64]) -> [f64; SUCCESS_STEPS] {
    let t = success_thresholds();
    core::array::from_fn(|i| share(ious, |v| v > t[i]))
}

/// Success AUC: the mean of [`success_curve`], in `[0, 1]`.
pub fn success_auc(ious: &[f64]) -> f64 {
    success_curve(ious).iter().sum::<f64>() / SUCCESS_STEPS as f64
}

/// Share of frames with IoU `> 0.5`.
pub fn success_rate(ious: &[f64]) -> f64 {
    share(ious, |v| v > 0.5)
}

/// Share of frames whose centre error is `<= px`.
pub fn precision_at(errors: &[f64], px: f64) -> f64 {
    share(errors, |e| e <= px)
}

/// Precision curve: [`precision_at`] for the thresholds `0, 1, ..., max_px` px.
pub fn precision_curve(errors: &[f64], max_px: usize) -> Vec<f64> {
    (0..=max_px)
        .map(|t| precision_at(errors, t as f64))
        .collect()
}

/// Arithmetic mean of the non-NaN values; 0 when there are none. Any infinite value gives
/// `f64::INFINITY` (never NaN).
pub fn mean(values: &[f64]) -> f64 {
    if values.iter().any(|v| v.is_infinite()) {
        return f64::INFINITY;
    }
    let (sum, n) = values
        .iter()
        .filter(|v| !v.is_nan())
        .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}

fn share(values: &[f64], pass: impl Fn(f64) -> bool) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.iter().filter(|&&v| pass(v)).count() as f64 / values.len() as f64
}

/// Per-frame scores and their summary over one sequence.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// Frames scored (ground truth valid).
    pub frames: usize,
    /// Frames skipped because their ground truth was empty or non-finite.
    pub skipped: usize,
    /// IoU of each scored frame.
    pub ious: Vec<f64>,
    /// Centre error of each scored frame, px.
    pub centre_errors: Vec<f64>,
    /// Mean IoU.
    pub mean_iou: f64,
    /// Mean centre error, px (infinite if some estimate was non-finite).
    pub mean_centre_error: f64,
    /// Share of frames with IoU > 0.5.
    pub success_rate: f64,
    /// Success AUC over the 21 thresholds.
    pub success_auc: f64,
    /// Share of frames with centre error <= 20 px.
    pub precision_20: f64,
    /// Success curve (see [`success_curve`]).
    pub success_curve: [f64; SUCCESS_STEPS],
    /// Precision curve for 0..=50 px (see [`precision_curve`]).
    pub precision_curve: Vec<f64>,
}

impl Evaluation {
    /// Scores `estimates` against `truth` frame by frame, over the shorter of the two.
    /// Frames whose ground truth is not [`BBox::is_valid`] are skipped (OTB convention);
    /// an empty or non-finite estimate (e.g. a lost tracker) scores IoU 0.
    pub fn new(truth: &[BBox], estimates: &[BBox]) -> Self {
        let (mut ious, mut centre_errors) = (Vec::new(), Vec::new());
        let mut skipped = 0;
        for (gt, est) in truth.iter().zip(estimates) {
            if gt.is_valid() {
                ious.push(gt.iou(est));
                centre_errors.push(gt.centre_error(est));
            } else {
                skipped += 1;
            }
        }
        Self::from_scores(ious, centre_errors, skipped)
    }

    /// Summary of per-frame scores (`ious` and `centre_errors` of the same frames).
    pub fn from_scores(ious: Vec<f64>, centre_errors: Vec<f64>, skipped: usize) -> Self {
        Self {
            frames: ious.len(),
            skipped,
            mean_iou: mean(&ious),
            mean_centre_error: mean(&centre_errors),
            success_rate: success_rate(&ious),
            success_auc: success_auc(&ious),
            precision_20: precision_at(&centre_errors, PRECISION_PX),
            success_curve: success_curve(&ious),
            precision_curve: precision_curve(&centre_errors, PRECISION_MAX_PX),
            ious,
            centre_errors,
        }
    }
}
