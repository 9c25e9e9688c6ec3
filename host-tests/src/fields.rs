//! Settings by name, read and written as text: what `--set FIELD=VALUE`, `--config FILE`
//! and the JSON output share, for the core's `Config` ([`crate::config_fields`]) and the
//! cf64 tracker's `Params` ([`crate::cf64::params`]).
//!
//! A settings type lists its fields once with [`field_table!`]; each becomes a [`Field`]
//! that sets and reads it through its type's [`FieldValue`].

use serde_json::Value;
use std::fmt;
use std::str::FromStr;

/// A type of setting: parsed from and shown as text.
pub trait FieldValue: Sized {
    /// Reads the text form; the error says what was expected.
    fn parse(text: &str) -> Result<Self, String>;
    /// The JSON form (a number, or a string for enums); its text parses back to `self`.
    fn to_json(&self) -> Value;
}

/// One field of a settings type `T`: its name and how to set and read it.
pub struct Field<T: 'static> {
    /// The field's name in `T`.
    pub name: &'static str,
    /// What the command line writes before the name (`cf.` for the cf64 tracker's).
    pub prefix: &'static str,
    set: fn(&mut T, &str) -> Result<(), String>,
    get: fn(&T) -> Value,
}

impl<T> Field<T> {
    /// A field named `name` (spelled `prefix` + `name` on the command line), set and read
    /// by `set` and `get`.
    pub const fn new(
        prefix: &'static str,
        name: &'static str,
        set: fn(&mut T, &str) -> Result<(), String>,
        get: fn(&T) -> Value,
    ) -> Self {
        Self {
            name,
            prefix,
            set,
            get,
        }
    }

    /// Sets this field of `settings` from `text`; the error names the field.
    pub fn set(&self, settings: &mut T, text: &str) -> Result<(), String> {
        (self.set)(settings, text.trim())
            .map_err(|e| format!("`{}{}`: {e}", self.prefix, self.name))
    }

    /// This field of `settings` in its JSON form.
    pub fn get(&self, settings: &T) -> Value {
        (self.get)(settings)
    }

    /// This field of `settings` as `--set` takes it.
    pub fn text(&self, settings: &T) -> String {
        match self.get(settings) {
            Value::String(s) => s,
            v => v.to_string(),
        }
    }
}

impl<T> fmt::Debug for Field<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", self.prefix, self.name)
    }
}

/// `[Field<$ty>]` of the named fields of `$ty`, each set and read through its type's
/// [`FieldValue`], spelled with `$prefix` on the command line.
macro_rules! field_table {
    ($ty:ty, $prefix:literal; $($name:ident,)*) => {
        &[$(
            $crate::fields::Field::new(
                $prefix,
                stringify!($name),
                |settings: &mut $ty, text| {
                    settings.$name = $crate::fields::FieldValue::parse(text)?;
                    Ok(())
                },
                |settings: &$ty| $crate::fields::FieldValue::to_json(&settings.$name),
            ),
        )*]
    };
}
pub(crate) use field_table;

/// Parses `name` or `name:ARG` against `choices` (lowercase names, case-insensitive),
/// returning the chosen name and its argument.
pub fn choice<'a>(
    text: &'a str,
    choices: &[&'static str],
    expected: &str,
) -> Result<(&'static str, Option<&'a str>), String> {
    let (name, arg) = match text.split_once(':') {
        Some((n, a)) => (n, Some(a.trim())),
        None => (text, None),
    };
    choices
        .iter()
        .find(|c| c.eq_ignore_ascii_case(name.trim()))
        .map(|c| (*c, arg))
        .ok_or_else(|| format!("expected {expected}, got {text:?}"))
}

/// Whole numbers: parsed, shown as JSON numbers.
macro_rules! whole_numbers {
    ($($ty:ty),*) => {$(
        impl FieldValue for $ty {
            fn parse(text: &str) -> Result<Self, String> {
                text.parse().map_err(|_| {
                    format!("expected a whole number in 0..={}, got {text:?}", <$ty>::MAX)
                })
            }
            fn to_json(&self) -> Value {
                Value::from(*self)
            }
        }
    )*};
}
whole_numbers!(u8, u32, u64, usize);

impl FieldValue for f64 {
    fn parse(text: &str) -> Result<Self, String> {
        f64::from_str(text)
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("expected a number, got {text:?}"))
    }
    fn to_json(&self) -> Value {
        Value::from(*self)
    }
}

impl FieldValue for bool {
    fn parse(text: &str) -> Result<Self, String> {
        match choice(text, &["true", "false"], "true or false")? {
            ("true", None) => Ok(true),
            ("false", None) => Ok(false),
            _ => Err(format!("expected true or false, got {text:?}")),
        }
    }
    fn to_json(&self) -> Value {
        Value::from(*self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Default, PartialEq)]
    struct Example {
        count: u32,
        share: f64,
        on: bool,
    }

    static EXAMPLE: &[Field<Example>] = field_table!(Example, "ex."; count, share, on,);

    #[test]
    fn a_table_sets_and_reads_each_field() {
        let mut e = Example::default();
        for (field, text) in EXAMPLE.iter().zip(["7", "0.25", "TRUE"]) {
            field.set(&mut e, text).unwrap();
        }
        assert_eq!(
            e,
            Example {
                count: 7,
                share: 0.25,
                on: true
            }
        );
        let texts: Vec<String> = EXAMPLE.iter().map(|f| f.text(&e)).collect();
        assert_eq!(texts, ["7", "0.25", "true"]);
        let e = EXAMPLE[0].set(&mut Example::default(), "-1").unwrap_err();
        assert!(e.starts_with("`ex.count`: expected a whole number"), "{e}");
        assert!(EXAMPLE[1].set(&mut Example::default(), "inf").is_err());
    }
}
