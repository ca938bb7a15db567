//! The checks of a key against the rest of the scene (a declaration's `needs` in
//! `scheme.rs`): each refuses a value that another key's choice makes wrong or inert, with
//! the reason the scene error gives.

use super::*;

/// A density diffusion's delta acts on the continuity equation.
pub(super) fn continuity_only(s: &SceneFile, delta: &f64) -> Result<(), Refusal> {
    if *delta > 0.0 && s.fluid.density_form == DensityForm::Summation {
        return Err(Refusal::new(
            "acts on the continuity equation: set [fluid] density_form = \"continuity\" or leave it at 0",
        ));
    }
    Ok(())
}

/// A background pressure beyond the Tait stiffness B would dominate the equation of state.
pub(super) fn below_tait_stiffness(s: &SceneFile, p: &f64) -> Result<(), Refusal> {
    let f = &s.fluid;
    let b = f.density * f.sound_speed * f.sound_speed / f.gamma;
    if *p > b {
        return Err(Refusal::new(format!(
            "must not exceed the Tait stiffness rho0 c0^2 / gamma = {b} (a few rho0 U^2 is enough), found {p}"
        )));
    }
    Ok(())
}

/// The total-Lagrangian stress has no tensile instability to hold off: the artificial
/// stress acts on the Jaumann formulation only.
pub(super) fn total_lagrangian_without_artificial_stress(
    s: &SceneFile,
    f: &SolidFormulation,
) -> Result<(), Refusal> {
    let art = s.solid.as_ref().map_or(0.0, |m| m.artificial_stress);
    if *f == SolidFormulation::TotalLagrangian && art > 0.0 {
        return Err(Refusal::new(format!(
            "\"total-lagrangian\" is free of the tensile instability: set artificial_stress = 0 (found {art})"
        )));
    }
    Ok(())
}

/// The extrapolated fluid pressure replaces the body's stress across a fluid-body pair:
/// the paper's whole stress there (`interface = "stress"`) needs the body's own.
pub(super) fn pressure_interface(s: &SceneFile, f: &SolidFluidPressure) -> Result<(), Refusal> {
    let whole = s
        .solid
        .as_ref()
        .is_some_and(|m| m.interface == SolidInterface::Stress);
    if *f == SolidFluidPressure::Extrapolated && whole {
        return Err(Refusal::new(
            "\"extrapolated\" meets the fluid with pressure alone: set fluid_pressure = \"own\" with interface = \"stress\"",
        ));
    }
    Ok(())
}

/// `wall_contact = false` needs walls to skip.
pub(super) fn skips_walls_there_are(s: &SceneFile, meet: &bool) -> Result<(), Refusal> {
    if !meet && s.walls.is_empty() {
        return Err(Refusal::new(
            "false has no effect: the scene has no [[walls]] for its bodies to skip",
        ));
    }
    Ok(())
}

/// The Lennard-Jones exponents: p1 > p2 > 0 (checked on p1, for both).
pub(super) fn lennard_jones_exponents(s: &SceneFile, p1: &i32) -> Result<(), Refusal> {
    let p2 = s.boundary.as_ref().map_or(6, |b| b.p2);
    if p2 <= 0 || *p1 <= p2 {
        return Err(Refusal::new(format!(
            "the exponents need p1 > p2 > 0, found p1 = {p1}, p2 = {p2}"
        )));
    }
    Ok(())
}

/// The kernel's support 2h holds about pi (2 h_factor)^2 particles in 2D and 4/3 pi (2
/// h_factor)^3 in 3D, and every pair is computed: at 8, about 800 and 17,000 (the usual 1.3:
/// 21 and 74). A larger h_factor is a slip of the keyboard, and a run that crawls on every
/// pair of the domain (h_factor 1e12 put all 6,400 particles of a small tank in each one's
/// reach: 40 s for three steps), not a scheme.
pub(super) fn support_within_reason(_: &SceneFile, h_factor: &f64) -> Result<(), Refusal> {
    const MAX: f64 = 8.0;
    if *h_factor > MAX {
        return Err(Refusal::new(format!(
            "{h_factor} x spacing puts about {:.0} particles in each one's support in 3D (the \
             usual 1.3: 74); at most {MAX}",
            4.0 / 3.0 * std::f64::consts::PI * (2.0 * h_factor).powi(3)
        )));
    }
    Ok(())
}

/// Morris's no-slip walls act on the laminar viscosity between fluid and dynamic walls.
pub(super) fn morris_walls(s: &SceneFile, no_slip: &NoSlip) -> Result<(), Refusal> {
    let dynamic = s
        .boundary
        .as_ref()
        .is_some_and(|b| b.wall_coupling != WallCoupling::LennardJonesOnly);
    if *no_slip == NoSlip::Morris && (!dynamic || s.fluid.viscosity <= 0.0) {
        return Err(Refusal::new(
            "\"morris\" acts on the laminar viscosity between fluid and dynamic wall particles: \
             it needs wall_coupling = \"dynamic\" or \"mdbc\" and fluid.viscosity > 0",
        ));
    }
    Ok(())
}

/// The cap of Morris's beta, where Morris's walls are on.
pub(super) fn beta_cap(s: &SceneFile, cap: &f64) -> Result<(), Refusal> {
    let morris = s
        .boundary
        .as_ref()
        .is_some_and(|b| b.no_slip == NoSlip::Morris);
    if morris && (cap.is_nan() || *cap < 1.0) {
        return Err(Refusal::new(format!(
            "the cap of beta = 1 + d_B / d_A must be >= 1, found {cap}"
        )));
    }
    Ok(())
}

/// Figure moments: zero or positive, ascending.
pub(super) fn ascending_moments(_: &SceneFile, figures: &[f64]) -> Result<(), Refusal> {
    for (i, &t) in figures.iter().enumerate() {
        Rule::NonNegative
            .check(Some(t))
            .map_err(|r| Refusal::at(format!("[{i}]"), r.reason))?;
        if i > 0 && t <= figures[i - 1] {
            return Err(Refusal::at(
                format!("[{i}]"),
                format!(
                    "the figure moments must increase: {t} follows {}",
                    figures[i - 1]
                ),
            ));
        }
    }
    Ok(())
}
