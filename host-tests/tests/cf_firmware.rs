//! The correlation-filter tracker's firmware run, on the host: the same scene and tracker
//! as `examples/cf_firmware.rs` in QEMU, so the same checksum over its estimates.
//!
//! CI runs the firmware, takes the `cf checksum 0x...` line it prints and passes the value
//! as `RBTRACK_CF_FIRMWARE_CHECKSUM`; this test then requires the host's checksum to
//! equal it. Without the variable it checks that the run is reproducible and tracks.

use rbtrack::fixed::Q16;
use rbtrack::profile::NoCounter;
use rbtrack::tracker::{CfConfig, Status};
use rbtrack_firmware::cf::{iou_permille, run_cf, CfFrameReport, FirmwareCfTracker};
use rbtrack_firmware::run::Checksum;
use rbtrack_firmware::scene::{FRAMES, FRAME_BYTES};

fn host_run(report: impl FnMut(&CfFrameReport)) -> Checksum {
    let mut frame = vec![0u8; FRAME_BYTES];
    let mut tracker = Box::new(FirmwareCfTracker::unstarted());
    run_cf(
        CfConfig::default(),
        &mut tracker,
        Q16::ONE,
        &mut frame,
        NoCounter,
        report,
    )
    .expect("the defaults are valid")
}

#[test]
fn host_reproduces_the_cf_firmware_checksum() {
    let (mut frames, mut lost, mut worst_error_px, mut iou) = (0, 0, 0.0f64, 0u32);
    let checksum = host_run(|r| {
        frames += 1;
        iou += iou_permille(&r.estimate.ellipse, &r.truth);
        lost += usize::from(r.estimate.status == Status::Lost);
        let dx = (r.estimate.ellipse.cx - r.truth.cx).to_f64();
        let dy = (r.estimate.ellipse.cy - r.truth.cy).to_f64();
        worst_error_px = worst_error_px.max(dx.hypot(dy));
    });
    let iou = iou / FRAMES as u32;
    println!(
        "host cf checksum {:#018x}, centre error up to {worst_error_px:.1} px, mean IoU 0.{iou:03}",
        checksum.value()
    );
    assert_eq!(frames, FRAMES);
    assert_eq!(
        lost, 0,
        "the firmware scene is easy: the tracker may not lose it"
    );
    assert!(iou >= 500, "mean IoU 0.{iou:03}");
    assert!(
        worst_error_px < 15.0,
        "centre error up to {worst_error_px:.1} px"
    );
    assert_eq!(host_run(|_| {}), checksum, "the run is deterministic");
    if let Ok(firmware) = std::env::var("RBTRACK_CF_FIRMWARE_CHECKSUM") {
        let firmware = firmware
            .trim()
            .strip_prefix("0x")
            .and_then(|h| u64::from_str_radix(h, 16).ok())
            .unwrap_or_else(|| panic!("RBTRACK_CF_FIRMWARE_CHECKSUM={firmware:?} is not 0x<hex>"));
        assert_eq!(
            checksum.value(),
            firmware,
            "host {:#018x} != firmware {firmware:#018x}",
            checksum.value()
        );
        println!("cf firmware checksum {firmware:#018x}: equal");
    }
}
