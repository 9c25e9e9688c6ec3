//! The paper's simulation study (section 3.1): the acceptance criteria, over the
//! 10 fixed seeds and the fixed parameters of `rbtrack_host::paper` (the same as
//! `rbtrack paper`).

use rbtrack_host::paper::{self, Params};

#[test]
fn paper_claims_reproduce() {
    let params = Params::STUDY;
    let study = paper::study(&params, paper::RUNS, paper::PARTICLES);
    print!("{}", paper::table(&study, &params));

    // RBPF clearly beats PF on location and on velocity.
    assert!(
        study.rbpf.loc < 0.8 * study.pf.loc,
        "RBPF location {} vs PF {}",
        study.rbpf.loc,
        study.pf.loc
    );
    assert!(
        study.rbpf.vel < study.pf.vel,
        "RBPF |u| {} vs PF {}",
        study.rbpf.vel,
        study.pf.vel
    );

    // The sweep's smallest location error lies near the true dependency 6, and the ends
    // are clearly worse.
    let best = study
        .sweep
        .iter()
        .min_by(|a, b| a.loc.total_cmp(&b.loc))
        .expect("sweep is not empty");
    assert!((4..=8).contains(&best.s), "minimum at S = {}", best.s);
    let at = |s: u32| {
        study
            .sweep
            .iter()
            .find(|p| p.s == s)
            .map(|p| p.loc)
            .expect("S in the sweep")
    };
    assert!(at(1) >= 1.5 * best.loc, "S = 1: {} vs {}", at(1), best.loc);
    assert!(
        at(15) >= 1.5 * best.loc,
        "S = 15: {} vs {}",
        at(15),
        best.loc
    );

    // RBPF with 50 particles at least as accurate as PF with 200.
    let count = |n: usize| {
        study
            .counts
            .iter()
            .find(|c| c.n == n)
            .expect("particle count in the study")
    };
    assert!(
        count(50).rbpf_loc <= count(200).pf_loc,
        "RBPF(50) {} vs PF(200) {}",
        count(50).rbpf_loc,
        count(200).pf_loc
    );
}

/// The CLI's JSON has the documented keys.
#[test]
fn json_has_the_documented_shape() {
    let params = Params {
        steps: 10,
        ..Params::STUDY
    };
    let study = paper::study(&params, 2, 25);
    let json = paper::json(&study, &params);
    for tracker in ["rbpf", "pf"] {
        for key in ["loc", "loc_std", "vel", "vel_std", "v", "v_std"] {
            assert!(json[tracker][key].is_number(), "{tracker}.{key} in {json}");
        }
        assert!(json[tracker].get("loc_runs").is_none(), "{json}");
    }
    assert_eq!(json["sweep"][0]["s"], 1);
    for key in ["loc", "v", "vel"] {
        assert!(json["sweep"][0][key].is_number(), "sweep.{key} in {json}");
    }
    assert_eq!(json["particles"][0]["n"], 25);
    for key in ["rbpf_loc", "pf_loc", "rbpf_vel", "pf_vel"] {
        assert!(json["particles"][0][key].is_number(), "{key} in {json}");
    }
    assert_eq!(json["params"]["runs"], 2);
    assert_eq!(json["params"]["steps"], 10);
    assert_eq!(study.sweep.len(), 15);
    assert_eq!(study.counts.len(), paper::PARTICLE_COUNTS.len());
}
