//! The Kalman filter of the RBPF's particle sizes: 4 states and 2 measurements in Q16.16,
//! with one covariance and one gain shared by every particle.
//!
//! # Model
//! The state is a particle's [`Size`] `(Hx, dHx, Hy, dHy)`: two (half-axis, rate) pairs,
//! x first, the RBPF paper's leaf. With the frame interval `dt`,
//!
//! ```text
//! A(dt) = [[1, dt, 0, 0],      H = [[1, 0, 0, 0],
//!          [0,  1, 0, 0],           [0, 0, 1, 0]]
//!          [0,  0, 1, dt],
//!          [0,  0, 0,  1]]
//! L_t = A L_{t-1} + w,  w ~ N(0, Q);     Y_t = H L_t + v,  v ~ N(0, R),
//! ```
//! the measurement `Y = (Hx, Hy)`. The paper uses `Q = 4 I4` and `R = 2 I2`
//! ([`BlockNoise::PAPER`]); both are configuration.
//!
//! The steps are separate, because the RBPF predicts each particle's *mean* with its own
//! rule (the scale follows the vertical motion, eq. 7 of the paper) but the *covariance*
//! with `P^- = A P A^T + Q`:
//! - covariance predict: [`SharedCovariance::predict`];
//! - mean predict (the standard `A mu`): [`predict_mean`];
//! - gain: [`SharedCovariance::gain`];
//! - mean update `mu += K (y - H mu)`: [`SharedGain::update_mean`];
//! - covariance update `P -= K H P`: [`SharedCovariance::update_cov`].
//!
//! # One covariance for all particles
//! The covariance recursion does not depend on the data, so when all particles share `Q`
//! and `R` they share `P` and `K` too: one `P` per filter, N means. `A`, `H` and a
//! [`BlockNoise`] are block-diagonal, so `P` splits into two independent 2x2 blocks
//! ([`Block`]: x = (Hx, dHx), y = (Hy, dHy)) and every division is a 64-bit scalar one.
//!
//! The tests hold this against the general per-particle filter (one mean and a full 4x4
//! covariance each, general symmetric `Q` and `R`, a closed-form 2x2 inverse in `i128`):
//! both give bit-for-bit the same means and covariances when the noise is block-diagonal
//! and `P` starts block-diagonal, because the gain and the covariance correction are each
//! one correctly rounded quotient of exact integers and the 4x4 quotient reduces to the
//! 2x2 one as a rational number. One exception: with a zero measurement variance a block's
//! innovation `S` can be 0; the general filter then skips the whole update (its 2x2 `S` is
//! singular), the shared one only that block's.
//!
//! # Number formats
//! - Means, covariances, `Q`, `R`, `S`, `dt`, measurements: [`Q16`] (Q16.16, range
//!   `[-32768, 32768)`, resolution `2^-16`). All operations saturate.
//! - Gains: raw `i32` in Q8.24 ([`GAIN_FRAC_BITS`] = 24), range `[-128, 128)`, resolution
//!   `6e-8`; a gain outside that range saturates (only with a covariance that is far from
//!   its steady state, e.g. a rate variance 10^4 times the position variance).
//! - Intermediates: `i64` for products and quotients.
//!
//! # Keeping `P` positive semidefinite
//! Exact arithmetic keeps `P` positive semidefinite, but the Q16.16 rails do not: without
//! measurements `P` grows every prediction (with `Q = 4 I`, `P00` reaches the rail after
//! about 30 steps) and an entry that sticks at the rail while its neighbours keep growing
//! makes `P` indefinite (`P01^2 > P00 P11`). So every prediction and update ends by setting
//! negative variances to 0 and limiting the covariance to `|P01| <= sqrt(P00 P11)` (rounded
//! down). This is a no-op while `P` is PSD, so it changes nothing away from the rails, and
//! makes each 2x2 block PSD exactly, as the property tests check (extreme `Q`, `R`, `dt`
//! and long runs without measurements).
//!
//! # Accuracy
//! Each stored covariance entry is within one rounding (`2^-17`) of the exact update of the
//! stored inputs; each predicted entry within two. Against an `f64` filter over 1,000 steps
//! with `Q = 4 I`, `R = 2 I` the relative error stays below `1e-3` (measured by the
//! tests, which print the figures: `cargo test -p rbtrack kalman::reference -- --nocapture`).
//!
//! # Cost
//! Per frame: a handful of 64-bit divisions for `P` and `K`, then per particle four
//! 32x32->64 multiplies for the mean update.
//!
//! # Examples
//! ```
//! use rbtrack::fixed::Q16;
//! use rbtrack::kalman::{predict_mean, BlockNoise, SharedCovariance, Size, Sym2};
//! let p0 = Sym2::diagonal(Q16::from_int(10), Q16::from_int(10));
//! let mut shared = SharedCovariance::new(p0, p0, BlockNoise::PAPER).unwrap();
//! let mut sizes = [Size::at_rest(Q16::from_int(25), Q16::from_int(40)); 8];
//! for size in sizes.iter_mut() {
//!     predict_mean(size, Q16::ONE);
//! }
//! shared.predict(Q16::ONE);
//! shared.update(&mut sizes, Q16::from_int(26), Q16::from_int(42));
//! assert!(sizes[0].hy > Q16::from_int(40) && sizes[0].hy < Q16::from_int(42));
//! ```

use crate::fixed::Q16;

#[cfg(test)]
mod general;
#[cfg(test)]
mod properties;
#[cfg(test)]
mod reference;
#[cfg(test)]
mod tests;

/// Fraction bits of a Kalman gain entry (Q8.24).
pub const GAIN_FRAC_BITS: u32 = 24;

/// A particle's size: the half-axes, px, and their rates, px per unit of `dt`, Q16.16; the
/// Kalman filter's state (the RBPF leaf), x first.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Size {
    /// Horizontal half-axis, px.
    pub hx: Q16,
    /// Its rate, px per unit of `dt`.
    pub dhx: Q16,
    /// Vertical half-axis, px.
    pub hy: Q16,
    /// Its rate, px per unit of `dt`.
    pub dhy: Q16,
}

impl Size {
    /// Half-axes `hx`, `hy` (px), at rest.
    pub const fn at_rest(hx: Q16, hy: Q16) -> Self {
        Self {
            hx,
            dhx: Q16::ZERO,
            hy,
            dhy: Q16::ZERO,
        }
    }
}

/// Symmetric 2x2 matrix `[[a00, a01], [a01, a11]]`, Q16.16 entries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sym2 {
    /// Entry (0, 0).
    pub a00: Q16,
    /// Entries (0, 1) and (1, 0).
    pub a01: Q16,
    /// Entry (1, 1).
    pub a11: Q16,
}

impl Sym2 {
    /// All zero.
    pub const ZERO: Self = Self::diagonal(Q16::ZERO, Q16::ZERO);

    /// `[[a00, 0], [0, a11]]`.
    pub const fn diagonal(a00: Q16, a11: Q16) -> Self {
        Self {
            a00,
            a01: Q16::ZERO,
            a11,
        }
    }

    /// Whether the matrix is positive semidefinite (`a00 >= 0`, `a11 >= 0`,
    /// `a01^2 <= a00 a11`), checked exactly.
    pub const fn is_psd(&self) -> bool {
        let (a, b, c) = (
            self.a00.to_bits() as i64,
            self.a01.to_bits() as i64,
            self.a11.to_bits() as i64,
        );
        a >= 0 && c >= 0 && b * b <= a * c
    }
}

/// Symmetric 4x4 matrix over `(Hx, dHx, Hy, dHy)`, Q16.16 entries; the fields are the upper
/// triangle, `aij` for row `i <= j` column `j`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[allow(missing_docs)]
pub struct Sym4 {
    pub a00: Q16,
    pub a01: Q16,
    pub a02: Q16,
    pub a03: Q16,
    pub a11: Q16,
    pub a12: Q16,
    pub a13: Q16,
    pub a22: Q16,
    pub a23: Q16,
    pub a33: Q16,
}

impl Sym4 {
    /// All zero.
    pub const ZERO: Self = Self::from_blocks(Sym2::ZERO, Sym2::ZERO);

    /// `diag(d[0], d[1], d[2], d[3])`.
    pub const fn diagonal(d: [Q16; 4]) -> Self {
        Self::from_blocks(Sym2::diagonal(d[0], d[1]), Sym2::diagonal(d[2], d[3]))
    }

    /// Block-diagonal matrix with the x block `(Hx, dHx)` and the y block `(Hy, dHy)`.
    pub const fn from_blocks(x: Sym2, y: Sym2) -> Self {
        Self {
            a00: x.a00,
            a01: x.a01,
            a02: Q16::ZERO,
            a03: Q16::ZERO,
            a11: x.a11,
            a12: Q16::ZERO,
            a13: Q16::ZERO,
            a22: y.a00,
            a23: y.a01,
            a33: y.a11,
        }
    }

    /// Entry `(i, j)` (either order); indices above 3 give zero.
    pub const fn get(&self, i: usize, j: usize) -> Q16 {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        match (i, j) {
            (0, 0) => self.a00,
            (0, 1) => self.a01,
            (0, 2) => self.a02,
            (0, 3) => self.a03,
            (1, 1) => self.a11,
            (1, 2) => self.a12,
            (1, 3) => self.a13,
            (2, 2) => self.a22,
            (2, 3) => self.a23,
            (3, 3) => self.a33,
            _ => Q16::ZERO,
        }
    }

    /// The x block `(Hx, dHx)`.
    pub const fn x_block(&self) -> Sym2 {
        Sym2 {
            a00: self.a00,
            a01: self.a01,
            a11: self.a11,
        }
    }

    /// The y block `(Hy, dHy)`.
    pub const fn y_block(&self) -> Sym2 {
        Sym2 {
            a00: self.a22,
            a01: self.a23,
            a11: self.a33,
        }
    }

    /// Whether every entry coupling the x block with the y block is zero.
    pub fn is_block_diagonal(&self) -> bool {
        self.a02 == Q16::ZERO
            && self.a03 == Q16::ZERO
            && self.a12 == Q16::ZERO
            && self.a13 == Q16::ZERO
    }
}

/// Block-diagonal noise, the kind the shared filter needs: `Q = diag(q_x, q_y)` with a 2x2
/// block per axis and `R = diag(r_x, r_y)`. All Q16.16.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BlockNoise {
    /// Process noise of `(Hx, dHx)`, Q16.16.
    pub q_x: Sym2,
    /// Process noise of `(Hy, dHy)`, Q16.16.
    pub q_y: Sym2,
    /// Measurement noise variance of `Hx`, Q16.16, `>= 0`.
    pub r_x: Q16,
    /// Measurement noise variance of `Hy`, Q16.16, `>= 0`.
    pub r_y: Q16,
}

impl BlockNoise {
    /// The paper's `Q = 4 I4`, `R = 2 I2`.
    pub const PAPER: Self = Self::diagonal(
        [
            Q16::from_int(4),
            Q16::from_int(4),
            Q16::from_int(4),
            Q16::from_int(4),
        ],
        [Q16::from_int(2), Q16::from_int(2)],
    );

    /// Diagonal `Q = diag(q)` over `(Hx, dHx, Hy, dHy)` and `R = diag(r)` over `(Hx, Hy)`.
    pub const fn diagonal(q: [Q16; 4], r: [Q16; 2]) -> Self {
        Self {
            q_x: Sym2::diagonal(q[0], q[1]),
            q_y: Sym2::diagonal(q[2], q[3]),
            r_x: r[0],
            r_y: r[1],
        }
    }

    /// Checks that every block is positive semidefinite; the error names the field.
    pub const fn check(&self) -> Result<(), KalmanError> {
        if !self.q_x.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("q_x"));
        }
        if !self.q_y.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("q_y"));
        }
        if self.r_x.to_bits() < 0 {
            return Err(KalmanError::NotPositiveSemidefinite("r_x"));
        }
        if self.r_y.to_bits() < 0 {
            return Err(KalmanError::NotPositiveSemidefinite("r_y"));
        }
        Ok(())
    }
}

/// A rejected Kalman configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum KalmanError {
    /// The named covariance is not positive semidefinite.
    NotPositiveSemidefinite(&'static str),
}

impl core::fmt::Display for KalmanError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NotPositiveSemidefinite(field) => {
                write!(f, "covariance `{field}` is not positive semidefinite")
            }
        }
    }
}

impl core::error::Error for KalmanError {}

// ---------------------------------------------------------------------------------------
// Integer kernels, shared with the general filter of the tests (the bit-exactness argument
// depends on it).

/// `a + dt * b` with one rounding (to nearest, halves up), saturating. No overflow:
/// `|a << 16| <= 2^47` and `|dt * b| <= 2^62`.
const fn axpy(a: Q16, dt: Q16, b: Q16) -> Q16 {
    let wide = ((a.to_bits() as i64) << Q16::FRAC_BITS) + dt.to_bits() as i64 * b.to_bits() as i64;
    Q16::saturate((wide + (1 << (Q16::FRAC_BITS - 1))) >> Q16::FRAC_BITS)
}

/// `$name(n, d)`: `n / d` rounded to nearest, halves away from zero, for `d > 0`, on the
/// integer type `$t`. A function of the rational `n / d` only, so scaling `n` and `d` by
/// the same positive factor does not change it. Needs `2 |n| + d` to fit the unsigned
/// type of `$t`'s width.
macro_rules! div_round {
    ($name:ident, $t:ty) => {
        const fn $name(n: $t, d: $t) -> i128 {
            let d = d.unsigned_abs();
            let q = (2 * n.unsigned_abs() + d) / (2 * d);
            if n < 0 {
                -(q as i128)
            } else {
                q as i128
            }
        }
    };
}

div_round!(div_round_i64, i64);
#[cfg(test)]
div_round!(div_round_i128, i128);

/// Saturates a gain quotient to Q8.24 (`i32`).
const fn sat_gain(k: i128) -> i32 {
    if k > i32::MAX as i128 {
        i32::MAX
    } else if k < i32::MIN as i128 {
        i32::MIN
    } else {
        k as i32
    }
}

/// `p - c` for a covariance entry `p` and a correction `c` (Q16.16 raw), saturating.
const fn sub_correction(p: Q16, c: i128) -> Q16 {
    let c = if c > i64::MAX as i128 {
        i64::MAX
    } else if c < i64::MIN as i128 {
        i64::MIN
    } else {
        c as i64
    };
    Q16::saturate((p.to_bits() as i64).saturating_sub(c))
}

/// `c` limited to `|c| <= sqrt(a b)` (rounded down), for variances `a`, `b` (negative ones
/// count as 0): the covariance of two variables can be no larger, so `[[a, c], [c, b]]`
/// is positive semidefinite. A no-op unless saturation or rounding broke that.
const fn limit_covariance(c: Q16, a: Q16, b: Q16) -> Q16 {
    let (a, b) = (a.to_bits(), b.to_bits());
    let a = if a > 0 { a as u64 } else { 0 };
    let b = if b > 0 { b as u64 } else { 0 };
    let bound = (a * b).isqrt() as i64; // < 2^31
    let v = c.to_bits() as i64;
    Q16::from_bits(if v > bound {
        bound
    } else if v < -bound {
        -bound
    } else {
        v
    } as i32)
}

/// A 2x2 covariance made positive semidefinite: variances `>= 0`, the covariance
/// limited by [`limit_covariance`].
const fn psd2(p: Sym2) -> Sym2 {
    let a00 = p.a00.max(Q16::ZERO);
    let a11 = p.a11.max(Q16::ZERO);
    Sym2 {
        a00,
        a01: limit_covariance(p.a01, a00, a11),
        a11,
    }
}

/// `x + (k * e) / 2^24` rounded (halves up), saturating; `k` Q8.24 raw, `e` Q16.16 raw,
/// the product in Q40 as an `i64` (already summed over measurements).
const fn add_gain_product(x: Q16, ke: i64) -> Q16 {
    let delta = (ke.saturating_add(1 << (GAIN_FRAC_BITS - 1))) >> GAIN_FRAC_BITS;
    Q16::saturate(x.to_bits() as i64 + delta)
}

/// `k * e` in Q40 (`k` Q8.24 raw, `e` Q16.16 raw); `|k e| <= 2^62`.
const fn gain_product(k: i32, e: Q16) -> i64 {
    k as i64 * e.to_bits() as i64
}

/// Standard mean prediction `mu <- A(dt) mu`: `Hx += dt dHx`, `Hy += dt dHy` (one rounding
/// each, saturating). Rates are unchanged.
///
/// # Arguments
/// - `size`: the mean, Q16.16.
/// - `dt`: frame interval, Q16.16 (1.0 for one frame).
pub fn predict_mean(size: &mut Size, dt: Q16) {
    size.hx = axpy(size.hx, dt, size.dhx);
    size.hy = axpy(size.hy, dt, size.dhy);
}

// ---------------------------------------------------------------------------------------
// The shared filter: two independent 2x2 blocks.

/// Covariance of one (position, rate) block: 2 states, 1 measurement (the position).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Block {
    /// Covariance of (position, rate), Q16.16.
    pub cov: Sym2,
}

/// Gain of one [`Block`]: `K = P[:, 0] / S`, `S = P00 + r`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BlockGain {
    /// Gains of position and rate on the position measurement, raw Q8.24.
    pub k: [i32; 2],
    /// Innovation variance `S`, Q16.16 (saturated).
    pub s: Q16,
}

impl Block {
    /// Covariance prediction with `A = [[1, dt], [0, 1]]` and process noise `q`, computed
    /// as `M = A P` then `M A^T`, one rounding per product, and kept positive
    /// semidefinite.
    pub fn predict(&mut self, dt: Q16, q: &Sym2) {
        let p = self.cov;
        let m00 = axpy(p.a00, dt, p.a01);
        let m01 = axpy(p.a01, dt, p.a11);
        self.cov = psd2(Sym2 {
            a00: axpy(m00, dt, m01) + q.a00,
            a01: m01 + q.a01,
            a11: p.a11 + q.a11,
        });
    }

    /// `S = P00 + r` unsaturated (Q16.16 raw).
    fn s_raw(&self, r: Q16) -> i64 {
        self.cov.a00.to_bits() as i64 + r.to_bits() as i64
    }

    /// Gain for measurement variance `r` (Q16.16); `S <= 0` gives a zero gain.
    pub fn gain(&self, r: Q16) -> BlockGain {
        let s = self.s_raw(r);
        let k = |p: Q16| {
            if s <= 0 {
                0
            } else {
                sat_gain(div_round_i64((p.to_bits() as i64) << GAIN_FRAC_BITS, s))
            }
        };
        BlockGain {
            k: [k(self.cov.a00), k(self.cov.a01)],
            s: Q16::saturate(s),
        }
    }

    /// Covariance update `P <- P - P[:, 0] P[0, :] / S` (one rounded quotient per entry,
    /// kept positive semidefinite); `S <= 0` leaves `P` unchanged.
    pub fn update(&mut self, r: Q16) {
        let s = self.s_raw(r);
        if s <= 0 {
            return;
        }
        let p = self.cov;
        let (c0, c1) = (p.a00.to_bits() as i64, p.a01.to_bits() as i64);
        self.cov = psd2(Sym2 {
            a00: sub_correction(p.a00, div_round_i64(c0 * c0, s)),
            a01: sub_correction(p.a01, div_round_i64(c0 * c1, s)),
            a11: sub_correction(p.a11, div_round_i64(c1 * c1, s)),
        });
    }
}

impl BlockGain {
    /// `(position, rate) += K (y - position)`, saturating; `y` Q16.16.
    pub fn update_mean(&self, position: &mut Q16, rate: &mut Q16, y: Q16) {
        let e = y - *position;
        let [k0, k1] = self.k;
        *position = add_gain_product(*position, gain_product(k0, e));
        *rate = add_gain_product(*rate, gain_product(k1, e));
    }
}

/// Gains of both blocks of a [`SharedCovariance`], applied to every particle's mean.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SharedGain {
    /// Gain of the x block `(Hx, dHx)` on the `Hx` measurement.
    pub x: BlockGain,
    /// Gain of the y block `(Hy, dHy)` on the `Hy` measurement.
    pub y: BlockGain,
}

impl SharedGain {
    /// Mean update `mu += K (y - H mu)` of one particle's size with the measured half-axes
    /// `hx`, `hy` (px, Q16.16).
    pub fn update_mean(&self, size: &mut Size, hx: Q16, hy: Q16) {
        self.x.update_mean(&mut size.hx, &mut size.dhx, hx);
        self.y.update_mean(&mut size.hy, &mut size.dhy, hy);
    }

    /// Innovation covariance `S = diag(S_x, S_y)`, Q16.16.
    pub const fn innovation_cov(&self) -> Sym2 {
        Sym2::diagonal(self.x.s, self.y.s)
    }
}

/// One covariance and gain for all particles (block-diagonal noise, shared by all).
///
/// Per frame: [`SharedCovariance::predict`] once; each particle's mean predicted by the
/// caller (e.g. [`predict_mean`]); [`SharedCovariance::gain`] once; [`SharedGain::update_mean`]
/// per particle; [`SharedCovariance::update_cov`] once. [`SharedCovariance::update`] does
/// the last three for a slice of sizes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SharedCovariance {
    x: Block,
    y: Block,
    noise: BlockNoise,
}

impl SharedCovariance {
    /// Zero covariances and noise, before one is configured (every bit zero).
    pub const UNSET: Self = match Self::new(
        Sym2::ZERO,
        Sym2::ZERO,
        BlockNoise::diagonal([Q16::ZERO; 4], [Q16::ZERO; 2]),
    ) {
        Ok(c) => c,
        Err(_) => panic!("zero covariances are positive semidefinite"),
    };

    /// Starts from the block covariances `cov_x` of `(Hx, dHx)` and `cov_y` of `(Hy, dHy)`
    /// (Q16.16). Rejects a noise or a covariance that is not positive semidefinite.
    pub const fn new(cov_x: Sym2, cov_y: Sym2, noise: BlockNoise) -> Result<Self, KalmanError> {
        if let Err(e) = noise.check() {
            return Err(e);
        }
        if !cov_x.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("cov_x"));
        }
        if !cov_y.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("cov_y"));
        }
        Ok(Self {
            x: Block { cov: cov_x },
            y: Block { cov: cov_y },
            noise,
        })
    }

    /// The noise in use.
    pub const fn noise(&self) -> &BlockNoise {
        &self.noise
    }

    /// The covariance shared by all particles, as a 4x4.
    pub const fn cov(&self) -> Sym4 {
        Sym4::from_blocks(self.x.cov, self.y.cov)
    }

    /// Covariance prediction `P <- A(dt) P A(dt)^T + Q` (`dt` Q16.16).
    pub fn predict(&mut self, dt: Q16) {
        self.x.predict(dt, &self.noise.q_x);
        self.y.predict(dt, &self.noise.q_y);
    }

    /// The gain for the current (predicted) covariance.
    pub fn gain(&self) -> SharedGain {
        SharedGain {
            x: self.x.gain(self.noise.r_x),
            y: self.y.gain(self.noise.r_y),
        }
    }

    /// Covariance update `P <- P - K H P`, after [`SharedCovariance::gain`].
    pub fn update_cov(&mut self) {
        self.x.update(self.noise.r_x);
        self.y.update(self.noise.r_y);
    }

    /// Gain, mean update of every size in `sizes` with the measured half-axes `hx`, `hy`
    /// (px, Q16.16), covariance update. Returns the gain used.
    pub fn update(&mut self, sizes: &mut [Size], hx: Q16, hy: Q16) -> SharedGain {
        let gain = self.gain();
        for size in sizes.iter_mut() {
            gain.update_mean(size, hx, hy);
        }
        self.update_cov();
        gain
    }
}
