//! Per-cell features of an image patch: Felzenszwalb's HOG (fHOG, Felzenszwalb et al.,
//! PAMI 2010, as Dollár's toolbox computes it for Staple and DSST) and the cell's mean grey.
//!
//! fHOG, per pixel then per cell of `cell x cell` px:
//! - the gradient by central differences (one-sided at the patch's edge) of each colour
//!   channel, the channel of largest magnitude kept;
//! - its orientation hard-binned to the nearest of 18 signed bins of 20 degrees
//!   (`round(atan2(gy, gx) / 20 deg) mod 18`);
//! - its magnitude, over `cell^2`, spread bilinearly over the 4 nearest cells (the cell
//!   coordinate of pixel `p` is `(p + 0.5) / cell - 0.5`);
//! - each cell's energy, the sum of squares of its 9 unsigned bins (signed bins `o` and
//!   `o + 9` added); each 2x2 block of cells gives the normaliser `1 / sqrt(sum + eps)`,
//!   the block grid edge-replicated so that every cell lies in 4 blocks;
//! - per cell and normaliser `n`, the bins times `n` clipped at 0.2; the 18 signed and the
//!   9 unsigned channels are half the sum over the 4 normalisers, and texture channel `k`
//!   is 0.2357 times the sum of the 18 clipped signed bins under normaliser `k`.

use super::image::Patch;

/// Signed orientation bins.
const SIGNED: usize = 18;
/// Unsigned orientation bins.
const UNSIGNED: usize = 9;
/// Clip of a normalised bin.
const CLIP: f64 = 0.2;
/// Weight of the texture channels.
const TEXTURE_WEIGHT: f64 = 0.2357;

/// Which fHOG channels a feature map keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Hog {
    /// 18 signed, 9 unsigned and 4 texture channels.
    Fhog31,
    /// 18 signed and 9 unsigned (Staple's choice).
    Fhog27,
    /// 9 unsigned and 4 texture.
    Texture13,
    /// 9 unsigned.
    Unsigned9,
    /// None.
    Off,
}

impl Hog {
    /// Channels kept.
    pub fn channels(self) -> usize {
        match self {
            Self::Fhog31 => 31,
            Self::Fhog27 => 27,
            Self::Texture13 => 13,
            Self::Unsigned9 => 9,
            Self::Off => 0,
        }
    }

    /// The kept channels' indices into the 31 (signed, unsigned, texture).
    fn kept(self) -> std::ops::Range<usize> {
        match self {
            Self::Fhog31 => 0..31,
            Self::Fhog27 => 0..27,
            Self::Texture13 => 18..31,
            Self::Unsigned9 => 18..27,
            Self::Off => 0..0,
        }
    }

    /// By name: `31`, `27`, `13`, `9` or `off`.
    pub fn parse(text: &str) -> Result<Self, String> {
        match text {
            "31" => Ok(Self::Fhog31),
            "27" => Ok(Self::Fhog27),
            "13" => Ok(Self::Texture13),
            "9" => Ok(Self::Unsigned9),
            "off" | "0" => Ok(Self::Off),
            _ => Err(format!("{text:?}: expected 31, 27, 13, 9 or off")),
        }
    }

    /// The name [`Hog::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Self::Fhog31 => "31",
            Self::Fhog27 => "27",
            Self::Texture13 => "13",
            Self::Unsigned9 => "9",
            Self::Off => "off",
        }
    }
}

/// How a pixel's gradient magnitude is measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Magnitude {
    /// `sqrt(gx^2 + gy^2)`.
    #[default]
    Euclidean,
    /// `max(|gx|, |gy|) + min(|gx|, |gy|) / 2`: within -11.8 % and +11.8 % of the root.
    MaxHalfMin,
    /// `|gx| + |gy|`.
    Sum,
    /// `max(|gx|, |gy|) + 3/8 min(|gx|, |gy|)`, the `3/8 min` floored to the core's
    /// 1/512 of a grey level: within -7.9 % and +6.8 % of the root.
    Octagon,
}

/// How a pixel's magnitude is shared between cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Spread {
    /// Bilinearly over the 4 nearest cells (cell coordinate `(p + 1/2) / cell - 1/2`).
    #[default]
    Bilinear,
    /// All to the cell the pixel lies in.
    Nearest,
    /// By the half of its cell it lies in, each way: 3/4 to its cell and 1/4 to the
    /// neighbour on that side (the mean of the bilinear weights over the half); a middle
    /// pixel of an odd cell all to its cell.
    Halves,
}

/// The per-pixel part of fHOG's definition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Gradients {
    /// Magnitude of a pixel's gradient.
    pub magnitude: Magnitude,
    /// Its share of the cells.
    pub spread: Spread,
}

impl Gradients {
    /// The core's definition (`rbtrack::cf::features`): the root magnitude shared by
    /// half-cells, one update a pixel for each of 4 cells at fixed weights.
    pub const CORE: Self = Self {
        magnitude: Magnitude::Euclidean,
        spread: Spread::Halves,
    };
}

impl Magnitude {
    /// By name: `euclidean`, `maxhalfmin`, `sum` or `octagon`.
    pub fn parse(text: &str) -> Result<Self, String> {
        match text {
            "euclidean" => Ok(Self::Euclidean),
            "maxhalfmin" => Ok(Self::MaxHalfMin),
            "sum" => Ok(Self::Sum),
            "octagon" => Ok(Self::Octagon),
            _ => Err(format!(
                "{text:?}: expected euclidean, maxhalfmin, sum or octagon"
            )),
        }
    }

    /// The name [`Magnitude::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Self::Euclidean => "euclidean",
            Self::MaxHalfMin => "maxhalfmin",
            Self::Sum => "sum",
            Self::Octagon => "octagon",
        }
    }

    /// The magnitude of gradient `(gx, gy)`.
    pub fn of(self, gx: f64, gy: f64) -> f64 {
        let (a, b) = (gx.abs(), gy.abs());
        match self {
            Self::Euclidean => (gx * gx + gy * gy).sqrt(),
            Self::MaxHalfMin => a.max(b) + 0.5 * a.min(b),
            Self::Sum => a + b,
            Self::Octagon => a.max(b) + (3.0 * a.min(b) * 512.0 / 8.0).floor() / 512.0,
        }
    }
}

impl Spread {
    /// By name: `bilinear`, `nearest` or `halves`.
    pub fn parse(text: &str) -> Result<Self, String> {
        match text {
            "bilinear" => Ok(Self::Bilinear),
            "nearest" => Ok(Self::Nearest),
            "halves" => Ok(Self::Halves),
            _ => Err(format!("{text:?}: expected bilinear, nearest or halves")),
        }
    }

    /// The name [`Spread::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Self::Bilinear => "bilinear",
            Self::Nearest => "nearest",
            Self::Halves => "halves",
        }
    }

    /// Pixel `p`'s two cells along an axis of `cells` cells of `cell` px and their
    /// weights (a cell outside the grid as cell 0 weighing 0).
    fn split(self, p: usize, cell: usize, cells: usize) -> [(usize, f64); 2] {
        let inside = |c: i64, w: f64| match c >= 0 && (c as usize) < cells {
            true => (c as usize, w),
            false => (0, 0.0),
        };
        let (k, j) = ((p / cell) as i64, p % cell);
        match self {
            Self::Bilinear => {
                let at = (p as f64 + 0.5) / cell as f64 - 0.5;
                let c0 = at.floor();
                let f = at - c0;
                [inside(c0 as i64, 1.0 - f), inside(c0 as i64 + 1, f)]
            }
            Self::Nearest => [inside(k, 1.0), (0, 0.0)],
            Self::Halves => match (2 * j + 1).cmp(&cell) {
                std::cmp::Ordering::Less => [inside(k, 0.75), inside(k - 1, 0.25)],
                std::cmp::Ordering::Greater => [inside(k, 0.75), inside(k + 1, 0.25)],
                std::cmp::Ordering::Equal => [inside(k, 1.0), (0, 0.0)],
            },
        }
    }
}

/// A stack of per-cell feature channels: `rows x cols` cells per channel.
#[derive(Clone, Debug, PartialEq)]
pub struct Features {
    /// Cells across.
    pub cols: usize,
    /// Cells down.
    pub rows: usize,
    /// Channels.
    pub channels: usize,
    /// Channel-major: `data[(c * rows + y) * cols + x]`.
    pub data: Vec<f64>,
}

impl Features {
    /// Cells per channel.
    pub fn cells(&self) -> usize {
        self.rows * self.cols
    }

    /// Channel `c`.
    pub fn channel(&self, c: usize) -> &[f64] {
        &self.data[c * self.cells()..(c + 1) * self.cells()]
    }

    /// Each channel times `window` (one value per cell).
    pub fn windowed(mut self, window: &[f64]) -> Self {
        let n = self.cells();
        for chunk in self.data.chunks_mut(n) {
            for (v, w) in chunk.iter_mut().zip(window) {
                *v *= w;
            }
        }
        self
    }
}

/// The features of `patch` in cells of `cell` px (`patch.width / cell` across, extra pixels
/// at the right and bottom ignored): the mean grey per cell (`/ 255 - 0.5`) first when
/// `grey`, then the `hog` channels.
pub fn features(
    patch: &Patch,
    cell: usize,
    hog: Hog,
    grey: bool,
    gradients: Gradients,
) -> Features {
    let (cols, rows) = (patch.width / cell, patch.height / cell);
    let mut data = Vec::with_capacity((usize::from(grey) + hog.channels()) * rows * cols);
    if grey {
        data.extend(grey_cells(patch, cell, cols, rows));
    }
    if hog != Hog::Off {
        let all = fhog(patch, cell, cols, rows, gradients);
        for c in hog.kept() {
            data.extend((0..rows * cols).map(|i| all[i * 31 + c]));
        }
    }
    Features {
        cols,
        rows,
        channels: data.len() / (rows * cols).max(1),
        data,
    }
}

/// Mean grey per cell, `/ 255 - 0.5`.
fn grey_cells(patch: &Patch, cell: usize, cols: usize, rows: usize) -> Vec<f64> {
    let grey = patch.grey();
    let mut out = vec![0.0; rows * cols];
    for (y, row) in out.chunks_mut(cols).enumerate() {
        for (x, v) in row.iter_mut().enumerate() {
            let mut sum = 0.0;
            for py in y * cell..(y + 1) * cell {
                for px in x * cell..(x + 1) * cell {
                    sum += grey[py * patch.width + px];
                }
            }
            *v = sum / (cell * cell) as f64 / 255.0 - 0.5;
        }
    }
    out
}

/// The gradient of the colour channel of largest magnitude: `(gx, gy)` per pixel.
fn gradient(patch: &Patch, x: usize, y: usize) -> (f64, f64) {
    let (w, h) = (patch.width, patch.height);
    let diff = |a: [f64; 3], b: [f64; 3], span: f64| [0, 1, 2].map(|c| (a[c] - b[c]) / span);
    let gx = match (x, w) {
        (_, 1) => [0.0; 3],
        (0, _) => diff(patch.at(1, y), patch.at(0, y), 1.0),
        (x, w) if x == w - 1 => diff(patch.at(x, y), patch.at(x - 1, y), 1.0),
        (x, _) => diff(patch.at(x + 1, y), patch.at(x - 1, y), 2.0),
    };
    let gy = match (y, h) {
        (_, 1) => [0.0; 3],
        (0, _) => diff(patch.at(x, 1), patch.at(x, 0), 1.0),
        (y, h) if y == h - 1 => diff(patch.at(x, y), patch.at(x, y - 1), 1.0),
        (y, _) => diff(patch.at(x, y + 1), patch.at(x, y - 1), 2.0),
    };
    let mut best = (0.0, 0.0);
    let mut best_m2 = -1.0;
    for c in 0..3 {
        let m2 = gx[c] * gx[c] + gy[c] * gy[c];
        if m2 > best_m2 {
            best_m2 = m2;
            best = (gx[c], gy[c]);
        }
    }
    best
}

/// The signed orientation bin of a gradient: nearest of 18 bins of 20 degrees
/// (`round(atan2(gy, gx) / 20 deg) mod 18`, a boundary going to the bin nearer 90 or 270
/// degrees, and those themselves to the bin above), with the
/// boundaries `10 + 20 k` degrees at the core's Q15 tangents
/// ([`rbtrack::cf::features::TANGENTS`]), so that both bin every gradient alike.
pub fn signed_bin(gx: f64, gy: f64) -> usize {
    // Folded into [0, 180): the lower half-plane is 9 bins on.
    let lower = gy < 0.0 || (gy == 0.0 && gx < 0.0);
    let (gx, gy) = if lower { (-gx, -gy) } else { (gx, gy) };
    let (ax, ay) = (gx.abs(), gy);
    // The first-quadrant boundaries the angle is at or past: mirrored, `9 -` those, so
    // that a tie goes to the bin nearer 90 degrees.
    let count = || {
        rbtrack::cf::features::TANGENTS
            .iter()
            .filter(|&&t| ay * 32768.0 >= f64::from(t) * ax)
            .count()
    };
    let passed = if gx > 0.0 {
        count()
    } else if gx == 0.0 {
        5
    } else {
        9 - count()
    };
    (passed + if lower { UNSIGNED } else { 0 }) % SIGNED
}

/// The 31 fHOG channels per cell: `out[cell * 31 + channel]`, cells row-major.
fn fhog(patch: &Patch, cell: usize, cols: usize, rows: usize, g: Gradients) -> Vec<f64> {
    // Orientation histograms, each pixel's magnitude shared over cells.
    let mut hist = vec![0.0; rows * cols * SIGNED];
    let scale = 1.0 / (cell * cell) as f64;
    for y in 0..rows * cell {
        let ys = g.spread.split(y, cell, rows);
        for x in 0..cols * cell {
            let (gx, gy) = gradient(patch, x, y);
            let m = g.magnitude.of(gx, gy) * scale;
            let o = signed_bin(gx, gy);
            for &(cy, wy) in &ys {
                for &(cx, wx) in &g.spread.split(x, cell, cols) {
                    hist[(cy * cols + cx) * SIGNED + o] += m * wy * wx;
                }
            }
        }
    }
    // Energy of the unsigned histogram per cell.
    let unsigned = |i: usize, o: usize| hist[i * SIGNED + o] + hist[i * SIGNED + o + UNSIGNED];
    let energy: Vec<f64> = (0..rows * cols)
        .map(|i| (0..UNSIGNED).map(|o| unsigned(i, o).powi(2)).sum())
        .collect();
    // Block normalisers on the edge-replicated (rows + 1) x (cols + 1) grid: block (by, bx)
    // covers cells by - 1..=by, bx - 1..=bx, clamped into the grid.
    let eps = 1e-4 / 4.0 / (cell as f64).powi(4);
    let cl = |v: i64, n: usize| v.clamp(0, (n as i64 - 2).max(0)) as usize;
    let norm = |by: usize, bx: usize| {
        let (y0, x0) = (cl(by as i64 - 1, rows), cl(bx as i64 - 1, cols));
        let (y1, x1) = ((y0 + 1).min(rows - 1), (x0 + 1).min(cols - 1));
        let e = energy[y0 * cols + x0]
            + energy[y1 * cols + x0]
            + energy[y0 * cols + x1]
            + energy[y1 * cols + x1];
        1.0 / (e + eps).sqrt()
    };
    let mut out = vec![0.0; rows * cols * 31];
    for y in 0..rows {
        for x in 0..cols {
            let i = y * cols + x;
            let f = &mut out[i * 31..(i + 1) * 31];
            let norms = [
                norm(y, x),
                norm(y + 1, x),
                norm(y, x + 1),
                norm(y + 1, x + 1),
            ];
            for (k, n) in norms.into_iter().enumerate() {
                let mut texture = 0.0;
                for o in 0..SIGNED {
                    let v = (hist[i * SIGNED + o] * n).min(CLIP);
                    f[o] += 0.5 * v;
                    texture += v;
                }
                for o in 0..UNSIGNED {
                    f[SIGNED + o] += 0.5 * (unsigned(i, o) * n).min(CLIP);
                }
                f[SIGNED + UNSIGNED + k] = TEXTURE_WEIGHT * texture;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `size x size` grey patch `128 + slope (x cos t + y sin t)`.
    fn ramp(size: usize, degrees: f64, slope: f64) -> Patch {
        let (s, c) = degrees.to_radians().sin_cos();
        let rgb = (0..size * size)
            .map(|i| {
                let (x, y) = ((i % size) as f64, (i / size) as f64);
                [128.0 + slope * (x * c + y * s); 3]
            })
            .collect();
        Patch {
            width: size,
            height: size,
            rgb,
        }
    }

    #[test]
    fn a_ramp_fills_its_orientation_bin_in_every_cell() {
        // A linear ramp has the same gradient everywhere: one signed bin per cell, whose
        // 2x2-block normalised value 0.5 clips to 0.2 under each of the 4 normalisers.
        for bin in 0..SIGNED {
            let f = features(
                &ramp(32, bin as f64 * 20.0, 2.0),
                4,
                Hog::Fhog31,
                false,
                Gradients::default(),
            );
            assert_eq!((f.cols, f.rows, f.channels), (8, 8, 31));
            for i in 0..f.cells() {
                for c in 0..31 {
                    let expected = if c == bin || c == SIGNED + bin % UNSIGNED {
                        0.4
                    } else if c >= SIGNED + UNSIGNED {
                        TEXTURE_WEIGHT * CLIP
                    } else {
                        0.0
                    };
                    let got = f.channel(c)[i];
                    assert!(
                        (got - expected).abs() < 1e-12,
                        "bin {bin} cell {i} channel {c}: {got}"
                    );
                }
            }
        }
    }

    #[test]
    fn orientation_bins_split_at_ten_degrees_off_their_centre() {
        assert_eq!(signed_bin(1.0, 0.0), 0);
        assert_eq!(signed_bin(0.0, 1.0), 5); // 90 degrees: 4.5 rounds up
        assert_eq!(signed_bin(-1.0, 0.0), 9);
        assert_eq!(signed_bin(0.0, -1.0), 14); // 270 degrees: 13.5 rounds up
        let at = |d: f64| signed_bin(d.to_radians().cos(), d.to_radians().sin());
        assert_eq!(at(9.9), 0);
        assert_eq!(at(10.1), 1);
        assert_eq!(at(355.0), 0);
        assert_eq!(at(345.0), 17);
    }

    #[test]
    fn orientation_bins_are_atan2_s_but_within_a_sliver_of_each_boundary() {
        // The Q15 tangents are within 3e-5 rad of 10 + 20 k degrees.
        let exact = |gx: f64, gy: f64| {
            let angle = gy.atan2(gx).rem_euclid(std::f64::consts::TAU);
            (angle * SIGNED as f64 / std::f64::consts::TAU + 0.5) as usize % SIGNED
        };
        let mut differ = 0;
        for i in 0..100_000 {
            let t = (i as f64 * 0.618_034).fract() * std::f64::consts::TAU;
            let (gx, gy) = (1e4 * t.cos(), 1e4 * t.sin());
            let off = (t.to_degrees() - 10.0)
                .rem_euclid(20.0)
                .min(20.0 - (t.to_degrees() - 10.0).rem_euclid(20.0));
            if signed_bin(gx, gy) != exact(gx, gy) {
                assert!(off < 0.002, "{} degrees", t.to_degrees());
                differ += 1;
            }
        }
        assert!(differ < 20, "{differ}");
    }

    #[test]
    fn a_step_edge_marks_only_the_cells_along_it() {
        // Dark left half, bright right half: the gradient points right (bin 0) on the two
        // pixel columns beside the edge, in cells 3 and 4 of each row (edge at x = 15.5).
        let rgb = (0..32 * 32)
            .map(|i| [if i % 32 < 16 { 20.0 } else { 220.0 }; 3])
            .collect();
        let patch = Patch {
            width: 32,
            height: 32,
            rgb,
        };
        let f = features(&patch, 4, Hog::Fhog31, false, Gradients::default());
        for y in 0..8 {
            for x in 0..8 {
                let i = y * 8 + x;
                let bin0 = f.channel(0)[i];
                if x == 3 || x == 4 {
                    assert!(bin0 > 0.3, "cell ({x}, {y}): {bin0}");
                } else {
                    assert_eq!(bin0, 0.0, "cell ({x}, {y})");
                }
                for c in 1..SIGNED {
                    assert_eq!(f.channel(c)[i], 0.0);
                }
            }
        }
        // Bright to dark is the opposite signed bin, the same unsigned one.
        let flipped = Patch {
            rgb: patch.rgb.iter().map(|p| p.map(|v| 240.0 - v)).collect(),
            ..patch
        };
        let g = features(&flipped, 4, Hog::Fhog31, false, Gradients::default());
        assert_eq!(g.channel(9), f.channel(0));
        assert_eq!(g.channel(SIGNED), f.channel(SIGNED));
    }

    #[test]
    fn channel_sets_select_from_the_31() {
        let patch = ramp(16, 40.0, 3.0);
        let all = features(&patch, 4, Hog::Fhog31, true, Gradients::default());
        assert_eq!(all.channels, 32);
        let cells = all.cells();
        for (hog, first) in [(Hog::Fhog27, 0), (Hog::Texture13, 18), (Hog::Unsigned9, 18)] {
            let f = features(&patch, 4, hog, false, Gradients::default());
            assert_eq!(f.channels, hog.channels());
            assert_eq!(
                f.data[..],
                all.data[(1 + first) * cells..(1 + first + hog.channels()) * cells]
            );
        }
        let grey = features(&patch, 4, Hog::Off, true, Gradients::default());
        assert_eq!(grey.data[..], all.data[..cells]);
    }

    #[test]
    fn grey_is_the_cell_mean_centred() {
        let rgb = (0..8 * 8)
            .map(|i| [if i % 8 < 4 { 0.0 } else { 255.0 }; 3])
            .collect();
        let patch = Patch {
            width: 8,
            height: 8,
            rgb,
        };
        let f = features(&patch, 4, Hog::Off, true, Gradients::default());
        assert_eq!(f.data, vec![-0.5, 0.5, -0.5, 0.5]);
    }
}
