//! Structured fuzz inputs shared by the targets: frames of any size, stride, pixel format
//! and content; tracker configurations in which every field may be out of range; ellipses
//! anywhere, the Q16.16 rails included.
//!
//! Each type derives [`Arbitrary`], so libFuzzer's bytes map onto it and mutations of the
//! bytes move through the space of frames and configurations. Every spec mixes "raw"
//! values (any `i32`, any `usize`) with small, plausible ones, so the fuzzer reaches both
//! the rejection paths and the per-frame path quickly.

use arbitrary::Arbitrary;
use rbtrack::cf::scale::ScaleSettings;
use rbtrack::fixed::Q16;
use rbtrack::rect::Rect;
use rbtrack::resample::Scheme;
use rbtrack::tracker::{
    calibration, max_pixels_per_step, Calibration, CfConfig, Config, CueMix, Estimate, Readout,
    SizeMeasurement, Status, Variant,
};
use rbtrack::window::Ellipse;

/// Largest frame buffer a spec builds, bytes (the rest of a bigger frame is left out, so
/// `ImageView::new` rejects it as too short).
pub const MAX_BUFFER: usize = 1 << 18;

/// A Q16.16 value.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum Q {
    /// Any raw value, the rails included.
    Raw(i32),
    /// A whole number.
    Int(i16),
    /// A fraction in `[0, 1)`.
    Frac(u16),
    /// 1.0.
    One,
    /// [`Q16::MAX`].
    Max,
    /// [`Q16::MIN`].
    Min,
    /// 0.
    Zero,
}

impl Q {
    /// The value.
    pub fn get(self) -> Q16 {
        match self {
            Q::Raw(v) => Q16::from_bits(v),
            Q::Int(v) => Q16::from_int(v as i32),
            Q::Frac(v) => Q16::from_bits(v as i32),
            Q::One => Q16::ONE,
            Q::Max => Q16::MAX,
            Q::Min => Q16::MIN,
            Q::Zero => Q16::ZERO,
        }
    }
}

/// A frame dimension, px.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum Dim {
    /// 0..=255.
    Small(u8),
    /// 0..=65535 (above `MAX_SIDE` from 16384 on).
    Medium(u16),
    /// Anything.
    Any(usize),
}

impl Dim {
    /// The value, px.
    pub fn get(self) -> usize {
        match self {
            Dim::Small(v) => v as usize,
            Dim::Medium(v) => v as usize,
            Dim::Any(v) => v,
        }
    }
}

/// Pixel format of a frame.
#[derive(Arbitrary, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `Gray8`.
    Gray8,
    /// `Rgb565Le`.
    Rgb565Le,
    /// `Rgb565Be`.
    Rgb565Be,
    /// `Rgb888`.
    Rgb888,
    /// `Bgr888`.
    Bgr888,
    /// `Yuyv`.
    Yuyv,
    /// `Uyvy`.
    Uyvy,
}

impl Format {
    /// Bytes per pixel.
    pub fn bytes_per_pixel(self) -> usize {
        match self {
            Format::Gray8 => 1,
            Format::Rgb888 | Format::Bgr888 => 3,
            _ => 2,
        }
    }
}

/// Calls `$body` with the type `$p` bound to the pixel format of `$format`.
#[macro_export]
macro_rules! with_format {
    ($format:expr, $p:ident => $body:expr) => {
        match $format {
            $crate::Format::Gray8 => {
                type $p = rbtrack::image::Gray8;
                $body
            }
            $crate::Format::Rgb565Le => {
                type $p = rbtrack::image::Rgb565Le;
                $body
            }
            $crate::Format::Rgb565Be => {
                type $p = rbtrack::image::Rgb565Be;
                $body
            }
            $crate::Format::Rgb888 => {
                type $p = rbtrack::image::Rgb888;
                $body
            }
            $crate::Format::Bgr888 => {
                type $p = rbtrack::image::Bgr888;
                $body
            }
            $crate::Format::Yuyv => {
                type $p = rbtrack::image::Yuyv;
                $body
            }
            $crate::Format::Uyvy => {
                type $p = rbtrack::image::Uyvy;
                $body
            }
        }
    };
}

/// A frame: size, stride and bytes, possibly inconsistent.
#[derive(Arbitrary, Debug, Clone)]
pub struct FrameSpec {
    /// Width, px.
    pub width: Dim,
    /// Height, px.
    pub height: Dim,
    /// Stride: `width + stride` (wrapping) unless `stride_raw`, then `stride` itself.
    pub stride: Dim,
    /// Whether `stride` is the stride itself rather than the padding.
    pub stride_raw: bool,
    /// Bytes missing from the end of the buffer.
    pub shorten: u8,
    /// Pixel bytes, repeated to fill the buffer (zeros when empty).
    pub pattern: Vec<u8>,
}

/// A built frame buffer and the size claimed for it.
#[derive(Debug, Clone)]
pub struct Frame {
    /// Bytes.
    pub buf: Vec<u8>,
    /// Claimed width, px.
    pub width: usize,
    /// Claimed height, px.
    pub height: usize,
    /// Claimed stride, px.
    pub stride: usize,
}

impl FrameSpec {
    /// Builds the buffer: as long as the claimed size needs (less `shorten` bytes) when
    /// that is at most [`MAX_BUFFER`], else just the pattern.
    pub fn build(&self, bytes_per_pixel: usize) -> Frame {
        let width = self.width.get();
        let height = self.height.get();
        let stride = if self.stride_raw {
            self.stride.get()
        } else {
            width.wrapping_add(self.stride.get())
        };
        let needed = height
            .checked_sub(1)
            .and_then(|rows| rows.checked_mul(stride))
            .and_then(|px| px.checked_add(width))
            .and_then(|px| px.checked_mul(bytes_per_pixel));
        let len = match needed {
            Some(n) if n <= MAX_BUFFER => n.saturating_sub(self.shorten as usize),
            _ => self.pattern.len().min(MAX_BUFFER),
        };
        let buf = if self.pattern.is_empty() {
            vec![0; len]
        } else {
            self.pattern.iter().copied().cycle().take(len).collect()
        };
        Frame {
            buf,
            width,
            height,
            stride,
        }
    }
}

/// An ellipse: absolute Q16.16 values, or placed relative to a frame.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum EllipseSpec {
    /// Any centre and half-axes.
    Absolute {
        /// Centre column.
        cx: Q,
        /// Centre row.
        cy: Q,
        /// Horizontal half-axis.
        hx: Q,
        /// Vertical half-axis.
        hy: Q,
    },
    /// Centre at `(fx, fy) / 255` of the frame, half-axes in px.
    Relative {
        /// Horizontal position, 0 (left) to 255 (right).
        fx: u8,
        /// Vertical position, 0 (top) to 255 (bottom).
        fy: u8,
        /// Horizontal half-axis, px.
        hx: u16,
        /// Vertical half-axis, px.
        hy: u16,
    },
}

impl EllipseSpec {
    /// The ellipse for a frame of `width x height` px.
    pub fn get(self, width: usize, height: usize) -> Ellipse {
        match self {
            EllipseSpec::Absolute { cx, cy, hx, hy } => {
                Ellipse::new(cx.get(), cy.get(), hx.get(), hy.get())
            }
            EllipseSpec::Relative { fx, fy, hx, hy } => {
                let at = |f: u8, side: usize| {
                    Q16::from_ratio(f as i64 * side.saturating_sub(1) as i64, 255)
                };
                Ellipse::new(
                    at(fx, width),
                    at(fy, height),
                    Q16::from_int(hx as i32),
                    Q16::from_int(hy as i32),
                )
            }
        }
    }
}

/// Filter variant.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum VariantSpec {
    /// Colour particle filter.
    ColourPf,
    /// Rao-Blackwellised particle filter.
    Rbpf,
}

/// Resampling scheme.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum SchemeSpec {
    /// Multinomial.
    Multinomial,
    /// Systematic.
    Systematic,
    /// Stratified.
    Stratified,
    /// Residual.
    Residual,
}

impl SchemeSpec {
    /// The scheme.
    pub fn get(self) -> Scheme {
        match self {
            SchemeSpec::Multinomial => Scheme::Multinomial,
            SchemeSpec::Systematic => Scheme::Systematic,
            SchemeSpec::Stratified => Scheme::Stratified,
            SchemeSpec::Residual => Scheme::Residual,
        }
    }
}

/// Estimate read-out.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum ReadoutSpec {
    /// Weighted mean.
    Mean,
    /// Best particle.
    Best,
    /// Robust mean with this radius.
    RobustMean(Q),
}

/// Cue combination.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum CueMixSpec {
    /// Average with this colour share.
    Average(Q),
    /// Product.
    Product,
}

/// A tracker configuration: the defaults of `variant`, with each field that is `Some`
/// replaced by any value (in range or not).
#[derive(Arbitrary, Debug, Clone)]
#[allow(missing_docs)]
pub struct ConfigSpec {
    pub variant: VariantSpec,
    pub seed: u64,
    pub pixels_per_window: Option<u32>,
    pub position_noise: Option<Q>,
    pub relative_position_noise: Option<Q>,
    pub velocity_noise: Option<Q>,
    pub velocity_keep: Option<Q>,
    pub scale_noise: Option<Q>,
    pub colour_sigma: Option<Q>,
    pub gradient_sigma: Option<Q>,
    pub cue_mix: Option<CueMixSpec>,
    pub gradient_points: Option<u8>,
    pub gradient_search: Option<u8>,
    pub resampling: Option<SchemeSpec>,
    pub resample_below: Option<Q>,
    pub readout: Option<ReadoutSpec>,
    pub adapt_rate: Option<Q>,
    pub adapt_above: Option<Q>,
    pub spread_penalty: Option<Q>,
    pub uncertain_below: Option<Q>,
    pub lost_below: Option<Q>,
    pub redetect_share: Option<Q>,
    pub scale_per_row: Option<Q>,
    pub kalman_q: Option<Q>,
    pub kalman_r: Option<Q>,
    pub scale_step: Option<Q>,
    pub min_half_axis: Option<Q>,
    pub background_weighting: Option<bool>,
    pub background_floor: Option<Q>,
    pub ring_scale: Option<Q>,
    pub split_halves: Option<bool>,
    pub contrast_sigma: Option<Option<Q>>,
    pub contrast_ring: Option<Q>,
    pub size_by_likelihood: Option<bool>,
    pub freeze_size: Option<bool>,
    pub redetect_prior: Option<Q>,
    pub learn_scale_per_row: Option<bool>,
}

impl ConfigSpec {
    /// The configuration.
    pub fn build(&self) -> Config {
        let mut c = Config::new(match self.variant {
            VariantSpec::ColourPf => Variant::ColourPf,
            VariantSpec::Rbpf => Variant::Rbpf,
        });
        c.seed = self.seed;
        let set = |field: &mut Q16, v: Option<Q>| {
            if let Some(v) = v {
                *field = v.get();
            }
        };
        if let Some(v) = self.pixels_per_window {
            c.pixels_per_window = v;
        }
        set(&mut c.position_noise, self.position_noise);
        set(&mut c.relative_position_noise, self.relative_position_noise);
        set(&mut c.velocity_noise, self.velocity_noise);
        set(&mut c.velocity_keep, self.velocity_keep);
        set(&mut c.scale_noise, self.scale_noise);
        set(&mut c.colour_sigma, self.colour_sigma);
        set(&mut c.gradient_sigma, self.gradient_sigma);
        if let Some(m) = self.cue_mix {
            c.cue_mix = match m {
                CueMixSpec::Average(a) => CueMix::Average(a.get()),
                CueMixSpec::Product => CueMix::Product,
            };
        }
        if let Some(v) = self.gradient_points {
            c.gradient_points = v;
        }
        if let Some(v) = self.gradient_search {
            c.gradient_search = v;
        }
        if let Some(s) = self.resampling {
            c.resampling = s.get();
        }
        set(&mut c.resample_below, self.resample_below);
        if let Some(r) = self.readout {
            c.readout = match r {
                ReadoutSpec::Mean => Readout::Mean,
                ReadoutSpec::Best => Readout::Best,
                ReadoutSpec::RobustMean(q) => Readout::RobustMean(q.get()),
            };
        }
        set(&mut c.adapt_rate, self.adapt_rate);
        set(&mut c.adapt_above, self.adapt_above);
        set(&mut c.spread_penalty, self.spread_penalty);
        set(&mut c.uncertain_below, self.uncertain_below);
        set(&mut c.lost_below, self.lost_below);
        set(&mut c.redetect_share, self.redetect_share);
        set(&mut c.scale_per_row, self.scale_per_row);
        set(&mut c.kalman_q, self.kalman_q);
        set(&mut c.kalman_r, self.kalman_r);
        set(&mut c.scale_step, self.scale_step);
        set(&mut c.min_half_axis, self.min_half_axis);
        let flag = |field: &mut bool, v: Option<bool>| {
            if let Some(v) = v {
                *field = v;
            }
        };
        flag(&mut c.background_weighting, self.background_weighting);
        set(&mut c.background_floor, self.background_floor);
        set(&mut c.ring_scale, self.ring_scale);
        flag(&mut c.split_halves, self.split_halves);
        if let Some(sigma) = self.contrast_sigma {
            c.contrast_sigma = sigma.map(Q::get);
        }
        set(&mut c.contrast_ring, self.contrast_ring);
        if let Some(likelihood) = self.size_by_likelihood {
            c.size_measurement = match likelihood {
                true => SizeMeasurement::Likelihood,
                false => SizeMeasurement::Contrast,
            };
        }
        flag(&mut c.freeze_size, self.freeze_size);
        set(&mut c.redetect_prior, self.redetect_prior);
        flag(&mut c.learn_scale_per_row, self.learn_scale_per_row);
        c
    }
}

/// Whether `init` is an initial ellipse `Tracker::new` must accept in a
/// `width x height` frame: half-axes at least `min_half_axis`, centre inside the frame.
pub fn init_is_valid(init: &Ellipse, min_half_axis: Q16, width: usize, height: usize) -> bool {
    let inside = |v: Q16, side: usize| v >= Q16::ZERO && v <= Q16::from_int(side as i32 - 1);
    init.hx >= min_half_axis
        && init.hy >= min_half_axis
        && inside(init.cx, width)
        && inside(init.cy, height)
}

/// Checks an estimate's score is in `[0, 1]` and its confidence is the score through
/// `table`.
fn check_confidence(e: &Estimate, table: &Calibration) {
    assert!(
        e.score >= Q16::ZERO && e.score <= Q16::ONE,
        "score {:?}",
        e.score
    );
    assert_eq!(e.confidence, table.confidence(e.score), "{e:?}");
}

/// Checks the documented guarantees of a step's result in a `width x height` frame:
/// centre inside the frame, half-axes positive and at most the frame's longer side (or
/// `min_half_axis` if that is larger), score in `[0, 1]` and the confidence the variant's
/// table gives it, and at most `max_pixels_per_step(n, pixels_per_window)` pixels read.
pub fn check_estimate(
    e: &Estimate,
    config: &Config,
    n: usize,
    pixels_visited: u32,
    width: usize,
    height: usize,
) {
    let el = e.ellipse;
    let max_x = Q16::from_int(width as i32 - 1);
    let max_y = Q16::from_int(height as i32 - 1);
    assert!(
        el.cx >= Q16::ZERO && el.cx <= max_x,
        "cx {:?} in {width}x{height}",
        el.cx
    );
    assert!(
        el.cy >= Q16::ZERO && el.cy <= max_y,
        "cy {:?} in {width}x{height}",
        el.cy
    );
    let max_half = max_x.max(max_y).max(config.min_half_axis);
    for h in [el.hx, el.hy] {
        assert!(
            h > Q16::ZERO && h <= max_half,
            "half-axis {h:?} in {width}x{height}"
        );
    }
    check_confidence(e, config.variant.calibration());
    let bound = max_pixels_per_step(n, config.pixels_per_window);
    assert!(
        pixels_visited as u64 <= bound,
        "{pixels_visited} pixels, N = {n}, bound {bound}"
    );
}

/// A correlation-filter tracker configuration: [`CfConfig::default`], with each field that
/// is `Some` replaced by any value (in range or not).
#[derive(Arbitrary, Debug, Clone)]
#[allow(missing_docs)]
pub struct CfConfigSpec {
    pub padding: Option<Q>,
    pub cell: Option<Dim>,
    pub sigma: Option<Q>,
    pub lambda: Option<u32>,
    pub cf_rate: Option<Q>,
    pub colour_rate: Option<Q>,
    pub inner_padding: Option<Q>,
    pub merge: Option<Q>,
    pub scale_step: Option<Q>,
    pub scale_sigma: Option<Q>,
    pub scale_lambda: Option<u32>,
    pub scale_area: Option<u32>,
    pub scale_cell: Option<Dim>,
    pub scale_interpolate: Option<bool>,
    pub scale_rate: Option<Q>,
    pub max_scale_change: Option<Q>,
    pub learn_above: Option<Q>,
    pub uncertain_below: Option<Q>,
    pub lost_below: Option<Q>,
    pub search_below: Option<Q>,
    pub search_until: Option<Q>,
    pub redetect: Option<u8>,
    pub redetect_above: Option<Q>,
    pub redetect_colour: Option<Q>,
    pub coast: Option<bool>,
    pub scale_above: Option<Q>,
    pub lead: Option<Q>,
}

impl CfConfigSpec {
    /// The configuration.
    pub fn build(&self) -> CfConfig {
        let mut c = CfConfig::default();
        let set = |field: &mut Q16, v: Option<Q>| {
            if let Some(v) = v {
                *field = v.get();
            }
        };
        set(&mut c.padding, self.padding);
        if let Some(v) = self.cell {
            c.cell = v.get();
        }
        set(&mut c.sigma, self.sigma);
        if let Some(v) = self.lambda {
            c.lambda = v;
        }
        set(&mut c.cf_rate, self.cf_rate);
        set(&mut c.colour_rate, self.colour_rate);
        set(&mut c.inner_padding, self.inner_padding);
        set(&mut c.merge, self.merge);
        let s: &mut ScaleSettings = &mut c.scale;
        set(&mut s.step, self.scale_step);
        set(&mut s.sigma, self.scale_sigma);
        if let Some(v) = self.scale_lambda {
            s.lambda = v;
        }
        if let Some(v) = self.scale_area {
            s.area = v;
        }
        if let Some(v) = self.scale_cell {
            s.cell = v.get();
        }
        if let Some(v) = self.scale_interpolate {
            s.interpolate = v;
        }
        set(&mut c.scale_rate, self.scale_rate);
        set(&mut c.max_scale_change, self.max_scale_change);
        set(&mut c.learn_above, self.learn_above);
        set(&mut c.uncertain_below, self.uncertain_below);
        set(&mut c.lost_below, self.lost_below);
        set(&mut c.search_below, self.search_below);
        set(&mut c.search_until, self.search_until);
        if let Some(v) = self.redetect {
            c.redetect = v.into();
        }
        set(&mut c.redetect_above, self.redetect_above);
        set(&mut c.redetect_colour, self.redetect_colour);
        if let Some(v) = self.coast {
            c.coast = v;
        }
        set(&mut c.scale_above, self.scale_above);
        set(&mut c.lead, self.lead);
        c
    }
}

/// An initial box: absolute Q16.16 values, or placed relative to a frame.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum RectSpec {
    /// Any corner and size, the rails included.
    Absolute {
        /// Left edge.
        x: Q,
        /// Top edge.
        y: Q,
        /// Width.
        w: Q,
        /// Height.
        h: Q,
    },
    /// Centre at `(fx, fy) / 255` of the frame, size `w x h` px.
    Relative {
        /// Horizontal position, 0 (left) to 255 (right).
        fx: u8,
        /// Vertical position, 0 (top) to 255 (bottom).
        fy: u8,
        /// Width, px.
        w: u8,
        /// Height, px.
        h: u8,
    },
}

impl RectSpec {
    /// The box for a frame of `width x height` px.
    pub fn get(self, width: usize, height: usize) -> Rect {
        match self {
            RectSpec::Absolute { x, y, w, h } => Rect::from_q16(x.get(), y.get(), w.get(), h.get()),
            RectSpec::Relative { fx, fy, w, h } => {
                let corner = |f: u8, side: usize, size: u8| {
                    f as i32 * side.saturating_sub(1).min(1 << 14) as i32 / 255 - size as i32 / 2
                };
                Rect::new(
                    corner(fx, width, w),
                    corner(fy, height, h),
                    w as i32,
                    h as i32,
                )
            }
        }
    }
}

/// Whether `CfTracker::start` must accept `init` in a `width x height` frame (given a
/// valid configuration): both sides at least 4 px, and the centre `x + (w-1)/2`,
/// `y + (h-1)/2` in `[0, width-1] x [0, height-1]`. Computed exactly on the raw Q16.16
/// values (twice the centre against twice the bounds), not through `Rect::centre`.
pub fn cf_init_is_valid(init: &Rect, width: usize, height: usize) -> bool {
    let four = 4_i64 << 16;
    let one = 1_i64 << 16;
    // 0 <= 2 x + w - 1 <= 2 (n - 1), Q16.16 bits.
    let inside = |corner: Q16, size: Q16, side: usize| {
        let twice = 2 * corner.to_bits() as i64 + size.to_bits() as i64 - one;
        let last = (side as i64 - 1).min(i16::MAX as i64) << 16;
        twice >= 0 && twice <= 2 * last
    };
    init.w.to_bits() as i64 >= four
        && init.h.to_bits() as i64 >= four
        && inside(init.x, init.w, width)
        && inside(init.y, init.h, height)
}

/// What a correlation-filter tracker started on: the frame's size and the first box's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CfStart {
    /// Frame width, px.
    pub width: usize,
    /// Frame height, px.
    pub height: usize,
    /// The first box's width and height, px.
    pub size: (Q16, Q16),
}

/// Checks the documented guarantees of a correlation-filter step (or camera motion) when
/// the tracker started as `start` says: centre inside that frame; the first box's aspect
/// ratio; each side at least 4 px and at most the frame's side or the first box's, if
/// larger; score in `[0, 1]` and the confidence the tracker's table gives it; and, for a
/// step after the estimate `previous` whose merged peak was `peak`, a size at most
/// `max_scale_change` from its size, the same size when the peak is below `scale_above`,
/// and the status the confidence and `config`'s thresholds give (`Lost` below
/// `lost_below`, `Uncertain` below `uncertain_below`; `Lost` after `Lost` below
/// `uncertain_below`, as a search holds it).
pub fn check_cf_estimate(
    e: &Estimate,
    config: &CfConfig,
    start: &CfStart,
    previous: Option<(&Estimate, Q16)>,
) {
    let (width, height) = (start.width, start.height);
    let el = e.ellipse;
    let max_x = Q16::from_int(width as i32 - 1);
    let max_y = Q16::from_int(height as i32 - 1);
    assert!(
        el.cx >= Q16::ZERO && el.cx <= max_x,
        "cx {:?} in {width}x{height}",
        el.cx
    );
    assert!(
        el.cy >= Q16::ZERO && el.cy <= max_y,
        "cy {:?} in {width}x{height}",
        el.cy
    );
    // Sizes in Q16.16 bits: a half-axis is half the size, floored, off by at most 2 bits.
    let bits = |v: Q16| i128::from(v.to_bits());
    let (w0, h0) = (bits(start.size.0), bits(start.size.1));
    let (hx, hy) = (bits(el.hx), bits(el.hy));
    let slack = 4 * (w0 + h0);
    assert!(
        (2 * hx * h0 - 2 * hy * w0).abs() <= slack,
        "aspect {:?} x {:?} of a first box {:?}",
        el.hx,
        el.hy,
        start.size
    );
    let four = 4i128 << 16;
    let most = |frame: usize, first: i128| (i128::from(frame as i32) << 16).max(first);
    for (half, frame, first) in [(hx, width, w0), (hy, height, h0)] {
        assert!(
            2 * half >= four - 4 && 2 * half <= most(frame, first) + 4,
            "side {} px in {width}x{height}, first box {:?}",
            2 * half / 65536,
            start.size
        );
    }
    check_confidence(e, &calibration::CORRELATION);
    if let Some((previous, peak)) = previous {
        let before = bits(previous.ellipse.hx);
        assert!(peak >= Q16::ZERO && peak <= Q16::ONE, "peak {peak:?}");
        if peak < config.scale_above {
            assert_eq!(el.hx, previous.ellipse.hx, "peak {peak:?}");
            assert_eq!(el.hy, previous.ellipse.hy, "peak {peak:?}");
        }
        // hx <= m before and before <= m hx, m in Q16.16. The size is the first box's
        // times a Q16.16 factor floored twice a step (the clamp to 1 / m and the product),
        // so a half-width may fall short by 2 bits of the factor, w0 / 2^16 bits of it,
        // and 2 more to the halving.
        let m = bits(config.max_scale_change);
        let off = 2 + (w0 >> 16);
        assert!(
            (hx - off) << 16 <= m * (before + off) && (before - off) << 16 <= m * (hx + off),
            "half-width {:?} after {:?}, at most {:?} apart",
            el.hx,
            previous.ellipse.hx,
            config.max_scale_change
        );
        let status = if e.confidence < config.lost_below {
            Status::Lost
        } else if e.confidence < config.uncertain_below {
            Status::Uncertain
        } else {
            Status::Tracking
        };
        // Lost may be held from a lost step while the tracker searches.
        let held = previous.status == Status::Lost
            && e.status == Status::Lost
            && e.confidence < config.uncertain_below;
        assert!(
            e.status == status || held,
            "{:?} at confidence {:?} after {:?}",
            e.status,
            e.confidence,
            previous.status
        );
    }
}
