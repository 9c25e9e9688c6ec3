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
pub fn features(patch: &Patch, cell: usize, hog: Hog, grey: bool) -> Features {
    let (cols, rows) = (patch.width / cell, patch.height / cell);
    let mut data = Vec::with_capacity((usize::from(grey) + hog.channels()) * rows * cols);
    if grey {
        data.extend(grey_cells(patch, cell, cols, rows));
    }
    if hog != Hog::Off {
        let all = fhog(patch, cell, cols, rows);
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

/// The signed orientation bin of a gradient: nearest of 18 bins of 20 degrees.
pub fn signed_bin(gx: f64, gy: f64) -> usize {
    let angle = gy.atan2(gx).rem_euclid(std::f64::consts::TAU);
    (angle * SIGNED as f64 / std::f64::consts::TAU + 0.5) as usize % SIGNED
}

/// The 31 fHOG channels per cell: `out[cell * 31 + channel]`, cells row-major.
fn fhog(patch: &Patch, cell: usize, cols: usize, rows: usize) -> Vec<f64> {
    // Orientation histograms, bilinear over cells.
    let mut hist = vec![0.0; rows * cols * SIGNED];
    let scale = 1.0 / (cell * cell) as f64;
    let split = |p: usize, cells: usize| {
        let at = (p as f64 + 0.5) / cell as f64 - 0.5;
        let c0 = at.floor();
        let f = at - c0;
        let c0 = c0 as i64;
        [(c0, 1.0 - f), (c0 + 1, f)].map(|(c, w)| {
            if c >= 0 && (c as usize) < cells {
                (c as usize, w)
            } else {
                (0, 0.0)
            }
        })
    };
    for y in 0..rows * cell {
        let ys = split(y, rows);
        for x in 0..cols * cell {
            let (gx, gy) = gradient(patch, x, y);
            let m = (gx * gx + gy * gy).sqrt() * scale;
            let o = signed_bin(gx, gy);
            for &(cy, wy) in &ys {
                for &(cx, wx) in &split(x, cols) {
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
            let f = features(&ramp(32, bin as f64 * 20.0, 2.0), 4, Hog::Fhog31, false);
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
        let f = features(&patch, 4, Hog::Fhog31, false);
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
        let g = features(&flipped, 4, Hog::Fhog31, false);
        assert_eq!(g.channel(9), f.channel(0));
        assert_eq!(g.channel(SIGNED), f.channel(SIGNED));
    }

    #[test]
    fn channel_sets_select_from_the_31() {
        let patch = ramp(16, 40.0, 3.0);
        let all = features(&patch, 4, Hog::Fhog31, true);
        assert_eq!(all.channels, 32);
        let cells = all.cells();
        for (hog, first) in [(Hog::Fhog27, 0), (Hog::Texture13, 18), (Hog::Unsigned9, 18)] {
            let f = features(&patch, 4, hog, false);
            assert_eq!(f.channels, hog.channels());
            assert_eq!(
                f.data[..],
                all.data[(1 + first) * cells..(1 + first + hog.channels()) * cells]
            );
        }
        let grey = features(&patch, 4, Hog::Off, true);
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
        let f = features(&patch, 4, Hog::Off, true);
        assert_eq!(f.data, vec![-0.5, 0.5, -0.5, 0.5]);
    }
}
