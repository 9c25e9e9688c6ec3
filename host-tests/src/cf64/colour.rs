//! The colour model: how likely each colour is to belong to the object rather than to its
//! surroundings (DAT, Possegger et al. 2015; Staple), and the colour response it gives.
//!
//! Two histograms over `2^bits` levels per R, G and B channel, each normalised by its
//! region's pixels: `O` of an object box (the target shrunk by the inner padding), `S` of
//! the surroundings (the patch outside the target box). A pixel of colour `u` is object
//! with probability `P(u) = O(u) / (O(u) + S(u))` (0 for a colour seen in neither). The
//! response at a place is the mean of `P` over a target-sized box there, read from an
//! integral image in four reads.

use super::image::Patch;

/// A box in patch px: pixel `(x, y)` is inside when `x0 <= x < x1`, `y0 <= y < y1` (pixel
/// indices, clamped to the patch).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    /// Left edge, px.
    pub x0: f64,
    /// Top edge, px.
    pub y0: f64,
    /// Right edge (exclusive), px.
    pub x1: f64,
    /// Bottom edge (exclusive), px.
    pub y1: f64,
}

impl Region {
    /// The same box at `1 / step` of the resolution.
    pub fn scaled(self, step: usize) -> Self {
        let k = step as f64;
        Self {
            x0: self.x0 / k,
            y0: self.y0 / k,
            x1: self.x1 / k,
            y1: self.y1 / k,
        }
    }

    /// The box of `size` px (width, height) centred on `centre` (px, in the continuous
    /// coordinates where pixel `k` covers `[k, k + 1)`).
    pub fn centred(centre: (f64, f64), size: (f64, f64)) -> Self {
        Self {
            x0: centre.0 - size.0 / 2.0,
            y0: centre.1 - size.1 / 2.0,
            x1: centre.0 + size.0 / 2.0,
            y1: centre.1 + size.1 / 2.0,
        }
    }

    /// Its pixel index ranges in a `width x height` patch: pixels whose centre
    /// (`k + 0.5`) lies inside, at least one each way.
    fn pixels(
        &self,
        width: usize,
        height: usize,
    ) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let range = |a: f64, b: f64, n: usize| {
            let lo = (a - 0.5).ceil().clamp(0.0, n as f64 - 1.0) as usize;
            let hi = ((b - 0.5).ceil().clamp(0.0, n as f64) as usize).max(lo + 1);
            lo..hi
        };
        (
            range(self.x0, self.x1, width),
            range(self.y0, self.y1, height),
        )
    }
}

/// Object and surroundings histograms.
#[derive(Clone, Debug, PartialEq)]
pub struct ColourModel {
    bits: u32,
    object: Vec<f64>,
    surroundings: Vec<f64>,
}

impl ColourModel {
    /// The model of `patch`: the object in `object`, the surroundings outside `target`;
    /// `bits` per channel (1..=8).
    pub fn new(patch: &Patch, object: Region, target: Region, bits: u32) -> Self {
        let (object, surroundings) = histograms(patch, object, target, bits);
        Self {
            bits,
            object,
            surroundings,
        }
    }

    /// Learns another patch's histograms at rate `eta`.
    pub fn learn(&mut self, patch: &Patch, object: Region, target: Region, eta: f64) {
        let (o, s) = histograms(patch, object, target, self.bits);
        for (a, b) in self.object.iter_mut().zip(o) {
            *a = (1.0 - eta) * *a + eta * b;
        }
        for (a, b) in self.surroundings.iter_mut().zip(s) {
            *a = (1.0 - eta) * *a + eta * b;
        }
    }

    /// `P(object | colour)` per pixel of `patch`, row-major.
    pub fn likelihood(&self, patch: &Patch) -> Vec<f64> {
        patch
            .rgb
            .iter()
            .map(|&p| {
                let u = bin(p, self.bits);
                let (o, s) = (self.object[u], self.surroundings[u]);
                if o + s > 0.0 {
                    o / (o + s)
                } else {
                    0.0
                }
            })
            .collect()
    }
}

/// The bin of a colour, `bits` of each channel.
fn bin(p: [f64; 3], bits: u32) -> usize {
    let level = |v: f64| (v.clamp(0.0, 255.0) as usize) >> (8 - bits);
    (level(p[0]) << (2 * bits)) | (level(p[1]) << bits) | level(p[2])
}

/// The object histogram (pixels in `object`) and the surroundings' (pixels outside
/// `target`), each summing to 1 (or all zero when its region is empty).
fn histograms(patch: &Patch, object: Region, target: Region, bits: u32) -> (Vec<f64>, Vec<f64>) {
    let bins = 1 << (3 * bits);
    let (mut o, mut s) = (vec![0.0; bins], vec![0.0; bins]);
    let (ox, oy) = object.pixels(patch.width, patch.height);
    let (tx, ty) = target.pixels(patch.width, patch.height);
    for y in 0..patch.height {
        for x in 0..patch.width {
            let u = bin(patch.at(x, y), bits);
            if ox.contains(&x) && oy.contains(&y) {
                o[u] += 1.0;
            }
            if !(tx.contains(&x) && ty.contains(&y)) {
                s[u] += 1.0;
            }
        }
    }
    for h in [&mut o, &mut s] {
        let total: f64 = h.iter().sum();
        if total > 0.0 {
            h.iter_mut().for_each(|v| *v /= total);
        }
    }
    (o, s)
}

/// Box sums over a `width x height` grid in four reads.
#[derive(Clone, Debug, PartialEq)]
pub struct Integral {
    width: usize,
    height: usize,
    /// `(width + 1) x (height + 1)` partial sums: `sums[y][x]` = sum over rows `< y`,
    /// columns `< x`.
    sums: Vec<f64>,
}

impl Integral {
    /// The integral image of `values` (`width x height`, row-major).
    pub fn new(values: &[f64], width: usize, height: usize) -> Self {
        let w1 = width + 1;
        let mut sums = vec![0.0; w1 * (height + 1)];
        for y in 0..height {
            let mut row = 0.0;
            for x in 0..width {
                row += values[y * width + x];
                sums[(y + 1) * w1 + x + 1] = sums[y * w1 + x + 1] + row;
            }
        }
        Self {
            width,
            height,
            sums,
        }
    }

    /// The mean over the pixels of `region` (clamped to the grid).
    pub fn mean(&self, region: Region) -> f64 {
        let (xs, ys) = region.pixels(self.width, self.height);
        let w1 = self.width + 1;
        let at = |y: usize, x: usize| self.sums[y * w1 + x];
        let sum = at(ys.end, xs.end) - at(ys.start, xs.end) - at(ys.end, xs.start)
            + at(ys.start, xs.start);
        sum / (xs.len() * ys.len()) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 20 x 20 patch: red square (px 5..15) on green, one blue pixel in the red.
    fn patch() -> Patch {
        let rgb = (0..400)
            .map(|i| {
                let (x, y) = (i % 20, i / 20);
                if (x, y) == (10, 10) {
                    [0.0, 0.0, 250.0]
                } else if (5..15).contains(&x) && (5..15).contains(&y) {
                    [250.0, 0.0, 0.0]
                } else {
                    [0.0, 250.0, 0.0]
                }
            })
            .collect();
        Patch {
            width: 20,
            height: 20,
            rgb,
        }
    }

    #[test]
    fn object_colours_score_one_and_surrounding_colours_zero() {
        let p = patch();
        let target = Region::centred((10.0, 10.0), (10.0, 10.0));
        let model = ColourModel::new(&p, target, target, 3);
        let l = model.likelihood(&p);
        assert_eq!(l[10 * 20 + 6], 1.0);
        assert_eq!(l[0], 0.0);
        assert_eq!(l[10 * 20 + 10], 1.0);
    }

    #[test]
    fn a_colour_in_both_scores_by_its_densities() {
        // The object box also covers one ring of green: 99 red, 1 blue, 44 green of 144
        // object px; 300 green of 300 surrounding px.
        let p = patch();
        let object = Region::centred((10.0, 10.0), (12.0, 12.0));
        let inner = Region::centred((10.0, 10.0), (10.0, 10.0));
        let model = ColourModel::new(&p, object, inner, 3);
        let green = model.likelihood(&p)[0];
        let (o, s) = (44.0 / 144.0, 1.0);
        assert!((green - o / (o + s)).abs() < 1e-12, "{green}");
    }

    #[test]
    fn box_means_read_from_the_integral_image() {
        let values: Vec<f64> = (0..12).map(f64::from).collect(); // 4 x 3
        let integral = Integral::new(&values, 4, 3);
        let all = Region::centred((2.0, 1.5), (4.0, 3.0));
        assert_eq!(integral.mean(all), 5.5);
        // Columns 1..=2, rows 1..=2: 5, 6, 9, 10.
        let inner = Region::centred((2.0, 2.0), (2.0, 2.0));
        assert_eq!(integral.mean(inner), 7.5);
    }

    #[test]
    fn learning_blends_the_histograms() {
        let p = patch();
        let target = Region::centred((10.0, 10.0), (10.0, 10.0));
        let mut model = ColourModel::new(&p, target, target, 3);
        let swapped = Patch {
            rgb: p.rgb.iter().map(|c| [c[1], c[0], c[2]]).collect(),
            ..p.clone()
        };
        model.learn(&swapped, target, target, 0.5);
        // Red is now half object (first patch), half surroundings (second).
        let red = model.likelihood(&p)[10 * 20 + 6];
        let (o, s) = (0.5 * 99.0 / 100.0, 0.5 * 300.0 / 300.0);
        assert!((red - o / (o + s)).abs() < 1e-12, "{red}");
    }
}
