//! Pictures of what a tracker did: boxes and ellipses drawn on RGB888 frames, image strips
//! (PNG), animated GIFs, and success / precision plots (PNG).
//!
//! Frames are RGB888, `width * height * 3` bytes, stride `width * 3`. Drawing clips to the
//! frame and ignores a buffer too short for its stated size (nothing is drawn out of
//! bounds, nothing panics). Ground truth is drawn in [`GREEN`]; each tracker in its own
//! colour (the caller's: `TrackerKind::colour`), curves that are no tracker's in the
//! colours of [`PALETTE`].
//!
//! Plots are drawn with `plotters` on an in-memory bitmap; text uses `ab_glyph` with the
//! Noto Sans Regular font embedded from the `ttf-noto-sans` crate, so no system font or
//! fontconfig is needed.

use crate::metrics::{BBox, PRECISION_PX};
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// An RGB888 colour.
pub type Rgb = [u8; 3];

/// Ground-truth colour.
pub const GREEN: Rgb = [0, 220, 0];
/// Colours of curves that are no tracker's (one per sequence, say), in order of use: none
/// near a tracker's colour.
pub const PALETTE: [Rgb; 6] = [
    [31, 119, 180],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [127, 127, 127],
];

/// The `i`-th colour of [`PALETTE`] (cycling).
pub fn palette(i: usize) -> Rgb {
    PALETTE[i % PALETTE.len()]
}

/// Why a picture could not be made or written.
#[derive(Debug)]
pub enum DrawError {
    /// A frame buffer does not hold `width * height * 3` bytes, or the size is zero.
    Size {
        /// Bytes expected.
        expected: usize,
        /// Bytes given.
        found: usize,
    },
    /// Nothing to draw (no frames, no series).
    Empty,
    /// Encoding or writing the file failed.
    Write {
        /// The output file.
        path: PathBuf,
        /// The encoder's or the file system's message.
        message: String,
    },
    /// The plotting library failed.
    Plot(String),
}

impl fmt::Display for DrawError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Size { expected, found } => {
                write!(f, "frame buffer holds {found} bytes, expected {expected}")
            }
            Self::Empty => write!(f, "nothing to draw"),
            Self::Write { path, message } => {
                write!(f, "cannot write {}: {message}", path.display())
            }
            Self::Plot(m) => write!(f, "plotting failed: {m}"),
        }
    }
}

impl std::error::Error for DrawError {}

fn check(rgb: &[u8], width: u32, height: u32) -> Result<(), DrawError> {
    let expected = width as usize * height as usize * 3;
    if expected == 0 || rgb.len() != expected {
        return Err(DrawError::Size {
            expected,
            found: rgb.len(),
        });
    }
    Ok(())
}

/// Sets pixel `(x, y)` if it lies in the frame and the buffer.
fn put(rgb: &mut [u8], width: u32, height: u32, x: i64, y: i64, c: Rgb) {
    if x < 0 || y < 0 || x >= width as i64 || y >= height as i64 {
        return;
    }
    let i = (y as usize * width as usize + x as usize) * 3;
    if let Some(p) = rgb.get_mut(i..i + 3) {
        p.copy_from_slice(&c);
    }
}

/// Fills the square of side `thickness` px centred near `(x, y)`.
fn dot(rgb: &mut [u8], width: u32, height: u32, x: i64, y: i64, c: Rgb, thickness: u32) {
    let t = thickness.max(1) as i64;
    let lo = -(t - 1) / 2;
    for dy in lo..lo + t {
        for dx in lo..lo + t {
            put(rgb, width, height, x + dx, y + dy, c);
        }
    }
}

/// Outlines `b` (0-based px; covers columns `x..x+w-1`) with lines `thickness` px wide,
/// drawn inward from the box edge. Non-finite boxes are ignored.
pub fn draw_box(rgb: &mut [u8], width: u32, height: u32, b: &BBox, colour: Rgb, thickness: u32) {
    if !(b.x.is_finite() && b.y.is_finite() && b.w.is_finite() && b.h.is_finite()) {
        return;
    }
    let clamp = |v: f64| v.round().clamp(-1.0e6, 1.0e6) as i64;
    let (x0, y0) = (clamp(b.x), clamp(b.y));
    let (x1, y1) = (clamp(b.x + b.w) - 1, clamp(b.y + b.h) - 1);
    let t = thickness.max(1) as i64;
    let (cx0, cx1) = (x0.max(-t), x1.min(width as i64 + t));
    let (cy0, cy1) = (y0.max(-t), y1.min(height as i64 + t));
    for k in 0..t {
        for x in cx0..=cx1 {
            put(rgb, width, height, x, y0 + k, colour);
            put(rgb, width, height, x, y1 - k, colour);
        }
        for y in cy0..=cy1 {
            put(rgb, width, height, x0 + k, y, colour);
            put(rgb, width, height, x1 - k, y, colour);
        }
    }
}

/// Outlines the ellipse with centre `(cx, cy)` and half-axes `(hx, hy)`, px, with a line
/// `thickness` px wide. Non-finite or huge ellipses are ignored.
#[allow(clippy::too_many_arguments)]
pub fn draw_ellipse(
    rgb: &mut [u8],
    width: u32,
    height: u32,
    (cx, cy, hx, hy): (f64, f64, f64, f64),
    colour: Rgb,
    thickness: u32,
) {
    let (hx, hy) = (hx.abs(), hy.abs());
    if ![cx, cy, hx, hy]
        .iter()
        .all(|v| v.is_finite() && v.abs() < 1.0e5)
    {
        return;
    }
    let steps = ((hx.max(hy) * 8.0).ceil() as usize).clamp(16, 20_000);
    for s in 0..steps {
        let a = s as f64 / steps as f64 * std::f64::consts::TAU;
        let x = (cx + hx * a.cos()).round() as i64;
        let y = (cy + hy * a.sin()).round() as i64;
        dot(rgb, width, height, x, y, colour, thickness);
    }
}

/// Draws a small `+` of arm `arm` px at `(x, y)`, px.
pub fn draw_cross(
    rgb: &mut [u8],
    width: u32,
    height: u32,
    (x, y): (f64, f64),
    arm: u32,
    colour: Rgb,
) {
    if !(x.is_finite() && y.is_finite() && x.abs() < 1.0e6 && y.abs() < 1.0e6) {
        return;
    }
    let (x, y, a) = (x.round() as i64, y.round() as i64, arm as i64);
    for d in -a..=a {
        put(rgb, width, height, x + d, y, colour);
        put(rgb, width, height, x, y + d, colour);
    }
}

/// Writes `lines` of text (each in its colour) in the top-left corner of an RGB888 frame,
/// on a darkened panel; the font size follows the frame's height (at least 10 px). A
/// frame too small for the text shows what fits.
pub fn draw_text_lines(
    rgb: &mut [u8],
    width: u32,
    height: u32,
    lines: &[(String, Rgb)],
) -> Result<(), DrawError> {
    check(rgb, width, height)?;
    if lines.is_empty() {
        return Ok(());
    }
    register_fonts();
    let size = (height / 24).max(10);
    let perr = |e: &dyn fmt::Display| DrawError::Plot(e.to_string());
    let root = BitMapBackend::with_buffer(rgb, (width, height)).into_drawing_area();
    let font = ("sans-serif", size).into_font();
    let white = font.color(&WHITE);
    let pad = (size / 4).max(2) as i32;
    let line_height = size as i32 + pad;
    let text_width = lines
        .iter()
        .map(|(text, _)| root.estimate_text_size(text, &white).map_or(0, |(w, _)| w))
        .max()
        .unwrap_or(0) as i32;
    let panel = [
        (0, 0),
        (text_width + 2 * pad, lines.len() as i32 * line_height + pad),
    ];
    root.draw(&Rectangle::new(panel, BLACK.mix(0.55).filled()))
        .map_err(|e| perr(&e))?;
    for (k, (text, [r, g, b])) in lines.iter().enumerate() {
        let style = font.clone().color(&RGBColor(*r, *g, *b));
        root.draw_text(text, &style, (pad, pad + k as i32 * line_height))
            .map_err(|e| perr(&e))?;
    }
    root.present().map_err(|e| perr(&e))
}

/// Writes an RGB888 frame as PNG.
pub fn save_png(
    path: impl AsRef<Path>,
    rgb: &[u8],
    width: u32,
    height: u32,
) -> Result<(), DrawError> {
    check(rgb, width, height)?;
    let path = path.as_ref();
    image::save_buffer(path, rgb, width, height, image::ExtendedColorType::Rgb8).map_err(|e| {
        DrawError::Write {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    })
}

/// Tiles equally sized RGB888 frames left to right, `columns` per row, with a `gap` px
/// dark-grey border; returns the image and its `(width, height)`, px.
pub fn tile(
    frames: &[&[u8]],
    width: u32,
    height: u32,
    columns: usize,
    gap: u32,
) -> Result<(Vec<u8>, u32, u32), DrawError> {
    if frames.is_empty() {
        return Err(DrawError::Empty);
    }
    for f in frames {
        check(f, width, height)?;
    }
    let cols = columns.clamp(1, frames.len());
    let rows = frames.len().div_ceil(cols);
    let out_w = cols as u32 * (width + gap) + gap;
    let out_h = rows as u32 * (height + gap) + gap;
    let mut out = vec![40u8; out_w as usize * out_h as usize * 3];
    let row_bytes = width as usize * 3;
    for (k, f) in frames.iter().enumerate() {
        let ox = gap + (k % cols) as u32 * (width + gap);
        let oy = gap + (k / cols) as u32 * (height + gap);
        for y in 0..height as usize {
            let dst = ((oy as usize + y) * out_w as usize + ox as usize) * 3;
            out[dst..dst + row_bytes].copy_from_slice(&f[y * row_bytes..(y + 1) * row_bytes]);
        }
    }
    Ok((out, out_w, out_h))
}

/// Writes frames side by side (`columns` per row, 4 px gaps) as one PNG strip.
pub fn save_strip(
    path: impl AsRef<Path>,
    frames: &[&[u8]],
    width: u32,
    height: u32,
    columns: usize,
) -> Result<(), DrawError> {
    let (img, w, h) = tile(frames, width, height, columns, 4)?;
    save_png(path, &img, w, h)
}

/// Writes RGB888 frames as an animated GIF that loops forever, `delay_ms` per frame.
/// Colours are quantised per frame (NeuQuant, speed 10).
pub fn save_gif(
    path: impl AsRef<Path>,
    frames: &[&[u8]],
    width: u32,
    height: u32,
    delay_ms: u32,
) -> Result<(), DrawError> {
    use image::codecs::gif::{GifEncoder, Repeat};
    if frames.is_empty() {
        return Err(DrawError::Empty);
    }
    for f in frames {
        check(f, width, height)?;
    }
    let path = path.as_ref();
    let werr = |message: String| DrawError::Write {
        path: path.to_path_buf(),
        message,
    };
    let file = std::fs::File::create(path).map_err(|e| werr(e.to_string()))?;
    let mut enc = GifEncoder::new_with_speed(std::io::BufWriter::new(file), 10);
    enc.set_repeat(Repeat::Infinite)
        .map_err(|e| werr(e.to_string()))?;
    let delay = image::Delay::from_numer_denom_ms(delay_ms, 1);
    for f in frames {
        let rgba: Vec<u8> = f
            .chunks_exact(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect();
        let buf = image::RgbaImage::from_raw(width, height, rgba)
            .ok_or_else(|| werr("frame buffer size mismatch".into()))?;
        enc.encode_frame(image::Frame::from_parts(buf, 0, 0, delay))
            .map_err(|e| werr(e.to_string()))?;
    }
    Ok(())
}

/// One line of a plot: a label, its y values at evenly spaced x and its colour.
#[derive(Clone, Copy, Debug)]
pub struct Series<'a> {
    /// Legend text (the plot appends the summary figure).
    pub label: &'a str,
    /// Y values, in `[0, 1]`.
    pub values: &'a [f64],
    /// The line's colour.
    pub colour: Rgb,
}

/// Plot size, px.
pub const PLOT_SIZE: (u32, u32) = (640, 480);

static FONT: Once = Once::new();

/// Registers the embedded Noto Sans as `sans-serif` for plotters (once).
pub(crate) fn register_fonts() {
    FONT.call_once(|| {
        // Cannot fail for the embedded, valid font; a failure would only lose the text.
        let _ = register_font("sans-serif", FontStyle::Normal, ttf_noto_sans::REGULAR);
    });
}

/// Success plot (PNG): share of frames with IoU above each threshold, for thresholds
/// evenly spaced over `[0, 1]` (21 values per series, as [`crate::metrics::success_curve`]);
/// the legend shows each series' AUC.
pub fn success_plot(
    path: impl AsRef<Path>,
    title: &str,
    series: &[Series],
) -> Result<(), DrawError> {
    let legend = |s: &Series| {
        let auc = s.values.iter().sum::<f64>() / s.values.len().max(1) as f64;
        format!("{} [{auc:.3}]", s.label)
    };
    let axes = Axes {
        x_label: "overlap threshold (IoU)",
        x_decimals: 1,
        y_label: "success rate",
        x_max: 1.0,
        span: (0.0, 1.0),
        legend_at: SeriesLabelPosition::UpperRight,
    };
    line_plot(path.as_ref(), title, &axes, series, legend)
}

/// Precision plot (PNG): share of frames with centre error within each threshold, for
/// thresholds `0, 1, ..., n-1` px (51 values per series for `0..=50` px, as
/// [`crate::metrics::precision_curve`]); the legend shows precision at 20 px.
pub fn precision_plot(
    path: impl AsRef<Path>,
    title: &str,
    series: &[Series],
) -> Result<(), DrawError> {
    let max_x = series
        .iter()
        .map(|s| s.values.len().saturating_sub(1))
        .max()
        .unwrap_or(0)
        .max(1) as f64;
    let legend = |s: &Series| {
        let p = s.values.get(PRECISION_PX as usize).copied().unwrap_or(0.0);
        format!("{} [{p:.3}]", s.label)
    };
    let axes = Axes {
        x_label: "location error threshold (px)",
        x_decimals: 0,
        y_label: "precision",
        x_max: max_x,
        span: (0.0, max_x),
        legend_at: SeriesLabelPosition::LowerRight,
    };
    line_plot(path.as_ref(), title, &axes, series, legend)
}

/// Error plot (PNG): each series' value per frame (`x` from 0 to its length), in
/// `[0, 1]`, with `y_label` naming the quantity; the legend shows each series' mean.
pub fn error_plot(
    path: impl AsRef<Path>,
    title: &str,
    y_label: &'static str,
    series: &[Series],
) -> Result<(), DrawError> {
    let frames = series.iter().map(|s| s.values.len()).max().unwrap_or(0);
    let legend = |s: &Series| {
        let mean = s.values.iter().sum::<f64>() / s.values.len().max(1) as f64;
        format!("{} [mean {mean:.3}]", s.label)
    };
    let axes = Axes {
        x_label: "frame",
        x_decimals: 0,
        y_label,
        x_max: frames.saturating_sub(1).max(1) as f64,
        span: (0.0, frames.saturating_sub(1).max(1) as f64),
        legend_at: SeriesLabelPosition::UpperRight,
    };
    line_plot(path.as_ref(), title, &axes, series, legend)
}

/// Reliability diagram (PNG): per tenth of the confidence, the share of frames on the
/// target, at the tenths' midpoints (10 values per series; a NaN, an empty tenth, is left
/// out), beside the diagonal of a calibrated confidence; the legend shows each series'
/// largest distance from it.
pub fn reliability_plot(
    path: impl AsRef<Path>,
    title: &str,
    series: &[Series],
) -> Result<(), DrawError> {
    let midpoints: Vec<f64> = (0..10).map(|i| (i as f64 + 0.5) / 10.0).collect();
    let mut all = vec![Series {
        label: "calibrated",
        values: &midpoints,
        colour: [160, 160, 160],
    }];
    all.extend_from_slice(series);
    let legend = |s: &Series| {
        let worst = s
            .values
            .iter()
            .zip(&midpoints)
            .filter(|(v, _)| v.is_finite())
            .map(|(v, m)| (v - m).abs())
            .fold(0.0, f64::max);
        format!("{} [{worst:.3}]", s.label)
    };
    let axes = Axes {
        x_label: "confidence",
        x_decimals: 1,
        y_label: "share of frames on the target (IoU >= 0.5)",
        x_max: 1.0,
        span: (0.05, 0.95),
        legend_at: SeriesLabelPosition::UpperLeft,
    };
    line_plot(path.as_ref(), title, &axes, &all, legend)
}

struct Axes {
    x_label: &'static str,
    x_decimals: usize,
    y_label: &'static str,
    /// The x axis runs from 0 to this.
    x_max: f64,
    /// The x of a series' first and last values (the others evenly between).
    span: (f64, f64),
    legend_at: SeriesLabelPosition,
}

fn line_plot(
    path: &Path,
    title: &str,
    axes: &Axes,
    series: &[Series],
    legend: impl Fn(&Series) -> String,
) -> Result<(), DrawError> {
    if series.is_empty() || series.iter().all(|s| s.values.is_empty()) {
        return Err(DrawError::Empty);
    }
    register_fonts();
    let (w, h) = PLOT_SIZE;
    let mut buf = vec![255u8; w as usize * h as usize * 3];
    {
        let perr = |e: &dyn fmt::Display| DrawError::Plot(e.to_string());
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| perr(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..axes.x_max, 0.0..1.0)
            .map_err(|e| perr(&e))?;
        chart
            .configure_mesh()
            .x_desc(axes.x_label)
            .y_desc(axes.y_label)
            .x_label_formatter(&|v| format!("{v:.*}", axes.x_decimals))
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| perr(&e))?;
        for s in series {
            let [r, g, b] = s.colour;
            let colour = RGBColor(r, g, b);
            let (first, last) = axes.span;
            let step = if s.values.len() > 1 {
                (last - first) / (s.values.len() - 1) as f64
            } else {
                0.0
            };
            let points = s
                .values
                .iter()
                .enumerate()
                .filter(|(_, v)| v.is_finite())
                .map(|(k, &v)| (first + k as f64 * step, v.clamp(0.0, 1.0)));
            chart
                .draw_series(LineSeries::new(points, colour.stroke_width(2)))
                .map_err(|e| perr(&e))?
                .label(legend(s))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .position(axes.legend_at.clone())
            .draw()
            .map_err(|e| perr(&e))?;
        root.present().map_err(|e| perr(&e))?;
    }
    save_png(path, &buf, w, h)
}
