//! The prescribed motion of a driven wall or solid in a scene file (`motion`): a steady
//! velocity or a table of laws (translation, oscillation, rotation, a wave maker's paddle,
//! a ramp). Checked and made into `MfMotion` by `scene::motion`.

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

/// `motion = { velocity, oscillation, rotation, ramp }`: a translation at `velocity` plus an
/// oscillation, and a turn about a pivot, each started smoothly over `ramp` where given.
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
    pub wave: Option<WaveMaker>,
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
                    "a velocity [vx, vy(, vz)] or a table of velocity, oscillation, rotation, wave \
                     and ramp",
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
