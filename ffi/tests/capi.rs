//! The C API refuses every bad argument with its code, never undefined behaviour, and
//! tracks as the core does.
#![allow(unsafe_code)]

use rbtrack::tracker::{CameraMotion, CfConfig, Config, Estimate, Status, Variant};
use rbtrack::{Ellipse, Gray8, ImageView, Rect, RgbCfTracker, RgbTracker, Q16};
use rbtrack_ffi::capi::rbt_error::{self, *};
use rbtrack_ffi::capi::*;
use std::ffi::{c_void, CStr};
use std::ptr::{null, null_mut};

/// Bytes of the largest tracker offered.
const LARGEST: usize = if RBT_TRACKER_CF_SIZE > RBT_TRACKER_RGB_200_SIZE {
    RBT_TRACKER_CF_SIZE
} else {
    RBT_TRACKER_RGB_200_SIZE
};

/// Memory for the largest tracker offered, aligned.
#[repr(C, align(8))]
struct Memory([u8; LARGEST + 8]);

fn memory() -> Box<Memory> {
    Box::new(Memory([0xA5; LARGEST + 8]))
}

/// A bright 16x16 square at `x0` on a dark 64x48 grey frame.
fn square(x0: usize) -> Vec<u8> {
    let mut buf = vec![40u8; 64 * 48];
    for y in 16..32 {
        buf[y * 64 + x0..y * 64 + x0 + 16].fill(220);
    }
    buf
}

fn image(buf: &[u8]) -> rbt_image {
    rbt_image {
        data: buf.as_ptr(),
        size: buf.len(),
        width: 64,
        height: 48,
        stride: 64,
        format: rbt_format::RBT_FORMAT_GRAY8 as u32,
    }
}

fn q(v: i32) -> rbt_q16 {
    v * RBT_Q16_ONE
}

fn default_config(variant: rbt_variant) -> rbt_config {
    let mut config = rbt_config::default();
    assert_eq!(
        unsafe { rbt_config_default(variant as u32, &mut config) },
        RBT_OK
    );
    config
}

/// A placed tracker of 50 particles started on the square at 20.
fn started(mem: &mut Memory, buf: &[u8]) -> *mut rbt_tracker {
    let mut tracker = null_mut();
    let place =
        unsafe { rbt_tracker_place_rgb_50(mem.0.as_mut_ptr().cast(), mem.0.len(), &mut tracker) };
    assert_eq!(place, RBT_OK);
    let config = default_config(rbt_variant::RBT_VARIANT_COLOUR_PF);
    let r#box = rbt_rect {
        x: q(20),
        y: q(16),
        w: q(16),
        h: q(16),
    };
    assert_eq!(
        unsafe { rbt_start(tracker, &config, &image(buf), &r#box) },
        RBT_OK
    );
    tracker
}

fn square_box() -> rbt_rect {
    rbt_rect {
        x: q(20),
        y: q(16),
        w: q(16),
        h: q(16),
    }
}

/// The placed correlation-filter tracker started on the square at 20.
fn started_cf(mem: &mut Memory, buf: &[u8]) -> *mut rbt_tracker {
    let mut tracker = null_mut();
    let place =
        unsafe { rbt_tracker_place_cf(mem.0.as_mut_ptr().cast(), mem.0.len(), &mut tracker) };
    assert_eq!(place, RBT_OK);
    let mut config = rbt_cf_config::default();
    assert_eq!(unsafe { rbt_cf_config_default(&mut config) }, RBT_OK);
    assert_eq!(
        unsafe { rbt_cf_start(tracker, &config, &image(buf), &square_box()) },
        RBT_OK
    );
    tracker
}

#[test]
fn the_correlation_filter_tracker_tracks_as_the_cores_does() {
    let mut mem = memory();
    let first = square(20);
    let tracker = started_cf(&mut mem, &first);
    let view = ImageView::<Gray8>::new(&first, 64, 48, 64).unwrap();
    let mut core = Box::new(RgbCfTracker::unstarted());
    core.start(CfConfig::default(), &view, Rect::new(20, 16, 16, 16))
        .unwrap();
    let mut got = rbt_estimate::default();
    assert_eq!(unsafe { rbt_estimate_of(tracker, &mut got) }, RBT_OK);
    assert_eq!(got, rbt_estimate::from(*core.estimate()));
    for x0 in [22, 24, 26, 28, 30] {
        let buf = square(x0);
        assert_eq!(unsafe { rbt_step(tracker, &image(&buf), &mut got) }, RBT_OK);
        let want = core.step(&ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap());
        assert_eq!(got, rbt_estimate::from(want));
    }
    assert!(got.cx > q(36), "it follows the square: {got:?}");
    let motion = rbt_motion {
        dx: -q(2),
        dy: 0,
        zoom: RBT_Q16_ONE,
        centre_x: q(32),
        centre_y: q(24),
    };
    assert_eq!(unsafe { rbt_camera_moved(tracker, &motion) }, RBT_OK);
    core.camera_moved(&CameraMotion {
        dx: Q16::from_int(-2),
        dy: Q16::ZERO,
        zoom: Q16::ONE,
        centre_x: Q16::from_int(32),
        centre_y: Q16::from_int(24),
    });
    assert_eq!(unsafe { rbt_estimate_of(tracker, &mut got) }, RBT_OK);
    assert_eq!(got, rbt_estimate::from(*core.estimate()));
}

#[test]
fn the_correlation_filter_tracker_relocates_as_the_cores_does() {
    let mut mem = memory();
    let first = square(20);
    let tracker = started_cf(&mut mem, &first);
    fn view(buf: &[u8]) -> ImageView<'_, Gray8> {
        ImageView::new(buf, 64, 48, 64).unwrap()
    }
    let mut core = Box::new(RgbCfTracker::unstarted());
    core.start(
        CfConfig::default(),
        &view(&first),
        Rect::new(20, 16, 16, 16),
    )
    .unwrap();
    let mut got = rbt_estimate::default();
    for x0 in [22, 24] {
        let buf = square(x0);
        assert_eq!(unsafe { rbt_step(tracker, &image(&buf), &mut got) }, RBT_OK);
        core.step(&view(&buf));
    }
    // The square jumps; a detector's box moves both trackers there, and they go on alike.
    let jumped = square(40);
    let r#box = rbt_rect {
        x: q(40),
        y: q(16),
        w: q(16),
        h: q(16),
    };
    assert_eq!(
        unsafe { rbt_relocate(tracker, &image(&jumped), &r#box) },
        RBT_OK
    );
    core.relocate(&view(&jumped), Rect::new(40, 16, 16, 16))
        .unwrap();
    assert_eq!(unsafe { rbt_estimate_of(tracker, &mut got) }, RBT_OK);
    assert_eq!(got, rbt_estimate::from(*core.estimate()));
    for x0 in [42, 44] {
        let buf = square(x0);
        assert_eq!(unsafe { rbt_step(tracker, &image(&buf), &mut got) }, RBT_OK);
        assert_eq!(got, rbt_estimate::from(core.step(&view(&buf))));
    }
    // Placed but not started: nothing to keep.
    let mut other = memory();
    let mut placed = null_mut();
    let place =
        unsafe { rbt_tracker_place_cf(other.0.as_mut_ptr().cast(), other.0.len(), &mut placed) };
    assert_eq!(place, RBT_OK);
    assert_eq!(
        unsafe { rbt_relocate(placed, &image(&jumped), &r#box) },
        RBT_ERR_MODEL_SETTINGS
    );
}

#[test]
fn a_call_for_the_other_kind_of_tracker_is_refused() {
    let (mut cf_mem, mut pf_mem) = (memory(), memory());
    let buf = square(20);
    let (cf, pf) = (started_cf(&mut cf_mem, &buf), started(&mut pf_mem, &buf));
    let (frame, r#box) = (image(&buf), square_box());
    let config = default_config(rbt_variant::RBT_VARIANT_RBPF);
    let mut cf_config = rbt_cf_config::default();
    unsafe {
        assert_eq!(rbt_cf_config_default(&mut cf_config), RBT_OK);
        assert_eq!(rbt_start(cf, &config, &frame, &r#box), RBT_ERR_TRACKER_KIND);
        assert_eq!(rbt_reset(cf, &frame, &r#box), RBT_ERR_TRACKER_KIND);
        assert_eq!(
            rbt_cf_start(pf, &cf_config, &frame, &r#box),
            RBT_ERR_TRACKER_KIND
        );
        // Each still tracks.
        let mut estimate = rbt_estimate::default();
        assert_eq!(rbt_step(cf, &image(&square(22)), &mut estimate), RBT_OK);
        assert_eq!(rbt_step(pf, &image(&square(22)), &mut estimate), RBT_OK);
        // Its own refusals: null pointers, short memory, a bad configuration or box.
        let mut out = null_mut();
        let base = cf_mem.0.as_mut_ptr().cast::<c_void>();
        assert_eq!(
            rbt_tracker_place_cf(base, RBT_TRACKER_CF_SIZE - 1, &mut out),
            RBT_ERR_MEMORY_SIZE
        );
        assert_eq!(
            rbt_tracker_place_cf(null_mut(), 1 << 20, &mut out),
            RBT_ERR_NULL
        );
        assert_eq!(rbt_cf_start(cf, null(), &frame, &r#box), RBT_ERR_NULL);
        assert_eq!(rbt_cf_start(cf, &cf_config, null(), &r#box), RBT_ERR_NULL);
        assert_eq!(rbt_cf_start(cf, &cf_config, &frame, null()), RBT_ERR_NULL);
        assert_eq!(rbt_cf_config_default(null_mut()), RBT_ERR_NULL);
        assert_eq!(rbt_cf_config_check(null(), null_mut(), 0), RBT_ERR_NULL);
        let odd_cell = rbt_cf_config {
            cell: 3,
            ..cf_config
        };
        assert_eq!(
            rbt_cf_start(cf, &odd_cell, &frame, &r#box),
            RBT_ERR_CONFIG_RANGE
        );
        let outside = rbt_rect { x: q(100), ..r#box };
        assert_eq!(
            rbt_cf_start(cf, &cf_config, &frame, &outside),
            RBT_ERR_BOX_OUTSIDE
        );
    }
}

#[test]
fn it_tracks_as_the_core_does() {
    let mut mem = memory();
    let first = square(20);
    let tracker = started(&mut mem, &first);
    let mut config = Config::new(Variant::ColourPf);
    config.seed = 1;
    let view = ImageView::<Gray8>::new(&first, 64, 48, 64).unwrap();
    let init: Ellipse = Rect::new(20, 16, 16, 16).into();
    let mut core = RgbTracker::<50>::new(config, &view, init).unwrap();
    for x0 in [22, 24, 26, 28] {
        let buf = square(x0);
        let mut got = rbt_estimate::default();
        assert_eq!(unsafe { rbt_step(tracker, &image(&buf), &mut got) }, RBT_OK);
        let want = core.step(&ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap());
        assert_eq!(got, rbt_estimate::from(want));
        let mut again = rbt_estimate::default();
        assert_eq!(unsafe { rbt_estimate_of(tracker, &mut again) }, RBT_OK);
        assert_eq!(again, got);
    }
}

#[test]
fn camera_motion_and_the_pan_tilt_head_act_as_the_cores() {
    use rbtrack::pantilt::{PanTilt, PanTiltConfig};
    use rbtrack::tracker::CameraMotion;
    let mut mem = memory();
    let first = square(20);
    let tracker = started(&mut mem, &first);
    let view = ImageView::<Gray8>::new(&first, 64, 48, 64).unwrap();
    let mut core = RgbTracker::<50>::new(
        Config::new(Variant::ColourPf),
        &view,
        Rect::new(20, 16, 16, 16),
    )
    .unwrap();
    let motion = rbt_motion {
        dx: q(4),
        dy: -q(1) / 2,
        zoom: RBT_Q16_ONE + RBT_Q16_ONE / 8,
        centre_x: q(32),
        centre_y: q(24),
    };
    let moved = CameraMotion {
        dx: Q16::from_int(4),
        dy: Q16::from_f64(-0.5),
        zoom: Q16::from_f64(1.125),
        centre_x: Q16::from_int(32),
        centre_y: Q16::from_int(24),
    };
    let mut head = unsafe { std::mem::zeroed::<rbt_pantilt>() };
    let mut head_config = rbt_pantilt_config::default();
    let mut core_head = PanTilt::new(PanTiltConfig::new(
        64,
        48,
        Q16::from_int(60),
        Q16::from_int(45),
    ))
    .unwrap();
    unsafe {
        assert_eq!(
            rbt_pantilt_config_default(64, 48, q(60), q(45), &mut head_config),
            RBT_OK
        );
        assert_eq!(rbt_pantilt_start(&mut head, &head_config), RBT_OK);
    }
    let buf = square(26);
    for _ in 0..3 {
        let mut got = rbt_estimate::default();
        let mut command = rbt_command::default();
        unsafe {
            assert_eq!(rbt_camera_moved(tracker, &motion), RBT_OK);
            assert_eq!(rbt_step(tracker, &image(&buf), &mut got), RBT_OK);
            assert_eq!(rbt_pantilt_step(&mut head, &got, &mut command), RBT_OK);
        }
        core.camera_moved(&moved);
        let want = core.step(&ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap());
        assert_eq!(got, rbt_estimate::from(want));
        let c = core_head.step(&want);
        assert_eq!(
            command,
            rbt_command {
                pan: c.pan.to_bits(),
                tilt: c.tilt.to_bits()
            }
        );
        assert_ne!(command, rbt_command::default(), "the head turns");
    }
}

#[test]
fn configurations_round_trip_and_every_code_has_a_name() {
    for variant in [Variant::ColourPf, Variant::Rbpf] {
        for config in [Config::new(variant), Config::paper(variant)] {
            let c = rbt_config::from(&config);
            let mut message = [0u8; 8];
            assert_eq!(
                unsafe { rbt_config_check(&c, message.as_mut_ptr().cast(), 8) },
                RBT_OK
            );
        }
    }
    let cf = rbt_cf_config::from(&CfConfig::default());
    let mut defaults = rbt_cf_config::default();
    assert_eq!(unsafe { rbt_cf_config_default(&mut defaults) }, RBT_OK);
    assert_eq!(defaults, cf);
    assert_eq!(unsafe { rbt_cf_config_check(&cf, null_mut(), 0) }, RBT_OK);
    for (bad, field) in [
        (rbt_cf_config { cell: 5, ..cf }, "cell"),
        (rbt_cf_config { redetect: 9, ..cf }, "redetect"),
        (
            rbt_cf_config {
                lost_below: cf.uncertain_below + 1,
                ..cf
            },
            "lost_below",
        ),
        (
            rbt_cf_config {
                scale_step: RBT_Q16_ONE,
                ..cf
            },
            "scale.step",
        ),
    ] {
        let mut message = [0xFFu8; 64];
        assert_eq!(
            unsafe { rbt_cf_config_check(&bad, message.as_mut_ptr().cast(), 64) },
            RBT_ERR_CONFIG_RANGE
        );
        let text = CStr::from_bytes_until_nul(&message)
            .unwrap()
            .to_str()
            .unwrap();
        assert!(text.contains(field), "{field}: {text}");
    }
    let mut names = std::collections::HashSet::new();
    for code in 0..=25 {
        let name = unsafe { CStr::from_ptr(rbt_error_name(code)) }
            .to_str()
            .unwrap();
        assert!(name.starts_with("RBT_"), "{code}: {name}");
        assert!(names.insert(name), "{code}: {name} twice");
    }
    for code in [-1, 26, i32::MAX] {
        let name = unsafe { CStr::from_ptr(rbt_error_name(code)) };
        assert_eq!(name.to_str().unwrap(), "unknown rbt_error code");
    }
    assert_eq!(rbt_error::RBT_ERR_TRACKER_KIND as i32, 25, "the last code");
}

#[test]
fn the_status_numbers_rise_with_confidence() {
    let numbers = [Status::Lost, Status::Uncertain, Status::Tracking].map(|status| {
        let estimate = Estimate {
            ellipse: Ellipse::new(
                Q16::from_int(20),
                Q16::from_int(20),
                Q16::from_int(8),
                Q16::from_int(8),
            ),
            vx: Q16::ZERO,
            vy: Q16::ZERO,
            score: Q16::ZERO,
            confidence: Q16::ZERO,
            status,
        };
        rbt_estimate::from(estimate).status
    });
    assert_eq!(numbers, [0, 1, 2]);
    let named = [
        rbt_status::RBT_STATUS_LOST,
        rbt_status::RBT_STATUS_UNCERTAIN,
        rbt_status::RBT_STATUS_TRACKING,
    ];
    assert_eq!(named.map(|s| s as u32), numbers);
}

#[test]
fn every_null_pointer_is_refused() {
    let mut mem = memory();
    let buf = square(20);
    let tracker = started(&mut mem, &buf);
    let (frame, config) = (image(&buf), default_config(rbt_variant::RBT_VARIANT_RBPF));
    let r#box = rbt_rect {
        x: q(20),
        y: q(16),
        w: q(16),
        h: q(16),
    };
    let mut estimate = rbt_estimate::default();
    let mut out = null_mut();
    unsafe {
        assert_eq!(
            rbt_tracker_place_rgb_100(null_mut(), 1 << 20, &mut out),
            RBT_ERR_NULL
        );
        assert_eq!(
            rbt_tracker_place_rgb_100(mem.0.as_mut_ptr().cast(), mem.0.len(), null_mut()),
            RBT_ERR_NULL
        );
        assert_eq!(rbt_start(null_mut(), &config, &frame, &r#box), RBT_ERR_NULL);
        assert_eq!(rbt_start(tracker, null(), &frame, &r#box), RBT_ERR_NULL);
        assert_eq!(rbt_start(tracker, &config, null(), &r#box), RBT_ERR_NULL);
        assert_eq!(rbt_start(tracker, &config, &frame, null()), RBT_ERR_NULL);
        assert_eq!(rbt_reset(tracker, null(), &r#box), RBT_ERR_NULL);
        assert_eq!(rbt_relocate(tracker, &frame, null()), RBT_ERR_NULL);
        assert_eq!(rbt_step(tracker, &frame, null_mut()), RBT_ERR_NULL);
        assert_eq!(rbt_step(tracker, null(), &mut estimate), RBT_ERR_NULL);
        assert_eq!(rbt_estimate_of(null_mut(), &mut estimate), RBT_ERR_NULL);
        assert_eq!(rbt_camera_moved(tracker, null()), RBT_ERR_NULL);
        assert_eq!(rbt_config_default(0, null_mut()), RBT_ERR_NULL);
        assert_eq!(rbt_config_check(null(), null_mut(), 0), RBT_ERR_NULL);
        let no_data = rbt_image {
            data: null(),
            ..frame
        };
        assert_eq!(rbt_step(tracker, &no_data, &mut estimate), RBT_ERR_NULL);
        assert_eq!(rbt_pantilt_start(null_mut(), null()), RBT_ERR_NULL);
        assert_eq!(
            rbt_pantilt_config_default(320, 240, q(60), q(45), null_mut()),
            RBT_ERR_NULL
        );
    }
}

#[test]
fn bad_memory_and_handles_are_refused() {
    let mut mem = memory();
    let base = mem.0.as_mut_ptr();
    let mut out = null_mut();
    unsafe {
        let short = RBT_TRACKER_RGB_100_SIZE - 1;
        assert_eq!(
            rbt_tracker_place_rgb_100(base.cast(), short, &mut out),
            RBT_ERR_MEMORY_SIZE
        );
        let odd = base.add(4).cast::<c_void>();
        assert_eq!(
            rbt_tracker_place_rgb_100(odd, RBT_TRACKER_RGB_100_SIZE, &mut out),
            RBT_ERR_MEMORY_ALIGN
        );
        assert!(out.is_null(), "nothing placed");
        // Memory no `rbt_tracker_place_*` wrote, aligned or not.
        let mut estimate = rbt_estimate::default();
        assert_eq!(
            rbt_estimate_of(base.cast(), &mut estimate),
            RBT_ERR_NOT_A_TRACKER
        );
        assert_eq!(
            rbt_estimate_of(base.add(1).cast(), &mut estimate),
            RBT_ERR_NOT_A_TRACKER
        );
        let mut head: rbt_pantilt = std::mem::zeroed();
        let mut command = rbt_command::default();
        assert_eq!(
            rbt_pantilt_step(&mut head, &estimate, &mut command),
            RBT_ERR_NOT_A_PANTILT
        );
    }
}

#[test]
fn bad_images_say_why() {
    let mut mem = memory();
    let buf = square(20);
    let tracker = started(&mut mem, &buf);
    let frame = image(&buf);
    let cases = [
        (rbt_image { format: 0, ..frame }, RBT_ERR_FORMAT),
        (rbt_image { format: 8, ..frame }, RBT_ERR_FORMAT),
        (rbt_image { width: 0, ..frame }, RBT_ERR_IMAGE_EMPTY),
        (
            rbt_image {
                width: 20_000,
                stride: 20_000,
                ..frame
            },
            RBT_ERR_IMAGE_TOO_LARGE,
        ),
        (
            rbt_image {
                stride: 63,
                ..frame
            },
            RBT_ERR_IMAGE_STRIDE,
        ),
        (
            rbt_image {
                size: buf.len() - 1,
                ..frame
            },
            RBT_ERR_IMAGE_SHORT,
        ),
        (
            rbt_image {
                format: rbt_format::RBT_FORMAT_RGB888 as u32,
                ..frame
            },
            RBT_ERR_IMAGE_SHORT,
        ),
        (
            rbt_image {
                format: rbt_format::RBT_FORMAT_YUYV as u32,
                width: 63,
                ..frame
            },
            RBT_ERR_IMAGE_ODD_YUV,
        ),
        (
            rbt_image {
                stride: u32::MAX,
                ..frame
            },
            RBT_ERR_IMAGE_SHORT,
        ),
    ];
    let mut estimate = rbt_estimate::default();
    for (bad, error) in cases {
        assert_eq!(
            unsafe { rbt_step(tracker, &bad, &mut estimate) },
            error,
            "{bad:?}"
        );
    }
}

#[test]
fn bad_boxes_configurations_and_estimates_say_why() {
    let mut mem = memory();
    let buf = square(20);
    let tracker = started(&mut mem, &buf);
    let frame = image(&buf);
    let mut config = default_config(rbt_variant::RBT_VARIANT_RBPF);
    let tiny = rbt_rect {
        x: q(20),
        y: q(16),
        w: q(1),
        h: q(16),
    };
    let outside = rbt_rect {
        x: q(100),
        y: q(16),
        w: q(16),
        h: q(16),
    };
    unsafe {
        assert_eq!(
            rbt_start(tracker, &config, &frame, &tiny),
            RBT_ERR_BOX_TOO_SMALL
        );
        assert_eq!(rbt_reset(tracker, &frame, &outside), RBT_ERR_BOX_OUTSIDE);
        assert_eq!(rbt_relocate(tracker, &frame, &outside), RBT_ERR_BOX_OUTSIDE);
        assert_eq!(rbt_config_default(2, &mut config), RBT_ERR_CONFIG_ENUM);
    }
    let mut message = [0x7Fu8; 64];
    let mut check = |config: &rbt_config| unsafe {
        let e = rbt_config_check(config, message.as_mut_ptr().cast(), message.len());
        (
            e,
            CStr::from_bytes_until_nul(&message)
                .unwrap()
                .to_str()
                .unwrap()
                .to_owned(),
        )
    };
    assert_eq!(unsafe { rbt_config_check(&config, null_mut(), 0) }, RBT_OK);
    let range = rbt_config {
        colour_sigma: 0,
        ..config
    };
    assert_eq!(
        check(&range),
        (
            RBT_ERR_CONFIG_RANGE,
            "configuration field `colour_sigma` out of range".into()
        )
    );
    let bad_enum = rbt_config {
        readout: 7,
        ..config
    };
    assert_eq!(
        check(&bad_enum),
        (
            RBT_ERR_CONFIG_ENUM,
            "configuration field `readout` holds an unknown value".into()
        )
    );
    let r#box = rbt_rect {
        x: q(20),
        y: q(16),
        w: q(16),
        h: q(16),
    };
    assert_eq!(
        unsafe { rbt_start(tracker, &range, &frame, &r#box) },
        RBT_ERR_CONFIG_RANGE
    );
    // A message buffer of 8 bytes gets 7 and the NUL.
    let mut short = [0x7Fu8; 8];
    unsafe { rbt_config_check(&range, short.as_mut_ptr().cast(), short.len()) };
    assert_eq!(
        CStr::from_bytes_until_nul(&short).unwrap().to_bytes(),
        b"configu"
    );
    let estimate = rbt_estimate {
        status: 3,
        ..rbt_estimate::default()
    };
    let mut head: rbt_pantilt = unsafe { std::mem::zeroed() };
    let mut head_config = rbt_pantilt_config::default();
    unsafe {
        assert_eq!(
            rbt_pantilt_config_default(320, 240, q(60), q(45), &mut head_config),
            RBT_OK
        );
        assert_eq!(rbt_pantilt_start(&mut head, &head_config), RBT_OK);
        let mut command = rbt_command::default();
        assert_eq!(
            rbt_pantilt_step(&mut head, &estimate, &mut command),
            RBT_ERR_STATUS
        );
        let fov = rbt_pantilt_config {
            fov_x: 0,
            ..head_config
        };
        assert_eq!(rbt_pantilt_start(&mut head, &fov), RBT_ERR_PANTILT_FOV);
    }
}
