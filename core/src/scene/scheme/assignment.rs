//! `TABLE.KEY=VALUE`: one scheme key set from the command line (`meshfree validate --set`),
//! checked against the key's declaration before anything runs.

use std::fmt;
use std::str::FromStr;

use super::{key, keys, Key, SceneFile};

/// A scene with every scheme table and only the keys they require, in which an assignment
/// is tried before any case's scene is built.
const PROBE: &str = r#"
dimension = 2
name = "probe"
[domain]
min = [0.0, 0.0]
max = [1.0, 1.0]
[discretisation]
spacing = 0.1
[time]
end = 1.0
output_interval = 1.0
[fluid]
density = 1000.0
sound_speed = 10.0
[solid]
density = 1000.0
sound_speed = 10.0
shear_modulus = 1.0e6
[boundary]
strength = 1.0
"#;

/// A scheme key and the value to give it in every scene that has its table.
#[derive(Clone, Debug)]
pub struct Assignment {
    pub key: &'static Key,
    pub value: toml::Value,
}

impl FromStr for Assignment {
    type Err = String;

    /// `fluid.density_diffusion=0.1`, `solid.fluid_pressure=extrapolated`: the value as
    /// TOML (a number, `true`, a quoted string), or a bare word as a string. The value is
    /// checked by setting it in the key's default table, so that a wrong type or an unknown
    /// choice is refused here, naming what the key takes.
    fn from_str(s: &str) -> Result<Assignment, String> {
        let (path, text) = s
            .split_once('=')
            .ok_or_else(|| format!("`{s}`: expected TABLE.KEY=VALUE, e.g. fluid.alpha=0.05"))?;
        let path = path.trim();
        let key = key(path).ok_or_else(|| {
            let near: Vec<&str> = keys()
                .map(|k| k.path)
                .filter(|p| p.split('.').next_back() == path.split('.').next_back())
                .collect();
            match near.as_slice() {
                [] => format!(
                    "`{path}` is not a scheme key (`meshfree scenes --reference` lists them)"
                ),
                _ => format!(
                    "`{path}` is not a scheme key; did you mean {}?",
                    near.join(" or ")
                ),
            }
        })?;
        let text = text.trim();
        let value = match toml::from_str::<toml::Table>(&format!("v = {text}")) {
            Ok(mut t) => t.remove("v").expect("the table parsed holds v"),
            Err(_) => toml::Value::String(text.to_string()),
        };
        let a = Assignment { key, value };
        let mut probe: SceneFile = toml::from_str(PROBE).expect("the probe scene parses");
        a.apply(&mut probe)
            .map_err(|e| format!("{path} = {text}: {e} ({} expected)", key.kind))?;
        (key.validate)(&probe).map_err(|e| format!("{path}{} = {text}: {}", e.at, e.reason))?;
        Ok(a)
    }
}

impl Assignment {
    /// Set the value in `file`; `Ok(false)` where the scene has no table of the key (a
    /// fluid-only scene and a `solid.` key), which it leaves as it is.
    pub fn apply(&self, file: &mut SceneFile) -> Result<bool, String> {
        if !(self.key.has_table)(file) {
            return Ok(false);
        }
        (self.key.set)(file, self.value.clone())?;
        Ok(true)
    }
}

impl fmt::Display for Assignment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}", self.key.path, self.value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_assignment_names_its_key_and_takes_a_toml_value_or_a_word() {
        let a: Assignment = "solid.fluid_pressure=extrapolated".parse().unwrap();
        assert_eq!(a.key.path, "solid.fluid_pressure");
        assert_eq!(a.value, toml::Value::String("extrapolated".into()));
        let b: Assignment = " fluid.density_diffusion = 0.1 ".parse().unwrap();
        assert_eq!(b.value, toml::Value::Float(0.1));
        assert_eq!(b.to_string(), "fluid.density_diffusion = 0.1");
        let c: Assignment = "boundary.wall_density_floor=true".parse().unwrap();
        assert_eq!(c.value, toml::Value::Boolean(true));
    }

    #[test]
    fn a_wrong_key_type_or_choice_is_refused_before_anything_runs() {
        let e = "density_diffusion=0.1".parse::<Assignment>().unwrap_err();
        assert!(e.contains("did you mean fluid.density_diffusion"), "{e}");
        let e = "fluid.nothing=1".parse::<Assignment>().unwrap_err();
        assert!(e.contains("not a scheme key"), "{e}");
        let e = "fluid.alpha".parse::<Assignment>().unwrap_err();
        assert!(e.contains("TABLE.KEY=VALUE"), "{e}");
        let e = "solid.fluid_pressure=sideways"
            .parse::<Assignment>()
            .unwrap_err();
        assert!(e.contains("solid.fluid_pressure = sideways"), "{e}");
        let e = "boundary.wall_density_floor=3"
            .parse::<Assignment>()
            .unwrap_err();
        assert!(e.contains("boundary.wall_density_floor = 3"), "{e}");
        let e = "fluid.alpha=-1".parse::<Assignment>().unwrap_err();
        assert!(e.contains("fluid.alpha = -1"), "{e}");
    }

    #[test]
    fn a_scene_without_the_table_is_left_as_it_is() {
        let a: Assignment = "solid.fluid_pressure=extrapolated".parse().unwrap();
        let mut f: SceneFile = toml::from_str(PROBE).unwrap();
        f.solid = None;
        let before = toml::to_string(&f).unwrap();
        assert_eq!(a.apply(&mut f), Ok(false));
        assert_eq!(toml::to_string(&f).unwrap(), before);
        let mut g: SceneFile = toml::from_str(PROBE).unwrap();
        assert_eq!(a.apply(&mut g), Ok(true));
        assert_eq!((a.key.get)(&g), Some(a.value.clone()));
    }
}
