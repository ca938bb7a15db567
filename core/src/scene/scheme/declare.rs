//! The machinery behind `scheme.rs`: what one key declares (`Key`), and the two macros that
//! turn a declaration into the serde struct or enum, its entry in the registry, its header
//! field, its validation and its paper value.
//!
//! A table is read in two steps, so that the defaults are written once, in the
//! declaration: serde reads a raw copy of it in which every key is optional (still with
//! `deny_unknown_fields`, so an unknown key, a wrong type or a bad choice is refused by serde
//! with its position), then `TryFrom` fills in each absent key's declared default, or
//! refuses a missing required one with serde's own words (`missing field `end``).

use super::SceneFile;
use crate::physics::params::SphParams;

/// One key of a scheme table (`[discretisation]`, `[time]`, `[fluid]`, `[solid]`,
/// `[boundary]`), as declared in `scheme.rs`.
pub struct Key {
    /// The dotted scene path, `fluid.density_diffusion`.
    pub path: &'static str,
    /// The field's doc comment: unit, meaning, citation.
    pub doc: &'static str,
    /// The Rust type as declared (`f64`, `bool`, `DiffusionForm`, `Option<f64>`).
    pub ty: &'static str,
    /// What the scene file writes: "number", "true or false", "integer", "one of", ...
    pub kind: &'static str,
    /// For a choice: every (name, help) in the file's spelling; else empty.
    pub choices: fn() -> Vec<(&'static str, &'static str)>,
    pub default: KeyDefault,
    pub paper: Paper,
    pub check: Check,
    pub param: Param,
    /// The key's value in a scene as TOML; `None` where its table, or an optional value,
    /// is absent.
    pub get: fn(&SceneFile) -> Option<toml::Value>,
    /// Set the key's value in a scene (its table must be present).
    pub set: fn(&mut SceneFile, toml::Value) -> Result<(), String>,
    /// Whether the scene has the key's table (`[solid]` of `solid.fluid_pressure`).
    pub has_table: fn(&SceneFile) -> bool,
    /// Set the key to its paper value, where that is fixed (`Paper::Is`).
    pub set_paper: Option<fn(&mut SceneFile)>,
    /// Check the key's value where its table is present: `check`'s range, then its `needs`.
    pub(crate) validate: fn(&SceneFile) -> Result<(), Refusal>,
}

impl Key {
    /// The table's name, `fluid` of `fluid.density_diffusion`.
    pub fn table(&self) -> &'static str {
        self.path.split_once('.').map_or(self.path, |(t, _)| t)
    }

    /// The key's name within its table, `density_diffusion`.
    pub fn name(&self) -> &'static str {
        self.path.split_once('.').map_or(self.path, |(_, k)| k)
    }

    /// Whether `--paper-exact` sets this key (`Paper::Is` or `Paper::From`): a switch of
    /// the scheme rather than a value the paper leaves to the scene.
    pub fn is_switch(&self) -> bool {
        !matches!(self.paper, Paper::Scene(_))
    }
}

impl std::fmt::Debug for Key {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Key").field("path", &self.path).finish()
    }
}

/// A key's default.
pub enum KeyDefault {
    /// The scene must give it.
    Required,
    /// An optional value whose absence means something of its own (the text says what).
    Absent(&'static str),
    /// This value, for this reason.
    Value {
        value: fn() -> toml::Value,
        why: &'static str,
    },
}

/// A key's value in the paper's own scheme (`--paper-exact`, `Scene::with_paper_exact`).
pub enum Paper {
    /// This value, for this reason (an equation, or "inert" where another switch's paper
    /// value turns its term off); `--paper-exact` sets it.
    Is {
        value: fn() -> toml::Value,
        why: &'static str,
    },
    /// Computed from the scene by `Scene::with_paper_exact` (the text says how).
    From(&'static str),
    /// The scene's own: a material constant, the resolution, run control, or something the
    /// paper leaves open (the text says which); `--paper-exact` keeps it.
    Scene(&'static str),
}

/// A key's validation: a range, and where the key depends on others, a check of the whole
/// scene (`needs`, with its one-line description).
pub struct Check {
    pub rule: Rule,
    pub needs: Option<&'static str>,
}

/// The range of a numeric key (others take `Any`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rule {
    /// Any value of the key's type.
    Any,
    /// A finite number > 0.
    Positive,
    /// A finite number >= 0.
    NonNegative,
    /// A number in [0, 1]; the text is the usual value's source, quoted in the error.
    Fraction(&'static str),
}

impl Rule {
    /// Check `x` (`None`: no number to check, e.g. an absent optional value).
    pub fn check(self, x: Option<f64>) -> Result<(), Refusal> {
        let Some(x) = x else { return Ok(()) };
        single_precision(x).map_err(Refusal::new)?;
        match self {
            Rule::Any => Ok(()),
            Rule::Positive if !(x.is_finite() && x > 0.0) => Err(Refusal::new(format!(
                "must be a positive number, found {x}"
            ))),
            Rule::NonNegative | Rule::Fraction(_) if !(x.is_finite() && x >= 0.0) => {
                Err(Refusal::new(format!("must be zero or positive, found {x}")))
            }
            Rule::Fraction(usual) if x > 1.0 => Err(Refusal::new(format!(
                "must lie in [0, 1] ({usual}), found {x}"
            ))),
            _ => Ok(()),
        }
    }

    /// The range in words, for the reference.
    pub fn describe(self) -> &'static str {
        match self {
            Rule::Any => "",
            Rule::Positive => "> 0",
            Rule::NonNegative => ">= 0",
            Rule::Fraction(_) => "in [0, 1]",
        }
    }
}

/// The solver computes in single precision: a number must be finite, no larger in
/// magnitude than f32::MAX (3.4e38), and either zero or no smaller in magnitude than the
/// smallest normal f32 (1.2e-38), which would round to zero or lose its digits.
pub fn single_precision(x: f64) -> Result<(), String> {
    if !x.is_finite() {
        return Err(format!("must be a finite number, found {x}"));
    }
    if x.abs() > f32::MAX as f64 {
        return Err(format!(
            "{x:e} is beyond single precision's range (3.4e38), in which the solver computes"
        ));
    }
    if x != 0.0 && x.abs() < f32::MIN_POSITIVE as f64 {
        return Err(format!(
            "{x:e} is below single precision's smallest normal number (1.2e-38), in which the \
             solver computes: it would round to zero"
        ));
    }
    Ok(())
}

/// Why a key's value was refused; `at` follows the key's path in the error's field
/// (`[2]` for `time.figures[2]`), usually empty.
#[derive(Clone, Debug, PartialEq)]
pub struct Refusal {
    pub at: String,
    pub reason: String,
}

impl Refusal {
    pub fn new(reason: impl Into<String>) -> Refusal {
        Refusal {
            at: String::new(),
            reason: reason.into(),
        }
    }

    pub fn at(at: impl Into<String>, reason: impl Into<String>) -> Refusal {
        Refusal {
            at: at.into(),
            reason: reason.into(),
        }
    }
}

/// Where a key goes in the parameter struct (`cuda/sph_params.h`).
pub enum Param {
    /// This field of `SphParams`.
    Field(&'static str),
    /// No field: the text says where the key acts (the run driver, the particle generator).
    None(&'static str),
}

/// A scheme table: the serde struct of one of the scene file's tables.
pub trait Table: Sized + Clone + 'static {
    /// The table's name in the file.
    const NAME: &'static str;
    /// Its keys, in the declaration's order.
    const KEYS: &'static [Key];
    /// What serde reads first: every key optional.
    type Raw;
    /// The table in a scene, where present.
    fn of(s: &SceneFile) -> Option<&Self>;
    fn of_mut(s: &mut SceneFile) -> Option<&mut Self>;
    /// Write every key's header field (`Param::Field`).
    fn write_params(&self, s: &SceneFile, p: &mut SphParams);
}

/// How a key's value goes into its header field, where the field takes it as it is:
/// numbers as f32, flags and choices as the header's int32_t (choices through their
/// `MF_*` constants).
pub trait ToParam<T> {
    fn to_param(&self) -> T;
}

impl ToParam<f32> for f64 {
    fn to_param(&self) -> f32 {
        *self as f32
    }
}

impl ToParam<i32> for i32 {
    fn to_param(&self) -> i32 {
        *self
    }
}

impl ToParam<i32> for bool {
    fn to_param(&self) -> i32 {
        *self as i32
    }
}

/// What a key's type looks like in a scene file, and its number for range checks.
pub trait KeyType {
    /// "number", "true or false", ...
    const KIND: &'static str;
    /// The value as a number, where it is one.
    fn number(&self) -> Option<f64> {
        None
    }
    /// (name, help) of every choice.
    fn choices() -> Vec<(&'static str, &'static str)> {
        Vec::new()
    }
}

impl KeyType for f64 {
    const KIND: &'static str = "number";
    fn number(&self) -> Option<f64> {
        Some(*self)
    }
}

impl KeyType for Option<f64> {
    const KIND: &'static str = "number";
    fn number(&self) -> Option<f64> {
        *self
    }
}

impl KeyType for i32 {
    const KIND: &'static str = "integer";
    fn number(&self) -> Option<f64> {
        Some(*self as f64)
    }
}

impl KeyType for bool {
    const KIND: &'static str = "true or false";
}

impl KeyType for Vec<f64> {
    const KIND: &'static str = "array of numbers";
}

/// A value as TOML; `None` for an absent optional value.
pub fn to_value<T: serde::Serialize>(v: &T) -> Option<toml::Value> {
    toml::Value::try_from(v).ok()
}

/// A doc comment's lines as one line: `///` lines arrive as " text" each.
pub const fn trim(s: &'static str) -> &'static str {
    s.trim_ascii()
}

/// Declares a scene choice: a string-tagged enum whose first variant is the default, each
/// variant with its scene name, its doc (the help `Named` gives a command line) and the
/// header constant it becomes.
macro_rules! choice {
    (
        $(#[doc = $doc:literal])*
        pub enum $name:ident {
            $(#[doc = $first_doc:literal])*
            $first:ident = $first_text:literal => $first_const:ident,
            $(
                $(#[doc = $vdoc:literal])*
                $variant:ident = $text:literal => $constant:ident,
            )*
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(
            Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize,
        )]
        pub enum $name {
            $(#[doc = $first_doc])*
            #[default]
            #[serde(rename = $first_text)]
            $first,
            $(
                $(#[doc = $vdoc])*
                #[serde(rename = $text)]
                $variant,
            )*
        }

        impl $crate::named::Named for $name {
            const ALL: &'static [(Self, &'static str, &'static str)] = &[
                (
                    $name::$first,
                    $first_text,
                    $crate::scene::scheme::declare::trim(concat!($($first_doc),*)),
                ),
                $((
                    $name::$variant,
                    $text,
                    $crate::scene::scheme::declare::trim(concat!($($vdoc),*)),
                ),)*
            ];
        }

        impl $crate::scene::scheme::declare::ToParam<i32> for $name {
            fn to_param(&self) -> i32 {
                match self {
                    $name::$first => $crate::physics::params::$first_const as i32,
                    $($name::$variant => $crate::physics::params::$constant as i32,)*
                }
            }
        }

        impl $crate::scene::scheme::declare::KeyType for $name {
            const KIND: &'static str = "one of";
            fn choices() -> Vec<(&'static str, &'static str)> {
                <$name as $crate::named::Named>::ALL
                    .iter()
                    .map(|(_, n, h)| (*n, *h))
                    .collect()
            }
        }
    };
}

/// Declares a scheme table: the serde struct (with its doc comments), its raw twin, the
/// registry entry of every key (`Table::KEYS`) and the writing of the header fields.
///
/// Each key: its doc comment, `name: type`, then
/// * `default: [required]`, `[absent "what absence means"]` (an `Option`) or
///   `[value, "why"]`;
/// * `paper: [is value, "why"]`, `[from "how the scene gives it"]` or `[scene "why"]`;
/// * `check: [Rule]` or `[Rule; needs_fn, "what it needs"]`, `needs_fn(&SceneFile, &value)`
///   checking the key against the rest of the scene;
/// * `param: [p.field]` (the value as the field takes it, `ToParam`),
///   `[p.field = |scene, value| ...]` or `[none "where it acts instead"]`;
/// * optionally `serde: [attributes]` for the serialised struct's field.
macro_rules! table {
    (
        $(#[doc = $doc:literal])*
        pub struct $name:ident at $at:ident $(($optional:ident))? {
            $(
                $(#[doc = $fdoc:literal])*
                $field:ident : $ty:ty {
                    default: $default:tt,
                    paper: $paper:tt,
                    check: $check:tt,
                    param: $param:tt
                    $(, serde: [$($serde:tt)*])?
                    $(,)?
                }
            ),* $(,)?
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
        #[serde(try_from = "<Self as crate::scene::scheme::declare::Table>::Raw")]
        pub struct $name {
            $(
                $(#[doc = $fdoc])*
                $(#[serde($($serde)*)])?
                pub $field: $ty,
            )*
        }

        /// The table as serde reads it: every key optional, unknown keys refused.
        mod $at {
            #[allow(unused_imports)]
            use super::*;

            #[derive(serde::Deserialize)]
            #[serde(deny_unknown_fields)]
            pub struct Raw {
                $(
                    #[serde(default)]
                    pub $field: Option<$ty>,
                )*
            }
        }

        impl TryFrom<$at::Raw> for $name {
            type Error = String;
            fn try_from(raw: $at::Raw) -> Result<Self, String> {
                Ok($name {
                    $($field: table!(@take raw $field $default),)*
                })
            }
        }

        impl $crate::scene::scheme::declare::Table for $name {
            const NAME: &'static str = stringify!($at);
            const KEYS: &'static [$crate::scene::scheme::declare::Key] = &[$(
                $crate::scene::scheme::declare::Key {
                    path: concat!(stringify!($at), ".", stringify!($field)),
                    doc: $crate::scene::scheme::declare::trim(concat!($($fdoc),*)),
                    ty: stringify!($ty),
                    kind: <$ty as $crate::scene::scheme::declare::KeyType>::KIND,
                    choices: <$ty as $crate::scene::scheme::declare::KeyType>::choices,
                    default: table!(@default $ty, $default),
                    paper: table!(@paper $ty, $paper),
                    check: table!(@check $check),
                    param: table!(@param $param),
                    get: |s| {
                        <$name as $crate::scene::scheme::declare::Table>::of(s)
                            .and_then(|t| $crate::scene::scheme::declare::to_value(&t.$field))
                    },
                    set: |s, v| {
                        let t = <$name as $crate::scene::scheme::declare::Table>::of_mut(s)
                            .ok_or_else(|| format!("the scene has no [{}] table", stringify!($at)))?;
                        t.$field = v.try_into().map_err(|e: toml::de::Error| e.to_string())?;
                        Ok(())
                    },
                    has_table: |s| <$name as $crate::scene::scheme::declare::Table>::of(s).is_some(),
                    set_paper: table!(@set_paper $name $field $ty, $paper),
                    validate: |s| {
                        let Some(t) = <$name as $crate::scene::scheme::declare::Table>::of(s) else {
                            return Ok(());
                        };
                        table!(@validate s t $field $check)
                    },
                },
            )*];
            type Raw = $at::Raw;
            fn of(s: &$crate::scene::scheme::SceneFile) -> Option<&Self> {
                table!(@of s $at $($optional)?)
            }
            fn of_mut(s: &mut $crate::scene::scheme::SceneFile) -> Option<&mut Self> {
                table!(@of_mut s $at $($optional)?)
            }
            #[allow(unused_variables)]
            fn write_params(
                &self,
                s: &$crate::scene::scheme::SceneFile,
                p: &mut $crate::physics::params::SphParams,
            ) {
                $(table!(@write s p self $field $param);)*
            }
        }
    };

    (@of $s:ident $at:ident) => { Some(&$s.$at) };
    (@of $s:ident $at:ident optional) => { $s.$at.as_ref() };
    (@of_mut $s:ident $at:ident) => { Some(&mut $s.$at) };
    (@of_mut $s:ident $at:ident optional) => { $s.$at.as_mut() };

    (@take $raw:ident $field:ident [required]) => {
        $raw.$field
            .ok_or_else(|| format!("missing field `{}`", stringify!($field)))?
    };
    (@take $raw:ident $field:ident [absent $why:literal]) => { $raw.$field.flatten() };
    (@take $raw:ident $field:ident [$value:expr, $why:literal]) => {
        $raw.$field.unwrap_or_else(|| $value)
    };

    (@default $ty:ty, [required]) => { $crate::scene::scheme::declare::KeyDefault::Required };
    (@default $ty:ty, [absent $why:literal]) => {
        $crate::scene::scheme::declare::KeyDefault::Absent($why)
    };
    (@default $ty:ty, [$value:expr, $why:literal]) => {
        $crate::scene::scheme::declare::KeyDefault::Value {
            value: || {
                let v: $ty = $value;
                $crate::scene::scheme::declare::to_value(&v).expect("a default is a value")
            },
            why: $why,
        }
    };

    (@paper $ty:ty, [is $value:expr, $why:literal]) => {
        $crate::scene::scheme::declare::Paper::Is {
            value: || {
                let v: $ty = $value;
                $crate::scene::scheme::declare::to_value(&v).expect("a paper value is a value")
            },
            why: $why,
        }
    };
    (@paper $ty:ty, [from $why:literal]) => { $crate::scene::scheme::declare::Paper::From($why) };
    (@paper $ty:ty, [scene $why:literal]) => { $crate::scene::scheme::declare::Paper::Scene($why) };

    (@set_paper $name:ident $field:ident $ty:ty, [is $value:expr, $why:literal]) => {
        Some(|s| {
            if let Some(t) = <$name as $crate::scene::scheme::declare::Table>::of_mut(s) {
                let v: $ty = $value;
                t.$field = v;
            }
        })
    };
    (@set_paper $name:ident $field:ident $ty:ty, [$($other:tt)*]) => { None };

    (@check [$rule:ident $(($usual:literal))?]) => {
        $crate::scene::scheme::declare::Check {
            rule: $crate::scene::scheme::declare::Rule::$rule $(($usual))?,
            needs: None,
        }
    };
    (@check [$rule:ident $(($usual:literal))?; $needs:path, $what:literal]) => {
        $crate::scene::scheme::declare::Check {
            rule: $crate::scene::scheme::declare::Rule::$rule $(($usual))?,
            needs: Some($what),
        }
    };

    (@validate $s:ident $t:ident $field:ident [$rule:ident $(($usual:literal))?]) => {
        $crate::scene::scheme::declare::Rule::$rule $(($usual))?
            .check($crate::scene::scheme::declare::KeyType::number(&$t.$field))
    };
    (@validate $s:ident $t:ident $field:ident
        [$rule:ident $(($usual:literal))?; $needs:path, $what:literal]) => {{
        $crate::scene::scheme::declare::Rule::$rule $(($usual))?
            .check($crate::scene::scheme::declare::KeyType::number(&$t.$field))?;
        $needs($s, &$t.$field)
    }};

    (@param [p . $pf:ident]) => { $crate::scene::scheme::declare::Param::Field(stringify!($pf)) };
    (@param [p . $pf:ident = $conv:expr]) => {
        $crate::scene::scheme::declare::Param::Field(stringify!($pf))
    };
    (@param [none $why:literal]) => { $crate::scene::scheme::declare::Param::None($why) };

    (@write $s:ident $p:ident $t:ident $field:ident [p . $pf:ident]) => {
        $p.$pf = $crate::scene::scheme::declare::ToParam::to_param(&$t.$field);
    };
    (@write $s:ident $p:ident $t:ident $field:ident [p . $pf:ident = $conv:expr]) => {
        $p.$pf = ($conv)($s, &$t.$field);
    };
    (@write $s:ident $p:ident $t:ident $field:ident [none $why:literal]) => {};
}
