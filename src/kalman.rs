//! Hand-unrolled Kalman filter with 4 states and 2 measurements, in Q16.16.
//!
//! # Model
//! The state is the RBPF leaf `L = (Hy, dHy, Hx, dHx)`: two (position, rate) pairs, here
//! indexed 0..4 in that order. With the frame interval `dt`,
//!
//! ```text
//! A(dt) = [[1, dt, 0, 0],      H = [[1, 0, 0, 0],
//!          [0,  1, 0, 0],           [0, 0, 1, 0]]
//!          [0,  0, 1, dt],
//!          [0,  0, 0,  1]]
//! L_t = A L_{t-1} + w,  w ~ N(0, Q);     Y_t = H L_t + v,  v ~ N(0, R).
//! ```
//! The paper uses `Q = 4 I4` and `R = 2 I2` ([`BlockNoise::PAPER`]); both are configuration.
//!
//! The steps are separate, because the RBPF predicts each particle's *mean* with its own
//! rule (the scale follows the vertical motion, eq. 7 of the paper) but the *covariance*
//! with `P^- = A P A^T + Q`:
//! - covariance predict: [`Filter::predict_cov`], [`SharedCovariance::predict`];
//! - mean predict (the standard `A mu`): [`predict_mean`];
//! - gain: [`Filter::gain`], [`SharedCovariance::gain`];
//! - mean update `mu += K (y - H mu)`: [`Gain::update_mean`], [`SharedGain::update_mean`];
//! - covariance update `P -= K H P`: [`Filter::update_cov`], [`SharedCovariance::update_cov`].
//!
//! # Two paths
//! - [`Filter`]: one mean and one full symmetric covariance ([`Sym4`], 10 values) per
//!   particle; general symmetric `Q` ([`Sym4`]) and `R` ([`Sym2`]).
//! - [`SharedCovariance`]: the covariance recursion does not depend on the data, so when
//!   all particles share `Q` and `R` they share `P` and `K` too. One `P` per filter, N means.
//!   `A`, `H` and a [`BlockNoise`] are block-diagonal, so `P` splits into two independent
//!   2x2 blocks ([`Block`]: y = (Hy, dHy), x = (Hx, dHx)) and every division is a 64-bit
//!   scalar one.
//!
//! Both paths give bit-for-bit the same means and covariances when the noise is
//! block-diagonal and `P` starts block-diagonal (tested below): the gain and the covariance
//! correction are each computed as one correctly rounded quotient of exact integers, and
//! the 4x4 quotient reduces to the 2x2 one as a rational number. One exception: with a
//! zero measurement variance a block's innovation `S` can be 0; the general path then
//! skips the whole update (its 2x2 `S` is singular), the shared path only that block's.
//!
//! # Number formats
//! - Means, covariances, `Q`, `R`, `S`, `dt`, measurements: [`Q16`] (Q16.16, range
//!   `[-32768, 32768)`, resolution `2^-16`). All operations saturate.
//! - Gains: raw `i32` in Q8.24 ([`GAIN_FRAC_BITS`] = 24), range `[-128, 128)`, resolution
//!   `6e-8`; a gain outside that range saturates (only with a covariance that is far from
//!   its steady state, e.g. a rate variance 10^4 times the position variance).
//! - Intermediates: `i64` for products, `i128` for the general path's 2x2 inverse.
//!
//! # Keeping `P` positive semidefinite
//! Exact arithmetic keeps `P` positive semidefinite, but the Q16.16 rails do not: without
//! measurements `P` grows every prediction (with `Q = 4 I`, `P00` reaches the rail after
//! about 30 steps) and an entry that sticks at the rail while its neighbours keep growing
//! makes `P` indefinite (`P01^2 > P00 P11`). So every prediction and update ends by setting
//! negative variances to 0 and limiting each covariance to `|P_ij| <= sqrt(P_ii P_jj)`
//! (rounded down). This is a no-op while `P` is PSD, so it changes nothing away from the
//! rails; in the shared path it makes each 2x2 block PSD exactly (the general path: each
//! pair). Tested in `host-tests/tests/properties.rs` (extreme `Q`, `R`, `dt` and long runs
//! without measurements).
//!
//! # Accuracy
//! Each stored covariance entry is within one rounding (`2^-17`) of the exact update of the
//! stored inputs; each predicted entry within two. Against an `f64` filter over 1,000 steps
//! with `Q = 4 I`, `R = 2 I` the relative error stays below `1e-3` (measured in
//! `host-tests/tests/kalman_reference.rs`, which prints the figures).
//!
//! # Cost
//! Shared path per frame: a handful of 64-bit divisions for `P` and `K`, then per particle
//! four 32x32->64 multiplies for the mean update. The general path spends 18 `i128`
//! divisions per particle per update; use it only when particles really differ in `Q`/`R`.
//!
//! # Examples
//! ```
//! use rbtrack::fixed::Q16;
//! use rbtrack::kalman::{predict_mean, BlockNoise, SharedCovariance, Sym2};
//! let p0 = Sym2::diagonal(Q16::from_int(10), Q16::from_int(10));
//! let mut shared = SharedCovariance::new(p0, p0, BlockNoise::PAPER).unwrap();
//! let mut means = [[Q16::from_int(40), Q16::ZERO, Q16::from_int(25), Q16::ZERO]; 8];
//! for m in means.iter_mut() {
//!     predict_mean(m, Q16::ONE);
//! }
//! shared.predict(Q16::ONE);
//! let y = [Q16::from_int(42), Q16::from_int(26)];
//! shared.update(&mut means, y);
//! assert!(means[0][0] > Q16::from_int(40) && means[0][0] < Q16::from_int(42));
//! ```

use crate::fixed::Q16;

/// Fraction bits of a Kalman gain entry (Q8.24).
pub const GAIN_FRAC_BITS: u32 = 24;

/// Leaf mean `(Hy, dHy, Hx, dHx)`: positions in Q16.16 pixels, rates in Q16.16 pixels per
/// unit of `dt`.
pub type Mean = [Q16; 4];

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

/// Symmetric 4x4 matrix over `(Hy, dHy, Hx, dHx)`, Q16.16 entries; the fields are the upper
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

    /// Block-diagonal matrix with the y block `(Hy, dHy)` and the x block `(Hx, dHx)`.
    pub const fn from_blocks(y: Sym2, x: Sym2) -> Self {
        Self {
            a00: y.a00,
            a01: y.a01,
            a02: Q16::ZERO,
            a03: Q16::ZERO,
            a11: y.a11,
            a12: Q16::ZERO,
            a13: Q16::ZERO,
            a22: x.a00,
            a23: x.a01,
            a33: x.a11,
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

    /// The y block `(Hy, dHy)`.
    pub const fn y_block(&self) -> Sym2 {
        Sym2 {
            a00: self.a00,
            a01: self.a01,
            a11: self.a11,
        }
    }

    /// The x block `(Hx, dHx)`.
    pub const fn x_block(&self) -> Sym2 {
        Sym2 {
            a00: self.a22,
            a01: self.a23,
            a11: self.a33,
        }
    }

    /// Whether every entry coupling the y block with the x block is zero.
    pub fn is_block_diagonal(&self) -> bool {
        self.a02 == Q16::ZERO
            && self.a03 == Q16::ZERO
            && self.a12 == Q16::ZERO
            && self.a13 == Q16::ZERO
    }

    /// Whether the matrix is positive semidefinite, by an `f64` LDL^T factorisation with a
    /// tolerance of `1e-9` times the largest diagonal entry. Configuration time only.
    #[allow(clippy::needless_range_loop)]
    pub fn is_psd(&self) -> bool {
        let mut m = [[0f64; 4]; 4];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = self.get(i, j).to_f64();
            }
        }
        let scale = (0..4).fold(0f64, |s, i| s.max(m[i][i].abs()));
        let tol = 1e-9 * scale.max(1e-12);
        let mut d = [0f64; 4];
        let mut l = [[0f64; 4]; 4];
        for j in 0..4 {
            let mut dj = m[j][j];
            for k in 0..j {
                dj -= l[j][k] * l[j][k] * d[k];
            }
            if dj < -tol {
                return false;
            }
            d[j] = dj;
            for i in (j + 1)..4 {
                let mut v = m[i][j];
                for k in 0..j {
                    v -= l[i][k] * l[j][k] * d[k];
                }
                if dj > tol {
                    l[i][j] = v / dj;
                } else if v.abs() > tol {
                    // Zero pivot with a non-zero off-diagonal entry: indefinite.
                    return false;
                }
            }
        }
        true
    }
}

/// General noise: process covariance `Q` (4x4) and measurement covariance `R` (2x2), Q16.16.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Noise {
    /// Process noise covariance `Q`, Q16.16 (pixels^2 per step).
    pub q: Sym4,
    /// Measurement noise covariance `R`, Q16.16 (pixels^2).
    pub r: Sym2,
}

impl Noise {
    /// Checks that `Q` and `R` are positive semidefinite. Configuration time only.
    pub fn check(&self) -> Result<(), KalmanError> {
        if !self.q.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("q"));
        }
        if !self.r.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("r"));
        }
        Ok(())
    }
}

/// Block-diagonal noise, the kind the shared path needs: `Q = diag(q_y, q_x)` with a 2x2
/// block per axis and `R = diag(r_y, r_x)`. All Q16.16.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BlockNoise {
    /// Process noise of `(Hy, dHy)`, Q16.16.
    pub q_y: Sym2,
    /// Process noise of `(Hx, dHx)`, Q16.16.
    pub q_x: Sym2,
    /// Measurement noise variance of `Hy`, Q16.16, `>= 0`.
    pub r_y: Q16,
    /// Measurement noise variance of `Hx`, Q16.16, `>= 0`.
    pub r_x: Q16,
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

    /// Diagonal `Q = diag(q)` and `R = diag(r)`.
    pub const fn diagonal(q: [Q16; 4], r: [Q16; 2]) -> Self {
        Self {
            q_y: Sym2::diagonal(q[0], q[1]),
            q_x: Sym2::diagonal(q[2], q[3]),
            r_y: r[0],
            r_x: r[1],
        }
    }

    /// The same noise as a general [`Noise`].
    pub const fn general(&self) -> Noise {
        Noise {
            q: Sym4::from_blocks(self.q_y, self.q_x),
            r: Sym2::diagonal(self.r_y, self.r_x),
        }
    }

    /// Checks that every block is positive semidefinite; the error names the field.
    pub const fn check(&self) -> Result<(), KalmanError> {
        if !self.q_y.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("q_y"));
        }
        if !self.q_x.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("q_x"));
        }
        if self.r_y.to_bits() < 0 {
            return Err(KalmanError::NotPositiveSemidefinite("r_y"));
        }
        if self.r_x.to_bits() < 0 {
            return Err(KalmanError::NotPositiveSemidefinite("r_x"));
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
// Integer kernels shared by both paths (the bit-exactness argument depends on it).

/// `a + dt * b` with one rounding (to nearest, halves up), saturating. No overflow:
/// `|a << 16| <= 2^47` and `|dt * b| <= 2^62`.
const fn axpy(a: Q16, dt: Q16, b: Q16) -> Q16 {
    let wide = ((a.to_bits() as i64) << 16) + dt.to_bits() as i64 * b.to_bits() as i64;
    Q16::saturate((wide + 0x8000) >> 16)
}

/// `n / d` rounded to nearest, halves away from zero, for `d > 0`. A function of the
/// rational `n / d` only, so scaling `n` and `d` by the same positive factor does not
/// change it. Needs `2 |n| + d < 2^128`.
const fn div_round_i128(n: i128, d: i128) -> i128 {
    let d = d.unsigned_abs();
    let q = (2 * n.unsigned_abs() + d) / (2 * d);
    if n < 0 {
        -(q as i128)
    } else {
        q as i128
    }
}

/// As [`div_round_i128`] on 64 bits, for `d > 0` and `2 |n| + d < 2^64`.
const fn div_round_i64(n: i64, d: i64) -> i128 {
    let d = d.unsigned_abs();
    let q = (2 * n.unsigned_abs() + d) / (2 * d);
    if n < 0 {
        -(q as i128)
    } else {
        q as i128
    }
}

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

/// [`psd2`] for every pair of a 4x4 covariance: variances `>= 0`, every covariance
/// limited by its two variances. On a block-diagonal `P` this is [`psd2`] of each block
/// (the off-block entries are 0 and stay 0), so both paths stay bit-identical.
const fn psd4(p: Sym4) -> Sym4 {
    let a00 = p.a00.max(Q16::ZERO);
    let a11 = p.a11.max(Q16::ZERO);
    let a22 = p.a22.max(Q16::ZERO);
    let a33 = p.a33.max(Q16::ZERO);
    Sym4 {
        a00,
        a01: limit_covariance(p.a01, a00, a11),
        a02: limit_covariance(p.a02, a00, a22),
        a03: limit_covariance(p.a03, a00, a33),
        a11,
        a12: limit_covariance(p.a12, a11, a22),
        a13: limit_covariance(p.a13, a11, a33),
        a22,
        a23: limit_covariance(p.a23, a22, a33),
        a33,
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

/// Standard mean prediction `mu <- A(dt) mu`: `Hy += dt dHy`, `Hx += dt dHx` (one rounding
/// each, saturating). Rates are unchanged.
///
/// # Arguments
/// - `mean`: `(Hy, dHy, Hx, dHx)`, Q16.16.
/// - `dt`: frame interval, Q16.16 (1.0 for one frame).
pub fn predict_mean(mean: &mut Mean, dt: Q16) {
    let [hy, dhy, hx, dhx] = *mean;
    *mean = [axpy(hy, dt, dhy), dhy, axpy(hx, dt, dhx), dhx];
}

// ---------------------------------------------------------------------------------------
// General path.

/// Kalman gain `K = P H^T S^-1` (4x2) and innovation covariance `S = H P H^T + R`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Gain {
    /// `K[i][m]`: gain of state `i` on measurement `m` (0 = Hy, 1 = Hx), raw Q8.24.
    pub k: [[i32; 2]; 4],
    /// Innovation covariance `S`, Q16.16 (saturated), for predictive likelihoods.
    pub s: Sym2,
}

impl Gain {
    /// Zero gain: the update leaves the mean alone.
    pub const ZERO: Self = Self {
        k: [[0; 2]; 4],
        s: Sym2::ZERO,
    };

    /// Mean update `mu += K (y - H mu)`, saturating.
    ///
    /// # Arguments
    /// - `mean`: `(Hy, dHy, Hx, dHx)`, Q16.16, the predicted mean the gain was made for.
    /// - `y`: measurement `(Hy, Hx)`, Q16.16.
    pub fn update_mean(&self, mean: &mut Mean, y: [Q16; 2]) {
        let [hy, dhy, hx, dhx] = *mean;
        let e0 = y[0] - hy;
        let e1 = y[1] - hx;
        let [k0, k1, k2, k3] = self.k;
        let step = |x: Q16, k: [i32; 2]| {
            add_gain_product(
                x,
                gain_product(k[0], e0).saturating_add(gain_product(k[1], e1)),
            )
        };
        *mean = [step(hy, k0), step(dhy, k1), step(hx, k2), step(dhx, k3)];
    }
}

/// Innovation covariance of the general path, unsaturated: `(S00, S01, S11)` Q16.16 raw in
/// `i64`, and `det S` in Q32.32 (`i128`).
struct Innovation {
    s00: i64,
    s01: i64,
    s11: i64,
    det: i128,
}

impl Innovation {
    fn new(p: &Sym4, r: &Sym2) -> Self {
        let s00 = p.a00.to_bits() as i64 + r.a00.to_bits() as i64;
        let s01 = p.a02.to_bits() as i64 + r.a01.to_bits() as i64;
        let s11 = p.a22.to_bits() as i64 + r.a11.to_bits() as i64;
        let det = s00 as i128 * s11 as i128 - s01 as i128 * s01 as i128;
        Self { s00, s01, s11, det }
    }
}

/// One particle's Kalman filter: mean and full symmetric covariance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Filter {
    /// Mean `(Hy, dHy, Hx, dHx)`, Q16.16.
    pub mean: Mean,
    /// Covariance `P`, Q16.16.
    pub cov: Sym4,
}

impl Filter {
    /// A filter at `mean` with covariance `cov`.
    pub const fn new(mean: Mean, cov: Sym4) -> Self {
        Self { mean, cov }
    }

    /// Standard mean prediction, see [`predict_mean`].
    pub fn predict_mean(&mut self, dt: Q16) {
        predict_mean(&mut self.mean, dt);
    }

    /// Covariance prediction `P <- A(dt) P A(dt)^T + Q`, saturating. Computed as `M = A P`
    /// then `M A^T`, one rounding per product (upper triangle only, so `P` stays symmetric);
    /// then kept positive semidefinite pairwise (see the module docs).
    ///
    /// # Arguments
    /// - `dt`: frame interval, Q16.16.
    /// - `q`: process noise, Q16.16.
    pub fn predict_cov(&mut self, dt: Q16, q: &Sym4) {
        let p = self.cov;
        let m00 = axpy(p.a00, dt, p.a01);
        let m01 = axpy(p.a01, dt, p.a11);
        let m02 = axpy(p.a02, dt, p.a12);
        let m03 = axpy(p.a03, dt, p.a13);
        let m22 = axpy(p.a22, dt, p.a23);
        let m23 = axpy(p.a23, dt, p.a33);
        self.cov = psd4(Sym4 {
            a00: axpy(m00, dt, m01) + q.a00,
            a01: m01 + q.a01,
            a02: axpy(m02, dt, m03) + q.a02,
            a03: m03 + q.a03,
            a11: p.a11 + q.a11,
            a12: axpy(p.a12, dt, p.a13) + q.a12,
            a13: p.a13 + q.a13,
            a22: axpy(m22, dt, m23) + q.a22,
            a23: m23 + q.a23,
            a33: p.a33 + q.a33,
        });
    }

    /// Mean and covariance prediction with the standard `A mu`.
    pub fn predict(&mut self, dt: Q16, noise: &Noise) {
        self.predict_mean(dt);
        self.predict_cov(dt, &noise.q);
    }

    /// Gain `K = P H^T S^-1` from the current (predicted) covariance, each entry one
    /// correctly rounded quotient (closed-form 2x2 inverse, `i128`). A singular `S`
    /// (`det S <= 0`, possible only with a singular `R`) gives [`Gain::ZERO`] with `S`.
    pub fn gain(&self, r: &Sym2) -> Gain {
        let p = &self.cov;
        let inn = Innovation::new(p, r);
        let s = Sym2 {
            a00: Q16::saturate(inn.s00),
            a01: Q16::saturate(inn.s01),
            a11: Q16::saturate(inn.s11),
        };
        if inn.det <= 0 {
            return Gain { s, ..Gain::ZERO };
        }
        // Columns of P H^T: c0 = P[:, 0], c1 = P[:, 2].
        let c0 = [p.a00, p.a01, p.a02, p.a03];
        let c1 = [p.a02, p.a12, p.a22, p.a23];
        let row = |a: Q16, b: Q16| {
            let (a, b) = (a.to_bits() as i128, b.to_bits() as i128);
            let n0 = a * inn.s11 as i128 - b * inn.s01 as i128;
            let n1 = b * inn.s00 as i128 - a * inn.s01 as i128;
            [
                sat_gain(div_round_i128(n0 << GAIN_FRAC_BITS, inn.det)),
                sat_gain(div_round_i128(n1 << GAIN_FRAC_BITS, inn.det)),
            ]
        };
        Gain {
            k: [
                row(c0[0], c1[0]),
                row(c0[1], c1[1]),
                row(c0[2], c1[2]),
                row(c0[3], c1[3]),
            ],
            s,
        }
    }

    /// Covariance update `P <- P - K H P = P - (P H^T) S^-1 (H P)`, each entry corrected
    /// by one correctly rounded quotient of exact integers (`i128`), upper triangle only;
    /// then kept positive semidefinite pairwise (see the module docs). Call after
    /// [`Filter::gain`] and with the same `R`.
    /// A singular `S` leaves `P` unchanged.
    pub fn update_cov(&mut self, r: &Sym2) {
        let p = self.cov;
        let inn = Innovation::new(&p, r);
        if inn.det <= 0 {
            return;
        }
        let (s00, s01, s11, det) = (inn.s00 as i128, inn.s01 as i128, inn.s11 as i128, inn.det);
        // Columns of P H^T: c0 = P[:, 0], c1 = P[:, 2].
        let [c00, c01, c02, c03] = [p.a00, p.a01, p.a02, p.a03].map(|v| v.to_bits() as i128);
        let [c10, c11, c12, c13] = [p.a02, p.a12, p.a22, p.a23].map(|v| v.to_bits() as i128);
        // Row i of (P H^T) adj(S): [c0_i s11 - c1_i s01, c1_i s00 - c0_i s01] (|.| < 2^64).
        let w = |a: i128, b: i128| [a * s11 - b * s01, b * s00 - a * s01];
        let (w0, w1, w2, w3) = (w(c00, c10), w(c01, c11), w(c02, c12), w(c03, c13));
        // Entry (i, j) of (P H^T) S^-1 (H P): (w_i . (c0_j, c1_j)) / det, Q48 / Q32.
        let corr = |wi: [i128; 2], a: i128, b: i128| div_round_i128(wi[0] * a + wi[1] * b, det);
        self.cov = psd4(Sym4 {
            a00: sub_correction(p.a00, corr(w0, c00, c10)),
            a01: sub_correction(p.a01, corr(w0, c01, c11)),
            a02: sub_correction(p.a02, corr(w0, c02, c12)),
            a03: sub_correction(p.a03, corr(w0, c03, c13)),
            a11: sub_correction(p.a11, corr(w1, c01, c11)),
            a12: sub_correction(p.a12, corr(w1, c02, c12)),
            a13: sub_correction(p.a13, corr(w1, c03, c13)),
            a22: sub_correction(p.a22, corr(w2, c02, c12)),
            a23: sub_correction(p.a23, corr(w2, c03, c13)),
            a33: sub_correction(p.a33, corr(w3, c03, c13)),
        });
    }

    /// Full update with measurement `y = (Hy, Hx)` (Q16.16): gain, mean, covariance.
    /// Returns the gain (its `s` gives the predictive likelihood of `y`).
    pub fn update(&mut self, y: [Q16; 2], r: &Sym2) -> Gain {
        let gain = self.gain(r);
        gain.update_mean(&mut self.mean, y);
        self.update_cov(r);
        gain
    }
}

// ---------------------------------------------------------------------------------------
// Shared path: two independent 2x2 blocks.

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
    /// Covariance prediction with `A = [[1, dt], [0, 1]]` and process noise `q` (the same
    /// rounding steps as [`Filter::predict_cov`]), kept positive semidefinite.
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
    /// Gain of the y block `(Hy, dHy)` on the `Hy` measurement.
    pub y: BlockGain,
    /// Gain of the x block `(Hx, dHx)` on the `Hx` measurement.
    pub x: BlockGain,
}

impl SharedGain {
    /// Mean update `mu += K (y - H mu)` for one particle; `y = (Hy, Hx)`, Q16.16.
    pub fn update_mean(&self, mean: &mut Mean, y: [Q16; 2]) {
        let [mut hy, mut dhy, mut hx, mut dhx] = *mean;
        self.y.update_mean(&mut hy, &mut dhy, y[0]);
        self.x.update_mean(&mut hx, &mut dhx, y[1]);
        *mean = [hy, dhy, hx, dhx];
    }

    /// Innovation covariance `S = diag(S_y, S_x)`, Q16.16.
    pub const fn innovation_cov(&self) -> Sym2 {
        Sym2::diagonal(self.y.s, self.x.s)
    }
}

/// One covariance and gain for all particles (block-diagonal noise, shared by all).
///
/// Per frame: [`SharedCovariance::predict`] once; each particle's mean predicted by the
/// caller (e.g. [`predict_mean`]); [`SharedCovariance::gain`] once; [`SharedGain::update_mean`]
/// per particle; [`SharedCovariance::update_cov`] once. [`SharedCovariance::update`] does
/// the last three for a slice of means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SharedCovariance {
    y: Block,
    x: Block,
    noise: BlockNoise,
}

impl SharedCovariance {
    /// Zero covariances and noise, before one is configured (every bit zero).
    pub const UNSET: Self = {
        let zero = Sym2::diagonal(Q16::ZERO, Q16::ZERO);
        match Self::new(
            zero,
            zero,
            BlockNoise::diagonal([Q16::ZERO; 4], [Q16::ZERO; 2]),
        ) {
            Ok(c) => c,
            Err(_) => panic!("zero covariances are positive semidefinite"),
        }
    };

    /// Starts from the block covariances `cov_y` of `(Hy, dHy)` and `cov_x` of `(Hx, dHx)`
    /// (Q16.16). Rejects a noise or a covariance that is not positive semidefinite.
    pub const fn new(cov_y: Sym2, cov_x: Sym2, noise: BlockNoise) -> Result<Self, KalmanError> {
        if let Err(e) = noise.check() {
            return Err(e);
        }
        if !cov_y.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("cov_y"));
        }
        if !cov_x.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("cov_x"));
        }
        Ok(Self {
            y: Block { cov: cov_y },
            x: Block { cov: cov_x },
            noise,
        })
    }

    /// The noise in use.
    pub const fn noise(&self) -> &BlockNoise {
        &self.noise
    }

    /// The covariance shared by all particles, as a 4x4.
    pub const fn cov(&self) -> Sym4 {
        Sym4::from_blocks(self.y.cov, self.x.cov)
    }

    /// Covariance prediction `P <- A(dt) P A(dt)^T + Q` (`dt` Q16.16).
    pub fn predict(&mut self, dt: Q16) {
        self.y.predict(dt, &self.noise.q_y);
        self.x.predict(dt, &self.noise.q_x);
    }

    /// The gain for the current (predicted) covariance.
    pub fn gain(&self) -> SharedGain {
        SharedGain {
            y: self.y.gain(self.noise.r_y),
            x: self.x.gain(self.noise.r_x),
        }
    }

    /// Covariance update `P <- P - K H P`, after [`SharedCovariance::gain`].
    pub fn update_cov(&mut self) {
        self.y.update(self.noise.r_y);
        self.x.update(self.noise.r_x);
    }

    /// Gain, mean update of every mean in `means` with measurement `y = (Hy, Hx)`
    /// (Q16.16), covariance update. Returns the gain used.
    pub fn update(&mut self, means: &mut [Mean], y: [Q16; 2]) -> SharedGain {
        let gain = self.gain();
        for mean in means.iter_mut() {
            gain.update_mean(mean, y);
        }
        self.update_cov();
        gain
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn q(v: f64) -> Q16 {
        Q16::from_f64(v)
    }

    fn paper_filter() -> (Filter, Noise) {
        let f = Filter::new(
            [q(40.0), q(0.5), q(25.0), q(-0.25)],
            Sym4::diagonal([q(10.0); 4]),
        );
        (f, BlockNoise::PAPER.general())
    }

    /// Shared path == per-particle path, bit for bit: 32 particles, 300 steps, random
    /// means, measurements and dt, diagonal and correlated block noise.
    #[test]
    fn shared_path_is_bit_exact_with_per_particle_filters() {
        let noises = [
            BlockNoise::PAPER,
            BlockNoise {
                q_y: Sym2 {
                    a00: q(0.25),
                    a01: q(0.5),
                    a11: q(1.0),
                },
                q_x: Sym2 {
                    a00: q(1.0 / 3.0),
                    a01: q(0.5),
                    a11: q(1.0),
                },
                r_y: q(3.0),
                r_x: q(0.7),
            },
        ];
        for (case, noise) in noises.iter().enumerate() {
            let mut rng = Rng::new(100 + case as u64);
            let p0y = Sym2 {
                a00: q(9.0),
                a01: q(1.5),
                a11: q(4.0),
            };
            let p0x = Sym2::diagonal(q(16.0), q(2.0));
            let mut shared = SharedCovariance::new(p0y, p0x, *noise).unwrap();
            let general = noise.general();
            let mut means = [[Q16::ZERO; 4]; 32];
            for m in means.iter_mut() {
                *m = [
                    q(50.0) + rng.gaussian(q(5.0)),
                    rng.normal(),
                    q(30.0) + rng.gaussian(q(5.0)),
                    rng.normal(),
                ];
            }
            let mut filters = means.map(|m| Filter::new(m, shared.cov()));
            for step in 0..300 {
                let dt = if step % 7 == 0 {
                    Q16::from_bits(rng.below(3 << 16) as i32)
                } else {
                    Q16::ONE
                };
                shared.predict(dt);
                for m in means.iter_mut() {
                    predict_mean(m, dt);
                }
                for f in filters.iter_mut() {
                    f.predict(dt, &general);
                }
                let y = [
                    q(50.0) + rng.gaussian(q(8.0)),
                    q(30.0) + rng.gaussian(q(8.0)),
                ];
                let g = shared.update(&mut means, y);
                for f in filters.iter_mut() {
                    let gf = f.update(y, &general.r);
                    assert_eq!(gf.s, g.innovation_cov());
                    assert_eq!(gf.k[0], [g.y.k[0], 0]);
                    assert_eq!(gf.k[1], [g.y.k[1], 0]);
                    assert_eq!(gf.k[2], [0, g.x.k[0]]);
                    assert_eq!(gf.k[3], [0, g.x.k[1]]);
                }
                for (f, m) in filters.iter().zip(means.iter()) {
                    assert_eq!(f.mean, *m, "case {case} step {step}");
                    assert_eq!(f.cov, shared.cov(), "case {case} step {step}");
                }
            }
        }
    }

    /// One step by hand: P = 10 I, Q = 4 I, R = 2 I, dt = 1.
    #[test]
    fn one_step_matches_hand_computation() {
        let (mut f, noise) = paper_filter();
        f.predict(Q16::ONE, &noise);
        // P^- y block: [[10 + 10 + 4, 10], [10, 14]] = [[24, 10], [10, 14]].
        assert_eq!(f.cov.a00, q(24.0));
        assert_eq!(f.cov.a01, q(10.0));
        assert_eq!(f.cov.a11, q(14.0));
        assert_eq!(f.mean, [q(40.5), q(0.5), q(24.75), q(-0.25)]);
        let g = f.update([q(41.5), q(24.75)], &noise.r);
        // S = 26, K = (24/26, 10/26); mean += K * 1.
        assert_eq!(g.s.a00, q(26.0));
        let k0 = g.k[0][0] as f64 / (1u64 << 24) as f64;
        assert!((k0 - 24.0 / 26.0).abs() < 1e-7);
        assert!((f.mean[0].to_f64() - (40.5 + 24.0 / 26.0)).abs() < 2e-5);
        assert!((f.mean[1].to_f64() - (0.5 + 10.0 / 26.0)).abs() < 2e-5);
        // P = P^- - c c^T / S, c = (24, 10).
        assert!((f.cov.a00.to_f64() - (24.0 - 576.0 / 26.0)).abs() < 1e-5);
        assert!((f.cov.a01.to_f64() - (10.0 - 240.0 / 26.0)).abs() < 1e-5);
        assert!((f.cov.a11.to_f64() - (14.0 - 100.0 / 26.0)).abs() < 1e-5);
        assert!(f.cov.is_psd());
    }

    /// A measurement near the Q16.16 rails saturates instead of wrapping.
    #[test]
    fn huge_measurements_saturate() {
        let (mut f, noise) = paper_filter();
        for _ in 0..50 {
            f.predict(Q16::ONE, &noise);
            f.update([Q16::MAX, Q16::MIN], &noise.r);
        }
        assert!(f.mean[0] > q(30_000.0));
        assert!(f.mean[2] < q(-30_000.0));
        assert!(f.cov.is_psd());
        // And back: no stuck state.
        for _ in 0..200 {
            f.predict(Q16::ONE, &noise);
            f.update([q(10.0), q(10.0)], &noise.r);
        }
        assert!((f.mean[0].to_f64() - 10.0).abs() < 1.0, "{:?}", f.mean);
        assert!((f.mean[2].to_f64() - 10.0).abs() < 1.0, "{:?}", f.mean);
        // Shared path, same abuse.
        let mut s = SharedCovariance::new(
            Sym2::diagonal(q(10.0), q(10.0)),
            Sym2::diagonal(q(10.0), q(10.0)),
            BlockNoise::PAPER,
        )
        .unwrap();
        let mut means = [[Q16::MIN, Q16::MAX, Q16::MAX, Q16::MIN]; 3];
        for _ in 0..20 {
            for m in means.iter_mut() {
                predict_mean(m, Q16::MAX);
            }
            s.predict(Q16::MAX);
            s.update(&mut means, [Q16::MAX, Q16::MIN]);
        }
        assert!(s.cov().is_psd());
    }

    /// Zero Q and R: the measured positions are taken exactly; P stays PSD.
    #[test]
    fn zero_noise() {
        let noise = Noise {
            q: Sym4::ZERO,
            r: Sym2::ZERO,
        };
        let mut f = Filter::new(
            [q(5.0), q(1.0), q(7.0), q(0.0)],
            Sym4::diagonal([q(1.0); 4]),
        );
        f.predict(Q16::ONE, &noise);
        f.update([q(8.0), q(9.0)], &noise.r);
        assert_eq!(f.mean[0], q(8.0));
        assert_eq!(f.mean[2], q(9.0));
        assert_eq!(f.cov.a00, Q16::ZERO);
        assert_eq!(f.cov.a22, Q16::ZERO);
        assert!(f.cov.is_psd());
        // Second step: the rate is learnt from the two exact positions.
        f.predict(Q16::ONE, &noise);
        f.update([q(10.0), q(9.0)], &noise.r);
        assert_eq!(f.mean[0], q(10.0));
        assert!((f.mean[1].to_f64() - 2.0).abs() < 1e-4, "{:?}", f.mean);
        // With P = 0 as well, S is singular: no update, no panic.
        let mut g = Filter::new([q(1.0); 4], Sym4::ZERO);
        g.predict(Q16::ONE, &noise);
        let gain = g.update([q(100.0), q(100.0)], &noise.r);
        assert_eq!(gain.k, [[0; 2]; 4]);
        assert_eq!(g.mean, [q(2.0), q(1.0), q(2.0), q(1.0)]);
        let mut b = Block { cov: Sym2::ZERO };
        assert_eq!(b.gain(Q16::ZERO).k, [0, 0]);
        b.update(Q16::ZERO);
        assert_eq!(b.cov, Sym2::ZERO);
    }

    /// Huge R: the measurement is ignored; huge Q: it is followed.
    #[test]
    fn huge_noise() {
        let big = q(30_000.0);
        let (f0, _) = paper_filter();
        let mut f = f0;
        let noise = Noise {
            q: Sym4::diagonal([q(0.01); 4]),
            r: Sym2::diagonal(big, big),
        };
        f.predict(Q16::ONE, &noise);
        f.update([q(1000.0), q(1000.0)], &noise.r);
        assert!((f.mean[0].to_f64() - 40.5).abs() < 1.0, "{:?}", f.mean);
        let mut f = f0;
        let noise = Noise {
            q: Sym4::diagonal([big; 4]),
            r: Sym2::diagonal(q(0.01), q(0.01)),
        };
        for _ in 0..5 {
            f.predict(Q16::ONE, &noise);
            f.update([q(1000.0), q(-1000.0)], &noise.r);
            assert!(f.cov.is_psd());
        }
        assert!((f.mean[0].to_f64() - 1000.0).abs() < 0.1, "{:?}", f.mean);
        assert!((f.mean[2].to_f64() + 1000.0).abs() < 0.1, "{:?}", f.mean);
    }

    /// Arbitrary bit patterns everywhere (covariances not PSD, negative noise, any dt):
    /// no overflow panic (tests run with overflow checks) in either path.
    #[test]
    fn arbitrary_inputs_never_panic() {
        let mut rng = Rng::new(77);
        let mut any = || {
            let w = rng.next_u32() as i32;
            match w & 3 {
                0 => Q16::from_bits(w),
                1 => Q16::MAX,
                2 => Q16::MIN,
                _ => Q16::from_bits(w >> 12),
            }
        };
        for _ in 0..20_000 {
            let mut sym4 = || Sym4 {
                a00: any(),
                a01: any(),
                a02: any(),
                a03: any(),
                a11: any(),
                a12: any(),
                a13: any(),
                a22: any(),
                a23: any(),
                a33: any(),
            };
            let (cov, q4) = (sym4(), sym4());
            let mut sym2 = || Sym2 {
                a00: any(),
                a01: any(),
                a11: any(),
            };
            let (r2, by, bx) = (sym2(), sym2(), sym2());
            let mut f = Filter::new([any(), any(), any(), any()], cov);
            let dt = any();
            let y = [any(), any()];
            f.predict(dt, &Noise { q: q4, r: r2 });
            let _ = f.update(y, &r2);
            let mut b = Block { cov: by };
            b.predict(dt, &bx);
            let g = b.gain(any());
            let (mut p, mut v) = (any(), any());
            g.update_mean(&mut p, &mut v, any());
            b.update(any());
        }
    }

    /// Regression (found by the `kalman` fuzz target): with no measurement for
    /// 31 steps (`Q = 4 I`), `P00` stuck at the rail while `P01` kept growing and `P`
    /// became indefinite; a negative `dt` made a variance negative. Both paths now stay
    /// positive semidefinite, and the shared one still equals the general one bit for bit.
    #[test]
    fn rails_keep_the_covariance_psd() {
        let noise = BlockNoise::PAPER;
        let p0 = Sym2::diagonal(q(2.0), q(4.0));
        let mut shared = SharedCovariance::new(p0, p0, noise).unwrap();
        let mut f = Filter::new([Q16::ZERO; 4], Sym4::from_blocks(p0, p0));
        let mut means = [[q(10.0), Q16::ZERO, q(10.0), Q16::ZERO]];
        let mut step = |dt: Q16, update: bool| {
            shared.predict(dt);
            f.predict_cov(dt, &noise.general().q);
            if update {
                shared.update(&mut means, [q(10.0), q(10.0)]);
                f.update([q(10.0), q(10.0)], &noise.general().r);
            }
            assert!(shared.cov().y_block().is_psd() && shared.cov().x_block().is_psd());
            assert_eq!(shared.cov(), f.cov);
            shared.cov()
        };
        let mut p = Sym4::ZERO;
        for _ in 0..2000 {
            p = step(Q16::ONE, false);
        }
        assert_eq!(p.a00, Q16::MAX);
        for _ in 0..50 {
            p = step(Q16::ONE, true);
        }
        // Back at the steady state of the paper's noise.
        assert!((p.a00.to_f64() - 1.7643).abs() < 1e-3, "{p:?}");
        for dt in [Q16::MIN, Q16::MAX, q(-3.0), q(700.0)] {
            step(dt, false);
            step(dt, true);
        }
    }

    /// dt = 0: A = I, so predict only adds Q and leaves the mean.
    #[test]
    fn dt_zero() {
        let (mut f, noise) = paper_filter();
        let before = f;
        f.predict(Q16::ZERO, &noise);
        assert_eq!(f.mean, before.mean);
        assert_eq!(f.cov, Sym4::diagonal([q(14.0); 4]));
    }

    /// Correlated measurement noise: general path still symmetric, PSD, and close to a
    /// float computation.
    #[test]
    fn correlated_noise_matches_float() {
        let mut f = Filter::new(
            [q(10.0), q(0.0), q(20.0), q(0.0)],
            Sym4 {
                a02: q(2.0),
                a13: q(0.5),
                ..Sym4::diagonal([q(5.0), q(1.0), q(6.0), q(2.0)])
            },
        );
        let r = Sym2 {
            a00: q(2.0),
            a01: q(1.0),
            a11: q(3.0),
        };
        let y = [q(12.0), q(17.0)];
        // Float reference of the gain.
        let p0 = f.cov;
        let p = |i, j| p0.get(i, j).to_f64();
        let (s00, s01, s11) = (p(0, 0) + 2.0, p(0, 2) + 1.0, p(2, 2) + 3.0);
        let det = s00 * s11 - s01 * s01;
        let k = |i| {
            let (a, b) = (p(i, 0), p(i, 2));
            [(a * s11 - b * s01) / det, (b * s00 - a * s01) / det]
        };
        let g = f.update(y, &r);
        for i in 0..4 {
            for m in 0..2 {
                let got = g.k[i][m] as f64 / (1u64 << 24) as f64;
                assert!((got - k(i)[m]).abs() < 1e-7, "{i} {m} {got} {:?}", k(i));
            }
        }
        assert!(f.cov.is_psd());
    }

    #[test]
    fn config_checks() {
        assert!(BlockNoise::PAPER.check().is_ok());
        assert!(BlockNoise::PAPER.general().check().is_ok());
        let bad = BlockNoise {
            r_x: q(-1.0),
            ..BlockNoise::PAPER
        };
        assert_eq!(
            bad.check(),
            Err(KalmanError::NotPositiveSemidefinite("r_x"))
        );
        let bad = BlockNoise {
            q_y: Sym2 {
                a00: q(1.0),
                a01: q(2.0),
                a11: q(1.0),
            },
            ..BlockNoise::PAPER
        };
        assert_eq!(
            bad.check(),
            Err(KalmanError::NotPositiveSemidefinite("q_y"))
        );
        let err = SharedCovariance::new(
            Sym2::diagonal(q(-1.0), q(1.0)),
            Sym2::ZERO,
            BlockNoise::PAPER,
        );
        assert_eq!(err, Err(KalmanError::NotPositiveSemidefinite("cov_y")));
        let indefinite = Sym4 {
            a03: q(3.0),
            ..Sym4::diagonal([q(1.0); 4])
        };
        assert!(!indefinite.is_psd());
        assert!(Sym4::ZERO.is_psd());
        let semidefinite = Sym4 {
            a02: q(1.0),
            ..Sym4::diagonal([q(1.0), q(0.0), q(1.0), q(2.0)])
        };
        assert!(semidefinite.is_psd());
        extern crate std;
        use std::string::ToString;
        assert_eq!(
            KalmanError::NotPositiveSemidefinite("q").to_string(),
            "covariance `q` is not positive semidefinite"
        );
        assert_eq!(Sym4::ZERO.get(7, 1), Q16::ZERO);
    }
}
