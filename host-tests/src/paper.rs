//! The RBPF paper's simulation study (section 3.1), on the core's fixed-point primitives.
//!
//! # The model
//! A point on a plane, state `s = (x, u, y, v)` plus a variance regime `psi`:
//!
//! ```text
//! psi_t ~ Markov([[.6, .2, .2], [.2, .6, .2], [.2, .2, .6]]),  V = (0.5, 1, 2)[psi_t]
//! x_t = x_{t-1} + T u_{t-1} + Ss n        u_t = u_{t-1} + sqrt(V) n
//! y_t = y_{t-1} + T v_{t-1} + Ss n        v_t = 6 u_{t-1}
//! Z_t = (x_t, y_t) + Sz n
//! ```
//! The paper leaves `T`, `Ss`, `Sz`, the start and the length open; this study fixes them
//! as [`T`], [`SS`], [`SZ`], [`X0`], [`U0`], [`Y0`], [`STEPS`] (see [`Params::STUDY`]).
//!
//! # The filters
//! Both filters know the model above except the dependency: they assume `v_t = S u_{t-1}`
//! with `S = 5` ([`S_MODEL`]; the truth is 6 on purpose). Both carry the regime `psi` in
//! each particle and draw its transitions from the same Markov matrix. Both resample every
//! step ([`SCHEME`]) and report the weighted mean of the particles before resampling.
//!
//! - **RBPF**: the root `u` (with `psi`) is sampled; the leaves `x`, `y`, `v` are exact
//!   given the root's path: `v_t = S u_{t-1}` is a known input, and `x`, `y` are random
//!   walks with known inputs. They map onto the core's [`kalman::SharedCovariance`]
//!   as its two (position, rate) blocks with `dt = T`: y block `(y, v)`, x block `(x, u)`,
//!   the rate slot holding the particle's velocity with variance 0, so `Q = diag(Ss^2, 0)`
//!   per block and `R = Sz^2`. The standard `A mu` predict then gives `x + T u_{t-1}` and
//!   `y + T v_{t-1}`, and the gain on the rate is 0. Since `Q` and `R` are shared, one
//!   covariance serves all particles. Weights are the predictive likelihood of `Z_t`,
//!   `N(Z; H mu^-, S)` with the (shared, diagonal) innovation covariance `S`.
//! - **PF**: everything sampled: `x`, `y` with the process noise `Ss`, `u` with `sqrt(V)`,
//!   and `v_t = S u_{t-1}` exactly as in the RBPF (so the two filters differ only in
//!   Rao-Blackwellisation); weights `N(Z; (x, y), Sz^2 I)`.
//!
//! The likelihood `exp(-d^2 / 2)` is the core's table ([`rbtrack::likelihood::exp_neg`]),
//! integer only: `d^2 / 2` in Q16.16, shifted by the smallest among the particles so that
//! the best particle always weighs 1 (no all-zero weight sets from underflow).
//!
//! # What it shows
//! With these parameters the RBPF's location error stays near `Sz` while the PF (same
//! model, same particles) now and then loses lock when the point moves fast: its particles
//! can absorb the 5-versus-6 drift in `y` only through the small position noise `Ss`,
//! whereas the RBPF's Kalman update corrects every particle's `y` directly. So the PF's
//! mean error is dominated by a few runs (`rbtrack paper` prints the per-run figures). With
//! 2,000 particles the PF agrees with the RBPF, which checks that both filter the same
//! model. The `|u|` errors differ less: `u_t` is not observed until `Z_{t+1}`, so both
//! filters carry the fresh innovation `sqrt(V) n` (mean absolute value ~0.86) in full.
//!
//! # Errors
//! Per run and time step: the Euclidean location error `|(x^, y^) - (x, y)|`, the velocity
//! errors `|u^ - u|` and `|v^ - v|`; per run their means over the `STEPS` steps; over runs
//! the mean and the (sample) standard deviation.

use rbtrack::fixed::Q16;
use rbtrack::kalman::{predict_mean, BlockNoise, SharedCovariance, Size, Sym2};
use rbtrack::likelihood::exp_neg;
use rbtrack::resample::{resample, Scheme};
use rbtrack::rng::Rng;
use serde::Serialize;

/// Sampling interval `T` (time units per step). With `|u|` reaching ~20 in 100 steps,
/// `y` moves up to `6 T |u|` ~ 36 units a step, so the 5-versus-6 dependency error is worth
/// up to ~6 units a step, several times `Sz`: the dependency matters, as in the paper.
pub const T: f64 = 0.3;
/// Process noise on each position, standard deviation `Ss` (position units per step).
pub const SS: f64 = 0.5;
/// Observation noise on each position, standard deviation `Sz` (position units).
pub const SZ: f64 = 2.0;
/// Steps per run (observations `Z_1..Z_STEPS`).
pub const STEPS: usize = 100;
/// Initial `x_0`.
pub const X0: f64 = 0.0;
/// Initial `u_0` (also `u_{-1}`, so `v_0 = 6 u_0`). The random walk of `u` (variance
/// about 1.17 a step) spreads it to a standard deviation of ~11 after 100 steps, so paths
/// stay within a few thousand units (far inside Q16.16's +-32768).
pub const U0: f64 = 0.0;
/// Initial `y_0`.
pub const Y0: f64 = 0.0;
/// Standard deviation of the filters' prior on `u_0`, centred on the truth.
pub const U0_SD: f64 = 1.0;
/// True dependency `v_t = S_TRUE u_{t-1}`.
pub const S_TRUE: f64 = 6.0;
/// Dependency the filters assume.
pub const S_MODEL: f64 = 5.0;
/// Particles per filter.
pub const PARTICLES: usize = 200;
/// Runs (seeds `1..=RUNS`).
pub const RUNS: usize = 10;
/// Resampling scheme of both filters.
pub const SCHEME: Scheme = Scheme::Systematic;
/// Regime variances `V`.
pub const VARIANCES: [f64; 3] = [0.5, 1.0, 2.0];
/// The dependencies swept: `S = 1..=15`.
pub const SWEEP: core::ops::RangeInclusive<u32> = 1..=15;
/// Particle counts compared.
pub const PARTICLE_COUNTS: [usize; 5] = [25, 50, 100, 200, 400];

/// The free parameters of the study, in one place (floats: configuration only; every
/// run converts them to Q16.16 once).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    /// Sampling interval `T`.
    pub t: f64,
    /// Position process noise `Ss` (standard deviation).
    pub ss: f64,
    /// Observation noise `Sz` (standard deviation).
    pub sz: f64,
    /// Steps per run.
    pub steps: usize,
    /// Initial state `(x0, u0, y0)`.
    pub start: [f64; 3],
    /// Prior standard deviation of `u_0` in the filters.
    pub u0_sd: f64,
    /// True dependency (6).
    pub s_true: f64,
    /// Resampling scheme.
    pub scheme: Scheme,
}

impl Params {
    /// The study's fixed parameters (the constants above).
    pub const STUDY: Self = Self {
        t: T,
        ss: SS,
        sz: SZ,
        steps: STEPS,
        start: [X0, U0, Y0],
        u0_sd: U0_SD,
        s_true: S_TRUE,
        scheme: SCHEME,
    };
}

impl Default for Params {
    fn default() -> Self {
        Self::STUDY
    }
}

/// `e^2 / (2 s)` in Q16.16, saturating, for `e` and `s` (variance, `> 0`) in Q16.16.
fn half_mahalanobis(e: Q16, s: Q16) -> i64 {
    let e = e.to_bits() as i64;
    let s = (s.to_bits() as i64).max(1);
    (e * e / s) >> 1
}

/// Turns the per-particle `d^2 / 2` values (Q16.16 raw) into likelihood weights
/// `65535 exp(-(d^2/2 - min))` by the core's table ([`exp_neg`]), in place.
fn weigh(weights: &mut [u32], half_d2: &[i64]) {
    let min = half_d2.iter().copied().min().unwrap_or(0);
    for (w, &h) in weights.iter_mut().zip(half_d2) {
        *w = exp_neg(Q16::saturate(h - min));
    }
}

/// Weighted mean of `values` (Q16.16) under `weights` (any scale, not all zero), as f64.
fn weighted_mean(weights: &[u32], values: impl Iterator<Item = Q16>) -> f64 {
    let (mut num, mut den) = (0i128, 0i128);
    for (&w, v) in weights.iter().zip(values) {
        num += w as i128 * v.to_bits() as i128;
        den += w as i128;
    }
    if den == 0 {
        return 0.0;
    }
    (num / den) as f64 / 65536.0
}

/// The fixed-point form of [`Params`] plus the regime tables, for one run.
#[derive(Debug, Clone)]
struct Model {
    t: Q16,
    ss: Q16,
    sz: Q16,
    sd: [Q16; 3],
    steps: usize,
    start: [Q16; 3],
    u0_sd: Q16,
    scheme: Scheme,
}

impl Model {
    fn new(p: &Params) -> Self {
        Self {
            t: Q16::from_f64(p.t),
            ss: Q16::from_f64(p.ss),
            sz: Q16::from_f64(p.sz),
            sd: VARIANCES.map(|v| Q16::from_f64(v.sqrt())),
            steps: p.steps,
            start: p.start.map(Q16::from_f64),
            u0_sd: Q16::from_f64(p.u0_sd),
            scheme: p.scheme,
        }
    }

    /// Next regime: stay with probability 0.6, else one of the two others (0.2 each).
    fn next_regime(regime: u8, rng: &mut Rng) -> u8 {
        match rng.below(5) {
            0..=2 => regime,
            3 => (regime + 1) % 3,
            _ => (regime + 2) % 3,
        }
    }

    /// `sqrt(V)` of a regime.
    fn sd(&self, regime: u8) -> Q16 {
        match regime {
            0 => self.sd[0],
            1 => self.sd[1],
            _ => self.sd[2],
        }
    }
}

/// A simulated path: the truth and the observations at `t = 0..=steps`. The filters take
/// `Z_0` as their prior on the position (variance `Sz^2`) and filter `Z_1..Z_steps`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Path {
    /// `x_t`.
    pub x: Vec<Q16>,
    /// `u_t`.
    pub u: Vec<Q16>,
    /// `y_t`.
    pub y: Vec<Q16>,
    /// `v_t`.
    pub v: Vec<Q16>,
    /// `Z_t = (x, y) + noise`.
    pub z: Vec<[Q16; 2]>,
}

/// Simulates the true path and its observations for one seed.
pub fn simulate(params: &Params, seed: u64) -> Path {
    let m = Model::new(params);
    let mut rng = Rng::new(seed);
    let s_true = Q16::from_f64(params.s_true);
    let [mut x, mut u, mut y] = m.start;
    let mut v = s_true * u;
    let mut regime = rng.below(3) as u8;
    let z0 = [x + rng.gaussian(m.sz), y + rng.gaussian(m.sz)];
    let mut path = Path {
        x: vec![x],
        u: vec![u],
        y: vec![y],
        v: vec![v],
        z: vec![z0],
    };
    for _ in 0..m.steps {
        regime = Model::next_regime(regime, &mut rng);
        let (u_prev, v_prev) = (u, v);
        x = x + m.t * u_prev + rng.gaussian(m.ss);
        y = y + m.t * v_prev + rng.gaussian(m.ss);
        v = s_true * u_prev;
        u = u_prev + rng.gaussian(m.sd(regime));
        let z = [x + rng.gaussian(m.sz), y + rng.gaussian(m.sz)];
        path.x.push(x);
        path.u.push(u);
        path.y.push(y);
        path.v.push(v);
        path.z.push(z);
    }
    path
}

/// Errors of one filter on one path, per time step `1..=steps`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunErrors {
    /// Euclidean location error.
    pub loc: Vec<f64>,
    /// `|u^ - u|`.
    pub u: Vec<f64>,
    /// `|v^ - v|`.
    pub v: Vec<f64>,
}

impl RunErrors {
    fn push(&mut self, path: &Path, t: usize, est: [f64; 4]) {
        let [x, u, y, v] = est;
        let truth = |s: &[Q16]| s.get(t).map_or(0.0, |q| q.to_f64());
        let (dx, dy) = (x - truth(&path.x), y - truth(&path.y));
        self.loc.push((dx * dx + dy * dy).sqrt());
        self.u.push((u - truth(&path.u)).abs());
        self.v.push((v - truth(&path.v)).abs());
    }
}

fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// Sample standard deviation (0 for fewer than two values).
fn std_dev(v: &[f64]) -> f64 {
    if v.len() < 2 {
        return 0.0;
    }
    let m = mean(v);
    (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
}

/// Seed of a filter's own random stream for a run.
fn filter_seed(seed: u64, salt: u64) -> u64 {
    seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ salt
}

/// Reorders `items` by the resampled `indices` into `scratch`, then swaps.
fn reorder<P: Copy>(items: &mut Vec<P>, scratch: &mut Vec<P>, indices: &[u16]) {
    scratch.clear();
    scratch.extend(
        indices
            .iter()
            .filter_map(|&i| items.get(i as usize).copied()),
    );
    core::mem::swap(items, scratch);
}

/// One RBPF particle: regime, root `u_t`, and the leaf mean `(x, u, y, v)` in the core
/// Kalman layout (`hx, dhx, hy, dhy`: position and rate of each axis).
#[derive(Debug, Clone, Copy)]
struct RbParticle {
    regime: u8,
    u: Q16,
    leaf: Size,
}

/// Runs the RBPF with `particles` particles and dependency `s_model` on `path`.
pub fn run_rbpf(
    params: &Params,
    path: &Path,
    s_model: f64,
    particles: usize,
    seed: u64,
) -> RunErrors {
    let m = Model::new(params);
    let s = Q16::from_f64(s_model);
    let mut rng = Rng::new(filter_seed(seed, 0x5262_7066));
    let var_z = m.sz * m.sz;
    let noise = BlockNoise {
        q_x: Sym2::diagonal(m.ss * m.ss, Q16::ZERO),
        q_y: Sym2::diagonal(m.ss * m.ss, Q16::ZERO),
        r_x: var_z,
        r_y: var_z,
    };
    let p0 = Sym2::diagonal(var_z, Q16::ZERO);
    let Ok(mut shared) = SharedCovariance::new(p0, p0, noise) else {
        return RunErrors::default();
    };
    // Prior: positions N(Z_0, Sz^2) (the shared P0), u ~ N(u_0, U0_SD^2).
    let [zx0, zy0] = path.z.first().copied().unwrap_or([Q16::ZERO; 2]);
    let u0 = m.start[1];
    let mut ps: Vec<RbParticle> = (0..particles)
        .map(|_| {
            let u = u0 + rng.gaussian(m.u0_sd);
            RbParticle {
                regime: rng.below(3) as u8,
                u,
                leaf: Size {
                    hx: zx0,
                    dhx: u,
                    hy: zy0,
                    dhy: s * u,
                },
            }
        })
        .collect();
    let mut scratch = Vec::with_capacity(particles);
    let mut weights = vec![0u32; particles];
    let mut half_d2 = vec![0i64; particles];
    let mut indices = vec![0u16; particles];
    let mut errors = RunErrors::default();
    for t in 1..=m.steps {
        let z = path.z.get(t).copied().unwrap_or([Q16::ZERO; 2]);
        // Propagate: leaf mean by A mu (x + T u_{t-1}, y + T v_{t-1}), root u_t sampled.
        shared.predict(m.t);
        let gain = shared.gain();
        let sv = gain.innovation_cov();
        for (p, h) in ps.iter_mut().zip(half_d2.iter_mut()) {
            predict_mean(&mut p.leaf, m.t);
            let (x_pred, y_pred) = (p.leaf.hx, p.leaf.hy);
            *h = half_mahalanobis(z[1] - y_pred, sv.a11) + half_mahalanobis(z[0] - x_pred, sv.a00);
            // Kalman update with Z_t (the same gain for all; commutes with resampling).
            gain.update_mean(&mut p.leaf, z[0], z[1]);
            let u_prev = p.u;
            p.regime = Model::next_regime(p.regime, &mut rng);
            p.u = u_prev + rng.gaussian(m.sd(p.regime));
            p.leaf.dhy = s * u_prev; // v_t = S u_{t-1}
            p.leaf.dhx = p.u; // x moves by u_t next step
        }
        shared.update_cov();
        weigh(&mut weights, &half_d2);
        let est = [
            weighted_mean(&weights, ps.iter().map(|p| p.leaf.hx)),
            weighted_mean(&weights, ps.iter().map(|p| p.u)),
            weighted_mean(&weights, ps.iter().map(|p| p.leaf.hy)),
            weighted_mean(&weights, ps.iter().map(|p| p.leaf.dhy)),
        ];
        errors.push(path, t, est);
        if resample(m.scheme, &mut weights, &mut rng, &mut indices).is_ok() {
            reorder(&mut ps, &mut scratch, &indices);
        }
    }
    errors
}

/// One PF particle: regime and the full state.
#[derive(Debug, Clone, Copy)]
struct PfParticle {
    regime: u8,
    x: Q16,
    u: Q16,
    y: Q16,
    v: Q16,
}

/// Runs the regular (bootstrap) particle filter with `particles` particles on `path`.
pub fn run_pf(
    params: &Params,
    path: &Path,
    s_model: f64,
    particles: usize,
    seed: u64,
) -> RunErrors {
    let m = Model::new(params);
    let s = Q16::from_f64(s_model);
    let mut rng = Rng::new(filter_seed(seed, 0x5066));
    let var_z = m.sz * m.sz;
    // Prior: positions sampled from N(Z_0, Sz^2), u ~ N(u_0, U0_SD^2).
    let [zx0, zy0] = path.z.first().copied().unwrap_or([Q16::ZERO; 2]);
    let u0 = m.start[1];
    let mut ps: Vec<PfParticle> = (0..particles)
        .map(|_| {
            let u = u0 + rng.gaussian(m.u0_sd);
            PfParticle {
                regime: rng.below(3) as u8,
                x: zx0 + rng.gaussian(m.sz),
                u,
                y: zy0 + rng.gaussian(m.sz),
                v: s * u,
            }
        })
        .collect();
    let mut scratch = Vec::with_capacity(particles);
    let mut weights = vec![0u32; particles];
    let mut half_d2 = vec![0i64; particles];
    let mut indices = vec![0u16; particles];
    let mut errors = RunErrors::default();
    for t in 1..=m.steps {
        let z = path.z.get(t).copied().unwrap_or([Q16::ZERO; 2]);
        for (p, h) in ps.iter_mut().zip(half_d2.iter_mut()) {
            let u_prev = p.u;
            p.x = p.x + m.t * u_prev + rng.gaussian(m.ss);
            p.y = p.y + m.t * p.v + rng.gaussian(m.ss);
            p.v = s * u_prev;
            p.regime = Model::next_regime(p.regime, &mut rng);
            p.u = u_prev + rng.gaussian(m.sd(p.regime));
            *h = half_mahalanobis(z[0] - p.x, var_z) + half_mahalanobis(z[1] - p.y, var_z);
        }
        weigh(&mut weights, &half_d2);
        let est = [
            weighted_mean(&weights, ps.iter().map(|p| p.x)),
            weighted_mean(&weights, ps.iter().map(|p| p.u)),
            weighted_mean(&weights, ps.iter().map(|p| p.y)),
            weighted_mean(&weights, ps.iter().map(|p| p.v)),
        ];
        errors.push(path, t, est);
        if resample(m.scheme, &mut weights, &mut rng, &mut indices).is_ok() {
            reorder(&mut ps, &mut scratch, &indices);
        }
    }
    errors
}

/// Mean and standard deviation over runs of the per-run time-averaged errors, and the
/// error curves over time averaged over runs.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Summary {
    /// Location error: mean over runs of the per-run mean over time.
    pub loc: f64,
    /// Its standard deviation over runs.
    pub loc_std: f64,
    /// `|u|` error, mean over runs.
    pub vel: f64,
    /// Its standard deviation over runs.
    pub vel_std: f64,
    /// `|v|` error, mean over runs.
    pub v: f64,
    /// Its standard deviation over runs.
    pub v_std: f64,
    /// Location error of each run (mean over time), in run order.
    #[serde(skip)]
    pub loc_runs: Vec<f64>,
    /// Location error at each time step `1..=steps`, mean over runs.
    #[serde(skip)]
    pub loc_curve: Vec<f64>,
    /// `|u|` error at each time step, mean over runs.
    #[serde(skip)]
    pub vel_curve: Vec<f64>,
}

impl Summary {
    /// Summarises runs.
    pub fn of(runs: &[RunErrors]) -> Self {
        let per = |f: fn(&RunErrors) -> &Vec<f64>| -> Vec<f64> {
            runs.iter().map(|r| mean(f(r))).collect()
        };
        let curve = |f: fn(&RunErrors) -> &Vec<f64>| -> Vec<f64> {
            let len = runs.iter().map(|r| f(r).len()).min().unwrap_or(0);
            (0..len)
                .map(|t| mean(&runs.iter().map(|r| f(r)[t]).collect::<Vec<_>>()))
                .collect()
        };
        let (loc, vel, v) = (per(|r| &r.loc), per(|r| &r.u), per(|r| &r.v));
        Self {
            loc: mean(&loc),
            loc_std: std_dev(&loc),
            vel: mean(&vel),
            vel_std: std_dev(&vel),
            v: mean(&v),
            v_std: std_dev(&v),
            loc_runs: loc,
            loc_curve: curve(|r| &r.loc),
            vel_curve: curve(|r| &r.u),
        }
    }
}

/// One point of the dependency sweep (RBPF).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepPoint {
    /// Assumed dependency `S`.
    pub s: u32,
    /// Location error, mean over runs.
    pub loc: f64,
    /// `|v|` error, mean over runs.
    pub v: f64,
    /// `|u|` error, mean over runs.
    pub vel: f64,
}

/// One point of the particle-count comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CountPoint {
    /// Particles.
    pub n: usize,
    /// RBPF location error, mean over runs.
    pub rbpf_loc: f64,
    /// PF location error, mean over runs.
    pub pf_loc: f64,
    /// RBPF `|u|` error, mean over runs.
    pub rbpf_vel: f64,
    /// PF `|u|` error, mean over runs.
    pub pf_vel: f64,
}

/// The whole study.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// Runs (seeds `1..=runs`).
    pub runs: usize,
    /// Particles of the main comparison.
    pub particles: usize,
    /// RBPF with `S = 5`.
    pub rbpf: Summary,
    /// PF with `S = 5`.
    pub pf: Summary,
    /// RBPF errors for `S = 1..=15`.
    pub sweep: Vec<SweepPoint>,
    /// Both filters at each of [`PARTICLE_COUNTS`].
    pub counts: Vec<CountPoint>,
}

/// Seed of run `r` (0-based).
pub fn run_seed(r: usize) -> u64 {
    r as u64 + 1
}

/// Runs the whole study: `runs` paths, the main comparison with `particles` particles,
/// the sweep (same particles) and the particle counts.
pub fn study(params: &Params, runs: usize, particles: usize) -> Study {
    let paths: Vec<(u64, Path)> = (0..runs)
        .map(|r| (run_seed(r), simulate(params, run_seed(r))))
        .collect();
    let rb = |s: f64, n: usize| -> Vec<RunErrors> {
        paths
            .iter()
            .map(|(seed, p)| run_rbpf(params, p, s, n, *seed))
            .collect()
    };
    let pf = |n: usize| -> Vec<RunErrors> {
        paths
            .iter()
            .map(|(seed, p)| run_pf(params, p, S_MODEL, n, *seed))
            .collect()
    };
    let rbpf = Summary::of(&rb(S_MODEL, particles));
    let pf_main = Summary::of(&pf(particles));
    let sweep = SWEEP
        .map(|s| {
            let sum = if s as f64 == S_MODEL {
                rbpf.clone()
            } else {
                Summary::of(&rb(s as f64, particles))
            };
            SweepPoint {
                s,
                loc: sum.loc,
                v: sum.v,
                vel: sum.vel,
            }
        })
        .collect();
    let counts = PARTICLE_COUNTS
        .iter()
        .map(|&n| {
            let (r, p) = if n == particles {
                (rbpf.clone(), pf_main.clone())
            } else {
                (Summary::of(&rb(S_MODEL, n)), Summary::of(&pf(n)))
            };
            CountPoint {
                n,
                rbpf_loc: r.loc,
                pf_loc: p.loc,
                rbpf_vel: r.vel,
                pf_vel: p.vel,
            }
        })
        .collect();
    Study {
        runs,
        particles,
        rbpf,
        pf: pf_main,
        sweep,
        counts,
    }
}

/// The study as a plain-text table.
pub fn table(study: &Study, params: &Params) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Paper simulation (section 3.1): T = {}, Ss = {}, Sz = {}, {} steps, start (x, u, y) = \
         ({}, {}, {}), truth v = {} u, filters assume S = {}",
        params.t,
        params.ss,
        params.sz,
        params.steps,
        params.start[0],
        params.start[1],
        params.start[2],
        params.s_true,
        S_MODEL
    );
    let _ = writeln!(
        out,
        "{} runs (seeds 1..={}), {} particles, {:?} resampling every step\n",
        study.runs, study.runs, study.particles, params.scheme
    );
    let _ = writeln!(
        out,
        "filter   location error     |u| error          |v| error"
    );
    for (name, s) in [("RBPF", &study.rbpf), ("PF", &study.pf)] {
        let _ = writeln!(
            out,
            "{name:<8} {:>7.3} +- {:<7.3} {:>7.3} +- {:<7.3} {:>7.3} +- {:<7.3}",
            s.loc, s.loc_std, s.vel, s.vel_std, s.v, s.v_std
        );
    }
    let runs = |s: &Summary| {
        s.loc_runs
            .iter()
            .map(|v| format!("{v:.2}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let _ = writeln!(out, "\nlocation error per run, RBPF: {}", runs(&study.rbpf));
    let _ = writeln!(out, "location error per run, PF:   {}", runs(&study.pf));
    let _ = writeln!(
        out,
        "\nRBPF against the assumed dependency S (truth 6), mean over runs\n S   location   |v| error   |u| error"
    );
    for p in &study.sweep {
        let _ = writeln!(
            out,
            "{:>2}   {:>8.3}   {:>9.3}   {:>9.3}",
            p.s, p.loc, p.v, p.vel
        );
    }
    let _ = writeln!(
        out,
        "\nerror against particle count, mean over runs\n   N   RBPF loc   PF loc   RBPF |u|   PF |u|"
    );
    for c in &study.counts {
        let _ = writeln!(
            out,
            "{:>4}   {:>8.3} {:>8.3}   {:>8.3} {:>8.3}",
            c.n, c.rbpf_loc, c.pf_loc, c.rbpf_vel, c.pf_vel
        );
    }
    out
}

/// The study's parameters as the JSON output shows them.
#[derive(Serialize)]
struct ParamsJson {
    t: f64,
    ss: f64,
    sz: f64,
    steps: usize,
    start: [f64; 3],
    s_true: f64,
    s_model: f64,
    runs: usize,
    particles: usize,
}

/// The study as the JSON output shows it.
#[derive(Serialize)]
struct StudyJson<'a> {
    rbpf: &'a Summary,
    pf: &'a Summary,
    sweep: &'a [SweepPoint],
    particles: &'a [CountPoint],
    params: ParamsJson,
}

/// The study as JSON: `{"rbpf": {"loc", "loc_std", "vel", "vel_std", "v", "v_std"},
/// "pf": {..}, "sweep": [{"s", "loc", "v", "vel"}], "particles": [{"n", "rbpf_loc",
/// "pf_loc", "rbpf_vel", "pf_vel"}], "params": {..}}`; non-finite numbers are `null`.
pub fn json(study: &Study, params: &Params) -> serde_json::Value {
    let doc = StudyJson {
        rbpf: &study.rbpf,
        pf: &study.pf,
        sweep: &study.sweep,
        particles: &study.counts,
        params: ParamsJson {
            t: params.t,
            ss: params.ss,
            sz: params.sz,
            steps: params.steps,
            start: params.start,
            s_true: params.s_true,
            s_model: S_MODEL,
            runs: study.runs,
            particles: study.particles,
        },
    };
    // Plain structs of numbers: serialising them cannot fail.
    serde_json::to_value(doc).unwrap_or_default()
}

/// Plot size, px (each figure has two panels side by side).
pub const PLOT_SIZE: (u32, u32) = (1200, 480);

/// One line of a panel.
struct Line<'a> {
    label: &'a str,
    points: Vec<(f64, f64)>,
    colour: plotters::style::RGBColor,
}

/// Draws `lines` into one panel with a caption and axis names.
fn panel<DB: plotters::prelude::DrawingBackend>(
    area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    caption: &str,
    x_desc: &str,
    y_desc: &str,
    lines: &[Line],
) -> Result<(), String> {
    use plotters::prelude::*;
    let all = lines.iter().flat_map(|l| l.points.iter());
    let (mut x0, mut x1, mut y1) = (f64::MAX, f64::MIN, 0f64);
    for &(x, y) in all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        if y.is_finite() {
            y1 = y1.max(y);
        }
    }
    if x0 >= x1 {
        x1 = x0 + 1.0;
    }
    let y1 = if y1 > 0.0 { y1 * 1.08 } else { 1.0 };
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d(x0..x1, 0f64..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    for line in lines {
        let colour = line.colour;
        chart
            .draw_series(LineSeries::new(
                line.points.iter().copied(),
                colour.stroke_width(2),
            ))
            .map_err(err)?
            .label(line.label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        chart
            .draw_series(
                line.points
                    .iter()
                    .map(|&p| Circle::new(p, 3, colour.filled())),
            )
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    Ok(())
}

/// Renders a two-panel figure into a PNG file.
fn figure(
    path: &std::path::Path,
    left: (&str, &str, &str, &[Line]),
    right: (&str, &str, &str, &[Line]),
) -> Result<(), String> {
    use plotters::prelude::*;
    crate::draw::register_fonts();
    let (w, h) = PLOT_SIZE;
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (a, b) = root.split_horizontally(w / 2);
        panel(&a, left.0, left.1, left.2, left.3)?;
        panel(&b, right.0, right.1, right.2, right.3)?;
        root.present().map_err(|e| e.to_string())?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).ok_or("bitmap size mismatch")?;
    img.save(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes the study's three figures into `dir` (created if missing) and returns their paths:
/// `paper_errors_over_time.png` (location and `|u|` error against time, both filters),
/// `paper_dependency_sweep.png` (RBPF location and `|v|` error against `S`),
/// `paper_particle_count.png` (location and `|u|` error against the particle count).
pub fn write_plots(
    study: &Study,
    dir: &std::path::Path,
) -> Result<Vec<std::path::PathBuf>, String> {
    use plotters::style::RGBColor;
    const RBPF: RGBColor = RGBColor(31, 119, 180);
    const PF: RGBColor = RGBColor(214, 39, 40);
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let over_time = |c: &[f64]| -> Vec<(f64, f64)> {
        c.iter()
            .enumerate()
            .map(|(t, &e)| ((t + 1) as f64, e))
            .collect()
    };
    let rb_label = format!("RBPF (S = {S_MODEL})");
    let pf_label = format!("PF (S = {S_MODEL})");
    let time_loc = [
        Line {
            label: &rb_label,
            points: over_time(&study.rbpf.loc_curve),
            colour: RBPF,
        },
        Line {
            label: &pf_label,
            points: over_time(&study.pf.loc_curve),
            colour: PF,
        },
    ];
    let time_vel = [
        Line {
            label: &rb_label,
            points: over_time(&study.rbpf.vel_curve),
            colour: RBPF,
        },
        Line {
            label: &pf_label,
            points: over_time(&study.pf.vel_curve),
            colour: PF,
        },
    ];
    let caption = format!(
        "mean over {} runs, {} particles",
        study.runs, study.particles
    );
    let p1 = dir.join("paper_errors_over_time.png");
    figure(
        &p1,
        (
            &format!("Location error ({caption})"),
            "time step",
            "location error",
            &time_loc,
        ),
        (
            &format!("|u| error ({caption})"),
            "time step",
            "|u| error",
            &time_vel,
        ),
    )?;
    let sweep_loc = [Line {
        label: "RBPF location error",
        points: study.sweep.iter().map(|p| (p.s as f64, p.loc)).collect(),
        colour: RBPF,
    }];
    let sweep_v = [Line {
        label: "RBPF |v| error",
        points: study.sweep.iter().map(|p| (p.s as f64, p.v)).collect(),
        colour: RBPF,
    }];
    let p2 = dir.join("paper_dependency_sweep.png");
    figure(
        &p2,
        (
            "Location error against assumed S (truth 6)",
            "S",
            "location error",
            &sweep_loc,
        ),
        (
            "|v| error against assumed S (truth 6)",
            "S",
            "|v| error",
            &sweep_v,
        ),
    )?;
    let count = |f: fn(&CountPoint) -> f64| -> Vec<(f64, f64)> {
        study.counts.iter().map(|c| (c.n as f64, f(c))).collect()
    };
    let n_loc = [
        Line {
            label: "RBPF",
            points: count(|c| c.rbpf_loc),
            colour: RBPF,
        },
        Line {
            label: "PF",
            points: count(|c| c.pf_loc),
            colour: PF,
        },
    ];
    let n_vel = [
        Line {
            label: "RBPF",
            points: count(|c| c.rbpf_vel),
            colour: RBPF,
        },
        Line {
            label: "PF",
            points: count(|c| c.pf_vel),
            colour: PF,
        },
    ];
    let p3 = dir.join("paper_particle_count.png");
    figure(
        &p3,
        (
            "Location error against particle count",
            "particles",
            "location error",
            &n_loc,
        ),
        (
            "|u| error against particle count",
            "particles",
            "|u| error",
            &n_vel,
        ),
    )?;
    Ok(vec![p1, p2, p3])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simulation_is_deterministic_and_in_range() {
        let p = Params::STUDY;
        assert_eq!(simulate(&p, 3), simulate(&p, 3));
        for seed in 1..=10 {
            let path = simulate(&p, seed);
            assert_eq!(path.x.len(), p.steps + 1);
            for t in 0..=p.steps {
                for q in [path.x[t], path.y[t], path.u[t], path.v[t]] {
                    assert!(q.to_f64().abs() < 16_000.0, "seed {seed} t {t}: {q}");
                }
            }
        }
    }
}
