//! Properties of both filters over random inputs that include the extremes: the shared
//! covariance stays symmetric positive semidefinite under extreme `Q`, `R`, `dt`,
//! measurements and long runs without measurements, positive definite after each
//! prediction away from the rails, and equal to the general filter's; the general
//! filter's stays pairwise positive semidefinite even with a coupled covariance and
//! correlated measurement noise.
//!
//! Case counts are proptest's default (256); set `PROPTEST_CASES` to run more.

use super::general::{Filter, Noise};
use super::{predict_mean, BlockNoise, SharedCovariance, Size, Sym2, Sym4};
use crate::fixed::Q16;
use crate::rng::Rng;
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use std::boxed::Box;
use std::vec::Vec;

/// Any Q16.16 value (a `dt`, a measurement): anything, the rails, or a plausible number
/// of pixels.
fn any_q16() -> impl Strategy<Value = Q16> {
    let plausible = (-300i32..300, 0i32..65536).prop_map(|(i, f)| Q16::from_bits((i << 16) | f));
    prop_oneof![
        any::<i32>().prop_map(Q16::from_bits),
        Just(Q16::MAX),
        Just(Q16::MIN),
        Just(Q16::ZERO),
        plausible,
    ]
}

/// A positive semidefinite 2x2 from any variances (`|.|` of anything, the rail included)
/// and a correlation in `[-1, 1]`.
fn psd2_case() -> impl Strategy<Value = Sym2> {
    (variance_case(), variance_case(), -1.0f64..=1.0).prop_map(|(a, c, rho)| {
        let bound = (a.to_bits() as u64 * c.to_bits() as u64).isqrt() as i64;
        let b = ((rho * bound as f64) as i64).clamp(-bound, bound) as i32;
        Sym2 {
            a00: a,
            a01: Q16::from_bits(b),
            a11: c,
        }
    })
}

/// A variance: 0, tiny, the configuration range, huge or the rail.
fn variance_case() -> impl Strategy<Value = Q16> {
    prop_oneof![
        Just(Q16::ZERO),
        (1i32..256).prop_map(Q16::from_bits),
        (1i32..=1024 << 16).prop_map(Q16::from_bits),
        (1i32 << 26..=i32::MAX).prop_map(Q16::from_bits),
        Just(Q16::MAX),
    ]
}

#[derive(Debug, Clone, Copy)]
enum KalmanOp {
    /// Predict with `dt = 1` (the tracker's).
    Predict,
    /// Predict with any `dt`.
    PredictDt(Q16),
    /// Measurement `(Hx, Hy)`.
    Update(Q16, Q16),
    /// Many predictions without a measurement (a long `Lost` stretch).
    Coast(u16),
}

fn kalman_ops() -> impl Strategy<Value = Vec<KalmanOp>> {
    prop::collection::vec(
        prop_oneof![
            6 => Just(KalmanOp::Predict),
            1 => any_q16().prop_map(KalmanOp::PredictDt),
            6 => (any_q16(), any_q16()).prop_map(|(a, b)| KalmanOp::Update(a, b)),
            1 => (1u16..3000).prop_map(KalmanOp::Coast),
        ],
        1..60,
    )
}

fn det_positive(p: &Sym2) -> bool {
    let (a, b, c) = (
        p.a00.to_bits() as i64,
        p.a01.to_bits() as i64,
        p.a11.to_bits() as i64,
    );
    a > 0 && a * c > b * b
}

fn at_rail(p: &Sym2) -> bool {
    [p.a00, p.a01, p.a11]
        .iter()
        .any(|v| *v == Q16::MAX || *v == Q16::MIN)
}

proptest! {
    #![proptest_config(ProptestConfig {
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions"))),
        ..ProptestConfig::default()
    })]

    /// The shared covariance: symmetric (block-diagonal, one value per off-diagonal
    /// pair), each block positive semidefinite after every operation, exactly in integers;
    /// after each prediction with a noise whose variances are at least 2^-8, positive
    /// definite unless an entry sits at a rail; the general path given the same noise
    /// stays bit-identical (for a measurement noise with non-zero variances).
    #[test]
    fn shared_covariance_stays_positive_definite(
        q_y in psd2_case(),
        q_x in psd2_case(),
        r in (variance_case(), variance_case()),
        p_y in psd2_case(),
        p_x in psd2_case(),
        ops in kalman_ops(),
    ) {
        let noise = BlockNoise { q_y, q_x, r_y: r.0, r_x: r.1 };
        let mut shared = SharedCovariance::new(p_x, p_y, noise).expect("PSD by construction");
        let mut general = Filter::new(Size::default(), Sym4::from_blocks(p_x, p_y));
        let gnoise: Noise = noise.general();
        let mut means = [Size::at_rest(Q16::from_int(10), Q16::from_int(20)); 3];
        let min_q = Q16::from_bits(256);
        let q_definite = [q_y.a00, q_y.a11, q_x.a00, q_x.a11].iter().all(|&v| v >= min_q)
            && det_positive(&q_y)
            && det_positive(&q_x);
        let check = |shared: &SharedCovariance, general: &Filter, predicted: bool| {
            let p = shared.cov();
            prop_assert!(p.is_block_diagonal());
            for i in 0..4 {
                for j in 0..4 {
                    prop_assert_eq!(p.get(i, j), p.get(j, i));
                }
            }
            for block in [p.x_block(), p.y_block()] {
                prop_assert!(block.is_psd(), "not PSD: {:?}", p);
                if predicted && q_definite && !at_rail(&block) {
                    prop_assert!(det_positive(&block), "not definite: {:?}", p);
                }
            }
            // With a zero measurement variance one block's S can be 0; the general path
            // then skips the whole update (its 2x2 S is singular), the shared one only
            // that block's. Otherwise the two are bit-identical.
            if noise.r_y > Q16::ZERO && noise.r_x > Q16::ZERO {
                prop_assert_eq!(p, general.cov);
            }
            Ok(())
        };
        for op in ops {
            match op {
                KalmanOp::Predict | KalmanOp::PredictDt(_) | KalmanOp::Coast(_) => {
                    let (dt, times) = match op {
                        KalmanOp::PredictDt(dt) => (dt, 1),
                        KalmanOp::Coast(n) => (Q16::ONE, n),
                        _ => (Q16::ONE, 1),
                    };
                    for _ in 0..times {
                        shared.predict(dt);
                        general.predict_cov(dt, &gnoise.q);
                        for m in means.iter_mut() {
                            predict_mean(m, dt);
                        }
                        check(&shared, &general, dt == Q16::ONE)?;
                    }
                }
                KalmanOp::Update(hx, hy) => {
                    shared.update(&mut means, hx, hy);
                    general.update([hx, hy], &gnoise.r);
                    check(&shared, &general, false)?;
                }
            }
        }
    }

    /// The general path with a coupled covariance (y and x blocks correlated) and
    /// correlated measurement noise: every variance stays `>= 0`, every pair
    /// `P_ij^2 <= P_ii P_jj`, and with `R` at least 2^-8 on its diagonal the whole 4x4
    /// stays positive semidefinite (`Sym4::is_psd`).
    #[test]
    fn general_covariance_stays_positive_semidefinite(
        l in prop::collection::vec(-64.0f64..64.0, 10),
        q in psd2_case(),
        r in (1.0f64 / 256.0..1024.0, 1.0f64 / 256.0..1024.0, -0.9f64..0.9),
        ops in kalman_ops(),
    ) {
        // P = L L^T, L lower triangular: positive semidefinite by construction.
        let lm = [
            [l[0], 0.0, 0.0, 0.0],
            [l[1], l[2], 0.0, 0.0],
            [l[3], l[4], l[5], 0.0],
            [l[6], l[7], l[8], l[9]],
        ];
        let p = |i: usize, j: usize| (0..4).map(|k| lm[i][k] * lm[j][k]).sum::<f64>();
        let f = |v: f64| Q16::from_f64(v);
        let cov = Sym4 {
            a00: f(p(0, 0)), a01: f(p(0, 1)), a02: f(p(0, 2)), a03: f(p(0, 3)),
            a11: f(p(1, 1)), a12: f(p(1, 2)), a13: f(p(1, 3)),
            a22: f(p(2, 2)), a23: f(p(2, 3)), a33: f(p(3, 3)),
        };
        let noise = Noise {
            q: Sym4::from_blocks(q, q),
            r: Sym2 { a00: f(r.0), a01: f(r.2 * (r.0 * r.1).sqrt()), a11: f(r.1) },
        };
        prop_assume!(noise.check().is_ok());
        let mut filter = Filter::new(Size::at_rest(Q16::from_int(12), Q16::from_int(30)), cov);
        for op in ops {
            let times = match op { KalmanOp::Coast(n) => n, _ => 1 };
            for _ in 0..times {
                match op {
                    KalmanOp::Update(y0, y1) => { filter.update([y0, y1], &noise.r); }
                    KalmanOp::PredictDt(dt) => filter.predict(dt, &noise),
                    _ => filter.predict(Q16::ONE, &noise),
                }
                let c = filter.cov;
                for i in 0..4 {
                    for j in 0..4 {
                        let (a, b, v) = (c.get(i, i).to_bits() as i64, c.get(j, j).to_bits() as i64, c.get(i, j).to_bits() as i64);
                        prop_assert!(a >= 0 && v * v <= a * b, "({}, {}) of {:?}", i, j, c);
                    }
                }
            }
        }
    }
}

/// The general path's full 4x4 PSD check over a long run of the tracker's kind (dt = 1,
/// a measurement every frame, coupled start, moderate noise).
#[test]
fn general_covariance_full_psd_in_normal_operation() {
    let mut rng = Rng::new(3);
    for _ in 0..200 {
        let mut v = || (rng.below(2000) as f64 - 1000.0) / 100.0;
        let lm = [
            [v(), 0.0, 0.0, 0.0],
            [v(), v(), 0.0, 0.0],
            [v(), v(), v(), 0.0],
            [v(), v(), v(), v()],
        ];
        let p = |i: usize, j: usize| (0..4).map(|k| lm[i][k] * lm[j][k]).sum::<f64>();
        let f = Q16::from_f64;
        let cov = Sym4 {
            a00: f(p(0, 0)),
            a01: f(p(0, 1)),
            a02: f(p(0, 2)),
            a03: f(p(0, 3)),
            a11: f(p(1, 1)),
            a12: f(p(1, 2)),
            a13: f(p(1, 3)),
            a22: f(p(2, 2)),
            a23: f(p(2, 3)),
            a33: f(p(3, 3)),
        };
        let thirty = Q16::from_int(30);
        let mut filter = Filter::new(
            Size {
                hx: thirty,
                dhx: thirty,
                hy: thirty,
                dhy: thirty,
            },
            cov,
        );
        let noise = BlockNoise::PAPER.general();
        for t in 0..300 {
            filter.predict(Q16::ONE, &noise);
            assert!(filter.cov.is_psd(), "predict {t}: {:?}", filter.cov);
            let y = [Q16::from_int(28), Q16::from_int(30 + (t % 7))];
            filter.update(y, &noise.r);
            assert!(filter.cov.is_psd(), "update {t}: {:?}", filter.cov);
        }
    }
}
