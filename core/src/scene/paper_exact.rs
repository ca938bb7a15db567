//! `--paper-exact`: a scene mapped to the paper's own scheme, for comparison with the
//! original code. Every switch of `crate::scene::scheme` takes its paper value: summation density
//! (eq. (8)), forward Euler at a fixed step (eq. (19)), artificial viscosity only (eq.
//! (10)), XSPH (eq. (18)), walls by the Lennard-Jones force alone (eq. (17)), an elastic
//! body's whole stress across every pair (eq. (16)), and none of the terms beyond the paper
//! (artificial stress, density diffusion, particle shifting, cohesion, background pressure,
//! no-slip walls), and an inflow band's ramped start (`[inflow] ramp`) becomes the paper's
//! impulsive one. The values the paper leaves open (alpha, beta, the step, XSPH epsilon)
//! come from the parameter study in `docs/reference/paper-scenes.md` (section `--paper-exact`):
//! forward Euler grows every undamped oscillation, so the paper's low-Mach advice
//! (alpha = 0, 0 < beta < 1) blows a resting tank up, and alpha has a floor.

use super::{Scene, SceneError};
use crate::scene::scheme;

/// What `with_paper_exact` appends to a scene's name (and the run to its default output
/// directory).
pub const NAME_SUFFIX: &str = "-paper-exact";

/// [-] Lowest linear artificial viscosity, eq. (10): forward Euler amplifies an undamped
/// oscillation every step, and alpha damps it.
pub const ALPHA_MIN: f64 = 0.3;
/// [-] The fixed step as a fraction of h / c, eq. (19) (dt < h / c), c the largest sound
/// speed of the scene (fluid or solid).
pub const DT_FRACTION: f64 = 0.05;

/// [-] The linear artificial viscosity with the effective kinematic viscosity nu [L^2/T]:
/// nu = alpha h c / 8 in 2D, alpha h c / 10 in 3D (Monaghan 2005, Rep. Prog. Phys. 68, 1703).
pub fn alpha_for_viscosity(nu: f64, h: f64, c: f64, dimension: u32) -> f64 {
    let k = if dimension == 3 { 10.0 } else { 8.0 };
    k * nu / (h * c)
}

impl Scene {
    /// The scene in the paper's own scheme (see the module docs); named `<name>-paper-exact`
    /// so that its output does not overwrite the default run's. Every switch with a fixed
    /// paper value takes it (`scheme::set_paper`); the two computed from the scene
    /// (`Paper::From` in `crate::scene::scheme`) are set here: the step, and alpha, into which a
    /// laminar viscosity goes as the artificial viscosity of the same effective nu (kept
    /// above `ALPHA_MIN`).
    pub fn with_paper_exact(&self) -> Result<Scene, SceneError> {
        let mut s = self.clone();
        let f = &mut s.file;
        let h = f.discretisation.h();
        let c = f.solid.as_ref().map_or(f.fluid.sound_speed, |m| {
            m.sound_speed.max(f.fluid.sound_speed)
        });
        if !f.name.ends_with(NAME_SUFFIX) {
            f.name = format!("{}{NAME_SUFFIX}", f.name);
        }
        let nu_alpha = alpha_for_viscosity(f.fluid.viscosity, h, f.fluid.sound_speed, f.dimension);
        let alpha = f.fluid.alpha.max(nu_alpha).max(ALPHA_MIN);
        scheme::set_paper(f);
        // An impulsive start, as the paper's "initial speed 15" (section 3.2): forward Euler
        // has no kick before the drift to set a ramp's velocity (`[inflow] ramp`).
        if let Some(i) = f.inflow.as_mut() {
            i.ramp = 0.0;
        }
        f.time.dt = Some(DT_FRACTION * h / c);
        f.fluid.alpha = alpha;
        s.text = format!(
            "# {} in meshfree's --paper-exact form (written from the parsed scene)\n{}",
            self.origin(),
            toml::to_string(&s.file).unwrap_or_default()
        );
        s.revalidate()?;
        Ok(s)
    }
}
