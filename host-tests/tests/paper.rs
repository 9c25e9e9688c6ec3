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
    for key in [
        "\"rbpf\": {\"loc\": ",
        "\"pf\": {\"loc\": ",
        "\"vel\": ",
        "\"sweep\": [{\"s\": 1, \"loc\": ",
        "\"v\": ",
        "\"particles\": [{\"n\": 25, \"rbpf_loc\": ",
        "\"pf_loc\": ",
    ] {
        assert!(json.contains(key), "{key} missing from {json}");
    }
    assert_eq!(study.sweep.len(), 15);
    assert_eq!(study.counts.len(), paper::PARTICLE_COUNTS.len());
}
