//! The tracker: per frame, where the target moved (the translation filter's response
//! merged with the colour response over the search region), how big it now is (the scale
//! filter), how sure that is, and the models' updates.

use super::colour::{ColourModel, Integral, Region};
use super::fft::C64;
use super::fhog::{features, Features};
use super::filter::{cosine_window, Filter};
use super::image::{Patch, RgbImage};
use super::params::Params;
use super::particles::Particles;
use super::scale::{ScaleFilter, ScaleParams};
use crate::metrics::BBox;
use rbtrack::fixed::Q16;
use rbtrack::tracker::search_offset;
use rbtrack::tracker::{calibration, Status};

/// Smallest target side, px.
const MIN_SIDE: f64 = 4.0;

/// Moves within this many cells of the merged response's peak, each way, lie in its lobe;
/// the margin is taken over those beyond.
pub const LOBE: usize = 2;

/// The tracker's answer for one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Output {
    /// The target's box, px (0-based).
    pub bbox: BBox,
    /// The move since the last frame, px (right, down).
    pub velocity: (f64, f64),
    /// The tracker's score, `0..=1`: the merged response's margin, its peak (the
    /// translation filter's answer and the colour score there weighed by `merge`) less the
    /// best value of the moves beyond the peak's lobe ([`LOBE`]).
    pub score: f64,
    /// The score through the core's correlation-filter table
    /// ([`rbtrack::tracker::calibration::CORRELATION`]), `0..=1`.
    pub confidence: f64,
    /// Tracking, uncertain or lost, by the confidence.
    pub status: Status,
}

/// The f64 correlation-filter tracker.
#[derive(Clone)]
pub struct Tracker {
    params: Params,
    frame_size: (f64, f64),
    /// Target centre, px (pixel centres at integer coordinates).
    centre: (f64, f64),
    /// Target size, px (width, height).
    size: (f64, f64),
    window: Vec<f64>,
    filter: Filter,
    colour: ColourModel,
    scale: Option<ScaleFilter>,
    /// The first box's size, px, and the bounds of the size factor on it.
    base: (f64, f64),
    factor_bounds: (f64, f64),
    last: Output,
    /// Frames in a row the target has been searched for.
    search_frames: usize,
    /// Where the target was last seen before a search, px.
    anchor: (f64, f64),
    /// Running mean of its moves, px a frame.
    velocity: (f64, f64),
    /// That velocity when the search began.
    lost_velocity: (f64, f64),
    /// Particles on the merged response, with `particles`.
    particles: Option<Particles>,
}

/// One search of a region: where the target is in it and how well it matches there.
struct Detection {
    geometry: Geometry,
    /// The region's colour samples.
    colours: Patch,
    /// The region's windowed features, transformed.
    spectra: Vec<C64>,
    /// The target's centre, px.
    found: (f64, f64),
    /// Its move from the region's centre, patch px.
    moved: (f64, f64),
    /// The merged response's peak.
    peak: f64,
    /// Its margin: the peak less the best value of the moves beyond its lobe, or the peak
    /// where the search has none.
    margin: f64,
    /// The colour response there.
    colour: f64,
    /// The merged response over the moves searched, `(2 reach.0 + 1) (2 reach.1 + 1)`
    /// cells, row-major.
    merged: Vec<f64>,
    /// The largest move searched, cells, across and down.
    reach: (i64, i64),
    /// The region's centre, px.
    centre: (f64, f64),
}

impl Detection {
    /// The merged response at `(x, y)` px, bilinear between cells; its least value outside
    /// the moves searched.
    fn map_at(&self, x: f64, y: f64, cell: f64) -> f64 {
        let side = (2 * self.reach.0 + 1) as usize;
        let rows = (2 * self.reach.1 + 1) as usize;
        let zoom = self.geometry.zoom();
        let u = (x - self.centre.0) * zoom.0 / cell + self.reach.0 as f64;
        let v = (y - self.centre.1) * zoom.1 / cell + self.reach.1 as f64;
        let (right, bottom) = ((side - 1) as f64, (rows - 1) as f64);
        if !(0.0..=right).contains(&u) || !(0.0..=bottom).contains(&v) {
            return self.merged.iter().copied().fold(f64::INFINITY, f64::min);
        }
        let (u0, v0) = (
            u.floor().min(right - 1.0).max(0.0),
            v.floor().min(bottom - 1.0).max(0.0),
        );
        let (fu, fv) = (u - u0, v - v0);
        let (i, j) = (u0 as usize, v0 as usize);
        let at = |a: usize, b: usize| self.merged[b.min(rows - 1) * side + a.min(side - 1)];
        (1.0 - fv) * ((1.0 - fu) * at(i, j) + fu * at(i + 1, j))
            + fv * ((1.0 - fu) * at(i, j + 1) + fu * at(i + 1, j + 1))
    }
}

/// Where the search region lies: its size in the frame, px, and how the resampled patch
/// maps to it.
#[derive(Clone, Copy, Debug)]
struct Geometry {
    /// Region size in the frame, px.
    region: (f64, f64),
    /// Patch side, px.
    side: usize,
    /// Target size in the patch, px.
    target: (f64, f64),
}

impl Geometry {
    fn new(params: &Params, size: (f64, f64)) -> Self {
        let pad = params.padding * (size.0 + size.1) / 2.0;
        let region = (size.0 + pad, size.1 + pad);
        let side = params.grid * params.cell;
        let s = side as f64;
        Self {
            region,
            side,
            target: (size.0 * s / region.0, size.1 * s / region.1),
        }
    }

    /// Patch px per frame px, per axis.
    fn zoom(&self) -> (f64, f64) {
        let s = self.side as f64;
        (s / self.region.0, s / self.region.1)
    }

    /// The target box in the patch, moved by `(dx, dy)` patch px.
    fn target_at(&self, dx: f64, dy: f64) -> Region {
        let c = self.side as f64 / 2.0;
        Region::centred((c + dx, c + dy), self.target)
    }

    /// The largest move the colour response can see, cells, across and down: the target
    /// box stays inside the patch.
    fn reach(&self, cell: usize) -> (i64, i64) {
        let s = self.side as f64;
        let room = |target: f64| (((s - target) / 2.0) / cell as f64).floor().max(0.0) as i64;
        (room(self.target.0), room(self.target.1))
    }
}

impl Tracker {
    /// Starts on `frame` with the target in `init` (0-based px); `seed` seeds the
    /// particles' draws.
    pub fn new(params: Params, frame: &RgbImage, init: &BBox, seed: u64) -> Result<Self, String> {
        params.validate()?;
        if !(init.is_valid() && init.w >= MIN_SIDE && init.h >= MIN_SIDE) {
            return Err(format!("initial box must be at least {MIN_SIDE} px a side"));
        }
        let centre = init.centre();
        let size = (init.w, init.h);
        let geometry = Geometry::new(&params, size);
        let window = cosine_window(params.grid, params.grid);
        let x = region_features(&params, frame, centre, &geometry).windowed(&window);
        let sigma =
            (geometry.target.0 * geometry.target.1).sqrt() * params.sigma / params.cell as f64;
        let filter = Filter::new(&x, sigma, params.lambda);
        let (object, target) = colour_regions(&params, &geometry, size, (0.0, 0.0));
        let colour = ColourModel::new(
            &colour_samples(&params, frame, centre, &geometry),
            object,
            target,
            params.colour_bits,
        );
        let scale = (params.scales > 0)
            .then(|| ScaleFilter::new(scale_params(&params), frame, centre, size));
        let frame_size = (frame.width as f64, frame.height as f64);
        let factor_bounds = (
            (MIN_SIDE / size.0).max(MIN_SIDE / size.1),
            (frame_size.0 / size.0).min(frame_size.1 / size.1).max(1.0),
        );
        Ok(Self {
            params,
            frame_size,
            centre,
            size,
            window,
            filter,
            colour,
            scale,
            base: size,
            factor_bounds,
            last: Output {
                bbox: *init,
                velocity: (0.0, 0.0),
                score: 1.0,
                confidence: calibrated(1.0),
                status: Status::Tracking,
            },
            search_frames: 0,
            anchor: centre,
            velocity: (0.0, 0.0),
            lost_velocity: (0.0, 0.0),
            particles: (params.particles > 0)
                .then(|| Particles::new(params.particles, centre, seed)),
        })
    }

    /// The last answer (the first box's before any step).
    pub fn last(&self) -> Output {
        self.last
    }

    /// The windowed features of the region of `geometry` around `centre`.
    fn features(&self, frame: &RgbImage, centre: (f64, f64), geometry: &Geometry) -> Features {
        region_features(&self.params, frame, centre, geometry).windowed(&self.window)
    }

    /// Searches the region around `centre` for the target at its current size.
    fn detect(&self, frame: &RgbImage, centre: (f64, f64)) -> Detection {
        let p = &self.params;
        let geometry = Geometry::new(p, self.size);
        let spectra = self
            .filter
            .spectra(&self.features(frame, centre, &geometry));
        let cf = self.filter.response(&spectra);
        let k = p.colour_step;
        let colours = colour_samples(p, frame, centre, &geometry);
        let likelihood = Integral::new(
            &self.colour.likelihood(&colours),
            colours.width,
            colours.height,
        );
        let g = p.grid;
        let most = g as i64 / 2 - 1;
        let (x, y) = geometry.reach(p.cell);
        let reach = (x.min(most), y.min(most));
        let cell = p.cell as f64;
        let cf_at = |dy: i64, dx: i64| {
            cf[dy.rem_euclid(g as i64) as usize * g + dx.rem_euclid(g as i64) as usize]
        };
        let colour_at = |dy: i64, dx: i64| {
            likelihood.mean(
                geometry
                    .target_at(dx as f64 * cell, dy as f64 * cell)
                    .scaled(k),
            )
        };
        let (side, rows) = ((2 * reach.0 + 1) as usize, (2 * reach.1 + 1) as usize);
        let mut merged = vec![0.0; side * rows];
        for dy in -reach.1..=reach.1 {
            for dx in -reach.0..=reach.0 {
                merged[(dy + reach.1) as usize * side + (dx + reach.0) as usize] =
                    (1.0 - p.merge) * cf_at(dy, dx) + p.merge * colour_at(dy, dx);
            }
        }
        let best = (0..merged.len())
            .max_by(|&a, &b| merged[a].total_cmp(&merged[b]))
            .unwrap_or(0);
        let (by, bx) = (best / side, best % side);
        let beyond = |i: usize| by.abs_diff(i / side) > LOBE || bx.abs_diff(i % side) > LOBE;
        let rival = (0..merged.len())
            .filter(|&i| beyond(i))
            .map(|i| merged[i])
            .reduce(f64::max)
            .unwrap_or(0.0);
        let fx = parabola_peak(bx, side, |x| merged[by * side + x]);
        let fy = parabola_peak(by, rows, |y| merged[y * side + bx]);
        let (dy, dx) = (by as i64 - reach.1, bx as i64 - reach.0);
        let zoom = geometry.zoom();
        let found = (
            (centre.0 + (dx as f64 + fx) * cell / zoom.0).clamp(0.0, self.frame_size.0 - 1.0),
            (centre.1 + (dy as f64 + fy) * cell / zoom.1).clamp(0.0, self.frame_size.1 - 1.0),
        );
        Detection {
            moved: ((found.0 - centre.0) * zoom.0, (found.1 - centre.1) * zoom.1),
            found,
            peak: merged[best],
            margin: merged[best] - rival,
            colour: colour_at(dy, dx),
            geometry,
            colours,
            spectra,
            merged,
            reach,
            centre,
        }
    }

    /// Tracks one frame.
    pub fn step(&mut self, frame: &RgbImage) -> Output {
        let p = self.params;
        let previous = self.centre;
        let searching = self.search_frames > 0;
        if searching && p.coast {
            // Where the target would be had it kept its velocity since the search began.
            self.anchor = (
                (self.anchor.0 + self.lost_velocity.0).clamp(0.0, self.frame_size.0 - 1.0),
                (self.anchor.1 + self.lost_velocity.1).clamp(0.0, self.frame_size.1 - 1.0),
            );
        }
        let predicted = match searching && p.coast {
            true => self.anchor,
            false => (
                self.centre.0 + p.lead * self.velocity.0,
                self.centre.1 + p.lead * self.velocity.1,
            ),
        };
        let predicted = match &mut self.particles {
            Some(particles) => {
                let sigma = p.particle_noise * (self.size.0 + self.size.1) / 2.0;
                particles.predict(sigma)
            }
            None => predicted,
        };
        let predicted = (
            predicted.0.clamp(0.0, self.frame_size.0 - 1.0),
            predicted.1.clamp(0.0, self.frame_size.1 - 1.0),
        );
        let usual = self.detect(frame, predicted);
        // A region other than the usual one that takes over only moves the target: nothing
        // is learnt this frame.
        let more = match searching {
            true => self.search_more(frame),
            false => None,
        };
        let (mut found, taken_over) = match more.filter(|d| d.peak > usual.peak) {
            Some(d) => (d, true),
            None => (usual, false),
        };
        self.centre = found.found;
        if let Some(particles) = &mut self.particles {
            let cell = p.cell as f64;
            let sigma = p.particle_noise * (self.size.0 + self.size.1) / 2.0;
            particles.propose(found.found, previous, p.particle_peak_share, sigma);
            let mean = particles.weigh(|x, y| found.map_at(x, y, cell), p.particle_tau);
            self.centre = (
                mean.0.clamp(0.0, self.frame_size.0 - 1.0),
                mean.1.clamp(0.0, self.frame_size.1 - 1.0),
            );
            let zoom = found.geometry.zoom();
            found.moved = (
                (self.centre.0 - found.centre.0) * zoom.0,
                (self.centre.1 - found.centre.1) * zoom.1,
            );
        }
        // The gates read the peak; the score, and so the confidence and the status, the
        // margin.
        let peak = found.peak.clamp(0.0, 1.0);
        let score = found.margin.clamp(0.0, 1.0);
        let confidence = calibrated(score);
        // A search begins below `search_below` and lasts until `search_until`; once lost,
        // the target stays lost while it lasts, until the confidence clears
        // `uncertain_below`.
        let still_searching = peak < p.search_below || (searching && peak < p.search_until);
        let held = still_searching && self.last.status == Status::Lost;
        let status = match confidence {
            c if c < p.lost_below || (held && c < p.uncertain_below) => Status::Lost,
            c if c < p.uncertain_below => Status::Uncertain,
            _ => Status::Tracking,
        };
        if still_searching {
            if self.search_frames == 0 {
                self.lost_velocity = self.velocity;
            }
            self.search_frames += 1;
        } else {
            self.search_frames = 0;
            self.anchor = self.centre;
        }

        // No scale samples on a search frame.
        let scales = self.scale.as_ref().filter(|_| !searching).map(|scale| {
            let z = scale.sample(frame, self.centre, self.size);
            let r = scale.response(&z);
            let i = (0..r.len())
                .max_by(|&a, &b| r[a].total_cmp(&r[b]))
                .unwrap_or(0);
            let between = match p.scale_interpolate {
                true => parabola_peak(i, r.len(), |k| r[k]),
                false => 0.0,
            };
            // Factors fall by `scale_step` per sample; a frame changes the size by at most
            // `scale_limit` of them.
            let factor = (scale.factors()[i] / p.scale_step.powf(between)).clamp(
                p.scale_step.powf(-p.scale_limit),
                p.scale_step.powf(p.scale_limit),
            );
            let f = (self.size.0 / self.base.0 * factor)
                .clamp(self.factor_bounds.0, self.factor_bounds.1);
            (z, i, f)
        });
        let old_size = self.size;
        if let Some((_, _, f)) = scales.as_ref().filter(|_| peak >= p.scale_above) {
            self.size = (self.base.0 * *f, self.base.1 * *f);
        }

        let learn = peak >= p.learn_above && !taken_over;
        if !learn {
            // Not sure enough of this frame to learn from it.
        } else if p.fresh_patch {
            self.learn_fresh(frame);
        } else {
            // The detection patch and samples, the target where it was found in them.
            let cell = p.cell as f64;
            let moved = found.moved;
            self.filter
                .learn(&found.spectra, (moved.1 / cell, moved.0 / cell), p.cf_rate);
            let (object, target) = colour_regions(&p, &found.geometry, old_size, moved);
            self.colour
                .learn(&found.colours, object, target, p.colour_rate);
            if let (Some(scale), Some((z, i, _))) = (&mut self.scale, &scales) {
                scale.learn(z, *i, p.scale_rate);
            }
        }
        let step = (self.centre.0 - previous.0, self.centre.1 - previous.1);
        self.velocity = (
            0.5 * (self.velocity.0 + step.0),
            0.5 * (self.velocity.1 + step.1),
        );
        let bbox = BBox::new(
            self.centre.0 - (self.size.0 - 1.0) / 2.0,
            self.centre.1 - (self.size.1 - 1.0) / 2.0,
            self.size.0,
            self.size.1,
        );
        self.last = Output {
            bbox,
            velocity: (self.centre.0 - previous.0, self.centre.1 - previous.1),
            score,
            confidence,
            status,
        };
        self.last
    }

    /// While searching: the region [`search_offset`] names for this frame of the search
    /// (none when `redetect` is 0), if its peak and colour score clear their thresholds.
    fn search_more(&self, frame: &RgbImage) -> Option<Detection> {
        let p = &self.params;
        let (ox, oy) = search_offset(self.search_frames - 1, p.redetect)?;
        let region = Geometry::new(p, self.size).region;
        let centre = (
            (self.anchor.0 + ox as f64 * region.0 / 2.0).clamp(0.0, self.frame_size.0 - 1.0),
            (self.anchor.1 + oy as f64 * region.1 / 2.0).clamp(0.0, self.frame_size.1 - 1.0),
        );
        let d = self.detect(frame, centre);
        (d.peak >= p.redetect_above && d.colour >= p.redetect_colour).then_some(d)
    }

    /// Learns the target on a new patch and new samples where it now is.
    fn learn_fresh(&mut self, frame: &RgbImage) {
        let p = self.params;
        let geometry = Geometry::new(&p, self.size);
        let x = self
            .filter
            .spectra(&self.features(frame, self.centre, &geometry));
        self.filter.learn(&x, (0.0, 0.0), p.cf_rate);
        let (object, target) = colour_regions(&p, &geometry, self.size, (0.0, 0.0));
        let colours = colour_samples(&p, frame, self.centre, &geometry);
        self.colour.learn(&colours, object, target, p.colour_rate);
        if let Some(scale) = &mut self.scale {
            let x = scale.sample(frame, self.centre, self.size);
            scale.learn(&x, scale.middle(), p.scale_rate);
        }
    }

    /// Moves the target with the picture: zoomed by `zoom` about `about` (px), then
    /// shifted by `shift` (px, right and down).
    pub fn camera_moved(&mut self, shift: (f64, f64), zoom: f64, about: (f64, f64)) {
        let moved = |c: f64, a: f64, d: f64| a + zoom * (c - a) + d;
        self.centre = (
            moved(self.centre.0, about.0, shift.0).clamp(0.0, self.frame_size.0 - 1.0),
            moved(self.centre.1, about.1, shift.1).clamp(0.0, self.frame_size.1 - 1.0),
        );
        self.anchor = (
            moved(self.anchor.0, about.0, shift.0).clamp(0.0, self.frame_size.0 - 1.0),
            moved(self.anchor.1, about.1, shift.1).clamp(0.0, self.frame_size.1 - 1.0),
        );
        if let Some(particles) = &mut self.particles {
            particles.shift(|x, y| (moved(x, about.0, shift.0), moved(y, about.1, shift.1)));
        }
        let f =
            (self.size.0 / self.base.0 * zoom).clamp(self.factor_bounds.0, self.factor_bounds.1);
        self.size = (self.base.0 * f, self.base.1 * f);
    }
}

/// The object's and the target's boxes in the patch, for a target of `size` px moved by
/// `moved` patch px from the patch's centre.
fn colour_regions(
    params: &Params,
    geometry: &Geometry,
    size: (f64, f64),
    moved: (f64, f64),
) -> (Region, Region) {
    let shrink = params.inner_padding * (size.0 + size.1) / 2.0;
    let zoom = geometry.zoom();
    let object = (
        ((size.0 - shrink) * zoom.0).max(1.0),
        ((size.1 - shrink) * zoom.1).max(1.0),
    );
    let c = geometry.side as f64 / 2.0;
    (
        Region::centred((c + moved.0, c + moved.1), object).scaled(params.colour_step),
        geometry
            .target_at(moved.0, moved.1)
            .scaled(params.colour_step),
    )
}

/// The offset in `-0.5..=0.5` of the top of the parabola through `value` at `at - 1`, `at`
/// and `at + 1` (of `0..n`), 0 at an edge or where the three do not curve down.
fn parabola_peak(at: usize, n: usize, value: impl Fn(usize) -> f64) -> f64 {
    if at == 0 || at + 1 >= n {
        return 0.0;
    }
    let (l, c, r) = (value(at - 1), value(at), value(at + 1));
    let curve = l - 2.0 * c + r;
    if curve < 0.0 {
        (0.5 * (l - r) / curve).clamp(-0.5, 0.5)
    } else {
        0.0
    }
}

/// The translation filter's features of the region of `geometry` around `centre`: of the
/// frame's 8-bit luma resampled to the patch with `luma_gradient` (the core's reading of a
/// frame), else of its colours.
fn region_features(
    params: &Params,
    frame: &RgbImage,
    centre: (f64, f64),
    geometry: &Geometry,
) -> Features {
    let p = params;
    let side = (geometry.side, geometry.side);
    let patch = match p.luma_gradient {
        true => frame.luma_patch(centre, geometry.region, side, p.resample()),
        false => frame.patch(centre, geometry.region, side, p.resample()),
    };
    features(&patch, p.cell, p.hog, p.grey, p.gradients())
}

/// The colour samples of the region of `geometry` around `centre`: `side / colour_step`
/// a side, each the frame pixel nearest its centre (as the core reads them).
fn colour_samples(
    params: &Params,
    frame: &RgbImage,
    centre: (f64, f64),
    geometry: &Geometry,
) -> Patch {
    let n = geometry.side.div_ceil(params.colour_step);
    frame.nearest(centre, geometry.region, (n, n))
}

pub(super) fn scale_params(params: &Params) -> ScaleParams {
    ScaleParams {
        scales: params.scales,
        step: params.scale_step,
        sigma: params.scale_sigma,
        area: params.scale_area,
        cell: params.scale_cell,
        hog: params.scale_hog,
        gradients: params.gradients(),
        lambda: params.scale_lambda,
        window: params.scale_window,
        luma: params.luma_gradient,
        resample: params.resample(),
    }
}

/// The confidence of `score` by the core's correlation-filter table (the reference
/// reports what the port reports).
fn calibrated(score: f64) -> f64 {
    calibration::CORRELATION
        .confidence(Q16::from_f64(score))
        .to_f64()
}
