//! The command line of `rbtrack` (clap, derive), and how its mistakes are reported:
//! a bad value on one line, an unknown option or a missing argument with the usage.

use super::input::RawLayout;
use super::runs::Start;
use super::TrackerKind;
use crate::config_fields::{Preset, Setting};
use crate::metrics::BBox;
use crate::pixels::Format;
use crate::run::{Bins, Shape, PARTICLE_COUNTS};
use crate::scene;
use crate::sequence::{self, GtOrigin};
use clap::error::ErrorKind;
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

/// Examples shown under `rbtrack --help`.
const EXAMPLES: &str = "Examples:
  rbtrack demo
  rbtrack track ../shared/data/Crossing --json
  rbtrack track clip.mp4 --init 120,80,30,60 --per-frame out/clip.csv --overlay out/clip
  rbtrack track dump.bin --raw 320x240:rgb565le --init 120,80,30,60
  rbtrack eval ../shared/data --tracker both --seeds 1,2,3 --set colour_sigma=0.15
  rbtrack eval ../shared/data --tracker both --seeds 1,2,3 --starts spatial
  rbtrack eval ../shared/data --tracker both --seeds 1,2,3 --camera pan-known
  rbtrack eval ../shared/data --tracker cf64 --starts spatial --set cf.grid=16
  rbtrack port ../shared/data ../valset --zero-based-sequences ball1_vot15
  rbtrack eval ../shared/data ../valset --tracker cf --starts spatial --zero-based-sequences ball1_vot15
  rbtrack follow ../shared/data/Woman
  rbtrack frames ../shared/data/Crossing out/Crossing.rgb
  rbtrack paper --runs 10";

/// `rbtrack`: the host tool of the rbtrack tracker core.
#[derive(Debug, Parser)]
#[command(
    name = "rbtrack",
    version,
    about = "Runs the rbtrack tracker core on synthetic scenes, image sequences, videos and \
             raw camera dumps, and scores it",
    after_help = EXAMPLES
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Track a built-in synthetic scene with both trackers: metrics table, image strip,
    /// animated GIF, success and precision plots
    #[command(allow_negative_numbers = true)]
    Demo(DemoArgs),
    /// Track one sequence: an image folder in OTB layout, a video file (read by ffmpeg)
    /// or a raw frame dump (--raw)
    #[command(allow_negative_numbers = true)]
    Track(TrackArgs),
    /// Track every sequence folder of each DATA_DIR, over one or more seeds: one row per
    /// sequence and tracker, the mean over sequences (with several folders: each folder's
    /// and the pooled mean), success and precision plots
    #[command(allow_negative_numbers = true)]
    Eval(EvalArgs),
    /// Check the port: the core's integer correlation-filter tracker (cf) and its f64
    /// reference (cf64 configured as the integer design) over every sequence of each
    /// DATA_DIR; per sequence, the first frame where they part, how their sizes compare
    /// before the reference loses the target, and both AUCs
    #[command(allow_negative_numbers = true)]
    Port(PortArgs),
    /// The cost model of the correlation-filter tracker: a configuration's Cortex-M4
    /// instructions a frame on the budget example's scene, stage by stage; or, given the
    /// budget example's output (cargo run --release --example budget --target
    /// thumbv7em-none-eabihf), each of its rows estimated against QEMU's count, failing
    /// where an estimate is off by more than 10 %
    Cost(CostArgs),
    /// Follow a target with a camera on a pan/tilt head, in closed loop: a virtual camera
    /// sees half of each frame where the head points, the colour PF tracks, the pan/tilt
    /// controller turns the head; centring figures, the camera's view and the error over
    /// time
    #[command(allow_negative_numbers = true)]
    Follow(FollowArgs),
    /// Decode one sequence folder's frames as track and eval do and write them as one
    /// raw RGB888 dump; prints WIDTHxHEIGHT:rgb888 and the frame count
    Frames(FramesArgs),
    /// The RBPF paper's simulation study (section 3.1): RBPF against PF, the dependency
    /// sweep S = 1..15 and the particle-count comparison
    #[command(allow_negative_numbers = true)]
    Paper(PaperArgs),
}

/// Options of `rbtrack follow`.
#[derive(Debug, Args)]
pub struct FollowArgs {
    /// Sequence folder (OTB layout, with ground truth) [default: the built-in synthetic
    /// scene]
    #[arg(value_name = "SEQUENCE_DIR")]
    pub sequence: Option<PathBuf>,
    /// Tracker
    #[arg(long, value_enum, value_name = "T", default_value = "cf")]
    pub tracker: TrackerKind,
    /// Seed of the tracker's random draws
    #[arg(long, value_name = "S", default_value = "1")]
    pub seed: u64,
    /// Configuration and particles.
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Box convention of the ground-truth file.
    #[command(flatten)]
    pub convention: Convention,
    /// Output folder (view.gif, strip.png, error.png)
    #[arg(long, value_name = "DIR", default_value = "out/follow")]
    pub out: PathBuf,
    /// Skip the animated GIF
    #[arg(long)]
    pub no_gif: bool,
    /// Print one JSON object instead of the text
    #[arg(long)]
    pub json: bool,
}

/// Options of `rbtrack frames`.
#[derive(Debug, Args)]
pub struct FramesArgs {
    /// Sequence folder (OTB layout: img/ with numbered JPEG or PNG frames)
    #[arg(value_name = "SEQUENCE_DIR")]
    pub sequence: PathBuf,
    /// The dump to write: RGB888 rows top to bottom, frames back to back
    #[arg(value_name = "OUT")]
    pub out: PathBuf,
}

/// Options of `rbtrack demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Output folder (strip.png, demo.gif, success.png, precision.png)
    #[arg(long, value_name = "DIR", default_value = "out/demo")]
    pub out: PathBuf,
    /// Scene: perspective, distractor, occlusion, brightness, fast or leave
    #[arg(long, value_name = "NAME", default_value = "perspective", value_parser = scene_named)]
    pub scene: scene::Variant,
    /// Scene length, 10..=1000 frames
    #[arg(long, value_name = "N", default_value = "100", value_parser = whole_in(10, 1000))]
    pub frames: usize,
    /// Skip the animated GIF
    #[arg(long)]
    pub no_gif: bool,
}

/// Tracker configuration and particle count, shared by `track` and `eval`.
#[derive(Debug, Args)]
pub struct ConfigArgs {
    /// Particles per tracker: 25, 50, 100, 200, 400 or 800
    #[arg(long, value_name = "N", default_value = "100", value_parser = particle_count)]
    pub particles: usize,
    /// Colour bins: rgb8x8x8 (512), rgb8x8x4 (256), yuv8x8x4 (256) or luma64 (64)
    #[arg(long, value_enum, value_name = "BINS", default_value = "rgb8x8x8")]
    pub bins: Bins,
    /// Set a field of the tracker's configuration (repeatable), e.g. colour_sigma=0.15,
    /// cue_mix=average:0.5, readout=robust_mean:8, resampling=systematic; `variant` and
    /// `seed` give the defaults of --tracker and --seed
    #[arg(long = "set", value_name = "FIELD=VALUE")]
    pub set: Vec<Setting>,
    /// TOML file of configuration fields (colour_sigma = 0.15, cue_mix = "product");
    /// --set wins over it
    #[arg(long = "config", value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// The configuration the file and --set apply to: default (the defaults), paper (the
    /// source papers' trackers, Config::paper) or core (cf64 as the core's integer
    /// correlation-filter tracker at its defaults: its f64 reference)
    #[arg(long, value_enum, value_name = "P", default_value = "default")]
    pub preset: Preset,
}

impl ConfigArgs {
    /// The trackers' particles and bins.
    pub fn shape(&self) -> Shape {
        Shape {
            particles: self.particles,
            bins: self.bins,
        }
    }
}

/// Which way box files count pixels.
#[derive(Clone, Copy, Debug, Args)]
#[group(multiple = false)]
pub struct Convention {
    /// Boxes (ground truth, --init, --boxes, --per-frame) count pixels from 0
    #[arg(long)]
    pub zero_based: bool,
    /// Boxes count pixels from 1, as OTB, UAV123, LaSOT and MOT files do (the default)
    #[arg(long)]
    pub one_based: bool,
}

impl Convention {
    /// The origin the flags state: 1-based unless `--zero-based`.
    pub fn origin(self) -> GtOrigin {
        if self.zero_based {
            GtOrigin::ZeroBased
        } else {
            GtOrigin::OneBased
        }
    }
}

/// Options of `rbtrack track`.
#[derive(Debug, Args)]
pub struct TrackArgs {
    /// A sequence folder (img/*.jpg|png, groundtruth_rect.txt), a video file ffmpeg reads,
    /// or a raw frame dump (with --raw)
    #[arg(value_name = "INPUT")]
    pub input: PathBuf,
    /// Tracker: rbpf (Rao-Blackwellised PF), pf (colour PF), cf (the correlation-filter
    /// tracker) or cf64 (its f64 reference) [default: cf, or the configuration's variant]
    #[arg(long, value_enum, value_name = "T")]
    pub tracker: Option<TrackerKind>,
    /// Seed of the tracker's random draws [default: 1, or the configuration's seed]
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// Configuration and particles.
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Pixel format decoded frames are converted to before tracking, as a camera would
    /// deliver them
    #[arg(long, value_enum, value_name = "F", default_value = "rgb888")]
    pub format: Format,
    /// INPUT is a raw dump: frames of WIDTHxHEIGHT px back to back in FORMAT (gray8,
    /// rgb565le, rgb565be, rgb888, yuyv, uyvy), handed to the tracker as they are
    #[arg(long, value_name = "WxH:FORMAT", conflicts_with = "format")]
    pub raw: Option<RawLayout>,
    /// Initial box instead of the first ground-truth line (in the box convention)
    #[arg(long, value_name = "x,y,w,h", value_parser = box_arg, allow_hyphen_values = true)]
    pub init: Option<BBox>,
    /// Ground-truth file (one x,y,w,h line per frame) [default: INPUT/groundtruth_rect.txt
    /// for a folder]
    #[arg(long, value_name = "FILE")]
    pub groundtruth: Option<PathBuf>,
    /// Box convention.
    #[command(flatten)]
    pub convention: Convention,
    /// Write the estimated box per frame, one x,y,w,h line each (the first: the initial
    /// box), in the box convention
    #[arg(long, value_name = "FILE")]
    pub boxes: Option<PathBuf>,
    /// Write a CSV row per frame: frame, box, ellipse, velocity, confidence, status
    #[arg(long = "per-frame", value_name = "FILE")]
    pub per_frame: Option<PathBuf>,
    /// Tell the tracker how the picture moved (a pan/tilt head's commands, an IMU): CSV
    /// lines frame,dx,dy[,zoom], the frame numbered from 1, the shift in px (the picture
    /// moving right and down is positive), the zoom about the frame's centre
    #[arg(long = "camera-motion", value_name = "FILE")]
    pub camera_motion: Option<PathBuf>,
    /// Write every frame as DIR/0001.png, ... with the estimate, its status and
    /// confidence, and the ground truth drawn
    #[arg(long, value_name = "DIR")]
    pub overlay: Option<PathBuf>,
    /// Print one JSON object (scores, settings, the configuration used)
    #[arg(long)]
    pub json: bool,
}

/// Trackers `eval` runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TrackerChoice {
    /// The Rao-Blackwellised PF.
    Rbpf,
    /// The colour PF.
    Pf,
    /// Both particle filters, over the same decoded frames.
    Both,
    /// The f64 correlation-filter tracker.
    Cf64,
    /// The core's correlation-filter tracker.
    Cf,
    /// The four, over the same decoded frames.
    All,
}

impl TrackerChoice {
    /// The trackers chosen.
    pub fn trackers(self) -> Vec<TrackerKind> {
        match self {
            Self::Rbpf => vec![TrackerKind::Rbpf],
            Self::Pf => vec![TrackerKind::Pf],
            Self::Both => TrackerKind::ALL.to_vec(),
            Self::Cf64 => vec![TrackerKind::Cf64],
            Self::Cf => vec![TrackerKind::Cf],
            Self::All => vec![
                TrackerKind::Rbpf,
                TrackerKind::Pf,
                TrackerKind::Cf64,
                TrackerKind::Cf,
            ],
        }
    }
}

/// The first boxes `eval` starts each sequence from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Starts {
    /// The first ground-truth box.
    Box,
    /// The box and six perturbed boxes ([`Start::SPATIAL`]).
    Spatial,
    /// Those and 14 more ([`Start::WIDE`]): 21 runs a sequence and seed.
    Wide,
}

impl Starts {
    /// The starts chosen.
    pub fn starts(self) -> &'static [Start] {
        match self {
            Self::Box => &Start::SPATIAL[..1],
            Self::Spatial => &Start::SPATIAL,
            Self::Wide => &Start::WIDE,
        }
    }
}

/// Options of `rbtrack eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Folders of sequence folders (OTB layout each); with several, all their sequences
    /// run together and the means are given per folder and pooled (each sequence weighing
    /// the same); a sequence name may be in one folder only
    #[arg(value_name = "DATA_DIR", required = true)]
    pub data: Vec<PathBuf>,
    /// Trackers: rbpf, pf, both (the particle filters), cf (the correlation-filter tracker),
    /// cf64 (its f64 reference) or all [default: cf, or the configuration's variant]
    #[arg(long, value_enum, value_name = "T")]
    pub tracker: Option<TrackerChoice>,
    /// Seed of the trackers' random draws [default: 1, or the configuration's seed]
    #[arg(long, value_name = "S", conflicts_with = "seeds")]
    pub seed: Option<u64>,
    /// Seeds, comma-separated (1,2,3): every tracker runs with each over the same decoded
    /// frames; the table shows means over the seeds and the AUC's range
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub seeds: Vec<u64>,
    /// First boxes: the ground truth's (box), or spatial: also shifted 2 px left, right,
    /// up and down and scaled by 0.95 and 1.05 about its centre (7 starts, every seed
    /// from each), or wide: those and 14 more (1 and 3 px shifts, 2 px diagonals, scales
    /// 0.9 and 1.1: 21 starts)
    #[arg(long, value_enum, value_name = "S", default_value = "box")]
    pub starts: Starts,
    /// A virtual camera over each sequence: still (a window 3/4 of the frame's width and
    /// height, centred on the first box as far as the frame allows), pan (the window
    /// sweeping back and forth, keeping the target in view, the tracker not told) or
    /// pan-known (the same sweep, the tracker told each frame's shift); ground truth moves
    /// with the window [default: the whole frame]
    #[arg(long, value_enum, value_name = "C")]
    pub camera: Option<crate::camera::Camera>,
    /// Configuration and particles.
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Pixel format decoded frames are converted to before tracking
    #[arg(long, value_enum, value_name = "F", default_value = "rgb888")]
    pub format: Format,
    /// Box convention of every ground-truth file, unless named below.
    #[command(flatten)]
    pub convention: Convention,
    /// Sequences whose ground truth counts pixels from 0, comma-separated folder names
    /// (e.g. ball1_vot15), each in some DATA_DIR
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub zero_based_sequences: Vec<String>,
    /// Write the plots into DIR (success.png, precision.png, per tracker with both)
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write the plots into out/eval (or --out) also with --json
    #[arg(long)]
    pub plots: bool,
    /// Write box files DIR/SEQUENCE.txt (SEQUENCE_TRACKER.txt with both trackers, then
    /// _seedS with several seeds and _START with several starts, before .txt)
    #[arg(long, value_name = "DIR")]
    pub boxes: Option<PathBuf>,
    /// Write DIR/SEQUENCE/0001.png, ... with every run's estimate, status and confidence
    #[arg(long, value_name = "DIR")]
    pub overlay: Option<PathBuf>,
    /// Print one JSON object instead of the table (no plots unless --out or --plots)
    #[arg(long)]
    pub json: bool,
    /// Also fit each tracker's confidence table to the runs, pooled, and print it with
    /// the reliability it gives (the core's tables are made so)
    #[arg(long)]
    pub calibrate: bool,
}

/// Options of `rbtrack port`.
#[derive(Debug, Args)]
pub struct PortArgs {
    /// Folders of sequence folders (OTB layout each)
    #[arg(value_name = "DATA_DIR", required = true)]
    pub data: Vec<PathBuf>,
    /// First boxes: the ground truth's (box), or spatial: also shifted 2 px left, right,
    /// up and down and scaled by 0.95 and 1.05 (7 starts), or wide (21 starts)
    #[arg(long, value_enum, value_name = "S", default_value = "box")]
    pub starts: Starts,
    /// The integer tracker's settings (cf.FIELD=VALUE); the reference follows them.
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Box convention of every ground-truth file, unless named below.
    #[command(flatten)]
    pub convention: Convention,
    /// Sequences whose ground truth counts pixels from 0, comma-separated folder names
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub zero_based_sequences: Vec<String>,
    /// Print one JSON object instead of the table
    #[arg(long)]
    pub json: bool,
}

/// Options of `rbtrack cost`.
#[derive(Debug, Args)]
pub struct CostArgs {
    /// The budget example's output, as QEMU prints it
    #[arg(value_name = "BUDGET_OUTPUT")]
    pub budget: Option<PathBuf>,
    /// Fit each stage's costs per operation to the budget example's rows and print them,
    /// with the rows they give
    #[arg(long, requires = "budget")]
    pub fit: bool,
    /// Without BUDGET_OUTPUT: the configuration (cf.FIELD=VALUE on --preset's; the
    /// preset core is the integer tracker's defaults)
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Without BUDGET_OUTPUT: print one JSON object instead of the table
    #[arg(long, conflicts_with = "budget")]
    pub json: bool,
}

/// Options of `rbtrack paper`.
#[derive(Debug, Args)]
pub struct PaperArgs {
    /// Runs (seeds 1..=N)
    #[arg(long, value_name = "N", default_value_t = crate::paper::RUNS, value_parser = whole_in(1, 10_000))]
    pub runs: usize,
    /// Particles of the main comparison and the sweep
    #[arg(long, value_name = "N", default_value_t = crate::paper::PARTICLES, value_parser = whole_in(1, 65_535))]
    pub particles: usize,
    /// Print JSON instead of the table
    #[arg(long)]
    pub json: bool,
    /// Also write PNG figures into DIR
    #[arg(long, value_name = "DIR")]
    pub plots: Option<PathBuf>,
}

/// A parser of whole numbers in `min..=max`.
fn whole_in(
    min: usize,
    max: usize,
) -> impl Fn(&str) -> Result<usize, String> + Clone + Send + Sync + 'static {
    move |text| match text.parse::<usize>() {
        Ok(n) if (min..=max).contains(&n) => Ok(n),
        _ => Err(format!("expected a whole number in {min}..={max}")),
    }
}

fn particle_count(text: &str) -> Result<usize, String> {
    text.parse::<usize>()
        .ok()
        .filter(|n| PARTICLE_COUNTS.contains(n))
        .ok_or_else(|| format!("expected one of {PARTICLE_COUNTS:?}"))
}

fn scene_named(text: &str) -> Result<scene::Variant, String> {
    scene::Variant::from_name(text).ok_or_else(|| {
        "expected perspective, distractor, occlusion, brightness, fast or leave".to_string()
    })
}

fn box_arg(text: &str) -> Result<BBox, String> {
    sequence::parse_bbox(text).map_err(|e| e.to_string())
}

/// Reports a command-line mistake (or prints the help or version asked for) and returns
/// the exit code: 0 for help and version, 2 for a mistake. A bad value is one line on
/// stderr, `rbtrack <subcommand>: <message>`; an unknown option or a missing argument
/// adds the usage.
pub fn report(e: &clap::Error) -> u8 {
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            // A closed stdout (`rbtrack --help | head -1`) is not worth a complaint.
            let _ = e.print();
            0
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            2
        }
        kind => {
            let subcommand = std::env::args().nth(1).filter(|a| {
                ["demo", "track", "eval", "port", "cost", "paper"].contains(&a.as_str())
            });
            let prefix = match subcommand {
                Some(s) => format!("rbtrack {s}: "),
                None => "rbtrack: ".to_string(),
            };
            let text = e.render().to_string();
            let text = text.trim_end().trim_start_matches("error: ");
            let with_usage = matches!(
                kind,
                ErrorKind::UnknownArgument
                    | ErrorKind::InvalidSubcommand
                    | ErrorKind::MissingRequiredArgument
                    | ErrorKind::MissingSubcommand
                    | ErrorKind::TooManyValues
                    | ErrorKind::WrongNumberOfValues
            );
            let shown = if with_usage {
                text.to_string()
            } else {
                // The first line, and the choices clap lists below it, if any.
                let mut lines = text.lines();
                let first = lines.next().unwrap_or_default();
                match lines
                    .map(str::trim)
                    .find(|l| l.starts_with("[possible values"))
                {
                    Some(choices) => format!("{first} {choices}"),
                    None => first.to_string(),
                }
            };
            eprintln!("{prefix}{shown}");
            2
        }
    }
}
