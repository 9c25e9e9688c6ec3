//! The `rbtrack` command-line program: its arguments ([`args`]) and the work behind each
//! subcommand ([`demo`], [`track`], [`eval`], [`port()`], [`cost()`], [`follow()`], [`frames()`], [`paper()`]); `main.rs` only parses and
//! dispatches.
//!
//! Conventions:
//! - Boxes are 0-based in memory ([`crate::metrics`]). Ground-truth files, `--init`, box
//!   files (`--boxes`) and per-frame files (`--per-frame`) count pixels from 1 unless
//!   `--zero-based` (or, for `eval`, `--zero-based-sequences`) says otherwise
//!   ([`crate::sequence::GtOrigin`]); the convention is stated, never guessed.
//! - Timings are tracking only: time inside the core's `step` (decoding and format
//!   conversion excluded) over the frames after the first, divided by their number.
//! - Scores follow OTB: every frame with a valid ground-truth box counts, the first
//!   (initialisation) frame included.
//! - Reports go to the writer given (stdout); `wrote <path>` notes too, or to stderr when
//!   the report is JSON. A write to a closed stdout ends the command with
//!   [`Failure::Output`], which `main` treats as a normal end.

pub mod args;
mod cost;
mod demo;
mod eval;
mod follow;
mod frames;
mod input;
mod port;
mod report;
mod runs;
mod track;

pub use cost::cost;
pub use demo::demo;
pub use eval::eval;
pub use follow::follow;
pub use frames::frames;
pub use port::port;
pub use track::track;

use crate::cf64;
use crate::config_fields::Overrides;
use crate::draw::Rgb;
use crate::paper;
use crate::run::{CoreCf, RunError, CF_SHAPES};
use args::{ConfigArgs, PaperArgs};
use indicatif::{ProgressBar, ProgressStyle};
use rbtrack::tracker::{Config, Variant};
use serde::Serialize;
use std::fmt;
use std::io::{self, Write};
use std::path::Path;

/// Why a command stopped.
#[derive(Debug)]
pub enum Failure {
    /// A failure reported on one line: bad input data, an unwritable file...
    Message(String),
    /// Standard output could not be written, e.g. closed early by its reader.
    Output(io::Error),
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Message(m) => f.write_str(m),
            Self::Output(e) => write!(f, "cannot write to standard output: {e}"),
        }
    }
}

impl std::error::Error for Failure {}

/// A [`Failure::Message`] of anything displayable.
pub(crate) fn fail(e: impl fmt::Display) -> Failure {
    Failure::Message(e.to_string())
}

/// Writes `text` to the command's output.
pub(crate) fn emit(out: &mut dyn Write, text: &str) -> Result<(), Failure> {
    out.write_all(text.as_bytes()).map_err(Failure::Output)
}

/// Notes a file written: on `out`, or on stderr when `out` carries JSON.
pub(crate) fn wrote(out: &mut dyn Write, json: bool, what: &str) -> Result<(), Failure> {
    if json {
        eprintln!("wrote {what}");
        Ok(())
    } else {
        emit(out, &format!("wrote {what}\n"))
    }
}

/// Which tracker a run uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum TrackerKind {
    /// The Rao-Blackwellised particle filter.
    Rbpf,
    /// The colour particle filter.
    Pf,
    /// The f64 correlation-filter tracker (Staple class, [`crate::cf64`]).
    Cf64,
    /// The core's correlation-filter tracker, in integers.
    Cf,
}

impl TrackerKind {
    /// The tracker a run uses when neither `--tracker` nor the configuration's `variant`
    /// names one: the core's correlation-filter tracker (the README's pick).
    pub const DEFAULT: TrackerKind = TrackerKind::Cf;

    /// The core's two particle filters, in the order tables and plots list them.
    pub const ALL: [TrackerKind; 2] = [TrackerKind::Rbpf, TrackerKind::Pf];

    /// The core's three trackers, the default first.
    pub const CORE: [TrackerKind; 3] = [TrackerKind::Cf, TrackerKind::Rbpf, TrackerKind::Pf];

    /// Command-line name: `rbpf`, `pf`, `cf64` or `cf`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Rbpf => "rbpf",
            Self::Pf => "pf",
            Self::Cf64 => "cf64",
            Self::Cf => "cf",
        }
    }

    /// The core's variant, for the particle filters.
    pub fn variant(self) -> Option<Variant> {
        match self {
            Self::Rbpf => Some(Variant::Rbpf),
            Self::Pf => Some(Variant::ColourPf),
            Self::Cf64 | Self::Cf => None,
        }
    }

    /// The tracker running `variant`.
    pub fn of(variant: Variant) -> Self {
        match variant {
            Variant::Rbpf => Self::Rbpf,
            Variant::ColourPf => Self::Pf,
        }
    }

    /// Its colour in every picture: its estimates on frames, its curves in plots, the
    /// browser page's (`web/www/rbtrack.js`, `TRACKER_COLOURS`). cf orange, RBPF yellow,
    /// PF cyan, cf64 magenta: apart from the ground truth's green, and from red and blue,
    /// which would vanish on the synthetic target's red shirt and blue trousers; dark
    /// enough to read on a plot's white.
    pub fn colour(self) -> Rgb {
        match self {
            Self::Cf => [255, 128, 0],
            Self::Rbpf => [230, 185, 0],
            Self::Pf => [0, 190, 210],
            Self::Cf64 => [220, 0, 220],
        }
    }

    /// Name of [`TrackerKind::colour`].
    pub fn colour_name(self) -> &'static str {
        match self {
            Self::Rbpf => "yellow",
            Self::Pf => "cyan",
            Self::Cf64 => "magenta",
            Self::Cf => "orange",
        }
    }
}

impl fmt::Display for TrackerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The `--config` file's settings, then the `--set`s.
pub(crate) fn overrides(args: &ConfigArgs) -> Result<Overrides, Failure> {
    let mut settings = match &args.config {
        Some(path) => {
            crate::config_fields::read_toml(path).map_err(|e| fail(format!("--config {e}")))?
        }
        None => Vec::new(),
    };
    settings.extend(args.set.iter().cloned());
    Ok(Overrides(settings, args.preset))
}

/// Fails when `overrides` set a field that none of `trackers` reads (a particle filter's
/// setting for a correlation-filter tracker, or a `cf.` field for a particle filter).
pub(crate) fn check_read(overrides: &Overrides, trackers: &[TrackerKind]) -> Result<(), Failure> {
    let particle_filter: Vec<bool> = trackers.iter().map(|t| t.variant().is_some()).collect();
    match overrides.unread_by(&particle_filter) {
        Some(name) => {
            let names: Vec<&str> = trackers.iter().map(|t| t.name()).collect();
            Err(fail(format!(
                "`{name}` is not a setting of --tracker {}: particle-filter settings are \
                 FIELD=VALUE, the correlation-filter trackers' cf.FIELD=VALUE",
                names.join(",")
            )))
        }
        None => Ok(()),
    }
}

/// The configuration of `tracker` with `seed` under `overrides`, checked; the error names
/// the tracker and the field. The cf64 tracker takes only the seed of it (and its own
/// settings from [`cf64_for`]).
pub(crate) fn config_for(
    overrides: &Overrides,
    tracker: TrackerKind,
    seed: u64,
) -> Result<Config, Failure> {
    overrides
        .config(tracker.variant().unwrap_or(Variant::Rbpf), seed)
        .map_err(|e| fail(format!("{tracker}: {e}")))
}

/// The cf64 tracker's settings under `overrides` (its `cf.` fields), checked, for the cf64
/// tracker; `None` for the others.
pub(crate) fn cf64_for(
    overrides: &Overrides,
    tracker: TrackerKind,
) -> Result<Option<cf64::Params>, Failure> {
    match tracker {
        TrackerKind::Cf64 => overrides.cf_params().map(Some).map_err(fail),
        _ => Ok(None),
    }
}

/// The core correlation-filter tracker's settings under `overrides` (the `cf.` fields it
/// has, on its defaults), checked, for its runs; `None` for the others.
pub(crate) fn cf_for(
    overrides: &Overrides,
    tracker: TrackerKind,
) -> Result<Option<CoreCf>, Failure> {
    if tracker != TrackerKind::Cf {
        return Ok(None);
    }
    let set = |base| {
        overrides
            .cf_params_on(base)
            .map_err(|e| fail(format!("cf: {e}")))
    };
    // Set twice: the second time on the first's integer settings, so that the fields the
    // integer tracker derives from others (the colour samples' step from the cell) follow
    // them unless set too.
    let first = set(core_cf_params(&CoreCf::default()))?;
    let params = set(cf64::Params::of_core(
        &first.core_config(),
        first.grid,
        first.scales,
    ))?;
    let config = params.to_core().map_err(|e| fail(format!("cf: {e}")))?;
    let (grid, scales) = (params.grid, params.scales);
    if !CF_SHAPES.contains(&(grid, scales)) {
        return Err(fail(RunError::CfShape(grid, scales).to_string()));
    }
    Ok(Some(CoreCf {
        config,
        grid,
        scales,
    }))
}

/// The core correlation-filter tracker's settings as the f64 tracker's.
fn core_cf_params(cf: &CoreCf) -> cf64::Params {
    cf64::Params::of_core(&cf.config, cf.grid, cf.scales)
}

/// The tracker a configuration asks for (`variant`), if it names one.
pub(crate) fn configured_tracker(overrides: &Overrides) -> Option<TrackerKind> {
    overrides.value::<Variant>("variant").map(TrackerKind::of)
}

/// The seed a configuration asks for (`seed`), or 1.
pub(crate) fn configured_seed(overrides: &Overrides) -> u64 {
    overrides.value::<u64>("seed").unwrap_or(1)
}

/// A run's settings in JSON form: the correlation-filter trackers' where it runs one,
/// else the core's configuration.
pub(crate) fn settings_json(spec: &runs::RunSpec) -> serde_json::Value {
    match (&spec.cf64, &spec.cf) {
        (Some(params), _) => params.to_json(),
        (None, Some(cf)) => cf_json(cf),
        (None, None) => {
            serde_json::to_value(crate::config_fields::ConfigJson(&spec.config)).unwrap_or_default()
        }
    }
}

/// The core correlation-filter tracker's settings, numbers as decimals.
fn cf_json(cf: &CoreCf) -> serde_json::Value {
    let (c, q) = (&cf.config, |v: rbtrack::Q16| v.to_f64());
    serde_json::json!({
        "grid": cf.grid,
        "scales": cf.scales,
        "padding": q(c.padding),
        "cell": c.cell,
        "sigma": q(c.sigma),
        "lambda": f64::from(c.lambda) / f64::from(1u32 << 30),
        "cf_rate": q(c.cf_rate),
        "colour_rate": q(c.colour_rate),
        "inner_padding": q(c.inner_padding),
        "merge": q(c.merge),
        "scale_step": q(c.scale.step),
        "scale_sigma": q(c.scale.sigma),
        "scale_lambda": f64::from(c.scale.lambda) / 2f64.powi(32),
        "scale_area": c.scale.area,
        "scale_cell": c.scale.cell,
        "scale_interpolate": c.scale.interpolate,
        "scale_rate": q(c.scale_rate),
        "max_scale_change": q(c.max_scale_change),
        "learn_above": q(c.learn_above),
        "scale_above": q(c.scale_above),
        "uncertain_below": q(c.uncertain_below),
        "lost_below": q(c.lost_below),
        "search_below": q(c.search_below),
        "search_until": q(c.search_until),
        "redetect": c.redetect,
        "redetect_above": q(c.redetect_above),
        "redetect_colour": q(c.redetect_colour),
        "coast": c.coast,
        "lead": q(c.lead),
    })
}

/// The settings of a run that differ from its tracker's defaults, as `FIELD=VALUE`s, or
/// `defaults`.
pub(crate) fn config_summary(spec: &runs::RunSpec) -> String {
    let changed = match (&spec.cf64, &spec.cf) {
        (Some(params), _) => params.changed(),
        (None, Some(cf)) => core_cf_params(cf).changed_from(&core_cf_params(&CoreCf::default())),
        (None, None) => crate::config_fields::changed_fields(&spec.config),
    };
    if changed.is_empty() {
        "defaults".to_string()
    } else {
        changed.join(", ")
    }
}

/// A progress bar of `len` steps (a spinner when unknown) on stderr, hidden when stderr
/// is not a terminal.
pub(crate) fn progress_bar(len: Option<u64>, what: &str) -> ProgressBar {
    let (bar, template) = match len {
        Some(n) => (
            ProgressBar::new(n),
            "{prefix} [{bar:30}] {pos}/{len} frames, ETA {eta}",
        ),
        None => (
            ProgressBar::new_spinner(),
            "{prefix} {spinner} {pos} frames",
        ),
    };
    let style = ProgressStyle::with_template(template)
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("#>.");
    bar.set_style(style);
    bar.set_prefix(what.to_string());
    bar
}

/// Creates `dir` and its parents.
pub(crate) fn create_dir(dir: &Path) -> Result<(), Failure> {
    std::fs::create_dir_all(dir).map_err(|e| fail(format!("cannot create {}: {e}", dir.display())))
}

/// `rbtrack paper`: the study's table or JSON, and its figures with `--plots DIR`.
pub fn paper(args: &PaperArgs, out: &mut dyn Write) -> Result<(), Failure> {
    let params = paper::Params::STUDY;
    let study = paper::study(&params, args.runs, args.particles);
    if args.json {
        emit(out, &format!("{}\n", paper::json(&study, &params)))?;
    } else {
        emit(out, &paper::table(&study, &params))?;
    }
    if let Some(dir) = &args.plots {
        let files = paper::write_plots(&study, dir).map_err(|e| fail(format!("plots: {e}")))?;
        for f in files {
            eprintln!("wrote {}", f.display());
        }
    }
    Ok(())
}
