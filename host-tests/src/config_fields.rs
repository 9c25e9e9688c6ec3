//! Every field of the core's [`Config`] by name, read and written as text: what
//! `--set FIELD=VALUE`, `--config FILE` (TOML) and the JSON output of `rbtrack` share.
//!
//! Values: Q16.16 fields as decimals (`scale_per_row=0.1`), integers as integers, enums by
//! lowercase name with an argument after a colon where they carry one (`cue_mix=product`,
//! `cue_mix=average:0.5`, `readout=robust_mean:8`, `resampling=systematic`,
//! `variant=rbpf`). The JSON form of a configuration ([`ConfigJson`]) prints every field
//! in these spellings, so its `key = value` lines are a `--config` file that reproduces it.
//!
//! [`FIELDS`] is the one table: a field added to `Config` is one more name in it, and a
//! unit test fails naming any field of `Config` it lacks.

use crate::cf64;
use crate::fields::{self, choice, field_table, FieldValue};
use rbtrack::fixed::Q16;
use rbtrack::resample::Scheme;
use rbtrack::tracker::{Config, CueMix, Readout, SizeMeasurement, Variant};
use serde::ser::{Serialize, SerializeMap, Serializer};
use serde_json::Value;
use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// One field of [`Config`]: its name and how to set and read it.
pub type Field = fields::Field<Config>;

impl Field {
    /// The field called `name`.
    pub fn named(name: &str) -> Option<&'static Field> {
        FIELDS.iter().find(|f| f.name == name)
    }
}

/// Every field of [`Config`], in its declaration order.
pub static FIELDS: &[Field] = field_table! {
    Config, "";
    variant,
    seed,
    pixels_per_window,
    position_noise,
    relative_position_noise,
    velocity_noise,
    noise_gain,
    noise_floor,
    velocity_keep,
    scale_noise,
    colour_sigma,
    gradient_sigma,
    cue_mix,
    gradient_points,
    gradient_search,
    resampling,
    resample_below,
    readout,
    adapt_rate,
    adapt_above,
    spread_penalty,
    uncertain_below,
    lost_below,
    redetect_share,
    scale_per_row,
    kalman_q,
    kalman_r,
    scale_step,
    min_half_axis,
    background_weighting,
    background_floor,
    ring_scale,
    split_halves,
    contrast_sigma,
    contrast_ring,
    size_measurement,
    freeze_size,
    redetect_prior,
    learn_scale_per_row,
};

/// Largest magnitude of a Q16.16 value.
const Q16_LIMIT: f64 = 32768.0;

impl FieldValue for Q16 {
    fn parse(text: &str) -> Result<Self, String> {
        match text.parse::<f64>() {
            Ok(v) if (-Q16_LIMIT..Q16_LIMIT).contains(&v) => Ok(Q16::from_f64(v)),
            _ => Err(format!(
                "expected a decimal number in -32768..32768, got {text:?}"
            )),
        }
    }
    /// The shortest decimal that reads back as the same Q16.16 value (five decimals
    /// always do: they resolve steps below half of 2^-16).
    fn to_json(&self) -> Value {
        let exact = self.to_f64();
        let shortest = (0..=5)
            .filter_map(|digits| format!("{exact:.digits$}").parse::<f64>().ok())
            .find(|v| Q16::from_f64(*v) == *self)
            .unwrap_or(exact);
        Value::from(shortest)
    }
}

/// `off`, or the value.
impl FieldValue for Option<Q16> {
    fn parse(text: &str) -> Result<Self, String> {
        match text.trim().eq_ignore_ascii_case("off") {
            true => Ok(None),
            false => Q16::parse(text)
                .map(Some)
                .map_err(|e| format!("{e}, or off")),
        }
    }
    fn to_json(&self) -> Value {
        match self {
            Some(v) => v.to_json(),
            None => Value::from("off"),
        }
    }
}

impl FieldValue for SizeMeasurement {
    fn parse(text: &str) -> Result<Self, String> {
        const EXPECTED: &str = "contrast or likelihood";
        match choice(text, &["contrast", "likelihood"], EXPECTED)? {
            ("contrast", None) => Ok(SizeMeasurement::Contrast),
            ("likelihood", None) => Ok(SizeMeasurement::Likelihood),
            _ => Err(format!("expected {EXPECTED}, got {text:?}")),
        }
    }
    fn to_json(&self) -> Value {
        Value::from(match self {
            SizeMeasurement::Contrast => "contrast",
            SizeMeasurement::Likelihood => "likelihood",
        })
    }
}

impl FieldValue for Variant {
    fn parse(text: &str) -> Result<Self, String> {
        match choice(text, &["rbpf", "pf"], "rbpf or pf")? {
            ("rbpf", None) => Ok(Variant::Rbpf),
            ("pf", None) => Ok(Variant::ColourPf),
            _ => Err(format!("expected rbpf or pf, got {text:?}")),
        }
    }
    fn to_json(&self) -> Value {
        Value::from(match self {
            Variant::Rbpf => "rbpf",
            Variant::ColourPf => "pf",
        })
    }
}

impl FieldValue for CueMix {
    fn parse(text: &str) -> Result<Self, String> {
        const EXPECTED: &str = "product or average:SHARE (SHARE the colour cue's share, 0..=1)";
        match choice(text, &["product", "average"], EXPECTED)? {
            ("product", None) => Ok(CueMix::Product),
            ("average", Some(share)) => Ok(CueMix::Average(Q16::parse(share)?)),
            _ => Err(format!("expected {EXPECTED}, got {text:?}")),
        }
    }
    fn to_json(&self) -> Value {
        Value::from(match self {
            CueMix::Product => "product".to_string(),
            CueMix::Average(share) => format!("average:{}", share.to_json()),
        })
    }
}

impl FieldValue for Readout {
    fn parse(text: &str) -> Result<Self, String> {
        const EXPECTED: &str = "mean, best or robust_mean:RADIUS (RADIUS in px)";
        match choice(text, &["mean", "best", "robust_mean"], EXPECTED)? {
            ("mean", None) => Ok(Readout::Mean),
            ("best", None) => Ok(Readout::Best),
            ("robust_mean", Some(radius)) => Ok(Readout::RobustMean(Q16::parse(radius)?)),
            _ => Err(format!("expected {EXPECTED}, got {text:?}")),
        }
    }
    fn to_json(&self) -> Value {
        Value::from(match self {
            Readout::Mean => "mean".to_string(),
            Readout::Best => "best".to_string(),
            Readout::RobustMean(radius) => format!("robust_mean:{}", radius.to_json()),
        })
    }
}

/// Resampling schemes by name.
const SCHEMES: [(&str, Scheme); 4] = [
    ("multinomial", Scheme::Multinomial),
    ("systematic", Scheme::Systematic),
    ("stratified", Scheme::Stratified),
    ("residual", Scheme::Residual),
];

impl FieldValue for Scheme {
    fn parse(text: &str) -> Result<Self, String> {
        let names = SCHEMES.map(|(n, _)| n);
        let expected = names.join(", ");
        let (name, arg) = choice(text, &names, &expected)?;
        match (SCHEMES.iter().find(|(n, _)| *n == name), arg) {
            (Some((_, scheme)), None) => Ok(*scheme),
            _ => Err(format!("expected {expected}, got {text:?}")),
        }
    }
    fn to_json(&self) -> Value {
        Value::from(
            SCHEMES
                .iter()
                .find(|(_, s)| s == self)
                .map_or("?", |(n, _)| *n),
        )
    }
}

/// One `FIELD=VALUE` setting, checked: the field exists and the value parses.
#[derive(Clone, Debug)]
pub struct Setting {
    /// The field.
    pub field: SettingField,
    /// The value as written.
    pub value: String,
}

/// The field a [`Setting`] sets: one of the core's [`Config`], or, named `cf.FIELD`, one
/// of the f64 correlation-filter tracker's [`cf64::Params`].
#[derive(Clone, Copy, Debug)]
pub enum SettingField {
    /// A field of [`Config`].
    Core(&'static Field),
    /// A field of [`cf64::Params`].
    Cf(&'static cf64::params::Field),
}

impl Setting {
    /// The setting of field `name` to `value`; the error names the field.
    pub fn new(name: &str, value: &str) -> Result<Self, String> {
        let name = name.trim();
        let field = match name.strip_prefix("cf.") {
            Some(cf) => {
                let field = cf64::params::Field::named(cf).ok_or_else(|| {
                    let names: Vec<&str> = cf64::params::FIELDS.iter().map(|f| f.name).collect();
                    format!(
                        "unknown field `{name}` of the correlation-filter trackers (fields: cf.{})",
                        names.join(", cf.")
                    )
                })?;
                field.set(&mut cf64::Params::default(), value)?;
                SettingField::Cf(field)
            }
            None => {
                let field = Field::named(name).ok_or_else(|| {
                    let names: Vec<&str> = FIELDS.iter().map(|f| f.name).collect();
                    format!(
                        "unknown configuration field `{name}` (fields: {}, and the cf64 \
                         tracker's cf.FIELD)",
                        names.join(", ")
                    )
                })?;
                field.set(&mut Config::new(Variant::Rbpf), value)?;
                SettingField::Core(field)
            }
        };
        Ok(Self {
            field,
            value: value.trim().to_string(),
        })
    }

    /// The core field it sets, if it sets one.
    fn core(&self) -> Option<&'static Field> {
        match self.field {
            SettingField::Core(f) => Some(f),
            SettingField::Cf(_) => None,
        }
    }
}

impl FromStr for Setting {
    type Err = String;

    /// Reads `FIELD=VALUE`.
    fn from_str(s: &str) -> Result<Self, String> {
        let (name, value) = s
            .split_once('=')
            .ok_or_else(|| format!("expected FIELD=VALUE, got {s:?}"))?;
        Self::new(name, value)
    }
}

/// The settings of a TOML file (`colour_sigma = 0.15`, `cue_mix = "average:0.5"`), in
/// the file's order; the error names the file and the field.
pub fn read_toml(path: &Path) -> Result<Vec<Setting>, String> {
    let at = |e: &dyn fmt::Display| format!("{}: {e}", path.display());
    let text = std::fs::read_to_string(path).map_err(|e| at(&e))?;
    let table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| at(&e.message()))?;
    table
        .iter()
        .map(|(name, value)| {
            let text = match value {
                toml::Value::String(s) => s.clone(),
                toml::Value::Integer(i) => i.to_string(),
                toml::Value::Float(f) => f.to_string(),
                toml::Value::Boolean(b) => b.to_string(),
                other => {
                    return Err(at(&format!(
                        "`{name}`: expected a number, a boolean or a string, got {}",
                        other.type_str()
                    )))
                }
            };
            Setting::new(name, &text).map_err(|e| at(&e))
        })
        .collect()
}

/// The configuration settings start from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Preset {
    /// `Config::new`: the defaults.
    #[default]
    Default,
    /// `Config::paper`: the source papers' trackers.
    Paper,
    /// The core's integer correlation-filter tracker at its defaults: for cf64, its f64
    /// reference (`cf64::Params::of_core`); for the other trackers, their defaults.
    Core,
}

impl Preset {
    /// The preset's configuration of `variant`.
    pub fn config(self, variant: Variant) -> Config {
        match self {
            Preset::Default | Preset::Core => Config::new(variant),
            Preset::Paper => Config::paper(variant),
        }
    }

    /// The f64 correlation-filter tracker's settings the preset starts from.
    pub fn cf_params(self) -> cf64::Params {
        match self {
            Preset::Default | Preset::Paper => cf64::Params::default(),
            Preset::Core => {
                let core = crate::run::CoreCf::default();
                cf64::Params::of_core(&core.config, core.grid, core.scales)
            }
        }
    }
}

/// Settings in the order they apply (a later one wins) on top of a preset: a `--config`
/// file's, then the command line's `--set`s.
#[derive(Clone, Debug, Default)]
pub struct Overrides(pub Vec<Setting>, pub Preset);

impl Overrides {
    /// The last value given for field `name`, parsed.
    pub fn value<T: FieldValue>(&self, name: &str) -> Option<T> {
        let setting = self
            .0
            .iter()
            .rev()
            .find(|s| s.core().is_some_and(|f| f.name == name))?;
        T::parse(&setting.value).ok()
    }

    /// The first setting none of `trackers` reads: a core field other than `seed` and
    /// `variant` is the particle filters', a `cf.` field the correlation-filter trackers'.
    pub fn unread_by(&self, particle_filter: &[bool]) -> Option<String> {
        let reads = |s: &Setting| match s.field {
            SettingField::Core(f) => {
                matches!(f.name, "seed" | "variant") || particle_filter.contains(&true)
            }
            SettingField::Cf(_) => particle_filter.contains(&false),
        };
        self.0.iter().find(|s| !reads(s)).map(|s| match s.field {
            SettingField::Core(f) => f.name.to_string(),
            SettingField::Cf(f) => format!("cf.{}", f.name),
        })
    }

    /// `Config::new(variant)` with every core setting applied, then `variant` and `seed`
    /// imposed, checked by [`Config::validate`].
    pub fn config(&self, variant: Variant, seed: u64) -> Result<Config, String> {
        let mut config = self.1.config(variant);
        for s in &self.0 {
            if let Some(field) = s.core() {
                field.set(&mut config, &s.value)?;
            }
        }
        config.variant = variant;
        config.seed = seed;
        config.validate().map_err(|e| e.to_string())?;
        Ok(config)
    }

    /// The preset's cf64 settings ([`Preset::cf_params`]) with every `cf.` setting
    /// applied, checked.
    pub fn cf_params(&self) -> Result<cf64::Params, String> {
        self.cf_params_on(self.1.cf_params())
    }

    /// `base` with the `cf.` fields set, checked.
    pub fn cf_params_on(&self, base: cf64::Params) -> Result<cf64::Params, String> {
        let mut params = base;
        for s in &self.0 {
            if let SettingField::Cf(field) = s.field {
                field.set(&mut params, &s.value)?;
            }
        }
        params.validate()?;
        Ok(params)
    }
}

/// The fields of `config` that differ from `Config::new(config.variant)` (the seed left
/// out), as `FIELD=VALUE`.
pub fn changed_fields(config: &Config) -> Vec<String> {
    let default = Config::new(config.variant);
    FIELDS
        .iter()
        .filter(|f| f.name != "seed" && f.get(config) != f.get(&default))
        .map(|f| format!("{}={}", f.name, f.text(config)))
        .collect()
}

/// A [`Config`] serialised as a JSON object of every field, in [`FIELDS`] order.
#[derive(Clone, Copy, Debug)]
pub struct ConfigJson<'a>(pub &'a Config);

impl Serialize for ConfigJson<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(FIELDS.len()))?;
        for f in FIELDS {
            map.serialize_entry(f.name, &f.get(self.0))?;
        }
        map.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The top-level field names of a `Config`, read from its pretty `Debug` output (one
    /// `name: value` line per field, indented by four spaces).
    fn debug_field_names(config: &Config) -> Vec<String> {
        format!("{config:#?}")
            .lines()
            .filter_map(|line| {
                let rest = line.strip_prefix("    ")?;
                let (name, _) = rest.split_once(':')?;
                (!rest.starts_with(' ')
                    && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
                .then(|| name.to_string())
            })
            .collect()
    }

    #[test]
    fn the_table_covers_every_config_field() {
        let names = debug_field_names(&Config::new(Variant::Rbpf));
        assert!(
            names.len() >= 20,
            "read {names:?} from Config's Debug output"
        );
        let missing: Vec<&String> = names.iter().filter(|n| Field::named(n).is_none()).collect();
        assert!(
            missing.is_empty(),
            "Config fields without an entry in config_fields::FIELDS: {missing:?}"
        );
        assert_eq!(names.len(), FIELDS.len(), "{names:?}");
    }

    #[test]
    fn every_value_reads_back_as_printed() {
        let mut config = Config::new(Variant::ColourPf);
        config.cue_mix = CueMix::Average(Q16::from_f64(0.3));
        config.readout = Readout::RobustMean(Q16::from_int(8));
        config.resampling = Scheme::Residual;
        config.scale_per_row = Q16::from_f64(-0.1234);
        config.seed = u64::MAX;
        let mut paper = Config::paper(Variant::Rbpf);
        paper.size_measurement = SizeMeasurement::Likelihood;
        for base in [config, Config::new(Variant::Rbpf), paper] {
            let mut copy = Config::new(Variant::Rbpf);
            for f in FIELDS {
                f.set(&mut copy, &f.text(&base)).unwrap();
            }
            assert_eq!(copy, base);
        }
        assert_eq!(FIELDS[0].text(&config), "pf");
        let text = |name: &str| Field::named(name).unwrap().text(&config);
        assert_eq!(text("colour_sigma"), "0.1");
        assert_eq!(text("contrast_sigma"), "0.2");
        assert_eq!(text("split_halves"), "true");
        assert_eq!(text("size_measurement"), "contrast");
        assert_eq!(text("cue_mix"), "average:0.3");
        assert_eq!(text("readout"), "robust_mean:8.0");
        assert_eq!(text("resampling"), "residual");
        assert_eq!(text("pixels_per_window"), "300");
    }

    #[test]
    fn settings_parse_and_errors_name_the_field() {
        let s: Setting = "scale_per_row=0.1".parse().unwrap();
        let mut config = Config::new(Variant::Rbpf);
        s.core().unwrap().set(&mut config, &s.value).unwrap();
        assert_eq!(config.scale_per_row, Q16::from_f64(0.1));
        for (text, named) in [
            ("no_such_field=1", "`no_such_field`"),
            ("colour_sigma=abc", "`colour_sigma`"),
            ("gradient_points=300", "`gradient_points`"),
            ("cue_mix=average", "`cue_mix`"),
            ("readout=robust_mean:x", "`readout`"),
            ("resampling=fancy", "`resampling`"),
            ("scale_per_row=1e9", "`scale_per_row`"),
            ("colour_sigma", "FIELD=VALUE"),
        ] {
            let e = text.parse::<Setting>().unwrap_err();
            assert!(e.contains(named), "{text}: {e}");
            assert_eq!(e.lines().count(), 1, "{e}");
        }
        for (text, mix) in [
            ("cue_mix=product", CueMix::Product),
            ("cue_mix=Average:0.5", CueMix::Average(Q16::HALF)),
        ] {
            let s: Setting = text.parse().unwrap();
            s.core().unwrap().set(&mut config, &s.value).unwrap();
            assert_eq!(config.cue_mix, mix);
        }
    }

    #[test]
    fn overrides_apply_in_order_and_validate() {
        let o = Overrides(
            vec![
                "colour_sigma=0.5".parse().unwrap(),
                "colour_sigma=0.15".parse().unwrap(),
                "variant=pf".parse().unwrap(),
                "seed=9".parse().unwrap(),
            ],
            Preset::Default,
        );
        assert_eq!(o.value::<Variant>("variant"), Some(Variant::ColourPf));
        assert_eq!(o.value::<u64>("seed"), Some(9));
        let c = o.config(Variant::Rbpf, 3).unwrap();
        assert_eq!(c.colour_sigma, Q16::from_f64(0.15));
        assert_eq!((c.variant, c.seed), (Variant::Rbpf, 3));
        assert_eq!(changed_fields(&c), ["colour_sigma=0.15"]);
        let bad = Overrides(vec!["lost_below=0.9".parse().unwrap()], Preset::Default);
        let e = bad.config(Variant::Rbpf, 1).unwrap_err();
        assert!(e.contains("lost_below"), "{e}");
        let paper = Overrides(vec!["seed=2".parse().unwrap()], Preset::Paper);
        assert_eq!(paper.config(Variant::Rbpf, 2).unwrap(), {
            let mut c = Config::paper(Variant::Rbpf);
            c.seed = 2;
            c
        });
        let e = bad.config(Variant::Rbpf, 1).unwrap_err();
        assert!(e.contains("lost_below"), "{e}");
    }

    #[test]
    fn json_lists_every_field_in_order() {
        let json = serde_json::to_value(ConfigJson(&Config::new(Variant::Rbpf))).unwrap();
        let map = json.as_object().unwrap();
        assert_eq!(map.len(), FIELDS.len());
        assert_eq!(map["cue_mix"], "product");
        assert_eq!(map["colour_sigma"], 0.1);
        assert_eq!(map["contrast_sigma"], "off");
        let text = serde_json::to_string(&ConfigJson(&Config::new(Variant::Rbpf))).unwrap();
        assert!(
            text.starts_with("{\"variant\":\"rbpf\",\"seed\":1,"),
            "{text}"
        );
    }
}
