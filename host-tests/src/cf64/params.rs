//! Every setting of the f64 correlation-filter tracker in one place, settable by name
//! (`rbtrack --set cf.grid=16`).

use super::fhog::{Gradients, Hog, Magnitude, Spread};
use super::image::Resample;
use crate::fields::{self, field_table, FieldValue};
use rbtrack::tracker::{calibration, CfConfig};
use serde_json::Value;

/// The tracker's settings. [`Params::default`] is the configuration the measurements in
/// docs/accuracy.md chose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Cells a side of the search region's square grid.
    pub grid: usize,
    /// Cell side, px of the resampled region.
    pub cell: usize,
    /// Context around the target: the search region is the target plus `padding` times
    /// the mean of its width and height, each way.
    pub padding: f64,
    /// fHOG channels of the translation filter.
    pub hog: Hog,
    /// A grey channel (the cell's mean) beside them.
    pub grey: bool,
    /// fHOG's measure of a pixel's gradient magnitude, in both filters.
    pub hog_magnitude: Magnitude,
    /// fHOG's share of a pixel's magnitude between cells, in both filters.
    pub hog_spread: Spread,
    /// fHOG gradients of the luma alone, not of the strongest colour channel: what a grey
    /// or YUV camera gives, and what the integer tracker reads.
    pub luma_gradient: bool,
    /// Resample the region bilinearly (2 x 2 source pixels an output pixel, as
    /// OpenCV's `INTER_LINEAR`), not by the mean of each output pixel's footprint where it
    /// shrinks: a bounded cost whatever the target's size.
    pub bilinear: bool,
    /// Width of the desired response: this share of the target's `sqrt(w h)`, in cells.
    pub sigma: f64,
    /// Regulariser of the translation filter.
    pub lambda: f64,
    /// Learning rate of the translation filter.
    pub cf_rate: f64,
    /// Bits per colour channel of the colour histograms (3: 8x8x8 bins).
    pub colour_bits: u32,
    /// The colour model reads one sample per `colour_step` patch px each way, the frame
    /// pixel nearest its centre.
    pub colour_step: usize,
    /// Learning rate of the colour histograms.
    pub colour_rate: f64,
    /// The object's histogram is taken this share of the target's mean side inside its box.
    pub inner_padding: f64,
    /// Weight of the colour response in the merged response, `0..=1`.
    pub merge: f64,
    /// Scales of the scale filter (0: the size stays the first box's).
    pub scales: usize,
    /// Ratio between neighbouring scales.
    pub scale_step: f64,
    /// Width of the scale filter's desired response, times `sqrt(scales)`, in scales.
    pub scale_sigma: f64,
    /// Learning rate of the scale filter.
    pub scale_rate: f64,
    /// Largest area of the scale filter's samples, px^2.
    pub scale_area: f64,
    /// fHOG cell of the scale filter's samples, px.
    pub scale_cell: usize,
    /// fHOG channels of the scale filter.
    pub scale_hog: Hog,
    /// Regulariser of the scale filter.
    pub scale_lambda: f64,
    /// Largest change of size in a frame, in scale steps.
    pub scale_limit: f64,
    /// Weigh the scale samples by a Hann window over the scales.
    pub scale_window: bool,
    /// Read the scale between samples: the top of the parabola through the response's
    /// peak and its neighbours.
    pub scale_interpolate: bool,
    /// Learn only from frames whose score is at least this: an occluder or a
    /// look-alike scores low and is not learnt.
    pub learn_above: f64,
    /// Change the size only on frames whose score is at least this.
    pub scale_above: f64,
    /// While searching, search where the target would be had it kept its velocity.
    pub coast: bool,
    /// The search is centred this share of the smoothed velocity ahead.
    pub lead: f64,
    /// Below this confidence the target is uncertain.
    pub uncertain_below: f64,
    /// Below this confidence it is lost; once lost, it stays lost while the search lasts,
    /// until the confidence reaches `uncertain_below`.
    pub lost_below: f64,
    /// Below this merged peak the target is searched for, until the peak reaches
    /// `search_until`.
    pub search_below: f64,
    /// The merged peak that ends a search.
    pub search_until: f64,
    /// Ring regions a search visits between two searches of the anchor's region, one
    /// region a frame besides the usual one, as the core's `search_offset` (0: no
    /// re-detection).
    pub redetect: usize,
    /// A region searched takes over when its merged peak is at least this...
    pub redetect_above: f64,
    /// ...and its colour response there at least this.
    pub redetect_colour: f64,
    /// Particles reading the merged response (0: its peak is the estimate).
    pub particles: usize,
    /// Their position noise, a share of the target's mean side, px.
    pub particle_noise: f64,
    /// Share of them moved to the merged response's peak each frame before weighing.
    pub particle_peak_share: f64,
    /// Sharpness of their weights, merged-response units.
    pub particle_tau: f64,
    /// Learn on a new patch and new scale samples at the new position and size (true, as
    /// Staple), or on the frame's detection patch and samples with the desired responses
    /// peaked where the target was found in them (false: half the feature work).
    pub fresh_patch: bool,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            grid: 32,
            cell: 4,
            padding: 1.0,
            hog: Hog::Fhog27,
            grey: true,
            hog_magnitude: Magnitude::Euclidean,
            hog_spread: Spread::Bilinear,
            luma_gradient: false,
            bilinear: false,
            sigma: 1.0 / 16.0,
            lambda: 1e-3,
            cf_rate: 0.01,
            colour_bits: 5,
            colour_step: 1,
            colour_rate: 0.04,
            inner_padding: 0.2,
            merge: 0.3,
            scales: 33,
            scale_step: 1.02,
            scale_sigma: 0.25,
            scale_rate: 0.025,
            scale_area: 512.0,
            scale_cell: 4,
            scale_hog: Hog::Fhog31,
            scale_lambda: 1e-3,
            scale_limit: 16.0,
            scale_window: true,
            scale_interpolate: false,
            learn_above: 0.2,
            scale_above: 0.0,
            coast: false,
            lead: 0.0,
            uncertain_below: calibration::UNCERTAIN_BELOW.to_f64(),
            lost_below: calibration::LOST_BELOW.to_f64(),
            search_below: CfConfig::default().search_below.to_f64(),
            search_until: CfConfig::default().search_until.to_f64(),
            redetect: 0,
            redetect_above: 0.3,
            redetect_colour: 0.5,
            particles: 0,
            particle_noise: 0.1,
            particle_peak_share: 0.25,
            particle_tau: 0.05,
            fresh_patch: true,
        }
    }
}

impl FieldValue for Magnitude {
    fn parse(text: &str) -> Result<Self, String> {
        Magnitude::parse(text)
    }
    fn to_json(&self) -> Value {
        Value::from(self.name())
    }
}

impl FieldValue for Spread {
    fn parse(text: &str) -> Result<Self, String> {
        Spread::parse(text)
    }
    fn to_json(&self) -> Value {
        Value::from(self.name())
    }
}

impl FieldValue for Hog {
    fn parse(text: &str) -> Result<Self, String> {
        Hog::parse(text)
    }
    fn to_json(&self) -> Value {
        Value::from(self.name())
    }
}

/// One setting of [`Params`]: its name and how to set and read it.
pub type Field = fields::Field<Params>;

impl Field {
    /// The setting called `name` (without `cf.`).
    pub fn named(name: &str) -> Option<&'static Field> {
        FIELDS.iter().find(|f| f.name == name)
    }
}

/// Every setting of [`Params`], in declaration order.
pub static FIELDS: &[Field] = field_table! {
    Params, "cf.";
    grid,
    cell,
    padding,
    hog,
    grey,
    hog_magnitude,
    hog_spread,
    luma_gradient,
    bilinear,
    sigma,
    lambda,
    cf_rate,
    colour_bits,
    colour_step,
    colour_rate,
    inner_padding,
    merge,
    scales,
    scale_step,
    scale_sigma,
    scale_rate,
    scale_area,
    scale_cell,
    scale_hog,
    scale_lambda,
    scale_limit,
    scale_window,
    scale_interpolate,
    learn_above,
    scale_above,
    coast,
    lead,
    uncertain_below,
    lost_below,
    search_below,
    search_until,
    redetect,
    redetect_above,
    redetect_colour,
    particles,
    particle_noise,
    particle_peak_share,
    particle_tau,
    fresh_patch,
};

impl Params {
    /// Checks every setting; the error names the first one out of its range.
    pub fn validate(&self) -> Result<(), String> {
        let check = |ok: bool, name: &str, range: &str| {
            if ok {
                Ok(())
            } else {
                Err(format!("`cf.{name}` must be {range}"))
            }
        };
        let rate = |v: f64| (0.0..=1.0).contains(&v);
        check((4..=256).contains(&self.grid), "grid", "in 4..=256")?;
        check((1..=16).contains(&self.cell), "cell", "in 1..=16")?;
        check(self.padding > 0.0, "padding", "above 0")?;
        check(self.hog != Hog::Off || self.grey, "hog", "on, or grey true")?;
        check(self.sigma > 0.0, "sigma", "above 0")?;
        check(self.lambda > 0.0, "lambda", "above 0")?;
        check(rate(self.cf_rate), "cf_rate", "in 0..=1")?;
        check(
            (1..=8).contains(&self.colour_bits),
            "colour_bits",
            "in 1..=8",
        )?;
        check(
            (1..=8).contains(&self.colour_step),
            "colour_step",
            "in 1..=8",
        )?;
        check(rate(self.colour_rate), "colour_rate", "in 0..=1")?;
        check(
            (0.0..1.0).contains(&self.inner_padding),
            "inner_padding",
            "in 0..1",
        )?;
        check(rate(self.merge), "merge", "in 0..=1")?;
        check(self.scales <= 129, "scales", "in 0..=129")?;
        check(self.scale_step > 1.0, "scale_step", "above 1")?;
        check(self.scale_sigma > 0.0, "scale_sigma", "above 0")?;
        check(rate(self.scale_rate), "scale_rate", "in 0..=1")?;
        check(self.scale_area >= 64.0, "scale_area", "at least 64")?;
        check(
            (1..=16).contains(&self.scale_cell),
            "scale_cell",
            "in 1..=16",
        )?;
        check(self.scale_hog != Hog::Off, "scale_hog", "on")?;
        check(self.scale_lambda > 0.0, "scale_lambda", "above 0")?;
        check(rate(self.uncertain_below), "uncertain_below", "in 0..=1")?;
        check(
            (0.0..=self.uncertain_below).contains(&self.lost_below),
            "lost_below",
            "in 0..=uncertain_below",
        )?;
        check(rate(self.search_until), "search_until", "in 0..=1")?;
        check(
            (0.0..=self.search_until).contains(&self.search_below),
            "search_below",
            "in 0..=search_until",
        )?;
        check(self.redetect <= 8, "redetect", "in 0..=8")?;
        check(self.particles <= 10_000, "particles", "in 0..=10000")?;
        check(self.particle_noise >= 0.0, "particle_noise", "at least 0")?;
        check(
            rate(self.particle_peak_share),
            "particle_peak_share",
            "in 0..=1",
        )?;
        check(self.particle_tau > 0.0, "particle_tau", "above 0")?;
        Ok(())
    }

    /// Every field by name, in JSON form.
    pub fn to_json(&self) -> Value {
        Value::Object(
            FIELDS
                .iter()
                .map(|f| (f.name.to_string(), f.get(self)))
                .collect(),
        )
    }

    /// The fields that differ from the defaults, as `cf.FIELD=VALUE`.
    pub fn changed(&self) -> Vec<String> {
        self.changed_from(&Params::default())
    }

    /// The fields that differ from `base`, as `cf.FIELD=VALUE`.
    pub fn changed_from(&self, base: &Params) -> Vec<String> {
        FIELDS
            .iter()
            .filter(|f| f.get(self) != f.get(base))
            .map(|f| match f.get(self) {
                Value::String(s) => format!("cf.{}={s}", f.name),
                v => format!("cf.{}={v}", f.name),
            })
            .collect()
    }
}

impl Params {
    /// fHOG's per-pixel definition.
    pub fn gradients(&self) -> Gradients {
        Gradients {
            magnitude: self.hog_magnitude,
            spread: self.hog_spread,
        }
    }

    /// How patches read the frame.
    pub fn resample(&self) -> Resample {
        match self.bilinear {
            true => Resample::Bilinear,
            false => Resample::Area,
        }
    }
    /// The f64 settings of the core's integer tracker configured by `c` on a `grid x grid`
    /// grid of cells and `scales` scales: its reference in the tests. The integer tracker
    /// resamples the frame's 8-bit luma bilinearly, reads its fHOG gradients (shared
    /// between cells by half-cells), the 9 unsigned channels and the
    /// mean grey, colours in 3 bits a channel (the core's 8x8x8
    /// bins) at 2 samples a cell each way, learns on the detection's patch and samples,
    /// and reads the scale between samples without a window over them; while lost it
    /// searches as the integer tracker does (`redetect`, `coast`).
    pub fn of_core(c: &rbtrack::tracker::CfConfig, grid: usize, scales: usize) -> Self {
        let q = |v: rbtrack::Q16| v.to_f64();
        let step = q(c.scale.step);
        Self {
            grid,
            cell: c.cell,
            padding: q(c.padding),
            hog: Hog::Unsigned9,
            grey: true,
            hog_magnitude: Gradients::CORE.magnitude,
            hog_spread: Gradients::CORE.spread,
            luma_gradient: true,
            bilinear: true,
            sigma: q(c.sigma),
            lambda: f64::from(c.lambda) / f64::from(1u32 << 30),
            cf_rate: q(c.cf_rate),
            colour_bits: 3,
            colour_step: c.cell / 2,
            colour_rate: q(c.colour_rate),
            inner_padding: q(c.inner_padding),
            merge: q(c.merge),
            scales,
            scale_step: step,
            scale_sigma: q(c.scale.sigma),
            scale_rate: q(c.scale_rate),
            scale_area: f64::from(c.scale.area),
            scale_cell: c.scale.cell,
            scale_hog: Hog::Unsigned9,
            scale_lambda: f64::from(c.scale.lambda) / 2f64.powi(32),
            scale_limit: q(c.max_scale_change).ln() / step.ln(),
            scale_window: false,
            scale_interpolate: c.scale.interpolate,
            learn_above: q(c.learn_above),
            scale_above: q(c.scale_above),
            uncertain_below: q(c.uncertain_below),
            lost_below: q(c.lost_below),
            search_below: q(c.search_below),
            search_until: q(c.search_until),
            redetect: c.redetect,
            redetect_above: q(c.redetect_above),
            redetect_colour: q(c.redetect_colour),
            coast: c.coast,
            lead: q(c.lead),
            fresh_patch: false,
            ..Self::default()
        }
    }

    /// The core integer tracker's configuration these settings describe, where they
    /// describe one: checked, and [`Params::of_core`] of it gives them back, each number
    /// within its fixed-point rounding. The error names the first setting out of its
    /// range, or the first the integer tracker does not have (or has fixed).
    pub fn to_core(&self) -> Result<rbtrack::tracker::CfConfig, String> {
        let config = self.core_config();
        config
            .validate()
            .map_err(|e| format!("the integer tracker's settings: {e}"))?;
        let back = Self::of_core(&config, self.grid, self.scales);
        let near = |a: &Value, b: &Value| match (a.as_f64(), b.as_f64()) {
            (Some(a), Some(b)) => (a - b).abs() <= 1e-4 * a.abs().max(b.abs()).max(1.0),
            _ => a == b,
        };
        match FIELDS.iter().find(|f| !near(&f.get(self), &f.get(&back))) {
            Some(f) => Err(format!(
                "`cf.{}` is {} in the integer tracker (--tracker cf)",
                f.name,
                f.get(&back)
            )),
            None => Ok(config),
        }
    }

    /// The core integer tracker's settings nearest these, unchecked: the fields it has,
    /// rounded to its fixed point.
    pub fn core_config(&self) -> rbtrack::tracker::CfConfig {
        use rbtrack::cf::scale::ScaleSettings;
        let q = rbtrack::Q16::from_f64;
        let whole = |v: f64| v.round().clamp(0.0, f64::from(u32::MAX)) as u32;
        rbtrack::tracker::CfConfig {
            padding: q(self.padding),
            cell: self.cell,
            sigma: q(self.sigma),
            lambda: whole(self.lambda * f64::from(1u32 << 30)),
            cf_rate: q(self.cf_rate),
            colour_rate: q(self.colour_rate),
            inner_padding: q(self.inner_padding),
            merge: q(self.merge),
            scale: ScaleSettings {
                step: q(self.scale_step),
                sigma: q(self.scale_sigma),
                lambda: whole(self.scale_lambda * 2f64.powi(32)),
                area: whole(self.scale_area),
                cell: self.scale_cell,
                interpolate: self.scale_interpolate,
            },
            scale_rate: q(self.scale_rate),
            max_scale_change: q(self.scale_step.powf(self.scale_limit)),
            learn_above: q(self.learn_above),
            scale_above: q(self.scale_above),
            uncertain_below: q(self.uncertain_below),
            lost_below: q(self.lost_below),
            search_below: q(self.search_below),
            search_until: q(self.search_until),
            redetect: self.redetect,
            redetect_above: q(self.redetect_above),
            redetect_colour: q(self.redetect_colour),
            coast: self.coast,
            lead: q(self.lead),
        }
    }
}
