//! The example firmware's run, on the host: the same scene, seed and trackers as
//! `examples/firmware.rs` in QEMU, so the same checksum over all estimates.
//!
//! CI runs the firmware, takes the `checksum 0x...` line it prints and passes the value
//! as `RBTRACK_FIRMWARE_CHECKSUM`; this test then requires the host's checksum to equal
//! it. Without the variable it prints the host's checksum (`--nocapture`) and checks that
//! the run is reproducible and tracks.

use rbtrack::profile::NoCounter;
use rbtrack::tracker::{Status, Variant};
use rbtrack_firmware::run::{pixel_bound, run_all, Checksum, FirmwareTracker, FrameReport};
use rbtrack_firmware::scene::{FRAMES, FRAME_BYTES};

fn host_run(report: impl FnMut(Variant, &FrameReport)) -> Checksum {
    let mut frame = vec![0u8; FRAME_BYTES];
    let mut tracker = Box::new(FirmwareTracker::unstarted());
    run_all(&mut tracker, &mut frame, NoCounter, report)
        .expect("the firmware's configuration is valid")
}

/// Parses `0x` followed by up to 16 hex digits, as the firmware prints it.
fn parse_checksum(s: &str) -> Option<u64> {
    u64::from_str_radix(s.trim().strip_prefix("0x")?, 16).ok()
}

#[test]
fn host_reproduces_the_firmware_checksum() {
    let mut frames = 0;
    let mut lost = 0;
    let mut worst_error_px = 0.0f64;
    let checksum = host_run(|variant, r| {
        frames += 1;
        assert!(
            r.pixels <= pixel_bound(variant),
            "frame {}: {} pixels",
            r.frame,
            r.pixels
        );
        lost += usize::from(r.estimate.status == Status::Lost);
        let dx = (r.estimate.ellipse.cx - r.truth.cx).to_f64();
        let dy = (r.estimate.ellipse.cy - r.truth.cy).to_f64();
        worst_error_px = worst_error_px.max(dx.hypot(dy));
    });
    println!("host checksum {:#018x}", checksum.value());
    assert_eq!(frames, 2 * FRAMES);
    assert_eq!(
        lost, 0,
        "the firmware scene is easy: no tracker may lose it"
    );
    assert!(
        worst_error_px < 15.0,
        "centre error up to {worst_error_px:.1} px"
    );
    assert_eq!(host_run(|_, _| {}), checksum, "the run is deterministic");
    if let Ok(firmware) = std::env::var("RBTRACK_FIRMWARE_CHECKSUM") {
        let firmware = parse_checksum(&firmware)
            .unwrap_or_else(|| panic!("RBTRACK_FIRMWARE_CHECKSUM={firmware:?} is not 0x<hex>"));
        assert_eq!(
            checksum.value(),
            firmware,
            "host {:#018x} != firmware {firmware:#018x}",
            checksum.value()
        );
        println!("firmware checksum {firmware:#018x}: equal");
    }
}

#[test]
fn checksum_parsing() {
    assert_eq!(parse_checksum("0x00000000000000ff\n"), Some(255));
    assert_eq!(parse_checksum("ff"), None);
}
