//! What `meshfree stability` sweeps: maps of two parameters each over a base scene, with
//! the integrator, density form and wall coupling fixed per map.

use serde::{Deserialize, Serialize};

use super::Tier;
use meshfree_core::scene::scheme::{DensityForm, IntegratorChoice, WallCoupling};
use meshfree_core::scene::Scene;

/// The base scene of a map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Base {
    /// The square-column 2D dam break of `validate::dam_break` (error: surge front vs
    /// Martin & Moyce 1952).
    DamBreak,
    /// A stretched elastic strip (`cases::strip_scene_text`; error: particle clumping or
    /// fracture, the tensile instability).
    ElasticStrip,
}

/// A swept parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Param {
    /// `time.courant`.
    Courant,
    /// `fluid.alpha`, eq. (10).
    Alpha,
    /// A factor on `boundary.strength` (the Lennard-Jones C0, eq. (17)).
    LjStrength,
    /// `fluid.density_diffusion` (delta-SPH).
    DensityDiffusion,
    /// `solid.artificial_stress`.
    ArtificialStress,
}

impl Param {
    pub fn label(self) -> &'static str {
        match self {
            Param::Courant => "Courant number",
            Param::Alpha => "artificial viscosity alpha",
            Param::LjStrength => "Lennard-Jones C0 / scene C0",
            Param::DensityDiffusion => "density diffusion delta",
            Param::ArtificialStress => "artificial stress epsilon",
        }
    }
}

/// One axis: a parameter and its values.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Axis {
    pub param: Param,
    pub values: Vec<f64>,
}

/// One heat map.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MapDef {
    /// File-name friendly, e.g. `dam-break-symplectic-continuity`.
    pub name: String,
    pub title: String,
    pub base: Base,
    pub integrator: IntegratorChoice,
    pub density_form: DensityForm,
    pub wall_coupling: WallCoupling,
    pub x: Axis,
    pub y: Axis,
}

fn integrator_name(i: IntegratorChoice) -> &'static str {
    match i {
        IntegratorChoice::SymplecticEuler => "symplectic",
        IntegratorChoice::Euler => "euler",
        IntegratorChoice::Leapfrog => "leapfrog",
    }
}

fn integrator_title(i: IntegratorChoice) -> &'static str {
    match i {
        IntegratorChoice::SymplecticEuler => "symplectic Euler",
        IntegratorChoice::Euler => "forward Euler (the paper)",
        IntegratorChoice::Leapfrog => "leapfrog",
    }
}

fn density_name(d: DensityForm) -> &'static str {
    match d {
        DensityForm::Continuity => "continuity",
        DensityForm::Summation => "summation",
    }
}

/// The maps of a tier. Quick: two values per axis (a test calls it); full: five.
pub fn maps(tier: Tier) -> Vec<MapDef> {
    let quick = tier == Tier::Quick;
    let pick = |full: &[f64], q: &[f64]| if quick { q.to_vec() } else { full.to_vec() };
    let courant = pick(&[0.1, 0.2, 0.4, 0.8, 1.2], &[0.4, 1.2]);
    let alpha = pick(&[0.0, 0.01, 0.02, 0.05, 0.1], &[0.0, 0.05]);
    let lj = pick(&[0.1, 0.3, 1.0, 3.0, 10.0], &[0.1, 1.0]);
    let delta = pick(&[0.0, 0.05, 0.1, 0.2], &[0.0, 0.1]);
    let art = pick(&[0.0, 0.1, 0.2, 0.3, 0.5], &[0.0, 0.3]);
    let axis = |param, values: &Vec<f64>| Axis {
        param,
        values: values.clone(),
    };
    let mut out = Vec::new();
    for integrator in [
        IntegratorChoice::Leapfrog,
        IntegratorChoice::SymplecticEuler,
        IntegratorChoice::Euler,
    ] {
        for density_form in [DensityForm::Continuity, DensityForm::Summation] {
            let (i, d) = (integrator_name(integrator), density_name(density_form));
            out.push(MapDef {
                name: format!("dam-break-{i}-{d}"),
                title: format!(
                    "Dam break, {}, {d} density: Courant x alpha",
                    integrator_title(integrator)
                ),
                base: Base::DamBreak,
                integrator,
                density_form,
                wall_coupling: WallCoupling::Dynamic,
                x: axis(Param::Courant, &courant),
                y: axis(Param::Alpha, &alpha),
            });
        }
    }
    let sym = IntegratorChoice::SymplecticEuler;
    out.push(MapDef {
        name: "dam-break-lj-walls".into(),
        title: "Dam break, Lennard-Jones-only walls (the paper): Courant x C0".into(),
        base: Base::DamBreak,
        integrator: sym,
        density_form: DensityForm::Continuity,
        wall_coupling: WallCoupling::LennardJonesOnly,
        x: axis(Param::Courant, &courant),
        y: axis(Param::LjStrength, &lj),
    });
    out.push(MapDef {
        name: "dam-break-density-diffusion".into(),
        title: "Dam break, symplectic Euler, continuity: Courant x delta-SPH".into(),
        base: Base::DamBreak,
        integrator: sym,
        density_form: DensityForm::Continuity,
        wall_coupling: WallCoupling::Dynamic,
        x: axis(Param::Courant, &courant),
        y: axis(Param::DensityDiffusion, &delta),
    });
    for integrator in [
        IntegratorChoice::Leapfrog,
        IntegratorChoice::SymplecticEuler,
        IntegratorChoice::Euler,
    ] {
        let i = integrator_name(integrator);
        out.push(MapDef {
            name: format!("elastic-strip-{i}"),
            title: format!(
                "Stretched elastic strip, {}: Courant x artificial stress",
                integrator_title(integrator)
            ),
            base: Base::ElasticStrip,
            integrator,
            density_form: DensityForm::Continuity,
            wall_coupling: WallCoupling::Dynamic,
            x: axis(Param::Courant, &courant),
            y: axis(Param::ArtificialStress, &art),
        });
    }
    out
}

/// Set `param` to `value` in `scene` (validated by the caller).
pub fn apply(scene: &mut Scene, param: Param, value: f64) {
    let f = &mut scene.file;
    match param {
        Param::Courant => f.time.courant = Some(value),
        Param::Alpha => f.fluid.alpha = value,
        Param::LjStrength => {
            if let Some(b) = f.boundary.as_mut() {
                b.strength *= value;
            }
        }
        Param::DensityDiffusion => f.fluid.density_diffusion = value,
        Param::ArtificialStress => {
            if let Some(s) = f.solid.as_mut() {
                s.artificial_stress = value;
            }
        }
    }
}

/// Set the map's fixed choices in `scene`.
pub fn apply_fixed(scene: &mut Scene, map: &MapDef) {
    let f = &mut scene.file;
    f.time.integrator = map.integrator;
    f.fluid.density_form = map.density_form;
    if let Some(b) = f.boundary.as_mut() {
        b.wall_coupling = map.wall_coupling;
    }
}
