//! The prescribed motion of a driven wall or solid in a scene file (`motion`): a steady
//! velocity or a table of laws (translation, oscillation, rotation, a wave maker's paddle,
//! a ramp, a time series from a file). Checked and made into `MfMotion` by `scene::motion`;
//! a series' file read by `scene::motion_series`.

use serde::{Deserialize, Serialize};

/// A driven object's prescribed rigid motion (`motion` of a wall or a solid): a velocity
/// `[vx, vy(, vz)]` [L/T] (steady: a piston, a clamp with zeros), or a table of laws
/// (`MotionLaw`). The solver's form and equations: `MfMotion` (`physics::motion`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Motion {
    Velocity(Vec<f64>),
    Law(MotionLaw),
}

/// `motion = { velocity, oscillation, rotation, wave, series, ramp }`: a translation at
/// `velocity` plus an oscillation, and a turn about a pivot, each started smoothly over
/// `ramp` where given; plus a recorded displacement and turn (`series`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionLaw {
    /// \[L/T\] steady translation. Default none.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// A sinusoidal translation: displacement amplitude (sin(2 pi t / period + phase) - sin
    /// phase) (a piston wave maker, a shaken tank). Default none.
    #[serde(default)]
    pub oscillation: Option<Oscillation>,
    /// A turn about `pivot`, at a steady `rate` plus an oscillation of the angle (a flap, a
    /// sloshing tank, a stirrer). Default none.
    #[serde(default)]
    pub rotation: Option<Rotation>,
    /// A wave maker's paddle: the stroke of a regular wave of given height and period by
    /// linear wave-maker theory (a piston's oscillation or a flap's turn). Default none.
    #[serde(default)]
    pub wave: Option<Box<WaveMaker>>,
    /// A time series of the displacement and turn, from a CSV file (a recorded paddle, a
    /// measured ship motion), added to the laws'. Default none.
    #[serde(default)]
    pub series: Option<Box<Series>>,
    /// \[T\] a smooth start, (1 - cos(pi t / ramp)) / 2 of every velocity up to `ramp`
    /// (an oscillation's amplitude grows with it). Default 0: none.
    #[serde(default)]
    pub ramp: f64,
}

/// A paddle making regular waves along +x in still water of `depth` over a floor, y up
/// (`MotionLaw::wave`; `scene::wave`): the stroke S from the first-order transfer function
/// H / S of Biesel (Dean & Dalrymple 1991, sec. 6.2) with the wave number from the linear
/// dispersion relation. A piston moves by (S / 2) sin(2 pi t / period + phase) along x; a
/// flap, hinged at `hinge` on the floor, turns its top at the still-water level by as much.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaveMaker {
    pub paddle: Paddle,
    /// \[L\] the target wave height H (crest to trough).
    pub height: f64,
    /// \[T\] the wave period.
    pub period: f64,
    /// \[L\] the still-water depth at the paddle.
    pub depth: f64,
    /// \[rad\] default 0.
    #[serde(default)]
    pub phase: f64,
    /// \[L\] a flap's hinge: the point on the floor about which it turns (the paddle's
    /// face at the floor). Flaps only.
    #[serde(default)]
    pub hinge: Option<Vec<f64>>,
    /// An irregular sea instead of a regular wave (`scene::wave_spectrum`): `height` is then
    /// the significant wave height H_m0 = 4 sqrt(m0), `period` the peak period T_p, `phase`
    /// unused. Default none: a regular wave.
    #[serde(default)]
    pub spectrum: Option<Spectrum>,
    /// An irregular sea's paddle motion, made with the scene (`motion_series::make_all`).
    #[serde(skip)]
    pub made: crate::scene::motion_series::Loaded,
}

/// `spectrum = { shape, gamma, seed, components }`: the sea an irregular wave maker makes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spectrum {
    /// "jonswap" or "pierson-moskowitz".
    pub shape: SpectrumShape,
    /// JONSWAP's peak enhancement factor, 1 to 10. Default 3.3 (the North Sea's).
    #[serde(default = "default_gamma")]
    pub gamma: f64,
    /// The random phases' and frequencies' seed: one seed, one sea, on every machine.
    /// Default 0.
    #[serde(default)]
    pub seed: u64,
    /// The sea's linear components, 16 to 4096. Default 256.
    #[serde(default = "default_components")]
    pub components: u32,
    /// A focused wave group instead of a random sea: every component in phase at `focus`
    /// (NewWave, Tromans et al. 1991: amplitudes S(f) df / sum S df of the crest, the wave
    /// maker's `height` being then the crest's linear elevation at the focus). Default none.
    #[serde(default)]
    pub focus: Option<Focus>,
}

/// Where and when a focused wave group crests (`Spectrum::focus`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Focus {
    /// \[L\] along +x from the paddle's face at rest.
    pub distance: f64,
    /// \[T\] the time of the crest there.
    pub time: f64,
}

fn default_gamma() -> f64 {
    3.3
}

fn default_components() -> u32 {
    256
}

/// A wave spectrum's form.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SpectrumShape {
    /// Hasselmann et al. 1973: a fetch-limited sea, its peak sharpened by `gamma`.
    Jonswap,
    /// Pierson & Moskowitz 1964: a fully developed sea (JONSWAP with gamma = 1).
    PiersonMoskowitz,
}

/// `series = { file, pivot, axis, interpolation }`: a driven object's displacement and turn
/// over time, from a CSV file whose header names its columns: `t` \[T\] (increasing, the
/// first at or before 0, the last at or after the run's end) and any of `x`, `y`, `z` (3D)
/// \[L\], the pivot's position, and `angle` \[rad\], the turn about `pivot` (positive
/// anticlockwise about `axis`; z in 2D). The object is where the scene puts it at t = 0:
/// each column's value at t = 0 is taken off, so a record of absolute positions serves.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Series {
    /// The CSV file, relative to the scene file's directory.
    pub file: String,
    /// \[L\] the centre of the `angle` column's turn at t = 0 (it moves with the
    /// displacement). Only with an `angle` column.
    #[serde(default)]
    pub pivot: Option<Vec<f64>>,
    /// 3D: the `angle` column's axis, any length. 2D scenes turn about z: leave it out.
    #[serde(default)]
    pub axis: Option<Vec<f64>>,
    /// Between two rows: "linear" (the default: straight segments, as DualSPHysics' motion
    /// files; the velocity jumps at each row) or "cubic" (cubic Hermite with Catmull-Rom
    /// slopes: the velocity is continuous, for a sampled smooth record).
    #[serde(default)]
    pub interpolation: Interpolation,
    /// The knots read from the file (`motion_series::load_all`, when the scene is read).
    #[serde(skip)]
    pub loaded: crate::scene::motion_series::Loaded,
}

/// How a `Series` goes from one row to the next.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Interpolation {
    #[default]
    Linear,
    Cubic,
}

/// A wave maker's paddle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Paddle {
    /// Moves back and forth along x, the same stroke over the depth.
    Piston,
    /// Turns about a hinge on the floor: the stroke grows from the floor to the surface.
    Flap,
}

/// A sinusoidal translation of a driven object (`MotionLaw::oscillation`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Oscillation {
    /// \[L\] displacement amplitude, one number per axis.
    pub amplitude: Vec<f64>,
    /// \[T\] > 0.
    pub period: f64,
    /// \[rad\] Default 0: the object starts at its place, moving at its fastest.
    #[serde(default)]
    pub phase: f64,
}

/// A turn of a driven object about `pivot` (`MotionLaw::rotation`): theta(t) = rate t +
/// amplitude (sin(2 pi t / period + phase) - sin phase), positive anticlockwise about `axis`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rotation {
    /// \[L\] the centre of rotation at t = 0 (it moves with the translation).
    pub pivot: Vec<f64>,
    /// 3D: the axis, any length (normalised). 2D scenes turn about z: leave it out.
    #[serde(default)]
    pub axis: Option<Vec<f64>>,
    /// \[rad/T\] steady angular velocity. Default 0.
    #[serde(default)]
    pub rate: f64,
    /// \[rad\] amplitude of the angle's oscillation. Default 0.
    #[serde(default)]
    pub amplitude: f64,
    /// \[T\] period of the angle's oscillation (> 0 where `amplitude` is not 0).
    #[serde(default)]
    pub period: f64,
    /// \[rad\] Default 0.
    #[serde(default)]
    pub phase: f64,
}

impl<'de> Deserialize<'de> for Motion {
    /// A sequence is a velocity, a table a `MotionLaw` (its own errors: an unknown key, a
    /// wrong type, name the key), anything else an error that says both forms.
    fn deserialize<De: serde::Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
        struct Form;
        impl<'de> serde::de::Visitor<'de> for Form {
            type Value = Motion;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "a velocity [vx, vy(, vz)] or a table of velocity, oscillation, rotation, wave, \
                     series and ramp",
                )
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, a: A) -> Result<Motion, A::Error> {
                Vec::<f64>::deserialize(SeqAccessDeserializer::new(a)).map(Motion::Velocity)
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, a: A) -> Result<Motion, A::Error> {
                MotionLaw::deserialize(MapAccessDeserializer::new(a)).map(Motion::Law)
            }
        }
        d.deserialize_any(Form)
    }
}
