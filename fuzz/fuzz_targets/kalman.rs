//! The Kalman filter, both paths, with any noise, covariance, measurement and `dt`.
//!
//! Oracles: no panic; `SharedCovariance::new` accepts exactly positive semidefinite
//! noise and covariances; the shared path keeps `P` block-diagonal with both blocks
//! positive semidefinite (exactly, in integers) after every operation; the general path,
//! once it has predicted, keeps every variance `>= 0` and every pair
//! `P_ij^2 <= P_ii P_jj`.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rbtrack::fixed::Q16;
use rbtrack::kalman::{predict_mean, BlockNoise, Filter, Noise, SharedCovariance, Sym2, Sym4};
use rbtrack_fuzz::Q;

#[derive(Arbitrary, Debug, Clone, Copy)]
struct S2([Q; 3]);

impl S2 {
    fn get(self) -> Sym2 {
        Sym2 {
            a00: self.0[0].get(),
            a01: self.0[1].get(),
            a11: self.0[2].get(),
        }
    }
}

#[derive(Arbitrary, Debug, Clone)]
enum Op {
    Predict(Q),
    Update([Q; 2]),
    PredictMean(Q),
}

#[derive(Arbitrary, Debug, Clone)]
struct Input {
    q_y: S2,
    q_x: S2,
    r: [Q; 2],
    p_y: S2,
    p_x: S2,
    coupling: [Q; 4],
    means: Vec<[Q; 4]>,
    ops: Vec<Op>,
}

fuzz_target!(|input: Input| {
    let noise = BlockNoise {
        q_y: input.q_y.get(),
        q_x: input.q_x.get(),
        r_y: input.r[0].get(),
        r_x: input.r[1].get(),
    };
    let (p_y, p_x) = (input.p_y.get(), input.p_x.get());
    let mut means: Vec<[Q16; 4]> = input.means.iter().take(16).map(|m| m.map(Q::get)).collect();
    let shared = SharedCovariance::new(p_y, p_x, noise);
    let valid = noise.check().is_ok() && p_y.is_psd() && p_x.is_psd();
    assert_eq!(shared.is_ok(), valid);

    // The general path takes any matrices; give it the coupled covariance too.
    let mut cov = Sym4::from_blocks(p_y, p_x);
    cov.a02 = input.coupling[0].get();
    cov.a03 = input.coupling[1].get();
    cov.a12 = input.coupling[2].get();
    cov.a13 = input.coupling[3].get();
    let general = Noise {
        q: Sym4::from_blocks(noise.q_y, noise.q_x),
        r: Sym2::diagonal(noise.r_y, noise.r_x),
    };
    // The general path keeps P pairwise PSD once it has predicted (an update of a
    // singular S leaves P as it was, so the start need not be).
    let _ = general.check();
    let mut general_valid = false;
    let mut filter = Filter::new(means.first().copied().unwrap_or_default(), cov);

    let mut shared = shared.ok();
    for op in input.ops.iter().take(32) {
        match op {
            Op::Predict(dt) => {
                let dt = dt.get();
                if let Some(s) = shared.as_mut() {
                    s.predict(dt);
                }
                filter.predict(dt, &general);
                general_valid = true;
            }
            Op::Update(y) => {
                let y = [y[0].get(), y[1].get()];
                if let Some(s) = shared.as_mut() {
                    let g = s.update(&mut means, y);
                    let _ = g.innovation_cov();
                }
                let g = filter.update(y, &general.r);
                let _ = g.s;
            }
            Op::PredictMean(dt) => {
                for m in means.iter_mut() {
                    predict_mean(m, dt.get());
                }
                filter.predict_mean(dt.get());
            }
        }
        if let Some(s) = &shared {
            let p = s.cov();
            assert!(p.is_block_diagonal());
            assert!(p.y_block().is_psd() && p.x_block().is_psd(), "{p:?}");
        }
        if general_valid {
            let p = filter.cov;
            for i in 0..4 {
                for j in 0..4 {
                    let (a, b, c) = (
                        p.get(i, i).to_bits() as i64,
                        p.get(j, j).to_bits() as i64,
                        p.get(i, j).to_bits() as i64,
                    );
                    assert!(a >= 0 && c * c <= a * b, "({i}, {j}) of {p:?}");
                }
            }
        }
    }
});
