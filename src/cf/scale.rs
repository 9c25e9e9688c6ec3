//! The scale filter (DSST, Danelljan et al., BMVC 2014): a 1-D correlation filter over `S`
//! scaled samples of the target, each described by its fHOG cells; the integer port of the
//! host's `cf64::scale` with 9 unsigned channels of the luma and no window over the scales.
//!
//! Sample `s` is the target's box times `step^(mid - s)`, `mid = ceil(S / 2) - 1`,
//! resampled to a model size fixed by the first box (area at most `area` px^2, small boxes
//! grown to 3 cells a side, in whole cells, at least 2 a side, at most [`MAX_CELLS`]) and
//! described by the 9 unsigned fHOG
//! channels of its cells: one column of `D` features. Per feature `d`, `X_d` is the 1-D
//! transform of its row over the scales; the filter keeps
//! `A_d <- (1 - eta) A_d + eta Y conj(X_d)` and `B <- (1 - eta) B + eta sum_d |X_d|^2`,
//! `Y` the transform of a Gaussian over the scales (width `sqrt(S) sigma`) peaked at the
//! sample of the target's size; new samples `Z` answer `IFFT(sum_d A_d Z_d / (B + lambda))`,
//! peaked at the scale the target now has.
//!
//! # Two features in one transform
//! The features are real, so their spectra are Hermitian (`X_S-k = conj(X_k)`), and so are
//! the numerators. Features `2p` and `2p + 1` are transformed together, as the real and
//! imaginary parts of one row: `Z_p = X_2p + i X_2p+1`, whose mirror image gives both back
//! (`conj(Z_p,S-k) = X_2p - i X_2p+1`). The filter keeps only these pair spectra and the
//! pair numerators `P_p = A_2p + i A_2p+1`, half the memory and half the transforms of one
//! row per feature, and needs no unpacking: the new numerator of a pair is
//! `Y_k Z_p,S-k`, the denominator `sum_p (|Z_p,k|^2 + |Z_p,S-k|^2) / 2`, and with
//! `U_k = sum_p P_p,k conj(Z_p,S-k)` the response's spectrum is `(U_k + conj(U_S-k)) / 2`.
//!
//! # Fixed-point scales
//! - Features: Q15 from [`Extractor::extract`] (`|x| <= 2^15`), shifted to Q21.
//! - Pair spectra `Z_p`: the transform of Q21 features over the scales, Q21, `|Z| <=
//!   sqrt 2 S 2^21 <= 2^25.5`: the direct transform ([`forward_direct`], any `S` from 2
//!   to 16, within 1 LSB here), rounded, with no block exponent.
//! - Label: Q16 from [`exp_neg`] (peak 65,535), its spectrum `|Y| <= S 2^16`, Q16.
//! - Pair numerators `P_p`: the Q37 products `Y_k Z_p,S-k` rounded to Q17 (`>> 20`), `i32`,
//!   `|P| <= sqrt 2 S^2 2^17 <= 2^25.5`: learning blends them without a clamp (a blend
//!   lies between its old and new values).
//! - Denominator `B`: Q42, `i64`, `<= D S^2 2^42 < 2^58.2` (its sums of `|Z|^2` need no
//!   saturation); `lambda` (Q0.32) raised to Q42.
//! - `U_k + conj(U_S-k)`: each product Q38 floored to Q30 (`>> 8`), `<= 2^43`, the sum
//!   `<= 2^52.2`, `i64` (accumulated without saturation); twice the response's
//!   spectrum, so the quotient below shifts one bit less.
//! - Quotient by `B + lambda`: Q16 saturated to `i32` (in `i128`), the real parts of its
//!   direct inverse transform ([`inverse_direct_real`], `1/S` included): the response,
//!   Q16 (about 1 at the peak for the trained samples). The label's peak of 65,535 rather
//!   than 65,536 costs 1.5e-5 of it.
//!
//! The size factor `step^x` of a fractional `x` is the integer power times the binomial
//! series of `(1 + u)^f`, `u = step - 1 <= 1/2`, `0 <= f < 1`, 12 terms, in Q30: within
//! 2 LSB of Q16.16 for `|x| <= 8` at the steps allowed (1.2 measured).
//!
//! Against the host's f64 filter on the same (Q15) features of its test scene, the
//! responses agree within 3.0e-5 and the size factors within 8.8e-6 (4 scales of 1.18 and
//! 8 of 1.08); each on its own features of the frame, the factors within 1.2e-5
//! (`host-tests/tests/cf_scale.rs`). Stack: 640 bytes of cells for one sample, a few
//! hundred more; the filter itself is 9,336 bytes for `S = 4` on a 32-bit target.

use super::features::{Cell, Extractor, Sampling, CHANNELS};
use crate::fft::{forward_direct, inverse_direct_real, mirrored, Complex, MAX_DIRECT_POINTS};
use crate::fixed::{isqrt_u64, Q16};
use crate::image::{ImageView, PixelFormat};
use crate::likelihood::exp_neg;

/// Largest number of cells of a sample: 512 px^2 of 4 px cells.
pub const MAX_CELLS: usize = 32;

/// fHOG channels per cell the filter reads: the 9 unsigned ones (`Cell[1..10]`).
pub const CELL_FEATURES: usize = CHANNELS - 1;

/// Largest number of features of a sample, `D`.
pub const MAX_FEATURES: usize = MAX_CELLS * CELL_FEATURES;

/// Largest number of feature pairs, each transformed as one complex row.
const MAX_PAIRS: usize = MAX_FEATURES.div_ceil(2);

/// Left shift of the Q15 features to Q21.
const FEATURE_SHIFT: u32 = 6;

/// Right shift of the Q37 products `Y conj(X)` to the numerator's Q17.
const NUM_SHIFT: u32 = 20;

/// Right shift of the Q38 products `A Z` to Q30.
const SUM_SHIFT: u32 = 8;

/// Left shift of a Q30 quotient by a Q42 denominator to Q16, less 1 for the doubled sum
/// the pairs give.
const QUOTIENT_SHIFT: u32 = 16 + 42 - 30 - 1;

/// Q30 fraction bits of the powers of the step.
const POW_BITS: u32 = 30;

/// The scale filter's settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ScaleSettings {
    /// Ratio between neighbouring scales, Q16.16, limited to `(1, 1.5]`.
    pub step: Q16,
    /// Width of the desired response, times `sqrt(S)`, scales, Q16.16, limited to
    /// `[1/256, 64]`.
    pub sigma: Q16,
    /// Regulariser, in 2^-32 of a feature squared (Q0.32: 1e-3 is 4,294,967).
    pub lambda: u32,
    /// Largest model area, px^2 (`1..=65,536`; the model has at most [`MAX_CELLS`] cells).
    pub area: u32,
    /// fHOG cell of the samples, px (`2..=8`, even; [`CfConfig`](crate::tracker::CfConfig)
    /// refuses others, and the filter rounds an odd one down).
    pub cell: usize,
    /// Read the scale between samples (the parabola through the peak and its neighbours).
    pub interpolate: bool,
}

impl ScaleSettings {
    /// Every field zero.
    pub const UNSET: Self = Self {
        step: Q16::ZERO,
        sigma: Q16::ZERO,
        lambda: 0,
        area: 0,
        cell: 0,
        interpolate: false,
    };

    /// The settings limited to their ranges.
    fn limited(self) -> Self {
        Self {
            step: self.step.clamp(
                Q16::from_bits(Q16::ONE.to_bits() + 1),
                Q16::from_ratio(3, 2),
            ),
            sigma: self.sigma.clamp(Q16::from_bits(1 << 8), Q16::from_int(64)),
            area: self.area.clamp(1, 1 << 16),
            cell: self.cell.clamp(2, 8) & !1,
            ..self
        }
    }
}

/// The sampled grid: cells across and down.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Grid {
    cols: usize,
    rows: usize,
}

impl Grid {
    /// The model of a first box of `size` px (Q16.16) as the host's: each side times
    /// `sqrt(area / (w h))` where that shrinks it, else grown (up to that) until the shorter
    /// side is 3 cells; in whole cells, at least 2, at most [`MAX_CELLS`] (the longer side
    /// cut to `MAX_CELLS` over the other's cells, that at most half of them).
    fn new(settings: &ScaleSettings, size: (Q16, Q16)) -> Self {
        let (w, h) = (
            size.0.to_bits().max(1 << 16) as u64,
            size.1.to_bits().max(1 << 16) as u64,
        );
        let area = settings.area as u64;
        // floor(a sqrt(area / (a b))) = floor(sqrt(area a / b))
        let fit = |a: u64, b: u64| isqrt_u64((area * a).checked_div(b).unwrap_or(0));
        let shorter = w.min(h);
        let least = (3 * settings.cell as u64) << 16;
        // Q16.16 to whole px by shifts, and a division the optimiser can see is safe
        // inside the closure (no panic path: examples/no_panic.rs).
        let side = |a: u64, b: u64| match (a * b) >> 32 > area {
            true => fit(a, b),
            false if shorter >= least => a >> 16,
            false => ((a * least).checked_div(shorter).unwrap_or(0) >> 16).min(fit(a, b)),
        };
        let cells = |a: u64, b: u64| {
            (side(a, b) as usize)
                .checked_div(settings.cell)
                .unwrap_or(0)
                .max(2)
        };
        let (cols, rows) = (cells(w, h), cells(h, w));
        let (cols, rows) = if cols * rows <= MAX_CELLS {
            (cols, rows)
        } else if cols >= rows {
            let rows = rows.min(MAX_CELLS / 2);
            (MAX_CELLS / rows, rows)
        } else {
            let cols = cols.min(MAX_CELLS / 2);
            (cols, MAX_CELLS / cols)
        };
        Self { cols, rows }
    }
}

/// The scale filter, `S` scales (`2..=16`).
///
/// 9,336 bytes for `S = 4` on a 32-bit target (9,368 on a 64-bit host; 11,656 for `S = 5`,
/// 18,616 for `S = 8`): the numerator and the last samples' spectra, packed in pairs,
/// `MAX_FEATURES / 2 x S` complex each (4,608 bytes at `S = 4`), and `S` values of the
/// rest.
#[derive(Clone, Debug)]
pub struct ScaleFilter<const S: usize> {
    settings: ScaleSettings,
    grid: Grid,
    /// Features in use, `D = cols rows 9 <= MAX_FEATURES`.
    features: usize,
    /// Pairs of features in use, `ceil(D / 2)`.
    pairs: usize,
    /// `1 / (2 (sqrt(S) sigma)^2)`, per scale squared, Q16.16.
    cost: Q16,
    /// Regulariser, Q42.
    lambda: i64,
    /// Size factor of sample `s`, Q16.16.
    factors: [Q16; S],
    /// `P_p = A_2p + i A_2p+1`, Q17.
    num: [[Complex; S]; MAX_PAIRS],
    /// `B`, Q42.
    den: [i64; S],
    /// The last samples' spectra, `Z_p = X_2p + i X_2p+1`, Q21.
    samples: [[Complex; S]; MAX_PAIRS],
    /// The last response, Q16.
    response: [i32; S],
    /// The best of the last samples.
    best: usize,
}

impl<const S: usize> ScaleFilter<S> {
    /// A filter with nothing learnt, every bit zero.
    pub const UNSET: Self = Self {
        settings: ScaleSettings::UNSET,
        grid: Grid { cols: 0, rows: 0 },
        features: 0,
        pairs: 0,
        cost: Q16::ZERO,
        lambda: 0,
        factors: [Q16::ZERO; S],
        num: [[Complex::ZERO; S]; MAX_PAIRS],
        den: [0; S],
        samples: [[Complex::ZERO; S]; MAX_PAIRS],
        response: [0; S],
        best: 0,
    };

    /// The middle sample, factor 1: `ceil(S / 2) - 1`.
    pub const MIDDLE: usize = S.div_ceil(2) - 1;

    /// A filter for a target of `size` px (width, height, Q16.16) at `centre` (px,
    /// Q16.16), trained on `frame` there, its samples' features taken by `extractor`.
    pub fn new<P: PixelFormat>(
        settings: ScaleSettings,
        frame: &ImageView<'_, P>,
        centre: (Q16, Q16),
        size: (Q16, Q16),
        extractor: &mut Extractor,
    ) -> Self {
        let mut filter = Self::UNSET;
        filter.start(settings, frame, centre, size, extractor);
        filter
    }

    /// Trains afresh in place, as [`ScaleFilter::new`].
    pub fn start<P: PixelFormat>(
        &mut self,
        settings: ScaleSettings,
        frame: &ImageView<'_, P>,
        centre: (Q16, Q16),
        size: (Q16, Q16),
        extractor: &mut Extractor,
    ) {
        self.reset(settings, size);
        self.sample(frame, centre, size, extractor);
        self.learn_at(Self::MIDDLE, Q16::ONE);
    }

    /// A filter for a target of `size` px trained on the features `rows` as
    /// [`ScaleFilter::new`] on a frame's: `rows[d][s]` is feature `d` (cell `d / 9`,
    /// row-major, channel `1 + d % 9`) of sample `s`, Q15; missing rows count as zero.
    pub fn from_features(settings: ScaleSettings, size: (Q16, Q16), rows: &[[i16; S]]) -> Self {
        let mut filter = Self::UNSET;
        filter.reset(settings, size);
        filter.load(rows);
        filter.learn_at(Self::MIDDLE, Q16::ONE);
        filter
    }

    /// Samples the `S` scales of a target of `size` px at `centre` and returns the size
    /// factor of the best, Q16.16 (1: unchanged); keeps the samples for
    /// [`ScaleFilter::learn`].
    pub fn respond<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        centre: (Q16, Q16),
        size: (Q16, Q16),
        extractor: &mut Extractor,
    ) -> Q16 {
        self.sample(frame, centre, size, extractor);
        self.answer()
    }

    /// [`ScaleFilter::respond`] to the features `rows` (as [`ScaleFilter::from_features`]
    /// takes them).
    pub fn respond_features(&mut self, rows: &[[i16; S]]) -> Q16 {
        self.load(rows);
        self.answer()
    }

    /// Learns the samples of the last [`ScaleFilter::respond`] at `rate` (Q16.16 in
    /// `[0, 1]`), the desired response peaked at the best of them.
    pub fn learn(&mut self, rate: Q16) {
        self.learn_at(self.best, rate);
    }

    /// The last response over the scales, Q16 (sample `s` at `s`).
    pub fn response(&self) -> &[i32; S] {
        &self.response
    }

    /// The size factor of each sample, Q16.16.
    pub fn factors(&self) -> &[Q16; S] {
        &self.factors
    }

    /// The features per sample, `D`.
    pub fn features(&self) -> usize {
        self.features
    }

    /// Takes `settings` and the model of a first box of `size` px, with nothing learnt,
    /// in place.
    fn reset(&mut self, settings: ScaleSettings, size: (Q16, Q16)) {
        const { assert!(S >= 2 && S <= MAX_DIRECT_POINTS, "scale counts are 2 to 16") };
        let settings = settings.limited();
        let grid = Grid::new(&settings, size);
        // 1 / (2 S sigma^2) in Q16.16: 2^47 / (S b^2), b = sigma's bits (2^8..=2^22).
        let b = settings.sigma.to_bits() as u64;
        let cost = (1u64 << 47).checked_div(S as u64 * b * b).unwrap_or(0);
        for (s, f) in self.factors.iter_mut().enumerate() {
            *f = pow(settings.step, Q16::from_int(Self::MIDDLE as i32 - s as i32));
        }
        self.settings = settings;
        self.grid = grid;
        self.features = (grid.cols * grid.rows * CELL_FEATURES).min(MAX_FEATURES);
        self.pairs = self.features.div_ceil(2);
        self.cost = Q16::saturate(cost as i64);
        self.lambda = (settings.lambda as i64) << 10;
        self.num.fill([Complex::ZERO; S]);
        self.den.fill(0);
        self.samples.fill([Complex::ZERO; S]);
        self.response.fill(0);
        self.best = Self::MIDDLE;
    }

    /// The samples of a target of `size` px at `centre`, transformed.
    fn sample<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        centre: (Q16, Q16),
        size: (Q16, Q16),
        extractor: &mut Extractor,
    ) {
        let Grid { cols, rows } = self.grid;
        let cell = self.settings.cell;
        let mut cells: [Cell; MAX_CELLS] = [[0; CHANNELS]; MAX_CELLS];
        for (s, &f) in self.factors.iter().enumerate() {
            let extent = |side: Q16| side.saturating_mul(f).max(Q16::from_int(2));
            let sampling = Sampling {
                cx: centre.0,
                cy: centre.1,
                width: extent(size.0),
                height: extent(size.1),
                cols,
                rows,
                cell,
            };
            let n = (cols * rows).min(MAX_CELLS);
            let cells = cells.get_mut(..n).unwrap_or(&mut []);
            extractor.extract(frame, &sampling, cells);
            let values = cells.iter().flat_map(|c| c.get(1..).unwrap_or(&[]));
            store(&mut self.samples, values.copied(), s);
        }
        self.transform();
    }

    /// Loads the features `rows` as the samples, transformed.
    fn load(&mut self, rows: &[[i16; S]]) {
        for s in 0..S {
            let values = (0..self.features).map(|d| {
                let row = rows.get(d);
                row.and_then(|r| r.get(s)).copied().unwrap_or(0)
            });
            store(&mut self.samples, values, s);
        }
        self.transform();
    }

    /// Transforms the samples' pair rows over the scales, Q21.
    fn transform(&mut self) {
        for row in self.samples.iter_mut().take(self.pairs) {
            forward_direct(row);
        }
    }

    /// The response to the samples: keeps it and the best sample; returns its factor.
    fn answer(&mut self) -> Q16 {
        // U_k = sum_p P_p,k conj(Z_p,S-k); then 2 sum_d A_d,k X_d,k = U_k + conj(U_S-k).
        // Each product below 2^57.5 floored to Q30 (`>> 8`), the sums below 2^58.2 (module
        // doc): they wrap nowhere.
        let mut u = [(0i64, 0i64); S];
        for (z, a) in self.samples.iter().zip(&self.num).take(self.pairs) {
            for (k, t) in u.iter_mut().enumerate() {
                let (Some(w), Some(a)) = (z.get(S.wrapping_sub(k) % S), a.get(k)) else {
                    continue;
                };
                let p = |u: i32, v: i32| (i64::from(u) * i64::from(v)) >> SUM_SHIFT;
                t.0 = t.0.wrapping_add(p(a.re, w.re) + p(a.im, w.im));
                t.1 = t.1.wrapping_add(p(a.im, w.re) - p(a.re, w.im));
            }
        }
        let mut sum = [(0i64, 0i64); S];
        for ((t, u), w) in sum.iter_mut().zip(&u).zip(mirrored(&u)) {
            *t = (u.0.saturating_add(w.0), u.1.saturating_sub(w.1));
        }
        let mut q = [Complex::ZERO; S];
        for ((q, t), &b) in q.iter_mut().zip(sum).zip(&self.den) {
            let d = i128::from(b.saturating_add(self.lambda));
            let part = |n: i64| {
                let v = (i128::from(n) << QUOTIENT_SHIFT)
                    .checked_div(d)
                    .unwrap_or(0);
                v.clamp(i32::MIN.into(), i32::MAX.into()) as i32
            };
            *q = Complex::new(part(t.0), part(t.1));
        }
        self.response = inverse_direct_real(&q);
        // The last of equal peaks, as the host's `max_by`.
        let mut best = 0;
        for (s, &r) in self.response.iter().enumerate() {
            if self.response.get(best).is_some_and(|&b| r >= b) {
                best = s;
            }
        }
        self.best = best;
        let between = match self.settings.interpolate {
            true => parabola_peak(&self.response, best),
            false => Q16::ZERO,
        };
        let at = Q16::from_int(Self::MIDDLE as i32 - best as i32).saturating_sub(between);
        pow(self.settings.step, at)
    }

    /// Learns the samples at `rate`, the desired response peaked at sample `at`.
    fn learn_at(&mut self, at: usize, rate: Q16) {
        let eta = rate.clamp(Q16::ZERO, Q16::ONE).to_bits();
        let y = self.label(at);
        // Pair p's new numerator `Y conj(X_2p) + i Y conj(X_2p+1)` is `Y_k Z_p,S-k`, below
        // 2^29.5 (module doc): the blend, between the old and the new value, needs no
        // saturation. The energies `|Z_p,k|^2` below 2^55 a pair, their sums below 2^62.2:
        // they wrap nowhere.
        let mut energy = [0i64; S];
        let half = 1 << (NUM_SHIFT - 1);
        // The rate opaque: known to be at least 0, it would take longer unsigned products.
        let eta = core::hint::black_box(eta);
        for (z, a) in self.samples.iter().zip(&mut self.num).take(self.pairs) {
            for (k, (a, (y, e))) in a.iter_mut().zip(y.iter().zip(&mut energy)).enumerate() {
                let (Some(w), Some(v)) = (z.get(S.wrapping_sub(k) % S), z.get(k)) else {
                    continue;
                };
                let (wr, wi) = (i64::from(w.re), i64::from(w.im));
                let (yr, yi) = (i64::from(y.re), i64::from(y.im));
                let re = ((yr * wr - yi * wi + half) >> NUM_SHIFT) as i32;
                let im = ((yr * wi + yi * wr + half) >> NUM_SHIFT) as i32;
                *a = Complex::new(blended(a.re, re, eta), blended(a.im, im, eta));
                let (vr, vi) = (i64::from(v.re), i64::from(v.im));
                *e = e.wrapping_add(vr * vr + vi * vi);
            }
        }
        // sum_d |X_d,k|^2 = sum_p (|Z_p,k|^2 + |Z_p,S-k|^2) / 2.
        let mut den = [0i64; S];
        for ((d, e), m) in den.iter_mut().zip(&energy).zip(mirrored(&energy)) {
            *d = (e / 2).saturating_add(m / 2);
        }
        for (b, new) in self.den.iter_mut().zip(den) {
            let v = (i128::from(*b) * i128::from((1 << 16) - eta)
                + i128::from(new) * i128::from(eta)
                + (1 << 15))
                >> 16;
            *b = v.clamp(0, i64::MAX.into()) as i64;
        }
    }

    /// The transform of the Gaussian over the scales peaked at sample `at`, Q16.
    fn label(&self, at: usize) -> [Complex; S] {
        let mut y = [Complex::ZERO; S];
        for (s, v) in y.iter_mut().enumerate() {
            let d = s.abs_diff(at).min(64) as i32;
            *v = Complex::new(exp_neg(self.cost.mul_int(d * d)) as i32, 0);
        }
        *forward_direct(&mut y)
    }
}

/// Stores the features `values` (Q15) as sample `s` of the pair rows `rows`, Q21: feature
/// `2p` the real part of row `p`, `2p + 1` its imaginary part (0 past the last).
fn store<const S: usize>(rows: &mut [[Complex; S]], values: impl Iterator<Item = i16>, s: usize) {
    let mut values = values.map(|v| i32::from(v) << FEATURE_SHIFT);
    for row in rows.iter_mut() {
        let Some(re) = values.next() else { break };
        let im = values.next().unwrap_or(0);
        if let Some(x) = row.get_mut(s) {
            *x = Complex::new(re, im);
        }
    }
}

/// `old (1 - eta) + new eta`, `eta` Q16 in `[0, 1]`, rounded: between `old` and `new`,
/// so an `i32` without a clamp or saturation.
#[inline(always)]
fn blended(old: i32, new: i32, eta: i32) -> i32 {
    let v = i64::from(old) * i64::from((1 << 16) - eta) + i64::from(new) * i64::from(eta);
    ((v + (1 << 15)) >> 16) as i32
}

/// The offset of the top of the parabola through `r[at - 1..=at + 1]` from `at`, in
/// samples, Q16.16, within `[-1/2, 1/2]`; 0 at the ends or where it opens upwards.
fn parabola_peak(r: &[i32], at: usize) -> Q16 {
    let value = |k: Option<usize>| k.and_then(|k| r.get(k)).map(|&v| i64::from(v));
    let (Some(l), Some(c), Some(rt)) = (
        value(at.checked_sub(1)),
        value(Some(at)),
        value(at.checked_add(1)),
    ) else {
        return Q16::ZERO;
    };
    let curve = l - 2 * c + rt;
    if curve >= 0 {
        return Q16::ZERO;
    }
    let half = 1 << (Q16::FRAC_BITS - 1);
    let x = ((l - rt) << (Q16::FRAC_BITS - 1))
        .checked_div(curve)
        .unwrap_or(0);
    Q16::saturate(x.clamp(-half, half))
}

/// `step^x`, Q16.16, for `step` in `[1, 1.5]` (clamped into it) and `x` (Q16.16): the
/// integer power and the binomial series of `(1 + u)^f` (`u = step - 1`, `f` the fraction
/// of `x`), 12 terms, in Q30; saturates above `2^15`.
pub fn pow(step: Q16, x: Q16) -> Q16 {
    let one: i64 = 1 << POW_BITS;
    let step = step.to_bits().clamp(1 << 16, 3 << 15);
    let base = i64::from(step) << (POW_BITS - Q16::FRAC_BITS);
    let u = base - one;
    let f = i64::from(x.to_bits() & 0xffff) << (POW_BITS - Q16::FRAC_BITS);
    // (1 + u)^f = sum_k C(f, k) u^k, C(f, k + 1) = C(f, k) (f - k) / (k + 1): with
    // `0 <= f < 1` the ratio `(f - k) / (k + 1)` is within 1 and `|u| <= 1/2`, so the terms
    // shrink from 1 and every product fits an `i64`.
    let mut term = one;
    let mut frac = one;
    for k in 0..12i64 {
        let ratio = (f - k * one) / (k + 1);
        term = (((term * ratio) >> POW_BITS) * u) >> POW_BITS;
        frac += term;
    }
    let (one, base, frac) = (i128::from(one), i128::from(base), i128::from(frac));
    let cap = one << 40;
    let mut whole = one;
    for _ in 0..x.floor_int().unsigned_abs().min(64) {
        whole = ((whole * base + (one >> 1)) >> POW_BITS).min(cap);
    }
    let shift = 2 * POW_BITS - Q16::FRAC_BITS;
    let v = match x.floor_int() >= 0 {
        true => (frac * whole + (1 << (shift - 1))) >> shift,
        false => ((frac << Q16::FRAC_BITS) + (whole >> 1))
            .checked_div(whole)
            .unwrap_or(0),
    };
    Q16::saturate(v.clamp(0, i32::MAX.into()) as i64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fft::dft_f64;
    use crate::rng::Rng;
    use std::vec;
    use std::vec::Vec;

    const SETTINGS: ScaleSettings = ScaleSettings {
        step: Q16::from_bits(70_779), // 1.08
        sigma: Q16::from_ratio(1, 4),
        lambda: 4_294_967, // 1e-3
        area: 512,
        cell: 4,
        interpolate: true,
    };

    /// A 60 x 60 px target: a 22 x 22 px model, 5 x 5 cells, 225 features.
    const SIZE: (Q16, Q16) = (Q16::from_int(60), Q16::from_int(60));

    /// Features that vary smoothly with the log of the scale: feature `d` of sample `s` is
    /// `g_d(s + shift)`, `g_d` a random sinusoid of amplitude 0.15 (Q15) and period 8, 4
    /// or 8/3 scales (a shift is then circular; no constant part, which would answer at the
    /// label's peak whatever the shift).
    fn pyramid(shift: f64, seed: u64) -> Vec<[i16; 8]> {
        let mut rng = Rng::new(seed);
        (0..MAX_FEATURES)
            .map(|_| {
                let freq = core::f64::consts::TAU / 8.0 * (1 + rng.below(3)) as f64;
                let phase = 6.3 * rng.uniform().to_f64();
                core::array::from_fn(|s| {
                    let t = s as f64 + shift;
                    (0.15 * (freq * t + phase).sin() * 32768.0) as i16
                })
            })
            .collect()
    }

    fn best(filter: &ScaleFilter<8>) -> usize {
        let r = filter.response();
        (0..8).max_by_key(|&s| r[s]).unwrap_or(0)
    }

    #[test]
    fn the_model_is_the_hosts() {
        let f = ScaleFilter::<8>::from_features(SETTINGS, SIZE, &[]);
        assert_eq!(f.features(), 225);
        let grid = |cols, rows| Grid { cols, rows };
        // 60 x 60 px: 22 x 22 px, 5 x 5 cells.
        assert_eq!(f.grid, grid(5, 5));
        // A long box: 101 x 8 px, 25 x 2 cells, cut to 16 x 2.
        let long = (Q16::from_int(200), Q16::from_int(10));
        assert_eq!(Grid::new(&SETTINGS, long), grid(16, 2));
        // A small one: 10 x 9 px grows to 13 x 12 px, 3 x 3 cells.
        let small = (Q16::from_int(10), Q16::from_int(9));
        assert_eq!(Grid::new(&SETTINGS, small), grid(3, 3));
        // 16 x 26 px (416 px^2) stays as it is: 4 x 6 cells.
        let mid = (Q16::from_int(16), Q16::from_int(26));
        assert_eq!(Grid::new(&SETTINGS, mid), grid(4, 6));
        // One too thin for 2 cells across takes 2.
        let thin = (Q16::from_int(4), Q16::from_int(200));
        assert_eq!(Grid::new(&SETTINGS, thin), grid(2, 16));
        let want = [
            1.08f64.powi(3),
            1.08f64.powi(2),
            1.08,
            1.0,
            1.0 / 1.08,
            1.0 / 1.08f64.powi(2),
            1.0 / 1.08f64.powi(3),
            1.0 / 1.08f64.powi(4),
        ];
        for (f, w) in f.factors().iter().zip(want) {
            assert!((f.to_f64() - w).abs() * 65536.0 <= 2.0, "{f:?} {w}");
        }
    }

    #[test]
    fn powers_of_the_step_are_within_2_lsb() {
        let mut worst: f64 = 0.0;
        for step in [1.02, 1.05, 1.08, 1.2, 1.5] {
            for i in -8 * 64..=8 * 64 {
                let x = i as f64 / 64.0;
                let got = pow(Q16::from_f64(step), Q16::from_f64(x)).to_f64();
                let step = Q16::from_f64(step).to_f64();
                worst = worst.max((got - step.powf(x)).abs() * 65536.0);
            }
        }
        assert!(worst <= 2.0, "{worst} LSB");
        assert_eq!(pow(SETTINGS.step, Q16::ZERO), Q16::ONE);
    }

    #[test]
    fn its_size_is_stated() {
        assert_eq!(core::mem::size_of::<ScaleFilter<5>>(), 11_688);
        assert_eq!(core::mem::size_of::<ScaleFilter<8>>(), 18_648);
        assert!(core::mem::size_of::<ScaleFilter<16>>() <= 40 * 1024);
    }

    /// `(re, im)` pairs.
    type C = (f64, f64);

    fn mul(a: C, b: C) -> C {
        (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
    }

    /// The per-feature filter in f64 on the same features (Q15 as 1) and label: one
    /// transform, numerator `A_d` and `|X_d|^2` per feature, no pairs.
    struct Reference {
        num: Vec<Vec<C>>,
        den: Vec<f64>,
    }

    impl Reference {
        fn spectra(rows: &[[i16; 8]], features: usize) -> Vec<Vec<C>> {
            (0..features)
                .map(|d| {
                    let row = rows[d].map(|v| (f64::from(v) / 32768.0, 0.0));
                    dft_f64(&row, false)
                })
                .collect()
        }

        fn label(f: &ScaleFilter<8>, at: usize) -> Vec<C> {
            f.label(at)
                .iter()
                .map(|y| (f64::from(y.re) / 65536.0, f64::from(y.im) / 65536.0))
                .collect()
        }

        fn learn(&mut self, x: &[Vec<C>], y: &[C], eta: f64) {
            let mut den = [0.0; 8];
            for (a, x) in self.num.iter_mut().zip(x) {
                for k in 0..8 {
                    let new = mul(y[k], (x[k].0, -x[k].1));
                    a[k] = (
                        (1.0 - eta) * a[k].0 + eta * new.0,
                        (1.0 - eta) * a[k].1 + eta * new.1,
                    );
                    den[k] += x[k].0 * x[k].0 + x[k].1 * x[k].1;
                }
            }
            for (b, new) in self.den.iter_mut().zip(den) {
                *b = (1.0 - eta) * *b + eta * new;
            }
        }

        fn respond(&self, z: &[Vec<C>], lambda: f64) -> Vec<f64> {
            let q: Vec<C> = (0..8)
                .map(|k| {
                    let s = self.num.iter().zip(z).fold((0.0, 0.0), |t, (a, z)| {
                        let p = mul(a[k], z[k]);
                        (t.0 + p.0, t.1 + p.1)
                    });
                    let b = self.den[k] + lambda;
                    (s.0 / b, s.1 / b)
                })
                .collect();
            dft_f64(&q, true).iter().map(|v| v.0).collect()
        }
    }

    #[test]
    fn the_pairs_answer_as_one_filter_per_feature_in_f64() {
        // 225 features: the last pair's second feature is empty.
        let (x, z) = (pyramid(0.0, 4), pyramid(0.5, 5));
        let mut f = ScaleFilter::<8>::from_features(SETTINGS, SIZE, &x);
        let d = f.features();
        let lambda = f64::from(SETTINGS.lambda) / 2f64.powi(32);
        let mid = ScaleFilter::<8>::MIDDLE;
        let mut r = Reference {
            num: vec![vec![(0.0, 0.0); 8]; d],
            den: vec![0.0; 8],
        };
        let (xs, zs) = (Reference::spectra(&x, d), Reference::spectra(&z, d));
        r.learn(&xs, &Reference::label(&f, mid), 1.0);
        let check = |f: &ScaleFilter<8>, want: Vec<f64>| {
            for (&got, want) in f.response().iter().zip(want) {
                let got = f64::from(got) / 65536.0;
                assert!((got - want).abs() < 1e-4, "{:?}", f.response());
            }
        };
        f.respond_features(&z);
        check(&f, r.respond(&zs, lambda));
        // A quarter of a label a scale down, learnt from the new samples.
        f.learn_at(mid - 1, Q16::from_ratio(1, 4));
        r.learn(&zs, &Reference::label(&f, mid - 1), 0.25);
        f.respond_features(&x);
        check(&f, r.respond(&xs, lambda));
    }

    #[test]
    fn the_trained_samples_answer_at_the_middle() {
        let x = pyramid(0.0, 1);
        let mut f = ScaleFilter::<8>::from_features(SETTINGS, SIZE, &x);
        let factor = f.respond_features(&x);
        assert_eq!(best(&f), ScaleFilter::<8>::MIDDLE);
        assert!((factor.to_f64() - 1.0).abs() < 0.002, "{factor:?}");
        // The label less its bins 0 and 4, which these features lack: 0.74 at the peak.
        let peak = f.response()[ScaleFilter::<8>::MIDDLE];
        assert!((peak - 48_549).abs() < 100, "{:?}", f.response());
    }

    #[test]
    fn samples_shifted_by_a_scale_peak_a_scale_over() {
        let mut f = ScaleFilter::<8>::from_features(SETTINGS, SIZE, &pyramid(0.0, 2));
        for (shift, want) in [(1.0, 1.08), (-1.0, 1.0 / 1.08), (0.5, 1.08f64.sqrt())] {
            let factor = f.respond_features(&pyramid(shift, 2)).to_f64();
            assert!((factor / want - 1.0).abs() < 0.01, "{shift}: {factor}");
        }
        f.respond_features(&pyramid(1.0, 2));
        assert_eq!(best(&f), ScaleFilter::<8>::MIDDLE - 1);
    }

    #[test]
    fn learning_moves_the_peak() {
        let x = pyramid(0.0, 3);
        let mut f = ScaleFilter::<8>::from_features(SETTINGS, SIZE, &x);
        let mid = ScaleFilter::<8>::MIDDLE;
        // A little of a label two scales down leaves the peak; all of it moves it.
        f.load(&x);
        f.learn_at(mid - 2, Q16::from_ratio(1, 16));
        f.respond_features(&x);
        assert_eq!(best(&f), mid);
        f.learn_at(mid - 2, Q16::ONE);
        f.respond_features(&x);
        assert_eq!(best(&f), mid - 2);
        // Learning the best sample at rate 1 makes it answer as the trained ones.
        let mut f = ScaleFilter::<8>::from_features(SETTINGS, SIZE, &x);
        let y = pyramid(1.0, 3);
        f.respond_features(&y);
        f.learn(Q16::ONE);
        let factor = f.respond_features(&y);
        assert_eq!(best(&f), mid - 1);
        assert!((factor.to_f64() - 1.08).abs() < 0.002, "{factor:?}");
    }

    #[test]
    fn zero_features_answer_without_fault() {
        let mut f = ScaleFilter::<8>::from_features(SETTINGS, SIZE, &[]);
        let factor = f.respond_features(&[]);
        assert!(f.response().iter().all(|&r| r == 0));
        assert!(factor.to_bits() > 0);
        f.learn(Q16::ONE);
    }
}
