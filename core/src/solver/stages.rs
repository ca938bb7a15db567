//! The solver's stages (the paper's Fig. 1) in one list, `stage_list!`, and the `Solver`
//! trait that fixes their order. The list declares each stage once: the trait's method (its
//! doc, and its default where it has one), the `Stage` that names it, and through `Stage`
//! the decomposition's call (`exchange::Call::Stage`), a rank's service of it and the
//! forwarding of `exchange::Rank` and `exchange::Decomposed`. A new stage is a line here
//! plus its CPU and CUDA code; `tests` below walk the list.

use crate::physics::params::{SphParams, MF_INTEGRATOR_EULER};
use crate::solver::{BackendInfo, Fault, Persist, Readback};

/// The one list of the solver's stages, handed to the macro `$then` (a callback, so that the
/// trait, `Stage` and the forwarding impls each expand the same list). Each entry: the
/// stage's doc, its `Stage` variant, and the trait method's signature, with a default body
/// where a backend may leave the stage out (`{}`) or run it as other stages (`{ ... }`).
macro_rules! stage_list {
    ($then:ident) => {
        $then! {
            /// The open boundaries (`[[open_boundaries]]`, `physics::open::fate`): an
            /// inlet's buffer particles that reached the fluid join it and are replaced
            /// behind, fluid that entered an outlet joins its buffer, and particles past a
            /// buffer are removed: the particle count changes. First in the step, so that
            /// the grid build sorts the new particles in. Nothing without open boundaries
            /// (the default does nothing).
            OpenBoundaries: fn open_boundaries(&mut self) {}
            /// Neighbour search: cell index, sort by (cell, id), cell ranges, reorder.
            BuildGrid: fn build_grid(&mut self);
            /// Density by summation, eq. (8) (nothing for the continuity form); the Tait
            /// equation of state, eq. (9), and the solid pressure law; the artificial stress
            /// of solids.
            Density: fn density(&mut self);
            /// The fluid's pressure extrapolated to the bodies' particles and its Tait
            /// density, at which the force stage pairs them with the fluid (`[solid]
            /// fluid_pressure = "extrapolated"`: Adami, Hu & Adams 2012; `pairs::
            /// extrapolated_pair`). Nothing without solids or under "own" (the default does
            /// nothing).
            SolidInterface: fn solid_interface(&mut self) {}
            /// The total-Lagrangian bodies' stress (`[solid] formulation =
            /// "total-lagrangian"`, `crate::physics::tlsph`): the deformation gradient from the
            /// displacements, the Saint Venant-Kirchhoff stress, and the deviator of its
            /// Cauchy stress written into S, where the force stage reads it (the particle's
            /// density and pressure stay the continuity density's, the interface's).
            /// Nothing under the Jaumann rate (the default does nothing).
            SolidStress: fn solid_stress(&mut self) {}
            /// Accelerations: eqs. (7), (10), (16), (17), laminar viscosity, artificial
            /// stress, gravity.
            Forces: fn forces(&mut self);
            /// The total-Lagrangian bodies' internal force and hourglass control, added to
            /// the force stage's accelerations (which left out the stress term between
            /// particles of one total-Lagrangian body). Nothing under the Jaumann rate (the
            /// default does nothing).
            SolidForces: fn solid_forces(&mut self) {}
            /// The renormalised density gradients that the rates stage's density diffusion
            /// reads (Antuono et al. 2010's form: the fluid's under `density_diffusion_form =
            /// "antuono"`, each body's under `[solid] density_diffusion`), from the current
            /// positions and densities; nothing unless `params::needs_density_gradient`.
            DensityGradient: fn density_gradient(&mut self);
            /// Rates from the current velocities: d rho/dt (continuity, with the density
            /// diffusion of Molteni & Colagrossi 2009 where `density_diffusion` > 0), the
            /// XSPH velocity of eq. (18), and, with solids, the velocity gradient eq. (15),
            /// strain and rotation rates eqs. (13)-(14) and the Jaumann stress rate
            /// eq. (12).
            Rates: fn rates(&mut self);
            /// `forces` and `rates` of one state, as the paper's forward Euler takes them
            /// (both from the old velocities; neither reads what the other writes). A
            /// backend may compute both in one neighbour pass (the CUDA backend does); the
            /// default runs the two stages.
            ForcesAndRates: fn forces_and_rates(&mut self) {
                self.rates();
                self.forces();
            }
            /// The step size: fixed, or the CFL eq. (19) with the force and viscous limits.
            TimeStep: fn time_step(&mut self);
            /// v += dt a.
            Kick: fn kick(&mut self);
            /// x += dt (v + xsph), rho += dt d rho/dt, S += dt dS/dt, and the
            /// total-Lagrangian bodies' displacement u += dt (v + xsph); advances the clock.
            Drift: fn drift(&mut self);
            /// The forward Euler's `drift` then `kick` (the positions move with the old
            /// velocity). A backend may do both in one pass over the particles (the CUDA
            /// backend does).
            DriftKick: fn drift_kick(&mut self) {
                self.drift();
                self.kick();
            }
        }
    };
}
pub(crate) use stage_list;

/// The trait's stage methods, from the list.
macro_rules! trait_stages {
    ($($(#[$doc:meta])* $stage:ident: fn $name:ident(&mut $s:ident) $body:tt)*) => {
        $($(#[$doc])* fn $name(&mut $s) $body)*
    };
}

/// `Stage`, from the list.
macro_rules! stage_enum {
    ($($(#[$doc:meta])* $stage:ident: fn $name:ident(&mut $s:ident) $body:tt)*) => {
        /// A stage of `Solver` by name: what a decomposed run asks every rank to run
        /// (`exchange::Call::Stage`), and what a solver that passes stages on forwards.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
        pub enum Stage {
            $($(#[$doc])* $stage,)*
        }

        impl Stage {
            /// Every stage, in the list's order.
            pub const ALL: &'static [Stage] = &[$(Stage::$stage),*];

            /// The stage's method name (`"build_grid"`).
            pub fn name(self) -> &'static str {
                match self {
                    $(Stage::$stage => stringify!($name),)*
                }
            }

            /// Run this stage of `solver`.
            pub fn run<S: Solver + ?Sized>(self, solver: &mut S) {
                match self {
                    $(Stage::$stage => solver.$name(),)*
                }
            }
        }
    };
}
stage_list!(stage_enum);

/// Inside an `impl Solver`: each stage method as `self.run_stage(Stage::...)`, for a solver
/// that passes every stage on the same way (`exchange::Rank`, `exchange::Decomposed`).
macro_rules! forward_stages {
    ($($(#[$doc:meta])* $stage:ident: fn $name:ident(&mut $s:ident) $body:tt)*) => {
        $(fn $name(&mut self) {
            self.run_stage($crate::solver::Stage::$stage)
        })*
    };
}
pub(crate) use forward_stages;

/// The solver stages (Fig. 1) in the trait's one order, with the clock and the health
/// checks. What comes back from a solver is `Readback`'s, what a restart needs `Persist`'s.
pub trait Solver: Readback + Persist + Send {
    fn info(&self) -> BackendInfo;
    fn params(&self) -> &SphParams;
    fn len(&self) -> usize;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    fn has_solids(&self) -> bool;

    stage_list!(trait_stages);

    /// One time step, in the order of the paper's Fig. 1. The paper's forward Euler,
    /// eq. (19), takes every rate at the old velocity; the symplectic Euler kicks first and
    /// takes the rates, positions, density and stress from the new velocity.
    fn step(&mut self) {
        self.open_boundaries();
        self.build_grid();
        self.density();
        self.solid_interface();
        self.solid_stress();
        if self.params().integrator as u32 == MF_INTEGRATOR_EULER {
            self.density_gradient();
            self.forces_and_rates();
            self.solid_forces();
            self.time_step();
            self.drift_kick();
        } else {
            self.forces();
            self.solid_forces();
            self.time_step();
            self.kick();
            self.density_gradient();
            self.rates();
            self.drift();
        }
    }

    /// `steps` steps of `step`, as one batch: a backend may record the trait's `step` once
    /// and replay the recording (the CUDA backend replays a CUDA graph), never reorder it.
    fn advance(&mut self, steps: u64) {
        for _ in 0..steps {
            self.step();
        }
    }

    /// Simulated time \[T\] (a read-back on the GPU).
    fn time(&mut self) -> f64;
    fn steps(&self) -> u64;
    /// The first particle with non-finite values, a density out of the sane range, or
    /// outside the domain on a non-periodic axis.
    fn check(&mut self) -> Result<(), Fault>;
    /// `check` of the particles as they are now, whose fault may be reported later, by
    /// `queued_fault`, with the step, time and particle of this check: a GPU backend queues
    /// the check and keeps the first fault on the device, so that stepping never waits for
    /// it (`step::Stepper` reads it with the clock at the end of each batch). The default
    /// checks at once.
    fn queue_check(&mut self) -> Result<(), Fault> {
        self.check()
    }
    /// The first fault that the checks queued so far found, if any (the default queues
    /// none).
    fn queued_fault(&mut self) -> Result<(), Fault> {
        Ok(())
    }
    /// Remove every particle of a scene group (opening a gate). Returns how many went.
    fn remove_group(&mut self, group: u32) -> usize;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::params::MF_INTEGRATOR_LEAPFROG;
    use crate::physics::particle::Particle;
    use crate::solver::checkpoint::SolverCheckpoint;
    use crate::solver::frame::{Fields, PendingFrame};
    use crate::solver::{Diagnostics, PointSample};

    /// A solver that only records which stage methods ran, in order.
    struct Recorder {
        params: SphParams,
        ran: Vec<&'static str>,
    }

    macro_rules! record_stages {
        ($($(#[$doc:meta])* $stage:ident: fn $name:ident(&mut $s:ident) $body:tt)*) => {
            $(fn $name(&mut self) {
                self.ran.push(stringify!($name));
            })*
        };
    }

    impl Solver for Recorder {
        fn info(&self) -> BackendInfo {
            unreachable!("not a stage")
        }
        fn params(&self) -> &SphParams {
            &self.params
        }
        fn len(&self) -> usize {
            0
        }
        fn has_solids(&self) -> bool {
            false
        }
        stage_list!(record_stages);
        fn time(&mut self) -> f64 {
            unreachable!("not a stage")
        }
        fn steps(&self) -> u64 {
            unreachable!("not a stage")
        }
        fn check(&mut self) -> Result<(), Fault> {
            unreachable!("not a stage")
        }
        fn remove_group(&mut self, _: u32) -> usize {
            unreachable!("not a stage")
        }
    }

    impl Readback for Recorder {
        fn diagnostics(&mut self) -> Diagnostics {
            unreachable!("not a stage")
        }
        fn particles(&mut self) -> Vec<Particle> {
            unreachable!("not a stage")
        }
        fn capture(&mut self, _: Fields) -> Box<dyn PendingFrame> {
            unreachable!("not a stage")
        }
        fn sample_points(&mut self, _: &[[f32; 3]], _: bool, _: &mut Vec<PointSample>) {
            unreachable!("not a stage")
        }
        fn wall_surface(&self) -> &[[f32; 4]] {
            unreachable!("not a stage")
        }
        fn wall_forces(&mut self, _: &[u32]) -> Vec<[f64; 3]> {
            unreachable!("not a stage")
        }
    }

    impl Persist for Recorder {
        fn save(&mut self) -> SolverCheckpoint {
            unreachable!("not a stage")
        }
        fn restore(&mut self, _: &SolverCheckpoint) -> Result<(), String> {
            unreachable!("not a stage")
        }
    }

    fn recorder(integrator: u32) -> Recorder {
        Recorder {
            params: SphParams {
                integrator: integrator as _,
                ..SphParams::default()
            },
            ran: Vec::new(),
        }
    }

    /// Every stage of the list runs its own method and no other, under its own name.
    #[test]
    fn each_stage_runs_its_method() {
        for &stage in Stage::ALL {
            let mut r = recorder(MF_INTEGRATOR_EULER);
            stage.run(&mut r);
            assert_eq!(r.ran, [stage.name()], "{stage:?}");
        }
        let names: std::collections::HashSet<_> = Stage::ALL.iter().map(|s| s.name()).collect();
        assert_eq!(names.len(), Stage::ALL.len(), "two stages share a name");
    }

    /// The trait's order calls only stages of the list, and between the two integrators'
    /// orders every stage of the list is called: a stage added to the trait by hand, or
    /// listed and never stepped, fails here.
    #[test]
    fn the_order_steps_every_listed_stage_and_nothing_else() {
        let euler = {
            let mut r = recorder(MF_INTEGRATOR_EULER);
            r.step();
            r.ran
        };
        let other = {
            let mut r = recorder(MF_INTEGRATOR_LEAPFROG);
            r.step();
            r.ran
        };
        assert_eq!(
            euler,
            [
                "open_boundaries",
                "build_grid",
                "density",
                "solid_interface",
                "solid_stress",
                "density_gradient",
                "forces_and_rates",
                "solid_forces",
                "time_step",
                "drift_kick"
            ]
        );
        assert_eq!(
            other,
            [
                "open_boundaries",
                "build_grid",
                "density",
                "solid_interface",
                "solid_stress",
                "forces",
                "solid_forces",
                "time_step",
                "kick",
                "density_gradient",
                "rates",
                "drift"
            ]
        );
        for &stage in Stage::ALL {
            assert!(
                euler.contains(&stage.name()) || other.contains(&stage.name()),
                "{stage:?} is listed but no integrator's step runs it"
            );
        }
    }
}
