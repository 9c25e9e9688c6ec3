//! OTB sequence loading on tiny generated sequences, malformed inputs, and (when present)
//! the shared real sequences.

use rbtrack_host::metrics::BBox;
use rbtrack_host::pixels::{Format, Frame};
use rbtrack_host::sequence::*;
use std::path::{Path, PathBuf};

mod common;

/// A fresh sequence folder with an empty `img` folder.
fn temp_dir(name: &str) -> PathBuf {
    let dir = common::temp_dir("seq", name);
    std::fs::create_dir_all(dir.join("img")).unwrap();
    dir
}

const W: u32 = 8;
const H: u32 = 6;

/// A solid-colour frame with one marker pixel at (k, 0), so frames are told apart.
fn frame_pixels(k: u8) -> Vec<u8> {
    let mut rgb = [10u8, 100, 200].repeat((W * H) as usize);
    rgb[k as usize * 3] = 250;
    rgb
}

fn write_png(path: &Path, rgb: &[u8], w: u32, h: u32) {
    image::save_buffer(path, rgb, w, h, image::ExtendedColorType::Rgb8).unwrap();
}

#[test]
fn png_sequence_in_numeric_order() {
    let dir = temp_dir("png");
    // Written out of order, and with 10 after 2, to check the numeric sort.
    for (name, k) in [("0010.png", 2u8), ("0001.png", 0), ("0002.png", 1)] {
        write_png(&dir.join("img").join(name), &frame_pixels(k), W, H);
    }
    std::fs::write(dir.join("img/notes.txt"), "ignored").unwrap();
    std::fs::write(
        dir.join(GROUNDTRUTH_FILE),
        "1,1,4,3\n2 2 4 3\r\n\n3\t3\t4.5\t3\n",
    )
    .unwrap();

    let seq = Sequence::open(&dir, GtOrigin::OneBased).unwrap();
    assert_eq!(seq.len(), 3);
    assert_eq!((seq.width, seq.height), (W, H));
    assert_eq!(seq.origin, GtOrigin::OneBased);
    assert_eq!(
        seq.groundtruth,
        vec![
            BBox::new(0.0, 0.0, 4.0, 3.0),
            BBox::new(1.0, 1.0, 4.0, 3.0),
            BBox::new(2.0, 2.0, 4.5, 3.0),
        ]
    );
    assert_eq!(seq.init_box(), Some(BBox::new(0.0, 0.0, 4.0, 3.0)));
    let names: Vec<_> = seq
        .frame_paths
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["0001.png", "0002.png", "0010.png"]);

    let frames: Vec<Frame> = seq.frames().map(|f| f.unwrap()).collect();
    assert_eq!(frames.len(), 3);
    for (k, f) in frames.into_iter().enumerate() {
        assert_eq!((f.format, f.width, f.height), (Format::Rgb888, W, H));
        assert_eq!(f.bytes, frame_pixels(k as u8));
        let rgb565 = f.convert(Format::Rgb565Le).unwrap();
        assert_eq!(rgb565.bytes.len(), (W * H * 2) as usize);
    }
    assert!(matches!(
        seq.frame(3),
        Err(SequenceError::FrameIndex { index: 3, len: 3 })
    ));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn jpeg_sequence_decodes_close_to_source() {
    let dir = temp_dir("jpg");
    let rgb = [120u8, 60, 30].repeat((16 * 16) as usize);
    for name in ["0001.jpg", "0002.JPG"] {
        let path = dir.join("img").join(name);
        let file = std::fs::File::create(&path).unwrap();
        image::codecs::jpeg::JpegEncoder::new_with_quality(file, 95)
            .encode(&rgb, 16, 16, image::ExtendedColorType::Rgb8)
            .unwrap();
    }
    std::fs::write(dir.join(GROUNDTRUTH_FILE), "1,1,5,5\n1,1,5,5\n").unwrap();
    let seq = Sequence::open(&dir, GtOrigin::OneBased).unwrap();
    assert_eq!(seq.len(), 2);
    for f in seq.frames() {
        let f = f.unwrap();
        assert_eq!(f.bytes.len(), 16 * 16 * 3);
        for (a, b) in f.bytes.iter().zip(&rgb) {
            assert!((*a as i32 - *b as i32).abs() <= 6, "{a} vs {b}");
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn errors_are_reported_not_panicked() {
    // Missing folder, and folder without img/.
    let missing = std::env::temp_dir().join("rbtrack-no-such-sequence-folder");
    let e = Sequence::open(&missing, GtOrigin::OneBased).unwrap_err();
    assert!(matches!(e, SequenceError::MissingFolder(_)));
    assert!(e.to_string().contains("not found"), "{e}");
    let dir = temp_dir("noimg");
    std::fs::remove_dir(dir.join("img")).unwrap();
    assert!(matches!(
        Sequence::open(&dir, GtOrigin::OneBased),
        Err(SequenceError::MissingFolder(p)) if p.ends_with("img")
    ));
    let _ = std::fs::remove_dir_all(dir);

    // Empty img/.
    let dir = temp_dir("empty");
    let e = Sequence::open(&dir, GtOrigin::OneBased).unwrap_err();
    assert!(matches!(e, SequenceError::Empty(_)), "{e}");
    let _ = std::fs::remove_dir_all(dir);

    // Missing ground truth.
    let dir = temp_dir("nogt");
    write_png(&dir.join("img/0001.png"), &frame_pixels(0), W, H);
    let e = Sequence::open(&dir, GtOrigin::OneBased).unwrap_err();
    assert!(matches!(e, SequenceError::Io { .. }), "{e}");
    assert!(e.to_string().contains(GROUNDTRUTH_FILE), "{e}");

    // Malformed ground truth, with its line number.
    for (text, line) in [
        ("1,2,3,4\n1,2,3\n", 2),
        ("1,2,3,4\n\n1,2,3,4\n1,a,3,4\n", 4),
        ("1,2,3,4,5\n", 1),
        ("1,2,inf,4\n", 1),
    ] {
        std::fs::write(dir.join(GROUNDTRUTH_FILE), text).unwrap();
        match Sequence::open(&dir, GtOrigin::OneBased) {
            Err(e @ SequenceError::GroundTruth { .. }) => {
                let SequenceError::GroundTruth { line: l, .. } = e else {
                    unreachable!()
                };
                assert_eq!(l, line, "{text:?}");
                assert!(e.to_string().contains(&format!(":{line}:")), "{e}");
            }
            other => panic!("{text:?}: {other:?}"),
        }
    }

    // Unreadable first frame fails at open; unreadable later frame fails lazily.
    std::fs::write(dir.join(GROUNDTRUTH_FILE), "1,1,2,2\n1,1,2,2\n1,1,2,2\n").unwrap();
    std::fs::write(dir.join("img/0002.jpg"), b"not a jpeg at all").unwrap();
    write_png(&dir.join("img/0003.png"), &[0; 5 * 5 * 3], 5, 5);
    let seq = Sequence::open(&dir, GtOrigin::OneBased).unwrap();
    assert_eq!(seq.len(), 3);
    let results: Vec<_> = seq.frames().collect();
    assert!(results[0].is_ok());
    let e = results[1].as_ref().unwrap_err();
    assert!(matches!(e, SequenceError::Image { .. }), "{e}");
    assert!(e.to_string().contains("0002.jpg"), "{e}");
    let e = results[2].as_ref().unwrap_err();
    assert!(
        matches!(
            e,
            SequenceError::FrameSize {
                expected: (8, 6),
                found: (5, 5),
                ..
            }
        ),
        "{e}"
    );
    std::fs::write(dir.join("img/0001.png"), b"garbage").unwrap();
    assert!(matches!(
        Sequence::open(&dir, GtOrigin::OneBased),
        Err(SequenceError::Image { .. })
    ));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn origin_is_stated() {
    assert_eq!(GtOrigin::of_shared("ball1_vot15"), GtOrigin::ZeroBased);
    assert_eq!(GtOrigin::of_shared("Crossing"), GtOrigin::OneBased);
    assert_eq!(GtOrigin::default(), GtOrigin::OneBased);
    let b = BBox::new(5.0, 6.0, 7.0, 8.0);
    assert_eq!(GtOrigin::ZeroBased.to_zero_based(b), b);
    assert_eq!(
        GtOrigin::OneBased.to_zero_based(b),
        BBox::new(4.0, 5.0, 7.0, 8.0)
    );

    let dir = temp_dir("origin");
    write_png(&dir.join("img/0001.png"), &frame_pixels(0), W, H);
    std::fs::write(dir.join(GROUNDTRUTH_FILE), "5,6,7,8\n").unwrap();
    let seq = Sequence::open(&dir, GtOrigin::ZeroBased).unwrap();
    assert_eq!(seq.groundtruth, vec![b]);
    let gt = read_groundtruth(dir.join(GROUNDTRUTH_FILE), GtOrigin::OneBased).unwrap();
    assert_eq!(gt, vec![BBox::new(4.0, 5.0, 7.0, 8.0)]);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn groundtruth_nan_marks_missing_box() {
    let boxes = parse_groundtruth("1,2,3,4\nNaN,NaN,NaN,NaN\n").unwrap();
    assert_eq!(boxes.len(), 2);
    assert!(boxes[0].is_valid());
    assert!(!boxes[1].is_valid());
}

#[test]
fn init_argument() {
    assert_eq!(
        parse_bbox("10,20,30,40").unwrap(),
        BBox::new(10.0, 20.0, 30.0, 40.0)
    );
    assert_eq!(
        parse_bbox(" 1.5 2 3\t4 ").unwrap(),
        BBox::new(1.5, 2.0, 3.0, 4.0)
    );
    for bad in [
        "",
        "1,2,3",
        "1,2,3,4,5",
        "1,2,x,4",
        "1,2,-3,4",
        "1,2,0,4",
        "NaN,1,2,3",
    ] {
        let e = parse_bbox(bad).unwrap_err();
        assert!(matches!(e, SequenceError::BoxParse { .. }), "{bad:?}");
        assert!(e.to_string().contains("x,y,w,h"), "{e}");
    }
}

/// Opens every shared real sequence (if the data folder is there) and decodes its first
/// frame; sizes per the data README.
#[test]
fn shared_real_sequences() {
    let Some(root) = shared_data_dir() else {
        println!(
            "SKIPPED shared_real_sequences: no shared data folder (looked at ${DATA_ENV} if \
             set, else {}/../../shared/data)",
            env!("CARGO_MANIFEST_DIR")
        );
        return;
    };
    let expected = [
        ("Crossing", 120, (360, 240)),
        ("KiteSurf", 84, (480, 270)),
        ("ball1_vot15", 105, (1280, 720)),
        ("PETS09S2L1_id11", 284, (768, 576)),
        ("boat1_uav", 301, (1280, 720)),
    ];
    for (name, frames, size) in expected {
        let dir = root.join(name);
        if !dir.is_dir() {
            println!("SKIPPED {name}: not in {}", root.display());
            continue;
        }
        let seq = Sequence::open(&dir, GtOrigin::of_shared(name)).unwrap();
        assert_eq!(seq.len(), frames, "{name}");
        assert_eq!(seq.groundtruth.len(), frames, "{name}");
        assert_eq!((seq.width, seq.height), size, "{name}");
        assert!(seq.groundtruth.iter().all(|b| b.is_valid()), "{name}");
        let f = seq.frame(0).unwrap();
        assert_eq!(f.bytes.len(), (size.0 * size.1 * 3) as usize);
        let first = seq.init_box().unwrap();
        assert!(first.x >= 0.0 && first.y >= 0.0, "{name}: {first:?}");
        assert!(first.x + first.w <= size.0 as f64 + 1.0, "{name}");
    }
}

#[test]
fn optional_groundtruth_and_origin_round_trip() {
    let dir = temp_dir("optgt");
    write_png(&dir.join("img/0001.png"), &frame_pixels(0), W, H);
    let seq = Sequence::open_optional_groundtruth(&dir, GtOrigin::OneBased).unwrap();
    assert!(!seq.has_groundtruth());
    assert_eq!(seq.init_box(), None);
    assert_eq!(seq.len(), 1);
    // A ground-truth file that exists must still parse.
    std::fs::write(dir.join(GROUNDTRUTH_FILE), "1,2,3\n").unwrap();
    assert!(matches!(
        Sequence::open_optional_groundtruth(&dir, GtOrigin::OneBased),
        Err(SequenceError::GroundTruth { line: 1, .. })
    ));
    std::fs::write(dir.join(GROUNDTRUTH_FILE), "2,3,4,5\n").unwrap();
    let seq = Sequence::open_optional_groundtruth(&dir, GtOrigin::OneBased).unwrap();
    assert!(seq.has_groundtruth());
    assert_eq!(seq.init_box(), Some(BBox::new(1.0, 2.0, 4.0, 5.0)));
    let b = BBox::new(1.5, 2.0, 3.0, 4.0);
    for origin in [GtOrigin::OneBased, GtOrigin::ZeroBased] {
        assert_eq!(origin.to_zero_based(origin.from_zero_based(b)), b);
    }
    assert_eq!(
        GtOrigin::OneBased.from_zero_based(b),
        BBox::new(2.5, 3.0, 3.0, 4.0)
    );
    let _ = std::fs::remove_dir_all(dir);
}
