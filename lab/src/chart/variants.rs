//! The chart's scheme variants, and which of them a case runs: a variant is skipped, with
//! its reason, where it does not apply to the case's scheme or changes nothing in it.

use crate::validate::cylinder;
use meshfree_core::scene::scheme::{DensityForm, DiffusionForm, IntegratorChoice, KernelChoice};
use meshfree_core::scene::Scene;

/// The reason a variant that resolves to the case's default scheme is skipped: its point
/// would repeat the default's number.
pub const SAME_AS_DEFAULT: &str = "same as the default here";

/// A variant: a name and a change to the case's scene.
#[derive(Clone, Copy)]
pub(super) struct Variant {
    pub name: &'static str,
    pub edit: fn(&mut Scene),
    /// Why the variant does not apply to a case's scene (before the edit), where it does not.
    not_for: fn(&Scene) -> Option<&'static str>,
}

impl Variant {
    fn new(name: &'static str, edit: fn(&mut Scene)) -> Variant {
        Variant {
            name,
            edit,
            not_for: |_| None,
        }
    }

    /// The case's own scheme.
    pub fn default() -> Variant {
        Variant::new("default", |_| {})
    }

    /// A density diffusion: it acts on the continuity density, and a case with summation
    /// density is skipped rather than switched to the continuity form. The switch would
    /// change two things at once, and on the cylinder (the summation case) the continuity
    /// form lets the wall's density drift and the fluid in (scenes/vortex-street-re105.toml).
    fn density_diffusion(name: &'static str, edit: fn(&mut Scene)) -> Variant {
        Variant {
            not_for: |s| {
                (s.file.fluid.density_form == DensityForm::Summation).then_some(
                    "density diffusion acts on the continuity density; this case uses summation density",
                )
            },
            ..Variant::new(name, edit)
        }
    }
}

/// The variants run at a case's middle resolution, in order (the default not among them).
/// Quick: the first one only.
pub(super) fn case_variants(case: &str, quick: bool) -> Vec<Variant> {
    let mut all = vec![
        Variant::new("Wendland C2", |s| {
            s.file.discretisation.kernel = KernelChoice::WendlandC2
        }),
        Variant::new("summation density", |s| {
            s.file.fluid.density_form = DensityForm::Summation
        }),
        Variant::new("forward Euler", |s| {
            s.file.time.integrator = IntegratorChoice::Euler
        }),
        Variant::density_diffusion("delta-SPH 0.1", |s| s.file.fluid.density_diffusion = 0.1),
        Variant::density_diffusion("delta-SPH 0.1, Fourtakas", |s| {
            s.file.fluid.density_diffusion = 0.1;
            s.file.fluid.density_diffusion_form = DiffusionForm::Fourtakas;
        }),
        Variant::density_diffusion("delta-SPH 0.1, Antuono", |s| {
            s.file.fluid.density_diffusion = 0.1;
            s.file.fluid.density_diffusion_form = DiffusionForm::Antuono;
        }),
        Variant::new("shifting 0.2", |s| s.file.fluid.shifting = 0.2),
        Variant::new("Courant 0.4", |s| s.file.time.courant = Some(0.4)),
    ];
    if quick {
        all.truncate(1);
        return all;
    }
    all.push(viscosity_variant(case));
    if case == "cylinder" {
        // The validate case's scheme (issue #23: the wake without voids).
        all.push(Variant::new(
            "shifting 0.2, background pressure 2 q, Morris walls, ramped start",
            cylinder::confined,
        ));
    }
    all
}

/// The dam break's viscosity variant: alpha 0.05 instead of 0.02; the Taylor-Green
/// vortex's: artificial viscosity with the same nu = alpha h c0 / 8 (Monaghan 1992, 2D)
/// instead of the laminar term.
fn viscosity_variant(case: &str) -> Variant {
    if case == "dam-break" {
        Variant::new("alpha 0.05", |s| s.file.fluid.alpha = 0.05)
    } else {
        Variant::new("artificial viscosity", |s| {
            let f = &mut s.file;
            let h = f.discretisation.h();
            f.fluid.alpha = 8.0 * f.fluid.viscosity / (h * f.fluid.sound_speed);
            f.fluid.viscosity = 0.0;
        })
    }
}

/// Why `v` is not run on the case whose scene is `default` (at the resolution it would run
/// at), or None to run it: it does not apply to the case's scheme (its own check, else the
/// scene's refusal of the edited scene), or the edited scene resolves to the same
/// parameters as the default (`Scene::params`, the scheme as the solver gets it: a Courant
/// number the integrator already defaults to, a density form the case already has). The
/// resolved scheme is compared, not the run's result, so nothing runs to find out.
pub(super) fn skip_reason(default: &Scene, v: &Variant) -> Option<String> {
    if let Some(reason) = (v.not_for)(default) {
        return Some(reason.to_string());
    }
    let mut edited = default.clone();
    (v.edit)(&mut edited);
    if let Err(e) = edited.revalidate() {
        return Some(format!("refused by the case's scene: {e}"));
    }
    (edited.params() == default.params()).then(|| SAME_AS_DEFAULT.to_string())
}
