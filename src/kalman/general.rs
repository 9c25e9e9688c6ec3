//! The general per-particle Kalman filter, the tests' reference for the shared one: one
//! mean and one full symmetric 4x4 covariance per particle, general symmetric `Q` ([`Sym4`])
//! and `R` ([`Sym2`]), the gain by a closed-form 2x2 inverse in `i128` (18 `i128`
//! divisions per update). Built from the same integer kernels as the shared filter, so
//! that the two agree bit for bit where the noise is block-diagonal.

use super::{
    add_gain_product, axpy, div_round_i128, gain_product, limit_covariance, predict_mean, sat_gain,
    sub_correction, BlockNoise, KalmanError, Size, Sym2, Sym4, GAIN_FRAC_BITS,
};
use crate::fixed::Q16;

impl Sym4 {
    /// Whether the matrix is positive semidefinite, by an `f64` LDL^T factorisation with a
    /// tolerance of `1e-9` times the largest diagonal entry.
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn is_psd(&self) -> bool {
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
pub(crate) struct Noise {
    /// Process noise covariance `Q`, Q16.16 (pixels^2 per step).
    pub q: Sym4,
    /// Measurement noise covariance `R`, Q16.16 (pixels^2).
    pub r: Sym2,
}

impl Noise {
    /// Checks that `Q` and `R` are positive semidefinite.
    pub(crate) fn check(&self) -> Result<(), KalmanError> {
        if !self.q.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("q"));
        }
        if !self.r.is_psd() {
            return Err(KalmanError::NotPositiveSemidefinite("r"));
        }
        Ok(())
    }
}

impl BlockNoise {
    /// The same noise as a general [`Noise`].
    pub(crate) const fn general(&self) -> Noise {
        Noise {
            q: Sym4::from_blocks(self.q_x, self.q_y),
            r: Sym2::diagonal(self.r_x, self.r_y),
        }
    }
}

/// [`super::psd2`] for every pair of a 4x4 covariance: variances `>= 0`, every covariance
/// limited by its two variances. On a block-diagonal `P` this is `psd2` of each block
/// (the off-block entries are 0 and stay 0), so both filters stay bit-identical.
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

/// Kalman gain `K = P H^T S^-1` (4x2) and innovation covariance `S = H P H^T + R`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Gain {
    /// `K[i][m]`: gain of state `i` (`Hx, dHx, Hy, dHy`) on measurement `m` (0 = Hx,
    /// 1 = Hy), raw Q8.24.
    pub k: [[i32; 2]; 4],
    /// Innovation covariance `S`, Q16.16 (saturated), for predictive likelihoods.
    pub s: Sym2,
}

impl Gain {
    /// Zero gain: the update leaves the mean alone.
    const ZERO: Self = Self {
        k: [[0; 2]; 4],
        s: Sym2::ZERO,
    };

    /// Mean update `mu += K (y - H mu)`, saturating, for the measurement `y = (Hx, Hy)`
    /// (Q16.16) and the predicted mean the gain was made for.
    pub(crate) fn update_mean(&self, mean: &mut Size, y: [Q16; 2]) {
        let e0 = y[0] - mean.hx;
        let e1 = y[1] - mean.hy;
        let [k0, k1, k2, k3] = self.k;
        let step = |x: Q16, k: [i32; 2]| {
            add_gain_product(
                x,
                gain_product(k[0], e0).saturating_add(gain_product(k[1], e1)),
            )
        };
        *mean = Size {
            hx: step(mean.hx, k0),
            dhx: step(mean.dhx, k1),
            hy: step(mean.hy, k2),
            dhy: step(mean.dhy, k3),
        };
    }
}

/// Innovation covariance, unsaturated: `(S00, S01, S11)` Q16.16 raw in `i64`, and `det S`
/// in Q32.32 (`i128`).
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
pub(crate) struct Filter {
    /// Mean, Q16.16.
    pub mean: Size,
    /// Covariance `P` over `(Hx, dHx, Hy, dHy)`, Q16.16.
    pub cov: Sym4,
}

impl Filter {
    /// A filter at `mean` with covariance `cov`.
    pub(crate) const fn new(mean: Size, cov: Sym4) -> Self {
        Self { mean, cov }
    }

    /// Standard mean prediction, see [`predict_mean`].
    pub(crate) fn predict_mean(&mut self, dt: Q16) {
        predict_mean(&mut self.mean, dt);
    }

    /// Covariance prediction `P <- A(dt) P A(dt)^T + Q`, saturating. Computed as `M = A P`
    /// then `M A^T`, one rounding per product (upper triangle only, so `P` stays symmetric);
    /// then kept positive semidefinite pairwise.
    pub(crate) fn predict_cov(&mut self, dt: Q16, q: &Sym4) {
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
    pub(crate) fn predict(&mut self, dt: Q16, noise: &Noise) {
        self.predict_mean(dt);
        self.predict_cov(dt, &noise.q);
    }

    /// Gain `K = P H^T S^-1` from the current (predicted) covariance, each entry one
    /// correctly rounded quotient (closed-form 2x2 inverse, `i128`). A singular `S`
    /// (`det S <= 0`, possible only with a singular `R`) gives a zero gain with `S`.
    pub(crate) fn gain(&self, r: &Sym2) -> Gain {
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
    /// then kept positive semidefinite pairwise. Call after [`Filter::gain`] and with the
    /// same `R`. A singular `S` leaves `P` unchanged.
    pub(crate) fn update_cov(&mut self, r: &Sym2) {
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

    /// Full update with the measurement `y = (Hx, Hy)` (Q16.16): gain, mean, covariance.
    /// Returns the gain (its `s` gives the predictive likelihood of `y`).
    pub(crate) fn update(&mut self, y: [Q16; 2], r: &Sym2) -> Gain {
        let gain = self.gain(r);
        gain.update_mean(&mut self.mean, y);
        self.update_cov(r);
        gain
    }
}
