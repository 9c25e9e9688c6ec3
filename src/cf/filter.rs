//! The multi-channel translation filter over a `G x G` grid of cells, in the frequency
//! domain by [`crate::fft`]: the integer port of the host's f64 `cf64::filter`.
//!
//! With `X_l` the 2-D transform of channel `l` of the windowed features (the separable
//! Hann window `0.5 (1 - cos(2 pi (k + 1) / (G + 1)))` per axis), `Y` that of the desired
//! response (a Gaussian of `sigma` cells peaking at cell `(0, 0)`, wrapping) and `n = G^2`:
//!
//! `A_l <- (1 - eta) A_l + eta conj(Y_s) X_l / n`, `B <- (1 - eta) B + eta sum_l |X_l|^2 / n`,
//!
//! and a grid's response is `r = IFFT(sum_l conj(A_l) Z_l / (B + lambda))`, cell `(y, x)` a
//! move of `(y, x)` cells (wrapping). `Y_s` is `Y` times the phase ramp
//! `e^(-2 pi i (u dy + v dx) / G)` (`u`, `v` signed frequencies) for a target `(dy, dx)`
//! cells from the centre; at the Nyquist frequency `-G/2` the ramp's Hermitian part (the
//! real part of the f64 reference's response comes from it alone).
//!
//! # Channel pairs
//! Channels `2m` and `2m + 1` are one complex grid `a + i b`, one forward FFT each
//! (5 for the 10 channels), and the filter keeps their transforms `Z_m = X_2m + i X_2m+1`
//! as they are, without splitting them: the numerator's update is linear, so
//! `A_2m + i A_2m+1` learns `conj(Y_s) Z_m / n` (`Y_s` is Hermitian); the energy of a pair
//! is `|X_2m|^2 + |X_2m+1|^2 = (|Z_m[k]|^2 + |Z_m[-k]|^2) / 2`; and
//! `sum_m conj(A_2m + i A_2m+1) Z_m` is `sum_l conj(A_l) Z_l` plus an anti-Hermitian cross
//! term, which lands in the imaginary part of the inverse transform, discarded. Each
//! array is one `G x G` complex grid per pair, smaller than two half spectra.
//!
//! # Scales (`L = log2 G`; "natural" units: a feature of 1.0 is 1, Q15's 32,768)
//! - Windowed features: Q16, `|x| <= 1`. A pair's transform is below
//!   `2 ((G + 1) / 2)^2 2^16 <= 2^27.1` (the window sums to `((G + 1) / 2)^2`), so the FFT
//!   never shifts (its first shift is at `2^28`): the spectra `Z_m` are Q16, exponent 0
//!   (a nonzero one would be shifted back to Q16).
//! - Label: `Y1 / G` per axis, Q30 (`Y = Y1[u] Y1[v]`, the Gaussian is separable, and
//!   `|Y1| <= G`; its samples from [`crate::likelihood::exp_neg`], within 5e-5);
//!   `conj(Y_s) / n` is their product, Q30, magnitude at most 1.
//! - Numerator `A`: Q(30 - 2L), `|A| <= |Z| < G^2` natural: below `2^30`.
//! - Denominator `B`: Q(29 - 2L) in a `u32`, `B <= 10 ((G + 1) / 2)^4 / G^2 < 2.5 G^2`
//!   natural: below `2^31`, and below `2^32` with `lambda` added.
//! - `lambda`: `u32` in units of `2^-30` natural (1e-3 is 1,073,742), rounded to `B`'s
//!   scale when the filter is made.
//! - Before the inverse FFT, `R = sum_m conj(A_m) Z_m / (B + lambda)`, Q20, saturated at
//!   `+-2048` (the trained patch gives `R ~ Y`, at most `2 pi sigma^2`); the response is
//!   Q16.16.
//!
//! Products are `i64`: `|A| |Z| < 2^30 2^28` per pair, `5 2^58 < 2^61` summed. The
//! division takes one reciprocal of `B + lambda` per cell by
//! [`crate::fixed::div_u64_u32`] (32-bit divisions) and two 64-bit multiplies. Learning
//! needs no saturation but the denominator's clamp: a new numerator `conj(Y_s) Z_m / n`
//! is below `2^30` (`|conj(Y_s) / n| <= 1`, `|Z| < G^2` natural), so its difference from
//! the old fits an `i32` and the blend lies between them.
//!
//! # Accuracy
//! Against the f64 reference on the same Q15 features (`host-tests/tests/cf_filter.rs`,
//! 32 x 32, sigma 1 and 2, lambda 1e-3, learning at rates 0.01 to 0.1 with fractional
//! shifts): every response cell within 3.2e-5 of 1.0, the same peak.
//!
//! # Cost, per frame
//! `respond`: 5 forward and 1 inverse `G x G` FFTs, 22 multiplies and one reciprocal
//! (a few 32-bit divisions) a cell; `learn`: 45 multiplies a cell and `2 G` for the phase
//! ramps, in one pass over the spectra (a row's labels and energies kept beside it). At
//! `G = 16` the filter stage (`respond`) takes 270,693 instructions on the mean frame of
//! `cargo run --release --example cf_firmware --target thumbv7em-none-eabihf` (QEMU). Stack: under 1.5 KiB at `G = 32`; [`Filter::new`] returns the filter by value,
//! [`Filter::reset`] retrains one in place.

use super::features::{Cell, CHANNELS};
use crate::fft::{forward, forward_2d, inverse_2d, mirrored, Complex};
use crate::fixed::{div_u64_u32, Q16};
use crate::likelihood::{exp_neg, CostScale};
use crate::trig::cos_sin_bits;

/// Channel pairs: one complex FFT each.
const PAIRS: usize = CHANNELS / 2;

/// Fraction bits of the label's per-axis factors and of `conj(Y_s) / n`.
const LABEL_BITS: u32 = 30;

/// Fraction bits of the spectra `Z_m` (and of the windowed features).
const SPECTRUM_BITS: u32 = 16;

/// Fraction bits of `R`, the response's transform.
const RESPONSE_BITS: u32 = 20;

/// The filter's settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FilterSettings {
    /// Width of the desired response, cells, Q16.16, clamped to `[0.01, 10]`.
    pub sigma: Q16,
    /// Regulariser added to `sum_l |X_l|^2 / n`, in units of `2^-30` of a squared natural
    /// feature (a feature of 1.0, Q15's 32,768): 1e-3 is 1,073,742.
    pub lambda: u32,
}

/// The translation filter: about 94 KB for `G = 32` (see the module doc).
#[derive(Clone, Debug)]
pub struct Filter<const G: usize> {
    /// Transforms of the last grid's windowed channel pairs `X_2m + i X_2m+1`, Q16.
    spectra: [[[Complex; G]; G]; PAIRS],
    /// Numerator per pair, `A_2m + i A_2m+1`, Q(30 - 2 log2 G).
    num: [[[Complex; G]; G]; PAIRS],
    /// Denominator `B`, Q(29 - 2 log2 G).
    den: [[u32; G]; G],
    /// The response's transform, and `learn`'s working grid.
    scratch: [[Complex; G]; G],
    /// The label's 1-D transform over `G` cells divided by `G`, Q30.
    label: [i32; G],
    /// `lambda` in `den`'s scale.
    lambda: u32,
}

/// `x 2^by`, rounded (half up) and saturated to `i32`. Inlined: `by` is a constant at
/// most calls, which then reduce to a shift and a clamp.
#[inline(always)]
fn scale(x: i64, by: i32) -> i32 {
    let bits = match by {
        0.. => x.saturating_mul(1 << by.min(32)),
        // `(x + 2^(s - 1)) >> s`, without the sum's overflow.
        _ => ((x >> (by.unsigned_abs().min(62) - 1)) + 1) >> 1,
    };
    Q16::saturate(bits).to_bits()
}

/// `a b`, re and im, exact.
#[inline]
fn product(a: Complex, b: Complex) -> (i64, i64) {
    let (ar, ai, br, bi) = (a.re as i64, a.im as i64, b.re as i64, b.im as i64);
    (ar * br - ai * bi, ar * bi + ai * br)
}

/// `a b / 2^s`, rounded, saturated.
#[inline]
fn mul_shift(a: Complex, b: Complex, s: u32) -> Complex {
    let (re, im) = product(a, b);
    let by = -(s as i32);
    Complex::new(scale(re, by), scale(im, by))
}

/// `old + eta (new - old)`, `eta` Q16 in `[0, 1]`, rounded, saturated.
#[inline]
fn blend(old: i64, new: i64, eta: i64) -> i64 {
    old + ((eta * (new - old) + (1 << 15)) >> 16)
}

/// A numerator's new value `c z / 2^s`, rounded (half up), for the label `c = conj(Y_s) / n`
/// (Q30) and a spectrum `z` (Q16): each part two multiply-accumulates and a rounded
/// shift. `|c| <= 1` and `|z| <= 2 ((G + 1) / 2)^2 < G^2` natural (module doc), so each
/// part is below `2^30` in Q(30 - 2L): [`mul_shift`]'s saturation never acts.
#[inline(always)]
fn numerator(c: Complex, z: Complex, s: u32) -> Complex {
    // `c.im` is never `i32::MIN` (a saturated negation): its negation is exact.
    let (cr, ci, ni) = (
        i64::from(c.re),
        i64::from(c.im),
        i64::from(c.im.wrapping_neg()),
    );
    let (zr, zi) = (i64::from(z.re), i64::from(z.im));
    let half = 1 << (s - 1);
    Complex::new(
        ((cr * zr + ni * zi + half) >> s) as i32,
        ((cr * zi + ci * zr + half) >> s) as i32,
    )
}

/// `old + eta (new - old)` per part, `eta` Q16 in `[0, 1]`, rounded, as [`blend`]: for
/// parts below `2^30` (the numerators, [`numerator`]) the difference fits an `i32` (one
/// 32 x 32-bit multiply), and the result lies between `old` and `new` (no saturation).
#[inline(always)]
fn learnt(old: Complex, new: Complex, eta: i32) -> Complex {
    let part = |old: i32, new: i32| {
        let step = i64::from(eta) * i64::from(new.wrapping_sub(old));
        old.wrapping_add(((step + (1 << 15)) >> 16) as i32)
    };
    Complex::new(part(old.re, new.re), part(old.im, new.im))
}

/// `t / d` where `mant 2^-shift` stands for `1 / d`, rounded, saturated: `t` cut to 31
/// bits first, so that the product fits an `i64`.
#[inline]
fn divide(t: i64, mant: u32, shift: u32) -> i32 {
    let sh = (u64::BITS - t.unsigned_abs().leading_zeros()).saturating_sub(31);
    scale((t >> sh) * mant as i64, sh as i32 - shift as i32)
}

/// `0.5 (1 - cos(2 pi (k + 1) / (N + 1)))` for `k < N`, Q16 (below 1), at compile time.
const fn hann<const N: usize>() -> [u32; N] {
    let mut w = [0; N];
    let mut k = 0;
    while k < N {
        let (cos, _) = cos_sin_bits(k as u32 + 1, N as u32 + 1, 17);
        w[k] = (((1 << 17) - cos + 2) >> 2) as u32;
        k += 1;
    }
    w
}

impl<const G: usize> Filter<G> {
    /// `log2 G`, and a compile-time error unless `G` is a power of two in `4..=64`.
    const LOG2: u32 = {
        assert!(
            G.is_power_of_two() && G >= 4 && G <= 64,
            "filter grids are powers of two from 4 to 64 cells"
        );
        G.trailing_zeros()
    };

    /// Fraction bits of the numerator.
    const NUM_BITS: u32 = 30 - 2 * Self::LOG2;

    /// Fraction bits of the denominator.
    const DEN_BITS: u32 = 29 - 2 * Self::LOG2;

    /// The Hann window per axis, Q16.
    const WINDOW: [u32; G] = hann::<G>();

    /// An untrained filter, every bit zero (every response 0).
    pub const UNSET: Self = Self {
        spectra: [[[Complex::ZERO; G]; G]; PAIRS],
        num: [[[Complex::ZERO; G]; G]; PAIRS],
        den: [[0; G]; G],
        scratch: [[Complex::ZERO; G]; G],
        label: [0; G],
        lambda: 0,
    };

    /// A filter trained on one grid of features (rate 1).
    pub fn new(settings: FilterSettings, features: &[[Cell; G]; G]) -> Self {
        let mut filter = Self::UNSET;
        filter.reset(settings, features);
        filter
    }

    /// Trains the filter anew on one grid of features (rate 1), in place.
    pub fn reset(&mut self, settings: FilterSettings, features: &[[Cell; G]; G]) {
        self.label = Self::label(settings.sigma);
        let drop = 30 - Self::DEN_BITS;
        self.lambda = ((settings.lambda as u64 + (1 << (drop - 1))) >> drop) as u32;
        self.load(features);
        self.learn((Q16::ZERO, Q16::ZERO), Q16::ONE);
    }

    /// The response to `features`, Q16.16, cell `(y, x)` a move of `(y, x)` cells
    /// (wrapping); keeps their spectra for [`Filter::learn`].
    pub fn respond(&mut self, features: &[[Cell; G]; G], out: &mut [[i32; G]; G]) {
        self.load(features);
        for (u, (row, den)) in self.scratch.iter_mut().zip(&self.den).enumerate() {
            // `sum_m conj(A_m) Z_m` of the row's cells, a pair's row at a time.
            let mut sums = [(0i64, 0i64); G];
            for (a, z) in self.num.iter().zip(&self.spectra) {
                let (Some(a), Some(z)) = (a.get(u), z.get(u)) else {
                    continue;
                };
                for ((t, a), z) in sums.iter_mut().zip(a).zip(z) {
                    // `|a.im| < 2^30` (module doc): its negation is exact.
                    let (pr, pi) = product(Complex::new(a.re, a.im.wrapping_neg()), *z);
                    *t = (t.0 + pr, t.1 + pi);
                }
            }
            for ((r, d), (re, im)) in row.iter_mut().zip(den).zip(sums) {
                // 1 / (B + lambda) = mant 2^-(63 - s); R = 2^3 T / (B + lambda) (Q20 from
                // T in Q(46 - 2L) and B in Q(29 - 2L)).
                let d = d.saturating_add(self.lambda);
                let s = d.leading_zeros();
                *r = match d.checked_shl(s) {
                    Some(norm @ 1..) => {
                        let mant = div_u64_u32(1 << 63, norm).min(u32::MAX as u64) as u32;
                        let shift = 63 - s - 3;
                        Complex::new(divide(re, mant, shift), divide(im, mant, shift))
                    }
                    _ => Complex::ZERO,
                };
            }
        }
        let e = inverse_2d(&mut self.scratch);
        let by = e + 16 - RESPONSE_BITS as i32;
        for (row, r) in out.iter_mut().zip(&self.scratch) {
            for (o, r) in row.iter_mut().zip(r) {
                *o = scale(r.re as i64, by);
            }
        }
    }

    /// Learns the spectra of the last [`Filter::respond`] at `rate` (Q16.16, clamped to
    /// `[0, 1]`), the target `(dy, dx)` cells (Q16.16) from the grid's centre.
    pub fn learn(&mut self, (dy, dx): (Q16, Q16), rate: Q16) {
        let eta = rate.to_bits().clamp(0, Q16::ONE.to_bits());
        // conj(Y_s) / n, Q30, from the axes' factors; at the corner `(G/2, G/2)` the
        // Hermitian part is `Re(Fy Fx)`, the product of the real parts less that of the
        // imaginary ones.
        let ((fy, ny), (fx, nx)) = (self.axis(dy), self.axis(dx));
        let (cross, _) = product(Complex::new(ny, 0), Complex::new(nx, 0));
        let cross = scale(cross, -(LABEL_BITS as i32)) as i64;
        // Each cell's `sum_m |Z_m|^2 / 2n` to Q(29 - 2L) (below 2^31, module doc), and
        // `A_m <- A_m + eta (conj(Y_s) Z_m / n - A_m)`, Q30 Q16 to Q(30 - 2L): one pass
        // over the spectra.
        let drop = 2 * SPECTRUM_BITS + 1 + 2 * Self::LOG2 - Self::DEN_BITS;
        let shift = LABEL_BITS + SPECTRUM_BITS - Self::NUM_BITS;
        // Opaque: known to be at least 0, the rate would take a longer unsigned product.
        let eta_step = core::hint::black_box(eta);
        for (u, (h_row, y)) in self.scratch.iter_mut().zip(&fy).enumerate() {
            // The row's labels and energies, then each pair's row of the row.
            let mut labels = [Complex::ZERO; G];
            for (c, x) in labels.iter_mut().zip(&fx) {
                let p = mul_shift(*y, *x, LABEL_BITS);
                *c = Complex::new(p.re, p.im.saturating_neg());
            }
            if let (true, Some(c)) = (u == G / 2, labels.get_mut(G / 2)) {
                c.re = scale(c.re as i64 - cross, 0);
            }
            let mut energy = [0u64; G];
            for (num, z) in self.num.iter_mut().zip(&self.spectra) {
                let (Some(num), Some(z)) = (num.get_mut(u), z.get(u)) else {
                    continue;
                };
                let cells = num.iter_mut().zip(z).zip(labels.iter().zip(&mut energy));
                for ((a, z), (c, e)) in cells {
                    let (zr, zi) = (i64::from(z.re), i64::from(z.im));
                    *e += (zr * zr + zi * zi) as u64;
                    *a = learnt(*a, numerator(*c, *z, shift), eta_step);
                }
            }
            for (h, e) in h_row.iter_mut().zip(energy) {
                *h = Complex::new(scale(e as i64, -(drop as i32)), 0);
            }
        }
        // ...and with that of `-k`, `sum_l |X_l|^2 / n`.
        let eta = i64::from(eta);
        for (u, (den, h)) in self.den.iter_mut().zip(&self.scratch).enumerate() {
            let Some(mirror) = self.scratch.get((G - u) % G) else {
                continue;
            };
            for ((d, h), m) in den.iter_mut().zip(h).zip(mirrored(mirror)) {
                let b = blend(*d as i64, h.re as i64 + m.re as i64, eta);
                *d = b.clamp(0, u32::MAX as i64) as u32;
            }
        }
    }

    /// One axis's factor of `Y_s / n` for a shift of `shift` cells: `Y1[u] / G` times
    /// `e^(-2 pi i wrap(u) shift / G)`, Q30, the Nyquist frequency's real part only; and
    /// that one's imaginary part.
    fn axis(&self, shift: Q16) -> ([Complex; G], i32) {
        // e^(-2 pi i shift / G) and its powers.
        let turn = (G as i64) << Q16::FRAC_BITS;
        let k = (shift.to_bits() as i64).rem_euclid(turn) as u32;
        let (cos, sin) = cos_sin_bits(k, turn as u32, LABEL_BITS);
        let step = Complex::new(cos as i32, -sin as i32);
        let mut powers = [Complex::ZERO; G];
        let mut power = Complex::new(1 << LABEL_BITS, 0);
        for p in powers.iter_mut() {
            *p = power;
            power = mul_shift(power, step, LABEL_BITS);
        }
        let mut factors = [Complex::ZERO; G];
        let mut nyquist = 0;
        for (u, (f, y)) in factors.iter_mut().zip(&self.label).enumerate() {
            // wrap(u) = u below G/2, else u - G: the conjugate of the power G - u.
            let rotation = if u < G / 2 {
                powers.get(u).copied()
            } else {
                powers.get(G - u).map(|p| Complex::new(p.re, -p.im))
            };
            *f = mul_shift(
                Complex::new(*y, 0),
                rotation.unwrap_or_default(),
                LABEL_BITS,
            );
            if u == G / 2 {
                nyquist = f.im;
                f.im = 0;
            }
        }
        (factors, nyquist)
    }

    /// The transform over `G` cells of the Gaussian of `sigma` cells centred on cell 0
    /// (wrapping), divided by `G`, Q30: real, the Gaussian being even.
    fn label(sigma: Q16) -> [i32; G] {
        let sigma = Q16::from_bits(sigma.to_bits().clamp(656, 655_360));
        let cost = CostScale::from_sigma_q16(sigma).unwrap_or(CostScale::ZERO);
        let mut g = [Complex::ZERO; G];
        for (y, g) in g.iter_mut().enumerate() {
            let d = y.min(G - y) as i32;
            // 65,535 stands for 1: to Q16 (65,536), then Q(30 - L), so that the transform
            // divided by G is Q30.
            let q16 = (exp_neg(cost.cost(Q16::from_int(d * d))) as i64 * 65_537 + (1 << 15)) >> 16;
            *g = Complex::new(
                scale(q16, (LABEL_BITS - Q16::FRAC_BITS - Self::LOG2) as i32),
                0,
            );
        }
        let e = forward(&mut g);
        g.map(|v| scale(v.re as i64, e))
    }

    /// Windows `features` and keeps the transforms of their channel pairs, Q16.
    fn load(&mut self, features: &[[Cell; G]; G]) {
        Self::window_all(features, &mut self.spectra);
        for spectrum in self.spectra.iter_mut() {
            let e = forward_2d(spectrum);
            if e != 0 {
                for v in spectrum.as_flattened_mut() {
                    *v = Complex::new(scale(v.re as i64, e), scale(v.im as i64, e));
                }
            }
        }
    }

    /// Every channel pair of `features` times the window, Q16, as `a + i b` (pair `m` of
    /// channels `2m`, `2m + 1` into `out[m]`), in one pass over the cells: as
    /// [`Filter::window`] does a pair at a time.
    fn window_all(features: &[[Cell; G]; G], out: &mut [[[Complex; G]; G]; PAIRS]) {
        for (u, (cells, wy)) in features.iter().zip(&Self::WINDOW).enumerate() {
            for (v, (cell, wx)) in cells.iter().zip(&Self::WINDOW).enumerate() {
                let w = *wy as u64 * *wx as u64;
                let channels = cell.chunks_exact(2);
                for (spectrum, pair) in out.iter_mut().zip(channels) {
                    if let (Some(o), [a, b]) =
                        (spectrum.get_mut(u).and_then(|r| r.get_mut(v)), pair)
                    {
                        *o = Complex::new(windowed(*a, w), windowed(*b, w));
                    }
                }
            }
        }
    }

    /// Channels `2 pair` and `2 pair + 1` of `features` times the window, Q16, as
    /// `a + i b`.
    #[cfg(test)]
    fn window(features: &[[Cell; G]; G], pair: usize, out: &mut [[Complex; G]; G]) {
        let (a, b) = (2 * pair, 2 * pair + 1);
        for ((row, cells), wy) in out.iter_mut().zip(features).zip(&Self::WINDOW) {
            for ((v, cell), wx) in row.iter_mut().zip(cells).zip(&Self::WINDOW) {
                // Q15 times Q32 (below 1) to Q16.
                let w = (*wy as u64 * *wx as u64) as i64;
                let windowed = |c: Option<&i16>| scale(c.copied().unwrap_or(0) as i64 * w, -31);
                *v = Complex::new(windowed(cell.get(a)), windowed(cell.get(b)));
            }
        }
    }
}

/// A Q15 feature `c` times the window `w` (Q32, below 1) to Q16, rounded half up: below
/// `2^47` before the shift, so no saturation (as [`scale`] would apply).
#[inline(always)]
fn windowed(c: i16, w: u64) -> i32 {
    ((i64::from(c) * w as i64 + (1 << 30)) >> 31) as i32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use std::boxed::Box;

    const SETTINGS: FilterSettings = FilterSettings {
        sigma: Q16::ONE,
        lambda: 107_374, // 1e-4
    };

    #[test]
    fn scale_rounds_half_up_and_saturates() {
        for (x, by, want) in [
            (5, -1, 3),
            (-5, -1, -2),
            (6, -2, 2),
            (-6, -2, -1),
            (7, 0, 7),
            (3, 4, 48),
            (1 << 40, -8, i32::MAX),
            (-(1 << 40), -8, i32::MIN),
            (i64::MAX, -62, 2),
            (i64::MAX, -32, i32::MAX),
            (i64::MIN, -1, i32::MIN),
            (i64::MIN, -62, -2),
            (1 << 20, 20, i32::MAX),
        ] {
            let exact = (x as f64 * 2f64.powi(by) + 0.5).floor();
            let clamped = exact.clamp(i32::MIN.into(), i32::MAX.into()) as i32;
            assert_eq!(clamped, want, "{x} 2^{by}");
            assert_eq!(scale(x, by), want, "{x} 2^{by}");
        }
    }

    /// A random grid of features in their ranges (grey in `[-0.5, 0.5]`, fHOG in
    /// `[0, 0.4]`), moved by `(dy, dx)` cells (wrapping).
    fn pattern<const G: usize>(dy: usize, dx: usize) -> Box<[[Cell; G]; G]> {
        let mut rng = Rng::new(29);
        let mut grid = Box::new([[[0i16; CHANNELS]; G]; G]);
        for y in 0..G {
            for x in 0..G {
                for (c, v) in grid[(y + dy) % G][(x + dx) % G].iter_mut().enumerate() {
                    let u = (rng.next_u32() >> 17) as i32; // [0, 1) in Q15
                    *v = match c {
                        0 => (u - 16_384) as i16,
                        _ => (u * 2 / 5) as i16,
                    };
                }
            }
        }
        grid
    }

    fn response<const G: usize>(
        filter: &mut Filter<G>,
        grid: &[[Cell; G]; G],
    ) -> Box<[[i32; G]; G]> {
        let mut out = Box::new([[0; G]; G]);
        filter.respond(grid, &mut out);
        out
    }

    fn peak<const G: usize>(r: &[[i32; G]; G]) -> (usize, usize) {
        let i = (0..G * G).max_by_key(|&i| r[i / G][i % G]).unwrap_or(0);
        (i / G, i % G)
    }

    #[test]
    fn a_shifted_pattern_moves_the_peak_by_the_shift() {
        let mut filter = Box::new(Filter::<32>::new(SETTINGS, &pattern(0, 0)));
        let r = response(&mut filter, &pattern(0, 0));
        assert_eq!(peak(&r), (0, 0));
        let one = r[0][0] as f64 / 65_536.0;
        assert!((one - 1.0).abs() < 0.05, "peak {one}");
        for (dy, dx) in [(3, 5), (31, 1), (16, 30), (2, 16)] {
            assert_eq!(peak(&response(&mut filter, &pattern(dy, dx))), (dy, dx));
        }
    }

    #[test]
    fn learning_moves_the_model_towards_the_new_patch() {
        let (a, b) = (pattern::<16>(0, 0), pattern::<16>(2, 3));
        let mut filter = Box::new(Filter::new(SETTINGS, &a));
        assert_eq!(peak(&response(&mut filter, &b)), (2, 3));
        for _ in 0..100 {
            response(&mut filter, &b);
            filter.learn((Q16::ZERO, Q16::ZERO), Q16::from_f64(0.1));
        }
        // Adapted to b: b answers at the origin, a at minus the shift.
        assert_eq!(peak(&response(&mut filter, &b)), (0, 0));
        assert_eq!(peak(&response(&mut filter, &a)), (14, 13));
    }

    #[test]
    fn learning_with_a_moved_peak_equals_learning_the_moved_pattern() {
        // The windowed grid moved by (2, 3) cells (wrapping), learnt with the target at
        // (2, 3), trains the filter the unmoved grid learnt at the centre trains.
        let (a, probe) = (pattern::<16>(0, 0), pattern::<16>(1, 6));
        let mut centred = Box::new(Filter::new(SETTINGS, &pattern(5, 1)));
        let mut moved = centred.clone();
        centred.load(&a);
        centred.learn((Q16::ZERO, Q16::ZERO), Q16::HALF);
        for (m, spectrum) in moved.spectra.iter_mut().enumerate() {
            let mut windowed = [[Complex::ZERO; 16]; 16];
            Filter::<16>::window(&a, m, &mut windowed);
            for (y, row) in spectrum.iter_mut().enumerate() {
                for (x, v) in row.iter_mut().enumerate() {
                    *v = windowed[(y + 14) % 16][(x + 13) % 16];
                }
            }
            assert_eq!(forward_2d(spectrum), 0);
        }
        moved.learn((Q16::from_int(2), Q16::from_int(3)), Q16::HALF);
        let (r1, r2) = (response(&mut centred, &probe), response(&mut moved, &probe));
        let worst = r1
            .as_flattened()
            .iter()
            .zip(r2.as_flattened())
            .map(|(a, b)| (a - b).abs())
            .max();
        assert!(worst <= Some(8), "{worst:?} of 65536");
    }

    #[test]
    fn a_half_cell_target_peaks_between_two_cells() {
        let a = pattern::<16>(0, 0);
        let mut filter = Box::new(Filter::new(SETTINGS, &a));
        response(&mut filter, &a);
        filter.learn((Q16::ZERO, Q16::HALF), Q16::ONE);
        let r = response(&mut filter, &a);
        let (left, right) = (r[0][0], r[0][1]);
        assert!((left - right).abs() < 655, "{left} {right}");
        assert!(left > r[0][15] && right > r[0][2]);
    }

    #[test]
    fn the_filter_fits_in_96_kib() {
        assert!(core::mem::size_of::<Filter<32>>() <= 96 * 1024);
    }

    #[test]
    fn the_window_is_symmetric_positive_and_below_one() {
        let w = Filter::<32>::WINDOW;
        for k in 0..32 {
            assert!(w[k] > 0 && w[k] < 65_536);
            assert_eq!(w[k], w[31 - k]);
        }
    }
}
