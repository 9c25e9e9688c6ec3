//! Drawing, text on frames, image writing and plots.

use rbtrack_host::draw::*;
use rbtrack_host::metrics::{precision_curve, success_curve, BBox};
use std::path::PathBuf;

mod common;

fn temp_dir(name: &str) -> PathBuf {
    common::temp_dir("draw", name)
}

fn px(rgb: &[u8], w: u32, x: u32, y: u32) -> [u8; 3] {
    let i = ((y * w + x) * 3) as usize;
    [rgb[i], rgb[i + 1], rgb[i + 2]]
}

#[test]
fn box_outline_only() {
    let (w, h) = (20, 10);
    let mut rgb = vec![0u8; 20 * 10 * 3];
    draw_box(&mut rgb, w, h, &BBox::new(2.0, 3.0, 6.0, 4.0), GREEN, 1);
    assert_eq!(px(&rgb, w, 2, 3), GREEN);
    assert_eq!(px(&rgb, w, 7, 6), GREEN);
    assert_eq!(px(&rgb, w, 5, 3), GREEN);
    assert_eq!(px(&rgb, w, 4, 4), [0, 0, 0]); // interior
    assert_eq!(px(&rgb, w, 8, 3), [0, 0, 0]); // just outside
}

#[test]
fn ellipse_outline() {
    let (w, h) = (40, 40);
    let mut rgb = vec![0u8; 40 * 40 * 3];
    draw_ellipse(&mut rgb, w, h, (20.0, 20.0, 10.0, 5.0), RED_FOR_TEST, 1);
    assert_eq!(px(&rgb, w, 30, 20), RED_FOR_TEST);
    assert_eq!(px(&rgb, w, 10, 20), RED_FOR_TEST);
    assert_eq!(px(&rgb, w, 20, 15), RED_FOR_TEST);
    assert_eq!(px(&rgb, w, 20, 20), [0, 0, 0]);
    draw_cross(&mut rgb, w, h, (20.0, 20.0), 2, GREEN);
    assert_eq!(px(&rgb, w, 22, 20), GREEN);
}

const RED_FOR_TEST: Rgb = [255, 0, 0];

#[test]
fn drawing_never_panics_on_bad_input() {
    let mut rgb = vec![0u8; 10 * 10 * 3];
    let mut short = vec![0u8; 7];
    for b in [
        BBox::new(-50.0, -50.0, 200.0, 200.0),
        BBox::new(f64::NAN, 0.0, 5.0, 5.0),
        BBox::new(1e300, 1e300, 1e300, 1e300),
        BBox::new(3.0, 3.0, -4.0, 0.0),
    ] {
        draw_box(&mut rgb, 10, 10, &b, GREEN, 3);
        draw_box(&mut short, 10, 10, &b, GREEN, 3);
    }
    draw_ellipse(&mut rgb, 10, 10, (5.0, 5.0, f64::INFINITY, 2.0), GREEN, 2);
    draw_ellipse(&mut rgb, 10, 10, (-100.0, 5.0, 3.0, 2.0), GREEN, 2);
    draw_ellipse(&mut short, 10, 10, (5.0, 5.0, 3.0, 2.0), GREEN, 2);
    draw_cross(&mut rgb, 10, 10, (f64::NAN, 1.0), 3, GREEN);
    assert!(matches!(
        save_png(std::env::temp_dir().join("never.png"), &short, 10, 10),
        Err(DrawError::Size { .. })
    ));
}

#[test]
fn strip_gif_and_png_files() {
    let dir = temp_dir("files");
    let (w, h) = (16u32, 8u32);
    let frames: Vec<Vec<u8>> = (0..3u8)
        .map(|k| vec![k * 100; (w * h * 3) as usize])
        .collect();
    let refs: Vec<&[u8]> = frames.iter().map(|f| f.as_slice()).collect();

    let (tiled, tw, th) = tile(&refs, w, h, 2, 4).unwrap();
    assert_eq!((tw, th), (2 * (16 + 4) + 4, 2 * (8 + 4) + 4));
    assert_eq!(tiled.len(), (tw * th * 3) as usize);
    assert_eq!(px(&tiled, tw, 4 + 20, 4), [100; 3]); // second tile
    assert_eq!(px(&tiled, tw, 4, 4 + 12), [200; 3]); // third tile, second row

    save_strip(dir.join("strip.png"), &refs, w, h, 3).unwrap();
    let strip = image::open(dir.join("strip.png")).unwrap();
    assert_eq!((strip.width(), strip.height()), (3 * 20 + 4, 16));

    save_gif(dir.join("anim.gif"), &refs, w, h, 100).unwrap();
    let gif = std::fs::read(dir.join("anim.gif")).unwrap();
    assert_eq!(&gif[..6], b"GIF89a");

    assert!(matches!(
        save_gif(dir.join("none.gif"), &[], w, h, 100),
        Err(DrawError::Empty)
    ));
    assert!(matches!(tile(&[], w, h, 2, 4), Err(DrawError::Empty)));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn success_and_precision_plots_draw_each_series_in_its_colour() {
    let dir = temp_dir("plots");
    let ious: Vec<f64> = (0..50).map(|i| i as f64 / 50.0).collect();
    let errors: Vec<f64> = (0..50).map(|i| i as f64).collect();
    let (s, p) = (success_curve(&ious), precision_curve(&errors, 50));
    let halves = |values: &[f64]| values.iter().map(|v| v / 2.0).collect::<Vec<_>>();
    let (orange, teal) = ([255, 128, 0], [0, 190, 210]);
    let series = |values: &[f64], halved: &[f64]| {
        [(values, orange), (halved, teal)].map(|(values, colour)| (values.to_vec(), colour))
    };
    let plots = [
        ("success.png", series(&s, &halves(&s))),
        ("precision.png", series(&p, &halves(&p))),
    ];
    for (file, curves) in &plots {
        let series = curves.each_ref().map(|(values, colour)| Series {
            label: "pf",
            values,
            colour: *colour,
        });
        let path = dir.join(file);
        if *file == "success.png" {
            success_plot(&path, "Success", &series).unwrap();
        } else {
            precision_plot(&path, "Precision", &series).unwrap();
        }
        let img = image::open(&path).unwrap().into_rgb8();
        assert_eq!(img.dimensions(), PLOT_SIZE);
        // Some dark pixels: axes and text were drawn.
        assert!(img.pixels().filter(|p| p.0.iter().all(|&c| c < 80)).count() > 500);
        for colour in [orange, teal] {
            let drawn = img.pixels().filter(|p| p.0 == colour).count();
            assert!(drawn > 300, "{file}: {drawn} px of {colour:?}");
        }
    }
    assert!(matches!(
        success_plot(dir.join("x.png"), "x", &[]),
        Err(DrawError::Empty)
    ));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn text_lines_on_a_frame() {
    let (w, h) = (160, 120);
    let mut rgb = vec![128u8; w * h * 3];
    let lines = [
        ("frame 12".to_string(), [255, 255, 255]),
        ("rbpf tracking 0.91".to_string(), [255, 200, 0]),
    ];
    draw_text_lines(&mut rgb, w as u32, h as u32, &lines).unwrap();
    let px = |x: usize, y: usize| &rgb[(y * w + x) * 3..(y * w + x) * 3 + 3];
    // The panel darkens the corner; text pixels in both colours appear on it.
    assert!(px(1, 1).iter().all(|&c| c < 100), "{:?}", px(1, 1));
    let panel = (0..30).flat_map(|y| (0..w).map(move |x| (x, y)));
    let yellow = panel
        .clone()
        .filter(|&(x, y)| px(x, y)[0] > 150 && px(x, y)[2] < 100)
        .count();
    let white = panel
        .filter(|&(x, y)| px(x, y).iter().all(|&c| c > 150))
        .count();
    assert!(yellow > 10 && white > 10, "yellow {yellow}, white {white}");
    // The rest of the frame is untouched.
    assert_eq!(px(w - 1, h - 1), [128, 128, 128]);
    assert!(matches!(
        draw_text_lines(&mut rgb[1..], w as u32, h as u32, &lines),
        Err(DrawError::Size { .. })
    ));
}
